//! Tangential (friction) force laws.

use super::geometry::{LaneGeometry, Normal};
use super::lane::{Lane, V3};
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
    /// by the integrated tangential contact-point velocity `zeta`,
    /// `F_t = -min(k_t |zeta|, mu |F_n|) zeta/|zeta|`, truncated to the Coulomb limit
    /// `|zeta| <= mu F_n / k_t` while sliding. `mu = inf`: the spring is never truncated.
    ///
    /// Integration (see [`TangentialLaw::force`]): the history holds the spring half a step
    /// past the previous evaluation, `s = zeta(t - dt) + v_t(t - dt) dt/2`. Each evaluation
    /// rotates `s` into the current tangent plane (keeping its length), takes the spring
    /// `zeta(t) = s + v_t(t) dt/2` (the trapezoid rule over the step, second order),
    /// truncates it, and stores `zeta(t) + v_t(t) dt/2`. Advancing the spring by `v_t(t) dt`
    /// instead, with the predicted end-of-step velocity, puts it `v_t dt/2` ahead of the
    /// motion: a numerical dashpot `k_t dt/2` that made `eps_t` first order in dt (0.11 off
    /// at 25 steps per contact for `k_t = 50 N/m`, so `dt = "auto"` needed 500).
    CundallStrack { kt: f64, mu: f64 },
}

/// A spring vector `s` stored at the last evaluation, rotated into the tangent plane of the
/// normal `n` now, keeping its length (Cundall-Strack's tangential spring, the
/// spring-dashpot-slider's rolling spring). A wall's normal never turns: its springs have no
/// normal part, and the rescaling (a square root and a division) is skipped; at an axis wall
/// the normal component is set to zero, so the compiler drops it from what follows.
#[inline(always)]
pub(crate) fn turn_into_plane<L: Lane, N: Normal<L>>(n: &N, s: V3<L>) -> V3<L> {
    let zero = L::splat(0.0);
    let along = n.dot(s);
    let mut t = n.in_plane(s);
    let flat = L::equal(along, zero);
    if !L::all(flat) {
        let in_plane2 = t.norm_squared();
        let keep = flat | L::le(in_plane2, zero);
        let turned = t.scale(((in_plane2 + along * along) / in_plane2).sqrt());
        t = V3::select(keep, t, turned);
    }
    t
}

/// Effective mass (kg) of the tangential contact-point motion of two solid spheres whose
/// normal effective mass is `m_eff` (kg): `1/m_t = sum_k (1/m_k + R_k^2/I_k)` with
/// `I = (2/5) m R^2` gives `m_t = (2/7) m_eff` (a wall is the limit of infinite mass).
pub fn sphere_tangential_mass(m_eff: f64) -> f64 {
    2.0 / 7.0 * m_eff
}

/// Result of a tangential kernel (per lane: `TangentialForce<V3<L>, L>`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentialForce<F = Vec3, L = f64> {
    /// Force on particle i (N).
    pub force: F,
    /// Elastic energy held in the tangential spring (J).
    pub stored_energy: L,
    /// Dissipated power (W): `-F_t . v_t` (Haff-Werner); for Cundall-Strack the spring's
    /// elastic energy lost to its Coulomb truncation, per time step.
    pub dissipation_rate: L,
}

impl TangentialLaw {
    /// True if the law keeps a per-contact spring (Cundall-Strack).
    pub fn has_history(&self) -> bool {
        matches!(self, TangentialLaw::CundallStrack { .. })
    }

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

    /// Tangential force for the normal force magnitude `fn_` (already clamped, N): one
    /// contact, [`Self::force_lanes`] with one lane.
    #[inline(always)]
    pub fn force<N: Normal>(&self, g: &ContactGeometry<N>, fn_: f64, zeta: &mut Vec3, dt: f64) -> TangentialForce {
        let mut z = V3::from(*zeta);
        let t = self.force_lanes(&g.lanes(), fn_, &mut z, dt);
        *zeta = z.into();
        TangentialForce {
            force: t.force.into(),
            stored_energy: t.stored_energy,
            dissipation_rate: t.dissipation_rate,
        }
    }

    /// The law itself, over lanes: one contact, or the contacts of several grains with a wall
    /// side by side. Branches are selects; the work of a branch no lane takes is skipped.
    #[inline(always)]
    pub fn force_lanes<L: Lane, N: Normal<L>>(
        &self,
        g: &LaneGeometry<N, L>,
        fn_: L,
        zeta: &mut V3<L>,
        dt: f64,
    ) -> TangentialForce<V3<L>, L> {
        let zero = L::splat(0.0);
        match *self {
            TangentialLaw::None => TangentialForce {
                force: V3::zeros(),
                stored_energy: zero,
                dissipation_rate: zero,
            },
            TangentialLaw::HaffWerner { gamma_t, mu } => {
                // Viscous branch `-gamma_t v_t` while `gamma_t |v_t| <= mu F_n` (compared in
                // squares, no root); Coulomb branch `-mu F_n v_t/|v_t|` beyond. With
                // `mu = inf` the limit `inf * 0` of a contact at zero normal force is NaN,
                // which no comparison passes: the second test keeps the viscous branch.
                let speed2 = g.v_t.norm_squared();
                let limit = L::splat(mu) * fn_;
                let viscous = L::le(L::splat(gamma_t * gamma_t) * speed2, limit * limit) | L::mask(mu == f64::INFINITY);
                let mut force = g.v_t.scale(L::splat(-gamma_t));
                let mut dissipation_rate = L::splat(gamma_t) * speed2;
                if !L::all(viscous) {
                    let speed = speed2.sqrt();
                    force = V3::select(viscous, force, g.v_t.scale(-limit / speed));
                    dissipation_rate = L::select(viscous, dissipation_rate, limit * speed);
                }
                TangentialForce {
                    force,
                    stored_energy: zero,
                    dissipation_rate,
                }
            }
            TangentialLaw::CundallStrack { kt, mu } => {
                // Rotate the stored spring into the current tangent plane, keeping its
                // length.
                let s = turn_into_plane(&g.n, *zeta);
                // The spring now: the second half of the trapezoid over the last step.
                let half = g.v_t.scale(L::splat(0.5 * dt));
                let mut z = s + half;
                let limit = L::splat(mu) * fn_;
                let len2 = z.norm_squared();
                let mut stored = L::splat(0.5 * kt) * len2;
                let mut lost = zero;
                // Compared in squares: no root unless sliding. With `mu = inf` the limit is
                // infinite (never truncated), or NaN at zero normal force, which no
                // comparison passes (never truncated either).
                let sliding = L::lt(limit * limit, L::splat(kt * kt) * len2);
                if L::any(sliding) {
                    // Sliding: truncate the spring to the Coulomb limit; the elastic energy
                    // it loses is the energy friction dissipates. `1 / k_t` is computed once
                    // per loop: the root and the division are the only steps in line.
                    let scale = limit * L::splat(1.0 / kt) / len2.sqrt();
                    z = V3::select(sliding, z.scale(scale), z);
                    lost = L::select(sliding, stored * (L::splat(1.0) - scale * scale), zero);
                    stored = L::select(sliding, stored * (scale * scale), stored);
                }
                // The first half of the trapezoid over the next step.
                *zeta = z + half;
                TangentialForce {
                    force: z.scale(L::splat(-kt)),
                    stored_energy: stored,
                    // `1 / dt` is the same for every contact of a loop: computed once.
                    dissipation_rate: lost * L::splat(1.0 / dt),
                }
            }
        }
    }
}
