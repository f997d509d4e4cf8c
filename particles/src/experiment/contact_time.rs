//! Contact duration of head-on viscoelastic collisions of equal spheres against dissipation
//! A, radius R, Young's modulus Y and impact speed v (thesis 3.2.5, Fig 3.5), next to the
//! undamped closed form eq 3.19.

use serde::Serialize;

use super::collide::{Collision, Impact};
use crate::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use crate::SimError;

/// Base point of the sweeps (Fig 3.5): R = 0.5 mm, Y = 1e6 Pa, nu = 0.3, rho = 2500 kg/m^3,
/// A = 8.5e-6 s, v = 0.002 m/s.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactTimeCase {
    pub dissipation: f64,
    pub radius: f64,
    pub young: f64,
    pub speed: f64,
    pub poisson: f64,
    pub density: f64,
}

impl Default for ContactTimeCase {
    fn default() -> Self {
        Self {
            dissipation: 8.5e-6,
            radius: 5e-4,
            young: 1e6,
            speed: 0.002,
            poisson: 0.3,
            density: 2500.0,
        }
    }
}

/// One row of the study.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactTimeRow {
    /// Which parameter is varied: "dissipation", "radius", "young" or "speed".
    pub parameter: &'static str,
    pub value: f64,
    /// Measured contact duration (s).
    pub t_c: f64,
    /// Undamped closed form eq 3.19 (s).
    pub t_c_eq_3_19: f64,
    pub eps_n: f64,
}

impl ContactTimeCase {
    fn collision(&self, steps: f64) -> Collision {
        let law = ContactLaw {
            normal: NormalLaw::hertz(self.young / (1.0 - self.poisson * self.poisson), self.dissipation),
            tangential: TangentialLaw::None,
            rolling: RollingLaw::None,
        };
        let impact = Impact::Components { vn: self.speed, vt: 0.0 };
        Collision::equal_spheres(law, self.radius, self.density, impact, steps)
    }

    fn row(&self, parameter: &'static str, value: f64, steps: f64) -> Result<ContactTimeRow, SimError> {
        let c = self.collision(steps);
        let r = c.run()?;
        Ok(ContactTimeRow {
            parameter,
            value,
            t_c: r.t_c,
            t_c_eq_3_19: c.contact_time_estimate(),
            eps_n: r.eps_n,
        })
    }
}

/// The four sweeps of Fig 3.5 around `base`, `points` values each (log-spaced except A,
/// which is linear from 0), with `steps` steps per contact; fewer than 2 points is an error.
pub fn study(base: ContactTimeCase, points: usize, steps: f64) -> Result<Vec<ContactTimeRow>, SimError> {
    if points < 2 {
        return Err(SimError::InvalidParameter {
            field: "points".into(),
            message: format!("a sweep needs at least 2 values, got {points}"),
        });
    }
    let lin = |a: f64, b: f64| (0..points).map(move |k| a + (b - a) * k as f64 / (points - 1) as f64);
    let log = |a: f64, b: f64| lin(a.ln(), b.ln()).map(f64::exp);
    let mut rows = Vec::new();
    for a in lin(0.0, 1e-4) {
        rows.push(ContactTimeCase { dissipation: a, ..base }.row("dissipation", a, steps)?);
    }
    for r in log(1e-4, 5e-3) {
        rows.push(ContactTimeCase { radius: r, ..base }.row("radius", r, steps)?);
    }
    for y in log(1e5, 1e9) {
        rows.push(ContactTimeCase { young: y, ..base }.row("young", y, steps)?);
    }
    for v in log(1e-4, 1.0) {
        rows.push(ContactTimeCase { speed: v, ..base }.row("speed", v, steps)?);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dissipation_shortens_contact_weakly_and_speed_strongly() {
        let rows = study(ContactTimeCase::default(), 3, 400.0).unwrap();
        let of = |p: &str| rows.iter().filter(|r| r.parameter == p).collect::<Vec<_>>();
        let a = of("dissipation");
        // Undamped: equals eq 3.19.
        assert!((a[0].t_c / a[0].t_c_eq_3_19 - 1.0).abs() < 1e-4);
        // Damping changes t_c by well under a factor 2 over the range (Fig 3.5a).
        assert!(a.iter().all(|r| (r.t_c / a[0].t_c - 1.0).abs() < 0.5));
        // Contact time grows with radius, falls with Y and v (Fig 3.5b-d).
        let (r, y, v) = (of("radius"), of("young"), of("speed"));
        assert!(r.windows(2).all(|w| w[1].t_c > w[0].t_c));
        assert!(y.windows(2).all(|w| w[1].t_c < w[0].t_c));
        assert!(v.windows(2).all(|w| w[1].t_c < w[0].t_c));
    }
}
