//! Tangential (friction) force laws.

use super::geometry::Normal;
use super::ContactGeometry;
use crate::Vec3;

/// Tangential law of one kind of contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TangentialLaw {
    /// Frictionless (smooth) contact.
    None,
    /// Haff-Werner (eq 3.12): `F_t = -min(gamma_t |v_t|, mu |F_n|) v_t/|v_t|`; `gamma_t` in
    /// N s/m, `mu` dimensionless. No static friction: `F_t = 0` at `v_t = 0`. `mu = inf`
    /// (scene `friction = inf`) is the viscous branch alone, `F_t = -gamma_t v_t`, also at
    /// zero normal force: the uncapped floor the thesis' single-sphere runs imply (its
    /// Figs 3.7-3.12 roll without slip far beyond `Gamma = 7 mu / 2`).
    HaffWerner { gamma_t: f64, mu: f64 },
    /// Cundall-Strack (eq 4.32-4.34): a tangential spring of stiffness `k_t` (N/m) stretched
    /// by the integrated tangential contact-point velocity `zeta` (history),
    /// `F_t = -min(k_t |zeta|, mu |F_n|) zeta/|zeta|`. Each step `zeta` is first rotated into
    /// the current tangent plane (keeping its length), then advanced by `v_t dt`, then
    /// truncated to the Coulomb limit `|zeta| <= mu F_n / k_t` while sliding. `mu = inf`: the
    /// spring is never truncated.
    CundallStrack { kt: f64, mu: f64 },
}

/// Effective mass (kg) of the tangential contact-point motion of two solid spheres whose
/// normal effective mass is `m_eff` (kg): `1/m_t = sum_k (1/m_k + R_k^2/I_k)` with
/// `I = (2/5) m R^2` gives `m_t = (2/7) m_eff` (a wall is the limit of infinite mass).
pub fn sphere_tangential_mass(m_eff: f64) -> f64 {
    2.0 / 7.0 * m_eff
}

/// Result of a tangential kernel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentialForce {
    /// Force on particle i (N).
    pub force: Vec3,
    /// Elastic energy held in the tangential spring (J).
    pub stored_energy: f64,
    /// Dissipated power (W): `-F_t . v_t` minus the spring's storage rate.
    pub dissipation_rate: f64,
}

impl TangentialLaw {
    /// Friction coefficient of the Coulomb limit (0 for smooth contacts).
    pub fn mu(&self) -> f64 {
        match *self {
            TangentialLaw::None => 0.0,
            TangentialLaw::HaffWerner { mu, .. } | TangentialLaw::CundallStrack { mu, .. } => mu,
        }
    }

    /// Half period `pi sqrt(m_t / k_t)` (s) of a stuck Cundall-Strack spring on the
    /// tangential effective mass `m_t` (kg, see [`sphere_tangential_mass`]): the time the
    /// step must resolve during stick phases. `None` for laws without a spring.
    pub fn spring_half_period(&self, m_t: f64) -> Option<f64> {
        match *self {
            TangentialLaw::None | TangentialLaw::HaffWerner { .. } => None,
            TangentialLaw::CundallStrack { kt, .. } => Some(std::f64::consts::PI * (m_t / kt).sqrt()),
        }
    }

    /// Tangential force for the normal force magnitude `fn_` (already clamped, N).
    #[inline(always)]
    pub fn force<N: Normal>(&self, g: &ContactGeometry<N>, fn_: f64, zeta: &mut Vec3, dt: f64) -> TangentialForce {
        match *self {
            TangentialLaw::None => TangentialForce {
                force: Vec3::zeros(),
                stored_energy: 0.0,
                dissipation_rate: 0.0,
            },
            TangentialLaw::HaffWerner { gamma_t, mu } => {
                // Viscous branch `-gamma_t v_t` while `gamma_t |v_t| <= mu F_n` (compared in
                // squares, no root); Coulomb branch `-mu F_n v_t/|v_t|` beyond. With
                // `mu = inf` the limit `inf * 0` of a contact at zero normal force is NaN,
                // which no comparison passes: the second test keeps the viscous branch.
                let speed2 = g.v_t.norm_squared();
                let limit = mu * fn_;
                if gamma_t * gamma_t * speed2 <= limit * limit || mu == f64::INFINITY {
                    TangentialForce {
                        force: g.v_t * -gamma_t,
                        stored_energy: 0.0,
                        dissipation_rate: gamma_t * speed2,
                    }
                } else {
                    let speed = speed2.sqrt();
                    TangentialForce {
                        force: g.v_t * (-limit / speed),
                        stored_energy: 0.0,
                        dissipation_rate: limit * speed,
                    }
                }
            }
            TangentialLaw::CundallStrack { kt, mu } => {
                // Rotate the old spring into the current tangent plane, keeping its length.
                let old_len = zeta.norm();
                let mut z = *zeta - g.n.scaled(g.n.dot(zeta));
                let proj_len = z.norm();
                if proj_len > 0.0 {
                    z *= old_len / proj_len;
                }
                let before = 0.5 * kt * z.norm_squared();
                z += g.v_t * dt;
                let limit = mu * fn_;
                let len = z.norm();
                let mut force = z * -kt;
                if kt * len > limit {
                    // Sliding: truncate the spring to the Coulomb limit.
                    z *= limit / (kt * len);
                    force = z * -kt;
                }
                *zeta = z;
                let stored = 0.5 * kt * z.norm_squared();
                TangentialForce {
                    force,
                    stored_energy: stored,
                    dissipation_rate: -force.dot(&g.v_t) - (stored - before) / dt,
                }
            }
        }
    }
}
