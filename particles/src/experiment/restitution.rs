//! The restitution table: the collision laboratory ([`super::collide`]) swept over the
//! normal impact speed `g_n` and the ratio `g_t / g_n` of tangential to normal contact-point
//! speed, giving the normal restitution `eps_n` (eq 4.2) and the tangential restitution
//! `beta` (`eps_t` of the lab: -1 smooth, +1 perfectly rough reversal) of every impact.
//! The event-driven model reads such a table as its collision rule, so that hard collisions
//! carry the DEM's contact laws.
//!
//! Closed forms the table meets (tested in `particles/tests/restitution.rs`), for equal
//! spheres, `alpha = (2/7) m_eff` and `omega_n = sqrt(k_n / m_eff)` of a linear spring:
//! - sliding throughout (large `g_t / g_n`), any law: `beta = -1 + mu (1 + eps_n) (7/2) g_n / g_t`
//!   (Walton's Coulomb branch);
//! - Haff-Werner as `g_t -> 0`: `beta = -exp(-pi gamma_t / (alpha omega_n))`;
//! - Cundall-Strack as `g_t -> 0`: `beta = -cos(pi sqrt((k_t / k_n) (7/2)))`.

use super::collide::{Collision, Impact};
use crate::SimError;

/// One impact of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// Normal approach speed (m/s).
    pub g_n: f64,
    /// Tangential over normal contact-point speed at impact.
    pub g_t_over_g_n: f64,
    /// Normal restitution (eq 4.2).
    pub eps_n: f64,
    /// Tangential restitution (-1 smooth, +1 perfectly rough).
    pub beta: f64,
}

/// The impacts of `base` (its law, bodies, step and integrator; its impact is replaced) at
/// every `g_n` and every ratio, `g_n` varying slowest. Ratios must be positive: at zero the
/// tangential restitution is undefined. An impact the lab cannot resolve is an error naming
/// its speeds.
pub fn table(base: &Collision, g_n: &[f64], ratios: &[f64]) -> Result<Vec<Row>, SimError> {
    let mut rows = Vec::with_capacity(g_n.len() * ratios.len());
    for &vn in g_n {
        for &ratio in ratios {
            if !(ratio > 0.0 && ratio.is_finite()) {
                return Err(SimError::CollisionUnresolved {
                    reason: format!("g_t / g_n = {ratio}: the ratios must be positive (beta is undefined without a tangential speed)"),
                });
            }
            let c = Collision {
                impact: Impact::Components { vn, vt: ratio * vn },
                ..*base
            };
            let r = c.run().map_err(|e| match e {
                SimError::CollisionUnresolved { reason } => SimError::CollisionUnresolved {
                    reason: format!("at g_n = {vn} m/s, g_t / g_n = {ratio}: {reason}"),
                },
                other => other,
            })?;
            let beta = r.eps_t.ok_or_else(|| SimError::CollisionUnresolved {
                reason: format!("at g_n = {vn} m/s, g_t / g_n = {ratio}: no tangential contact speed to restitute"),
            })?;
            rows.push(Row {
                g_n: vn,
                g_t_over_g_n: ratio,
                eps_n: r.eps_n,
                beta,
            });
        }
    }
    Ok(rows)
}

/// Walton's Coulomb branch for equal spheres (q = 2/5): the `beta` of an impact that slides
/// throughout, `-1 + mu (1 + eps_n) (7/2) / (g_t / g_n)`.
pub fn coulomb_branch(mu: f64, eps_n: f64, g_t_over_g_n: f64) -> f64 {
    -1.0 + mu * (1.0 + eps_n) * 3.5 / g_t_over_g_n
}
