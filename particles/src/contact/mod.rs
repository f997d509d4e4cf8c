//! Contact law: one slot per sub-model (normal, tangential, rolling), each an enum with an
//! explicit variant for "off" where off makes sense, matched exhaustively.
//!
//! Every kernel is a pure function of a precomputed [`ContactGeometry`]; the same code serves
//! particle pairs and particle-wall contacts (a wall is an infinite-mass, infinite-radius
//! partner, eq 3.17-3.18). Per-contact history (the Cundall-Strack spring) is passed in
//! separately from the parameters.

pub mod choice;
pub mod geometry;
pub mod lane;
pub mod normal;
pub mod rolling;
pub mod tangential;

pub use geometry::{AxisNormal, ContactGeometry, LaneGeometry, Normal};
pub use lane::{Lane, V3};
pub use normal::NormalLaw;
pub use rolling::RollingLaw;
pub use tangential::TangentialLaw;

use crate::Vec3;

/// The complete law of one kind of contact (particle-particle, or particle-wall).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    pub normal: NormalLaw,
    pub tangential: TangentialLaw,
    pub rolling: RollingLaw,
}

impl ContactLaw {
    /// True if the law can produce a torque, so rotation must be integrated.
    pub fn produces_torque(&self) -> bool {
        !matches!(self.tangential, TangentialLaw::None) || !matches!(self.rolling, RollingLaw::None)
    }

    /// True if the law is history dependent (needs per-contact storage).
    pub fn has_history(&self) -> bool {
        matches!(self.tangential, TangentialLaw::CundallStrack { .. })
    }

    /// `f(law)` compiled once per combination of tangential and rolling variants (loop
    /// unswitching by hand): a loop over many contacts in `f` then tests the variants once,
    /// not once per contact, and each copy can be optimised for its laws. The arithmetic is
    /// the same in every copy.
    #[inline(always)]
    pub fn unswitched<R>(&self, f: impl FnOnce(&ContactLaw) -> R) -> R {
        let law = *self;
        match (law.tangential, law.rolling) {
            (TangentialLaw::None, RollingLaw::None) => f(&law),
            (TangentialLaw::None, RollingLaw::BrilliantovPoschel { .. }) => f(&law),
            (TangentialLaw::HaffWerner { .. }, RollingLaw::None) => f(&law),
            (TangentialLaw::HaffWerner { .. }, RollingLaw::BrilliantovPoschel { .. }) => f(&law),
            (TangentialLaw::CundallStrack { .. }, RollingLaw::None) => f(&law),
            (TangentialLaw::CundallStrack { .. }, RollingLaw::BrilliantovPoschel { .. }) => f(&law),
        }
    }
}

/// Forces and torques of one contact, plus diagnostics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// Total force on particle i (N); particle j receives the opposite.
    pub force: Vec3,
    /// Torque on particle i (N m).
    pub torque_i: Vec3,
    /// Torque on particle j (N m); ignored for walls.
    pub torque_j: Vec3,
    /// Normal force before the no-attraction clamp (N); the contact ends when it vanishes.
    pub normal_raw: f64,
    /// Normal force magnitude after the clamp, `>= 0` (N).
    pub normal: f64,
    /// Tangential force on i (N).
    pub tangential: Vec3,
    /// Energy stored in the contact (elastic normal + tangential spring), J.
    pub stored_energy: f64,
    /// Rate at which the contact dissipates mechanical energy (W), `>= 0` up to the
    /// elastic spring's exchange term (see [`evaluate`]).
    pub dissipation_rate: f64,
}

/// Evaluates the full contact law on a geometry.
///
/// `history` is the Cundall-Strack tangential spring of this contact (unused by the other
/// tangential laws) and is advanced by `dt`.
///
/// Torques act at the contact point, taken at the middle of the overlap: the lever arms
/// `a_i = R_i - xi/2` and `a_j = R_j - xi/2` add up to the centre distance, so total angular
/// momentum (orbital + spin) is conserved exactly by every pair force.
///
/// Dissipation rate: the power the contact takes from the particles' kinetic energy,
/// `F_n dxi/dt - F_t . v_t - M_roll . omega_rel`, minus the rate of change of the stored
/// elastic energy `F_el dxi/dt`; for Cundall-Strack the tangential part is the spring's
/// elastic energy lost to its Coulomb truncation, per step (a stuck spring stores, it does
/// not dissipate).
#[inline(always)]
pub fn evaluate<N: Normal>(law: &ContactLaw, g: &ContactGeometry<N>, history: &mut Vec3, dt: f64) -> ContactForce {
    let n = law.normal.evaluate(g.overlap, g.overlap_rate, g.r_eff);
    evaluate_loaded(law, g, n.raw, n.elastic, n.energy, history, dt)
}

/// [`evaluate`] with the unclamped normal force `normal_raw` (N) given instead of computed
/// from the normal law: a grain pinned to the floor (jumping off, eq 3.28) carries its
/// weight there, and its friction and rolling resistance feel that load.
#[inline(always)]
pub fn evaluate_with_normal<N: Normal>(
    law: &ContactLaw,
    g: &ContactGeometry<N>,
    normal_raw: f64,
    history: &mut Vec3,
    dt: f64,
) -> ContactForce {
    evaluate_loaded(law, g, normal_raw, 0.0, 0.0, history, dt)
}

/// The shared tail of [`evaluate`] and [`evaluate_with_normal`] for one contact: [`finish`]
/// with one lane.
#[inline(always)]
fn evaluate_loaded<N: Normal>(
    law: &ContactLaw,
    g: &ContactGeometry<N>,
    normal_raw: f64,
    elastic: f64,
    stored: f64,
    history: &mut Vec3,
    dt: f64,
) -> ContactForce {
    let mut zeta = lane::V3::from(*history);
    let c = finish(law, &g.lanes(), normal_raw, elastic, stored, &mut zeta, dt);
    *history = zeta.into();
    ContactForce {
        force: c.force.into(),
        torque_i: c.torque_i.into(),
        torque_j: c.torque_j.into(),
        normal_raw: c.normal_raw,
        normal: c.normal,
        tangential: c.tangential.into(),
        stored_energy: c.stored_energy,
        dissipation_rate: c.dissipation_rate,
    }
}

/// [`evaluate`] over lanes: the full law on `g`, for contacts side by side.
#[inline(always)]
pub fn evaluate_lanes<L: Lane, N: Normal<L>>(law: &ContactLaw, g: &LaneGeometry<N, L>, history: &mut V3<L>, dt: f64) -> LaneForce<L> {
    let n = law.normal.evaluate(g.overlap, g.overlap_rate, g.r_eff);
    finish(law, g, n.raw, n.elastic, n.energy, history, dt)
}

/// [`ContactForce`] over lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneForce<L> {
    pub force: V3<L>,
    pub torque_i: V3<L>,
    pub torque_j: V3<L>,
    pub normal_raw: L,
    pub normal: L,
    pub tangential: V3<L>,
    pub stored_energy: L,
    pub dissipation_rate: L,
}

/// Tangential and rolling laws under the normal force `normal_raw`, whose elastic part is
/// `elastic` (storing `stored` J), and the sums of a contact: the one code every contact,
/// pair or wall, one lane or several, goes through.
#[inline(always)]
fn finish<L: Lane, N: Normal<L>>(
    law: &ContactLaw,
    g: &LaneGeometry<N, L>,
    normal_raw: L,
    elastic: L,
    stored: L,
    history: &mut V3<L>,
    dt: f64,
) -> LaneForce<L> {
    let normal = normal_raw.max(L::splat(0.0));

    let tang = law.tangential.force_lanes(g, normal, history, dt);
    let roll = law.rolling.torque_lanes(g, normal);

    let force = g.n.scaled(normal) + tang.force;
    let lever = g.n.cross(tang.force);
    let torque_i = lever.scale(-g.arm_i) + roll;
    let torque_j = lever.scale(-g.arm_j) - roll;

    let dissipation_rate = (normal - elastic) * g.overlap_rate + tang.dissipation_rate - roll.dot(g.omega_rel);
    LaneForce {
        force,
        torque_i,
        torque_j,
        normal_raw,
        normal,
        tangential: tang.force,
        stored_energy: stored + tang.stored_energy,
        dissipation_rate,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> ContactLaw {
        ContactLaw {
            normal: NormalLaw::hertz(1e6 / 0.91, 8.5e-6),
            tangential: TangentialLaw::CundallStrack { kt: 500.0, mu: 0.7 },
            rolling: RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 },
        }
    }

    fn sphere(x: Vec3, v: Vec3, w: Vec3, r: f64) -> geometry::Sphere {
        geometry::Sphere { x, v, w, r }
    }

    fn sample_geometry(swap: bool) -> ContactGeometry {
        let (ri, rj) = (4e-4, 3e-4);
        let xi = Vec3::new(0.0, 0.0, 0.0);
        let xj = Vec3::new(6.9e-4, 0.5e-4, -0.2e-4);
        let vi = Vec3::new(0.1, -0.02, 0.03);
        let vj = Vec3::new(-0.05, 0.01, 0.0);
        let wi = Vec3::new(10.0, -5.0, 2.0);
        let wj = Vec3::new(-3.0, 4.0, 7.0);
        if swap {
            ContactGeometry::pair(sphere(xj, vj, wj, rj), sphere(xi, vi, wi, ri)).unwrap()
        } else {
            ContactGeometry::pair(sphere(xi, vi, wi, ri), sphere(xj, vj, wj, rj)).unwrap()
        }
    }

    #[test]
    fn action_equals_reaction_and_swap_mirrors() {
        let g = sample_geometry(false);
        let gs = sample_geometry(true);
        let (mut h, mut hs) = (Vec3::zeros(), Vec3::zeros());
        let f = evaluate(&law(), &g, &mut h, 1e-6);
        let fs = evaluate(&law(), &gs, &mut hs, 1e-6);
        assert!((f.force + fs.force).norm() < 1e-12 * f.force.norm());
        assert!((f.torque_i - fs.torque_j).norm() < 1e-12 * f.torque_i.norm());
        assert!((f.torque_j - fs.torque_i).norm() < 1e-12 * f.torque_i.norm());
    }

    #[test]
    fn total_angular_momentum_rate_vanishes() {
        let g = sample_geometry(false);
        let mut h = Vec3::zeros();
        let f = evaluate(&law(), &g, &mut h, 1e-6);
        let d = g.n * (g.arm_i + g.arm_j); // r_i - r_j
        let total = d.cross(&f.force) + f.torque_i + f.torque_j;
        assert!(total.norm() < 1e-14 * d.norm() * f.force.norm(), "{total}");
    }

    #[test]
    fn coulomb_bound_and_no_attraction() {
        let g = sample_geometry(false);
        let mut h = Vec3::new(0.0, 1.0, 0.0); // huge stored spring
        let f = evaluate(&law(), &g, &mut h, 1e-6);
        assert!(f.normal >= 0.0);
        assert!(f.tangential.norm() <= 0.7 * f.normal * (1.0 + 1e-12));
    }

    #[test]
    fn infinite_friction_is_the_viscous_branch_alone_even_at_zero_normal_force() {
        // Haff-Werner with mu = inf (scene `friction = inf`): F_t = -gamma_t v_t whatever F_n,
        // including a touching contact with no normal force (inf * 0 must not give NaN).
        let g = sample_geometry(false);
        let gamma_t = 0.007;
        let law = TangentialLaw::HaffWerner {
            gamma_t,
            mu: f64::INFINITY,
        };
        let mut h = Vec3::zeros();
        for fn_ in [0.0, 1e-9, 1.0] {
            let t = law.force(&g, fn_, &mut h, 1e-6);
            assert!((t.force + g.v_t * gamma_t).norm() <= 1e-15, "F_n = {fn_}: {:?}", t.force);
        }
        // Cundall-Strack with mu = inf: the spring is never truncated. From rest it is
        // half a step's slip at the evaluation, and the history a full step's.
        let law = TangentialLaw::CundallStrack {
            kt: 500.0,
            mu: f64::INFINITY,
        };
        let mut zeta = Vec3::zeros();
        let t = law.force(&g, 0.0, &mut zeta, 1e-3);
        assert!(t.force.iter().all(|c| c.is_finite()) && t.force.norm() > 0.0);
        assert!((t.force + g.v_t * (500.0 * 0.5e-3)).norm() <= 1e-12 * t.force.norm());
        assert!((zeta - g.v_t * 1e-3).norm() <= 1e-12 * zeta.norm());
    }

    #[test]
    fn cundall_strack_at_an_axis_wall_equals_the_general_wall() {
        // An axis-aligned wall drops its springs' normal component by setting it to zero
        // (`Normal::in_plane`); the general wall subtracts it. Over a run of steps that stick and slide,
        // force, torque and spring agree (`==` treats -0 and +0 as equal).
        let (r, o) = (4e-4, Vec3::new(0.013, 0.02, 0.0));
        let vw = Vec3::zeros(); // a wall moving off a grain would leave no normal force
        for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let mut normal = Vec3::zeros();
            normal[axis] = sign;
            let (mut h_axis, mut h_general) = (Vec3::zeros(), Vec3::zeros());
            let (mut stuck, mut sliding) = (0, 0);
            for k in 0..40 {
                let phase = k as f64 * 0.3;
                let x = o + normal * (r - 2e-6);
                // Slip back and forth along one direction: stuck after each reversal.
                let v = Vec3::new(0.03, -0.02, 0.01) * phase.sin();
                let w = Vec3::new(4.0, -2.5, 1.2) * phase.sin();
                let general = ContactGeometry::wall(x, v, w, r, o, normal, vw).unwrap();
                let f_general = evaluate(&law(), &general, &mut h_general, 1e-5);
                let f_axis = match axis {
                    0 => evaluate(
                        &law(),
                        &ContactGeometry::<AxisNormal<0>>::axis_wall(x, v, w, r, o, sign, vw).unwrap(),
                        &mut h_axis,
                        1e-5,
                    ),
                    1 => evaluate(
                        &law(),
                        &ContactGeometry::<AxisNormal<1>>::axis_wall(x, v, w, r, o, sign, vw).unwrap(),
                        &mut h_axis,
                        1e-5,
                    ),
                    _ => evaluate(
                        &law(),
                        &ContactGeometry::<AxisNormal<2>>::axis_wall(x, v, w, r, o, sign, vw).unwrap(),
                        &mut h_axis,
                        1e-5,
                    ),
                };
                // (`torque_j` is a wall's: infinite lever arm, not used.)
                let parts = |f: &ContactForce| (f.force, f.torque_i, f.tangential, f.normal, f.stored_energy, f.dissipation_rate);
                assert!(
                    parts(&f_axis) == parts(&f_general),
                    "axis {axis} sign {sign} step {k}: {f_axis:?} != {f_general:?}"
                );
                assert!(h_axis == h_general, "axis {axis} sign {sign} step {k}: {h_axis} != {h_general}");
                assert_eq!(h_axis[axis], 0.0, "a wall's spring has no normal part");
                if f_axis.tangential.norm() < 0.7 * f_axis.normal * (1.0 - 1e-9) {
                    stuck += 1;
                } else {
                    sliding += 1;
                }
            }
            assert!(
                stuck > 0 && sliding > 0,
                "axis {axis} sign {sign}: both regimes: {stuck} stuck, {sliding} sliding"
            );
        }
    }

    #[test]
    fn a_stuck_cundall_strack_spring_follows_the_trapezoid_rule() {
        // Tangential slip at a steady rate u, then at rate -u: the spring is the integral of
        // the slip, k_t times the trapezoid sum, exactly (no lead of half a step).
        let mut g = sample_geometry(false);
        let law = TangentialLaw::CundallStrack { kt: 500.0, mu: 0.7 };
        let (dt, fn_) = (1e-6, 1.0); // Coulomb limit far away
        let u = g.v_t;
        let mut zeta = Vec3::zeros();
        let mut last = Vec3::zeros();
        for k in 0..10 {
            g.v_t = if k < 6 { u } else { -u };
            last = law.force(&g, fn_, &mut zeta, dt).force;
        }
        // Slip: half a step from rest, five steps at u, the step of the switch (half a step
        // each way, cancelling), three steps at -u: 0.5 + 5 - 3 = 2.5 steps of u.
        let expected = u * (-500.0 * 2.5 * dt);
        assert!((last - expected).norm() <= 1e-9 * expected.norm(), "{last} against {expected}");
    }
}
