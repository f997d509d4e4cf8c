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
    /// N s/m, `mu` dimensionless. The viscous branch is capped where it would remove more than
    /// two thirds of a contact's slip in one step ([`implicit_damping`]), so it is stable at
    /// any step. No static friction: `F_t = 0` at `v_t = 0`. `mu = inf`
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

/// The damping coefficient (N s/m) of a viscous force `-gamma_t v` over a step on a contact
/// of tangential mass `m_t`, from `gamma_t` and `ratio = gamma_t dt / m_t`:
/// `gamma_t / max(1, 3 ratio / 2)`.
///
/// With velocity Verlet's force predictor (the force is evaluated on `v + F dt / m_t`, the
/// previous step's force), a contact whose impulse removes a fraction `b` of the slip it sees
/// relaxes with the roots of `x^2 - (1 - 3b/2) x - b/2`, whose larger root is
/// `1 - b + b^2/2 + O(b^3)`.
/// - Up to `ratio = 2/3` the force is the explicit `-gamma_t v` (`b = ratio`): the root is
///   `exp(-ratio)` to second order, so `eps_t` converges as `dt^2`.
/// - Beyond, the impulse removes two thirds of the slip it sees (`b = 2/3`), where the roots
///   decay fastest (by 0.58 per step). The explicit force alone grows without bound from
///   `ratio = 1` on.
///
/// Backward Euler (`gamma_t / (1 + ratio)`, `b = ratio / (1 + ratio)`), used before, is also
/// stable, but its root is `1 - ratio + 3 ratio^2 / 2`: first order. On the experiment's
/// seeds (`eps_t` of a 45-degree impact at 0.63 m/s on the floor) it missed the converged
/// `eps_t` by 0.038 at 15 steps per contact (`ratio = 0.19`) where the explicit force misses
/// by 0.004, so `dt = "auto"` needed 70 steps per contact instead of 15 (issue 39).
#[inline(always)]
pub fn implicit_damping<L: Lane>(gamma_t: L, ratio: L) -> L {
    gamma_t / L::splat(1.0).max(L::splat(1.5) * ratio)
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
                // Viscous branch `-gamma v_t` while `gamma |v_t| <= mu F_n` (compared in
                // squares, no root); Coulomb branch `-mu F_n v_t/|v_t|` beyond. The viscous
                // branch is capped: `gamma` is [`implicit_damping`] of `gamma_t`, the
                // explicit `gamma_t` up to `gamma_t dt / m_t = 2/3`, beyond it the force that
                // removes two thirds of the slip in one step, instead of overshooting zero
                // slip once the ratio nears 1; `gamma_t` itself where the mobility `1 / m_t`
                // is 0. With `mu = inf` the limit `inf * 0` of a contact
                // at zero normal force is NaN, which no comparison passes: the second test
                // keeps the viscous branch.
                let gamma = implicit_damping(L::splat(gamma_t), L::splat(gamma_t * dt) * g.mobility);
                let speed2 = g.v_t.norm_squared();
                let limit = L::splat(mu) * fn_;
                let viscous = L::le(gamma * gamma * speed2, limit * limit) | L::mask(mu == f64::INFINITY);
                let mut force = g.v_t.scale(-gamma);
                let mut dissipation_rate = gamma * speed2;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::geometry::Sphere;

    const GAMMA_T: f64 = 0.007;

    fn haff_werner(mu: f64) -> TangentialLaw {
        TangentialLaw::HaffWerner { gamma_t: GAMMA_T, mu }
    }

    /// Two grains of the thesis' smallest size (R = 0.25 mm, 2500 kg/m^3) sliding past each
    /// other, with the pair's tangential mobility `7 / (2 m_eff)`.
    fn slipping_pair(slip: f64) -> ContactGeometry {
        let r = 0.25e-3;
        let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let a = Sphere {
            x: Vec3::zeros(),
            v: Vec3::new(slip, 0.0, 0.0),
            w: Vec3::zeros(),
            r,
        };
        let b = Sphere {
            x: Vec3::new(0.0, 0.0, -1.99 * r),
            v: Vec3::zeros(),
            w: Vec3::zeros(),
            r,
        };
        let g = ContactGeometry::pair(a, b).unwrap();
        g.with_mobility(1.0 / sphere_tangential_mass(0.5 * m))
    }

    /// `gamma_t dt / m_t` of a geometry at step `dt`.
    fn ratio(g: &ContactGeometry, dt: f64) -> f64 {
        GAMMA_T * dt * g.mobility
    }

    #[test]
    fn the_viscous_branch_is_the_explicit_law_up_to_two_thirds_of_the_slip() {
        // Mobility 0 (infinitely heavy grains), or `gamma_t dt / m_t <= 2/3`: the explicit
        // law, bit for bit (second order under velocity Verlet's predictor).
        let g = slipping_pair(1e-3);
        let mut zeta = Vec3::zeros();
        let explicit = -g.v_t * GAMMA_T;
        let heavy = haff_werner(f64::INFINITY).force(&g.with_mobility(0.0), 1.0, &mut zeta, 6e-6);
        assert_eq!(heavy.force, explicit);
        assert_eq!(heavy.dissipation_rate, GAMMA_T * g.v_t.norm_squared());
        let two_thirds = 2.0 / 3.0 / (GAMMA_T * g.mobility);
        for dt in [1e-10, 1e-8, 1e-6, 0.5 * two_thirds, two_thirds] {
            assert!(ratio(&g, dt) <= 2.0 / 3.0 * (1.0 + 1e-12));
            let t = haff_werner(f64::INFINITY).force(&g, 1.0, &mut zeta, dt);
            assert_eq!(t.force, explicit, "dt {dt:e}, ratio {}", ratio(&g, dt));
        }
    }

    #[test]
    fn the_viscous_branch_never_removes_more_than_two_thirds_of_the_slip() {
        // The impulse over one step takes the slip of the pair from v_t to v_t (1 - ratio)
        // up to a ratio of 2/3, and to a third of it beyond: never past zero, whatever the
        // step.
        for dt in [1e-6, 6e-6, 8e-6, 1e-4] {
            let g = slipping_pair(1e-3);
            let a = ratio(&g, dt);
            let t = haff_werner(f64::INFINITY).force(&g, 1.0, &mut Vec3::zeros(), dt);
            let after = g.v_t + t.force * (dt * g.mobility);
            let expected = if a <= 2.0 / 3.0 { g.v_t * (1.0 - a) } else { g.v_t / 3.0 };
            assert!(
                (after - expected).norm() <= 1e-12 * g.v_t.norm(),
                "ratio {a}: {after} against {expected}"
            );
            assert!(after.dot(&g.v_t) > 0.0, "ratio {a}: the slip reversed");
        }
    }

    #[test]
    fn the_coulomb_limit_holds_for_any_slip_load_and_step() {
        for slip in [1e-6, 1e-4, 1e-2, 1.0] {
            for fn_ in [0.0, 1e-7, 1e-5, 1e-3] {
                for dt in [1e-7, 6e-6, 1e-4] {
                    let g = slipping_pair(slip);
                    let t = haff_werner(0.7).force(&g, fn_, &mut Vec3::zeros(), dt);
                    assert!(t.force.norm() <= 0.7 * fn_ * (1.0 + 1e-12), "slip {slip}, F_n {fn_}, dt {dt}");
                    // Opposed to the slip, and the power it books is the power it takes.
                    assert!(t.force.dot(&g.v_t) <= 0.0);
                    assert!((t.dissipation_rate + t.force.dot(&g.v_t)).abs() <= 1e-12 * t.dissipation_rate.max(1e-300));
                }
            }
        }
    }

    /// The slip of one contact under its own friction alone, integrated as the simulation
    /// does (velocity Verlet with the force evaluated on the predicted velocity
    /// `v(t) + F(t) dt / m_t`), from the force `f0` on it: the slips the force sees, step by
    /// step, the slip after the last step, and the dissipation booked as the simulation
    /// books it: the power at the predicted slip times `dt`, less the kick's excess
    /// ([`crate::integrate::verlet_excess`], the second number alone).
    fn relaxation(g: ContactGeometry, dt: f64, steps: usize, f0: f64) -> (Vec<f64>, f64, (f64, f64)) {
        let law = haff_werner(f64::INFINITY);
        let (mut v, mut f, mut seen) = (g.v_t.x, f0, Vec::new());
        let (mut booked, mut excess) = (0.0, 0.0);
        for _ in 0..steps {
            let predicted = v + f * dt * g.mobility;
            let geometry = ContactGeometry {
                v_t: Vec3::new(predicted, 0.0, 0.0),
                ..g
            };
            let t = law.force(&geometry, 1.0, &mut Vec3::zeros(), dt);
            let f_new = t.force.x;
            v += 0.5 * (f + f_new) * dt * g.mobility;
            f = f_new;
            seen.push(predicted);
            booked += t.dissipation_rate * dt;
            excess += crate::integrate::verlet_excess(&[t.force], &[geometry.v_t], &[Vec3::new(v, 0.0, 0.0)], dt);
        }
        (seen, v, (booked, excess))
    }

    #[test]
    fn the_ledger_books_the_energy_a_relaxing_slip_loses() {
        // A contact starts with a slip and no force, and the viscous branch alone relaxes it
        // (Verlet with the force predictor, as the simulation). Booked at the predicted slip,
        // the dissipation exceeds the kinetic energy `m_t v^2 / 2` lost by 0.13 % at
        // `gamma_t dt / m_t = 0.05`, 2.3 % at 0.2, 11 % at 0.4, half at the cap (2/3 and
        // beyond); less the kick's excess it is the energy lost, to rounding.
        let g = slipping_pair(1e-3);
        let m_t = 1.0 / g.mobility;
        for (b, old_miss) in [(0.05, 1.2e-3), (0.2, 2.2e-2), (0.4, 0.11), (2.0 / 3.0, 0.49), (1.9, 0.49)] {
            let dt = b / (GAMMA_T * g.mobility);
            let (_, v, (booked, excess)) = relaxation(g, dt, 4000, 0.0);
            let lost = 0.5 * m_t * (g.v_t.x * g.v_t.x - v * v);
            let (old, new) = ((booked - lost) / lost, (booked - excess - lost) / lost);
            println!("ratio {b}: booked {booked:e} J, lost {lost:e} J, excess {excess:e} J, miss {old:.2e} -> {new:.2e}");
            assert!(
                old > old_miss,
                "ratio {b}: the booking at the predicted slip missed by {old:e} only"
            );
            assert!(new.abs() < 1e-12, "ratio {b}: the ledger misses {new:e} of the energy lost");
        }
    }

    #[test]
    fn the_slip_decays_at_steps_where_the_explicit_law_blows_up() {
        // gamma_t dt / m_t from 0.5 to 50 for the smallest pair (1.8 at the stripe scene's
        // automatic step, 2.4 at the thesis' 8e-6 s): the slip dies away. The explicit force
        // (mobility 0 in the law, the true mobility in the motion) grows without bound from
        // a ratio of 1 on under the force predictor.
        for dt in [1.7e-6, 6e-6, 8e-6, 2e-5, 1.7e-4] {
            let g = slipping_pair(1e-3);
            let a = ratio(&g, dt);
            let (slips, _, _) = relaxation(g, dt, 200, 0.0);
            assert!(slips.iter().all(|s| s.abs() <= 1e-3 * (1.0 + 1e-12)), "ratio {a}: the slip grew");
            assert!(slips[199].abs() < 1e-9, "ratio {a}: slip {:e} after 200 steps", slips[199]);
            if a > 1.2 {
                let explicit = relaxation_explicit(g, dt, 200);
                let blown = explicit.iter().any(|s| !s.is_finite() || s.abs() > 1.0);
                assert!(blown, "ratio {a}: the explicit law did not blow up");
            }
        }
    }

    #[test]
    fn the_slip_relaxes_as_the_exponential_to_second_order() {
        // Over one relaxation time `m_t / gamma_t` in n steps (ratio 1/n), the slip the
        // simulation carries (velocity Verlet, force on the predicted velocity) approaches
        // exp(-1) of its start with an error falling as 1/n^2: halving the step quarters it
        // (backward Euler, the law of issue 41, halved it).
        let g = slipping_pair(1e-3);
        let tau = 1.0 / (GAMMA_T * g.mobility);
        let error = |n: usize| {
            // The friction acts from the start (a contact slipping at v_t already).
            let (_, v, _) = relaxation(g, tau / n as f64, n, -GAMMA_T * g.v_t.x);
            (v / g.v_t.x - (-1.0f64).exp()).abs()
        };
        let (e4, e8, e16) = (error(4), error(8), error(16));
        assert!(e4 < 0.05, "{e4}");
        for (coarse, fine) in [(e4, e8), (e8, e16)] {
            let order = (coarse / fine).log2();
            assert!((1.8..2.3).contains(&order), "order {order} ({coarse:e} -> {fine:e})");
        }
    }

    /// [`relaxation`] with the explicit force `-gamma_t v_t` (the law before issue 41).
    fn relaxation_explicit(g: ContactGeometry, dt: f64, steps: usize) -> Vec<f64> {
        let (mut v, mut f, mut seen) = (g.v_t.x, 0.0, Vec::new());
        for _ in 0..steps {
            let predicted = v + f * dt * g.mobility;
            let f_new = -GAMMA_T * predicted;
            v += 0.5 * (f + f_new) * dt * g.mobility;
            f = f_new;
            seen.push(predicted);
        }
        seen
    }
}
