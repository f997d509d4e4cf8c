//! Collision rules: instantaneous maps of the velocities and spins of two bodies meeting at
//! a contact normal, pure functions tested alone (appendix A of the sawtooth paper; Walton
//! 1993).
//!
//! Conventions, in the plane of motion with `perp(a) = (-a_z, a_x)` and scalar spins `w`
//! (about the axis normal to the plane, `w x a = w perp(a)`):
//! - `n` is the unit normal from body 2 to body 1, `t = perp(n)`;
//! - the relative velocity of the contact points is `g = v1 - v2 - (R1 w1 + R2 w2) t`, with
//!   `g_n = g . n < 0` while approaching and `g_t = g . t`;
//! - after the collision `g_n' = -e g_n` and `g_t' = -beta g_t`: `beta = -1` is smooth (no
//!   tangential impulse), `beta = +1` perfectly rough (the slip reverses);
//! - with the inertia factor `q = I / (m R^2)` (2/5 spheres, 1/2 disks) and the reduced mass
//!   `m12`, the impulse on body 1 is `J = -(1 + e) m12 g_n n - (1 + beta) m12 q / (1 + q) g_t t`;
//!   it conserves momentum and the angular momentum about the contact point, and dissipates
//!   `1/2 m12 [(1 - e^2) g_n^2 + q / (1 + q) (1 - beta^2) g_t^2]`.
//!
//! Walton's rule takes `beta = min(beta0, -1 + mu (1 + e) (1 + q) / q |g_n| / |g_t|)`: sticking
//! with the tangential restitution `beta0` unless Coulomb's law `|J_t| <= mu |J_n|` caps it
//! (sliding). A wall is a body of infinite mass that does not turn.

use crate::Vec2;

/// Normal restitution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Restitution {
    /// A constant `e` in [0, 1].
    Constant(f64),
    /// The mixture paper's `e(g_n) = 1 - (1 - e0) (|g_n| / v0)^(3/4)` below `v0`, `e0` above:
    /// slow collisions are nearly elastic, which keeps a gas from collapsing.
    VelocityDependent { e0: f64, v0: f64 },
}

impl Restitution {
    /// `e` at the normal approach speed `|g_n|` (m/s).
    pub fn at(&self, gn: f64) -> f64 {
        match *self {
            Restitution::Constant(e) => e,
            Restitution::VelocityDependent { e0, v0 } => {
                let s = gn.abs();
                if s < v0 {
                    1.0 - (1.0 - e0) * (s / v0).powf(0.75)
                } else {
                    e0
                }
            }
        }
    }
}

/// A table of `(eps_n, beta)` against the impact speed `g_n` and the ratio `g_t / g_n`, as
/// the DEM's collision lab measures it; read bilinearly, clamped to its range.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Increasing normal speeds (m/s).
    pub g_n: Vec<f64>,
    /// Increasing ratios `|g_t| / |g_n|` (>= 0).
    pub ratio: Vec<f64>,
    /// `eps_n[i][j]` at `g_n[i]`, `ratio[j]`.
    pub eps_n: Vec<Vec<f64>>,
    /// `beta[i][j]`, the same grid.
    pub beta: Vec<Vec<f64>>,
}

/// What is wrong with a restitution table.
#[derive(Clone, Debug, PartialEq)]
pub enum TableError {
    /// An axis is empty, not finite or not increasing.
    Axes,
    /// A column does not hold one row per `g_n` and one value per ratio.
    Shape { column: &'static str },
    /// A column's values leave `[lo, 1]`.
    Range { column: &'static str, lo: f64 },
}

impl std::fmt::Display for TableError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TableError::Axes => write!(f, "the g_n and g_t/g_n axes must be finite and increasing"),
            TableError::Shape { column } => write!(f, "{column} must hold one row per g_n and one value per ratio"),
            TableError::Range { column, lo } => write!(f, "{column} values must lie in [{lo}, 1]"),
        }
    }
}

impl std::error::Error for TableError {}

impl Table {
    /// Checks the grid: increasing axes of at least one point, rows of the right length,
    /// `eps_n` in [0, 1] and `beta` in [-1, 1].
    pub fn validate(&self) -> Result<(), TableError> {
        let increasing = |a: &[f64]| !a.is_empty() && a.iter().all(|x| x.is_finite()) && a.windows(2).all(|w| w[1] > w[0]);
        if !increasing(&self.g_n) || !increasing(&self.ratio) {
            return Err(TableError::Axes);
        }
        for (name, grid, lo) in [("eps_n", &self.eps_n, 0.0), ("beta", &self.beta, -1.0)] {
            if grid.len() != self.g_n.len() || grid.iter().any(|r| r.len() != self.ratio.len()) {
                return Err(TableError::Shape { column: name });
            }
            if grid.iter().flatten().any(|&x| !(lo..=1.0).contains(&x)) {
                return Err(TableError::Range { column: name, lo });
            }
        }
        Ok(())
    }

    /// `(eps_n, beta)` at `|g_n|`, `|g_t| / |g_n|`.
    pub fn at(&self, gn: f64, ratio: f64) -> (f64, f64) {
        let locate = |axis: &[f64], x: f64| -> (usize, usize, f64) {
            if axis.len() == 1 || x <= axis[0] {
                return (0, 0, 0.0);
            }
            let k = axis.partition_point(|&a| a <= x);
            if k >= axis.len() {
                let last = axis.len() - 1;
                return (last, last, 0.0);
            }
            let (a, b) = (axis[k - 1], axis[k]);
            (k - 1, k, (x - a) / (b - a))
        };
        let (i0, i1, fi) = locate(&self.g_n, gn.abs());
        let (j0, j1, fj) = locate(&self.ratio, ratio.abs());
        let read = |g: &Vec<Vec<f64>>| {
            let lo = g[i0][j0] * (1.0 - fj) + g[i0][j1] * fj;
            let hi = g[i1][j0] * (1.0 - fj) + g[i1][j1] * fj;
            lo * (1.0 - fi) + hi * fi
        };
        (read(&self.eps_n), read(&self.beta))
    }
}

/// The rule of one contact class.
#[derive(Clone, Debug, PartialEq)]
pub enum Rule {
    /// Walton's rule: normal restitution, Coulomb friction `mu` (>= 0) and the tangential
    /// restitution of sticking contacts `beta0` in [-1, 1].
    Walton { e: Restitution, mu: f64, beta0: f64 },
    /// Coefficients read from a table measured with the DEM's contact laws.
    Table(std::sync::Arc<Table>),
}

impl Rule {
    /// A smooth rule of constant restitution `e` (no friction).
    pub fn smooth(e: f64) -> Self {
        Rule::Walton {
            e: Restitution::Constant(e),
            mu: 0.0,
            beta0: -1.0,
        }
    }

    /// Checks the parameters; `field` names the rule in errors.
    pub fn validate(&self, field: &str) -> Result<(), crate::EventsError> {
        use crate::error::invalid;
        match self {
            Rule::Walton { e, mu, beta0 } => {
                match *e {
                    Restitution::Constant(e) if !(0.0..=1.0).contains(&e) => {
                        return Err(invalid(&format!("{field}.e"), format!("must lie in [0, 1], got {e}")))
                    }
                    Restitution::VelocityDependent { e0, v0 } => {
                        if !(0.0..=1.0).contains(&e0) {
                            return Err(invalid(&format!("{field}.e"), format!("must lie in [0, 1], got {e0}")));
                        }
                        if !(v0.is_finite() && v0 > 0.0) {
                            return Err(invalid(&format!("{field}.v0"), format!("must be a positive speed, got {v0}")));
                        }
                    }
                    _ => {}
                }
                if mu.is_nan() || *mu < 0.0 {
                    return Err(invalid(&format!("{field}.mu"), format!("must be >= 0, got {mu}")));
                }
                if !(-1.0..=1.0).contains(beta0) {
                    return Err(invalid(&format!("{field}.beta0"), format!("must lie in [-1, 1], got {beta0}")));
                }
                Ok(())
            }
            Rule::Table(t) => t.validate().map_err(|e| invalid(field, e.to_string())),
        }
    }

    /// `(e, beta)` for an impact with `g_n < 0` and tangential slip `g_t`, inertia factor `q`.
    pub fn coefficients(&self, gn: f64, gt: f64, q: f64) -> (f64, f64) {
        match self {
            Rule::Walton { e, mu, beta0 } => {
                let e = e.at(gn);
                if gt == 0.0 {
                    return (e, *beta0);
                }
                let coulomb = -1.0 + mu * (1.0 + e) * (1.0 + q) / q * gn.abs() / gt.abs();
                (e, beta0.min(coulomb))
            }
            Rule::Table(t) => t.at(gn, if gn == 0.0 { 0.0 } else { gt / gn }),
        }
    }
}

/// One body at a contact: velocity, spin, radius, mass (`f64::INFINITY` for a wall, which
/// neither turns nor recoils) and inertia factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    pub v: Vec2,
    pub w: f64,
    pub r: f64,
    pub m: f64,
    pub q: f64,
}

/// What a collision did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    pub v1: Vec2,
    pub w1: f64,
    pub v2: Vec2,
    pub w2: f64,
    /// Normal and tangential relative speeds before (`g_n < 0`).
    pub gn: f64,
    pub gt: f64,
    /// The coefficients used.
    pub e: f64,
    pub beta: f64,
    /// Kinetic energy lost, in the frame of body 2 for a wall (J, >= 0).
    pub dissipated: f64,
}

/// The inertia factor of a contact: both bodies must share it (one `q` per run); a wall takes
/// the particle's.
fn tangential_factor(q: f64) -> f64 {
    q / (1.0 + q)
}

/// Collides body 1 with body 2 at the unit normal `n` (from 2 to 1) with coefficients from
/// `rule`; `override_coefficients` replaces them (the collapse guards).
pub fn collide(b1: Body, b2: Body, n: Vec2, rule: &Rule, override_coefficients: Option<(f64, f64)>) -> Outcome {
    let t = Vec2::new(-n.y, n.x);
    let wall = b2.m.is_infinite();
    let spin2 = if wall { 0.0 } else { b2.r * b2.w };
    let g = b1.v - b2.v - (b1.r * b1.w + spin2) * t;
    let (gn, gt) = (g.dot(&n), g.dot(&t));
    let q = b1.q;
    let (e, beta) = override_coefficients.unwrap_or_else(|| rule.coefficients(gn, gt, q));
    let m12 = if wall { b1.m } else { b1.m * b2.m / (b1.m + b2.m) };
    let k = tangential_factor(q);
    let jn = -(1.0 + e) * m12 * gn;
    let jt = -(1.0 + beta) * m12 * k * gt;
    let j = jn * n + jt * t;
    let v1 = b1.v + j / b1.m;
    let w1 = b1.w - b1.r * jt / (b1.q * b1.m * b1.r * b1.r);
    let (v2, w2) = if wall {
        (b2.v, b2.w)
    } else {
        (b2.v - j / b2.m, b2.w - b2.r * jt / (b2.q * b2.m * b2.r * b2.r))
    };
    let dissipated = 0.5 * m12 * ((1.0 - e * e) * gn * gn + k * (1.0 - beta * beta) * gt * gt);
    Outcome {
        v1,
        w1,
        v2,
        w2,
        gn,
        gt,
        e,
        beta,
        dissipated,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn energy(b: &Body, v: Vec2, w: f64) -> f64 {
        if b.m.is_infinite() {
            return 0.0;
        }
        0.5 * b.m * v.norm_squared() + 0.5 * b.q * b.m * b.r * b.r * w * w
    }

    fn check(b1: Body, b2: Body, n: Vec2, rule: &Rule) -> Result<(), TestCaseError> {
        let o = collide(b1, b2, n, rule, None);
        let t = Vec2::new(-n.y, n.x);
        // Momentum, and the angular momentum about the contact point (the spins change by
        // the torque of the tangential impulse, which is zero about the contact point).
        let p0 = b1.m * b1.v + b2.m * b2.v;
        let p1 = b1.m * o.v1 + b2.m * o.v2;
        prop_assert!((p1 - p0).norm() <= 1e-12 * (b1.m * b1.v.norm() + b2.m * b2.v.norm() + 1e-30));
        let cross = |a: Vec2, b: Vec2| a.x * b.y - a.y * b.x;
        // About the contact point c: body 1's centre at c + R1 n, body 2's at c - R2 n.
        let l = |v1: Vec2, w1: f64, v2: Vec2, w2: f64| {
            b1.q * b1.m * b1.r * b1.r * w1 + b1.m * cross(b1.r * n, v1) + b2.q * b2.m * b2.r * b2.r * w2 + b2.m * cross(-b2.r * n, v2)
        };
        let scale = b1.m * b1.r * (b1.v.norm() + b1.r * b1.w.abs()) + b2.m * b2.r * (b2.v.norm() + b2.r * b2.w.abs()) + 1e-30;
        prop_assert!((l(o.v1, o.w1, o.v2, o.w2) - l(b1.v, b1.w, b2.v, b2.w)).abs() <= 1e-12 * scale);
        // The energy lost is the closed form, and never negative.
        let e0 = energy(&b1, b1.v, b1.w) + energy(&b2, b2.v, b2.w);
        let e1 = energy(&b1, o.v1, o.w1) + energy(&b2, o.v2, o.w2);
        prop_assert!(o.dissipated >= -1e-15 * e0);
        prop_assert!(
            ((e0 - e1) - o.dissipated).abs() <= 1e-10 * e0.max(1e-300),
            "{} vs {}",
            e0 - e1,
            o.dissipated
        );
        // The relative contact velocity after: g_n' = -e g_n, g_t' = -beta g_t.
        let g1 = o.v1 - o.v2 - (b1.r * o.w1 + b2.r * o.w2) * t;
        prop_assert!((g1.dot(&n) + o.e * o.gn).abs() <= 1e-9 * (o.gn.abs() + o.gt.abs()));
        prop_assert!((g1.dot(&t) + o.beta * o.gt).abs() <= 1e-9 * (o.gn.abs() + o.gt.abs()));
        // Coulomb: |J_t| <= mu |J_n| for Walton's rule.
        if let Rule::Walton { mu, .. } = rule {
            let jn = b1.m * (o.v1 - b1.v).dot(&n);
            let jt = b1.m * (o.v1 - b1.v).dot(&t);
            prop_assert!(jt.abs() <= mu * jn.abs() * (1.0 + 1e-9) + 1e-18);
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn walton_conserves_momenta_and_loses_the_closed_form_energy(
            m1 in 0.1f64..10.0, m2 in 0.1f64..10.0, r1 in 0.5f64..2.0, r2 in 0.5f64..2.0,
            vx1 in -3.0f64..3.0, vz1 in -3.0f64..3.0, vx2 in -3.0f64..3.0, vz2 in -3.0f64..3.0,
            w1 in -5.0f64..5.0, w2 in -5.0f64..5.0, angle in 0.0f64..std::f64::consts::TAU,
            e in 0.0f64..=1.0, mu in 0.0f64..2.0, beta0 in -1.0f64..=1.0, disk in any::<bool>(),
        ) {
            let q = if disk { 0.5 } else { 0.4 };
            let n = Vec2::new(angle.cos(), angle.sin());
            let b1 = Body { v: Vec2::new(vx1, vz1), w: w1, r: r1, m: m1, q };
            let b2 = Body { v: Vec2::new(vx2, vz2), w: w2, r: r2, m: m2, q };
            prop_assume!((b1.v - b2.v).dot(&n) < -1e-3);
            check(b1, b2, n, &Rule::Walton { e: Restitution::Constant(e), mu, beta0 })?;
        }
    }

    #[test]
    fn constant_beta_loses_the_closed_form_energy_and_smooth_disks_keep_their_spin() {
        let n = Vec2::new(1.0, 0.0);
        let b1 = Body {
            v: Vec2::new(-1.0, 0.3),
            w: 2.0,
            r: 1e-3,
            m: 2e-3,
            q: 0.4,
        };
        let b2 = Body {
            v: Vec2::new(0.5, -0.2),
            w: -1.0,
            r: 1.5e-3,
            m: 3e-3,
            q: 0.4,
        };
        let rough = Rule::Walton {
            e: Restitution::Constant(0.8),
            mu: f64::INFINITY,
            beta0: 0.35,
        };
        let o = collide(b1, b2, n, &rough, None);
        let m12 = 2e-3 * 3e-3 / 5e-3;
        let closed = 0.5 * m12 * ((1.0 - 0.64) * o.gn * o.gn + 0.4 / 1.4 * (1.0 - 0.35f64.powi(2)) * o.gt * o.gt);
        assert!((o.dissipated - closed).abs() < 1e-15, "{} {}", o.dissipated, closed);
        assert_eq!(o.beta, 0.35, "an infinite mu never slides");
        let smooth = collide(b1, b2, n, &Rule::smooth(1.0), None);
        assert_eq!((smooth.w1, smooth.w2), (b1.w, b2.w));
        assert!(smooth.dissipated.abs() < 1e-18);
        // A wall: the particle's own momentum is not conserved, the wall is unchanged, the
        // normal speed reverses by e.
        let wall = Body {
            v: Vec2::new(0.0, 0.7),
            w: 0.0,
            r: 0.0,
            m: f64::INFINITY,
            q: 0.4,
        };
        let ball = Body {
            v: Vec2::new(0.2, -1.3),
            w: 0.0,
            r: 1e-3,
            m: 1e-3,
            q: 0.4,
        };
        let o = collide(ball, wall, Vec2::new(0.0, 1.0), &Rule::smooth(0.5), None);
        assert!(((o.v1.y - 0.7) - 0.5 * 2.0).abs() < 1e-12, "{}", o.v1.y);
        assert_eq!(o.v2, wall.v);
    }

    #[test]
    fn velocity_dependent_restitution_is_elastic_at_rest_and_e0_above_v0() {
        let r = Restitution::VelocityDependent { e0: 0.7, v0: 0.1 };
        assert_eq!(r.at(0.0), 1.0);
        assert_eq!(r.at(-0.2), 0.7);
        assert!((r.at(0.1 * 0.5f64.powf(4.0 / 3.0)) - (1.0 - 0.3 * 0.5)).abs() < 1e-12);
    }

    #[test]
    fn a_table_is_read_bilinearly_and_clamped() {
        let t = Table {
            g_n: vec![0.1, 1.0],
            ratio: vec![0.0, 2.0],
            eps_n: vec![vec![0.9, 0.8], vec![0.7, 0.6]],
            beta: vec![vec![-0.5, -1.0], vec![0.5, 0.0]],
        };
        t.validate().unwrap();
        assert_eq!(t.at(0.1, 0.0), (0.9, -0.5));
        let (e, b) = t.at(0.55, 1.0);
        assert!((e - 0.75).abs() < 1e-12 && (b - -0.25).abs() < 1e-12);
        assert_eq!(t.at(5.0, 9.0), (0.6, 0.0));
        let bad = Table {
            beta: vec![vec![-2.0, 0.0], vec![0.0, 0.0]],
            ..t
        };
        let err = bad.validate().unwrap_err();
        assert_eq!(err, TableError::Range { column: "beta", lo: -1.0 });
        assert_eq!(err.to_string(), "beta values must lie in [-1, 1]");
        let short = Table {
            eps_n: vec![vec![0.9]],
            ..bad
        };
        assert_eq!(short.validate().unwrap_err(), TableError::Shape { column: "eps_n" });
    }
}
