//! Chapter 4: the hard-sphere coefficient of normal restitution `eps_n^HS` (eq 4.1) of oblique
//! soft-sphere impacts against the impact eccentricity `e = d / l` (Fig 4.2-4.10).

use serde::Serialize;

use super::collide::{Collision, Impact};
use crate::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use crate::SimError;

/// Two identical spheres of radius `radius` (m) and density `density` (kg/m^3) colliding at
/// relative speed `speed` (m/s) under `law`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EccentricStudy {
    pub name: &'static str,
    pub law: ContactLaw,
    pub radius: f64,
    pub density: f64,
    pub speed: f64,
}

/// One point of an eccentricity sweep.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EccentricPoint {
    pub e: f64,
    pub eps_n_hs: f64,
    pub eps_n: f64,
    pub phi: f64,
    pub t_c: f64,
    /// eq 4.16 evaluated with the measured `phi` (valid for elastic, smooth spheres only):
    /// `cos phi - sin phi / sqrt(1/e^2 - 1)`.
    pub eq_4_16: f64,
}

impl EccentricStudy {
    /// Runs one impact at eccentricity `e` with `steps` steps per contact time.
    pub fn point(&self, e: f64, steps: f64) -> Result<EccentricPoint, SimError> {
        let impact = Impact::Eccentric { v: self.speed, e };
        let c = Collision::equal_spheres(self.law, self.radius, self.density, impact, steps);
        let r = c.run()?;
        let eq_4_16 = if e > 0.0 {
            r.phi.cos() - r.phi.sin() / (1.0 / (e * e) - 1.0).sqrt()
        } else {
            1.0
        };
        Ok(EccentricPoint {
            e,
            eps_n_hs: r.eps_n_hs,
            eps_n: r.eps_n,
            phi: r.phi,
            t_c: r.t_c,
            eq_4_16,
        })
    }

    /// Sweeps `e` over `es`.
    pub fn sweep(&self, es: &[f64], steps: f64) -> Result<Vec<EccentricPoint>, SimError> {
        es.iter().map(|&e| self.point(e, steps)).collect()
    }
}

/// The thesis' four configurations (Fig 4.4, 4.7, 4.10): linear dashpot (k = 1.5e5 N/m,
/// gamma = 0, rho = 1140 kg/m^3) and viscoelastic soft silicon rubber (Y = 0.01 GPa,
/// nu = 0.5, rho = 2000 kg/m^3, A = 0), each smooth and with Cundall-Strack friction
/// (k_t = 1e5 N/m, mu = 1e8); R = 0.1 m, v = 10 m/s.
pub fn thesis_studies() -> Vec<EccentricStudy> {
    let linear = NormalLaw::Linear { kn: 1.5e5, gamma_n: 0.0 };
    let rubber = NormalLaw::hertz(1e7 / (1.0 - 0.25), 0.0);
    let friction = TangentialLaw::CundallStrack { kt: 1e5, mu: 1e8 };
    let law = |normal, tangential| ContactLaw {
        normal,
        tangential,
        rolling: RollingLaw::None,
    };
    let study = |name, normal, tangential, density| EccentricStudy {
        name,
        law: law(normal, tangential),
        radius: 0.1,
        density,
        speed: 10.0,
    };
    vec![
        study("linear, smooth", linear, TangentialLaw::None, 1140.0),
        study("linear, friction", linear, friction, 1140.0),
        study("viscoelastic, smooth", rubber, TangentialLaw::None, 2000.0),
        study("viscoelastic, friction", rubber, friction, 2000.0),
    ]
}
