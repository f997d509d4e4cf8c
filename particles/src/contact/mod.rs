//! Contact law: one slot per sub-model (normal, tangential, rolling), each an enum with an
//! explicit variant for "off" where off makes sense, matched exhaustively.
//!
//! Every kernel is a pure function of a precomputed [`ContactGeometry`]; the same code serves
//! particle pairs and particle-wall contacts (a wall is an infinite-mass, infinite-radius
//! partner, eq 3.17-3.18). Per-contact history (the Cundall-Strack tangential spring and the
//! spring-dashpot-slider's rolling spring, a [`History`]) is passed in separately from the
//! parameters.

pub mod choice;
pub mod geometry;
pub mod lane;
pub mod normal;
pub mod rolling;
pub mod tangential;

pub use geometry::{AxisNormal, ContactGeometry, LaneGeometry, Normal};
pub use lane::{Lane, V3};
pub use normal::NormalLaw;
pub use rolling::{RollingLaw, RollingLoad};
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

    /// True if the law is history dependent (needs per-contact storage): a tangential or a
    /// rolling spring.
    pub fn has_history(&self) -> bool {
        self.tangential.has_history() || self.rolling.has_history()
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
            (TangentialLaw::None, RollingLaw::SpringDashpotSlider { .. }) => f(&law),
            (TangentialLaw::HaffWerner { .. }, RollingLaw::None) => f(&law),
            (TangentialLaw::HaffWerner { .. }, RollingLaw::BrilliantovPoschel { .. }) => f(&law),
            (TangentialLaw::HaffWerner { .. }, RollingLaw::SpringDashpotSlider { .. }) => f(&law),
            (TangentialLaw::CundallStrack { .. }, RollingLaw::None) => f(&law),
            (TangentialLaw::CundallStrack { .. }, RollingLaw::BrilliantovPoschel { .. }) => f(&law),
            (TangentialLaw::CundallStrack { .. }, RollingLaw::SpringDashpotSlider { .. }) => f(&law),
        }
    }
}

/// The history of one contact (per lane: `History<V3<L>>`): the Cundall-Strack tangential
/// spring `slide` (m) and the spring-dashpot-slider's rolling spring `roll` (rad). Each is
/// zero, and unused, under a law without it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct History<F = Vec3> {
    pub slide: F,
    pub roll: F,
}

impl History {
    /// Tangential spring `slide`, no rolling spring.
    pub fn sliding(slide: Vec3) -> Self {
        Self {
            slide,
            roll: Vec3::zeros(),
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
    /// The force on i less its elastic normal part (N): the normal damping and the
    /// tangential force, whose work the ledger books as dissipated (see [`LaneForce::drag`]).
    pub drag: Vec3,
    /// Energy stored in the contact (elastic normal + tangential spring + rolling spring), J.
    pub stored_energy: f64,
    /// Rate at which the contact dissipates mechanical energy (W), `>= 0` up to the
    /// elastic spring's exchange term (see [`evaluate`]).
    pub dissipation_rate: f64,
}

/// Evaluates the full contact law on a geometry.
///
/// `history` holds the springs of this contact (the Cundall-Strack tangential spring, the
/// spring-dashpot-slider's rolling spring; unused by the other laws) and is advanced by
/// `dt`. The rolling coefficient is the law's own; [`evaluate_with`] takes the contact's.
///
/// Torques act at the contact point, taken at the middle of the overlap: the lever arms
/// `a_i = R_i - xi/2` and `a_j = R_j - xi/2` add up to the centre distance, so total angular
/// momentum (orbital + spin) is conserved exactly by every pair force.
///
/// Dissipation rate: the power the contact takes from the particles' kinetic energy,
/// `F_n dxi/dt - F_t . v_t - M_roll . omega_rel`, minus the rate of change of the stored
/// elastic energy `F_el dxi/dt`; for Cundall-Strack the tangential part is the spring's
/// elastic energy lost to its Coulomb truncation, per step (a stuck spring stores, it does
/// not dissipate), and likewise for the spring-dashpot-slider's rolling spring (see
/// [`rolling::RollingTorque::dissipation_rate`]).
#[inline(always)]
pub fn evaluate<N: Normal>(law: &ContactLaw, g: &ContactGeometry<N>, history: &mut History, dt: f64) -> ContactForce {
    evaluate_with(law, g, None, history, law.rolling.mu_r(), dt)
}

/// [`evaluate`] with the contact's own rolling coefficient `mu_r` (the mean of its grains'
/// per-grain values, see [`RollingLaw::SpringDashpotSlider`]) and, with `load`, the
/// unclamped normal force `load` (N) given instead of computed from the normal law: a grain
/// pinned to the floor (jumping off, eq 3.28) carries its weight there, and its friction and
/// rolling resistance feel that load (a rolling spring's default stiffness is then the
/// normal law's at the overlap that would carry it, [`NormalLaw::stiffness_under`]).
#[inline(always)]
pub fn evaluate_with<N: Normal>(
    law: &ContactLaw,
    g: &ContactGeometry<N>,
    load: Option<f64>,
    history: &mut History,
    mu_r: f64,
    dt: f64,
) -> ContactForce {
    let n = match load {
        Some(f) => normal::NormalForce {
            raw: f,
            elastic: 0.0,
            energy: 0.0,
        },
        None => law.normal.evaluate(g.overlap, g.overlap_rate, g.r_eff),
    };
    let stiffness = match load {
        Some(f) if law.rolling.has_history() => (law.normal.stiffness_under(f, g.r_eff), 0.0),
        _ => (0.0, 0.0),
    };
    let mut h = History {
        slide: lane::V3::from(history.slide),
        roll: lane::V3::from(history.roll),
    };
    let c = finish(law, &g.lanes(), n, load.map(|_| stiffness), &mut h, mu_r, dt);
    *history = History {
        slide: h.slide.into(),
        roll: h.roll.into(),
    };
    ContactForce {
        force: c.force.into(),
        torque_i: c.torque_i.into(),
        torque_j: c.torque_j.into(),
        normal_raw: c.normal_raw,
        normal: c.normal,
        tangential: c.tangential.into(),
        drag: c.drag.into(),
        stored_energy: c.stored_energy,
        dissipation_rate: c.dissipation_rate,
    }
}

/// [`evaluate_with`] over lanes (the normal force from the normal law): the full law on `g`,
/// for contacts side by side, each with its rolling coefficient `mu_r`.
#[inline(always)]
pub fn evaluate_lanes<L: Lane, N: Normal<L>>(
    law: &ContactLaw,
    g: &LaneGeometry<N, L>,
    history: &mut History<V3<L>>,
    mu_r: L,
    dt: f64,
) -> LaneForce<L> {
    let n = law.normal.evaluate(g.overlap, g.overlap_rate, g.r_eff);
    finish(law, g, n, None, history, mu_r, dt)
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
    /// The force on i less its elastic normal part, `n (F_n - F_el) + F_t`: the force whose
    /// power `dissipation_rate` books (with the rolling torque's). The step's ledger
    /// corrects that booking with it (`crate::sim`, [`crate::integrate::verlet_excess`]).
    pub drag: V3<L>,
    pub stored_energy: L,
    pub dissipation_rate: L,
}

/// Tangential and rolling laws under the normal force `n` (unclamped, its elastic part and
/// energy), and the sums of a contact: the one code every contact, pair or wall, one lane or
/// several, goes through. `stiffness`: the normal stiffness and its rate for the rolling
/// spring where the caller knows them (a given load); `None`: from the normal law at the
/// geometry's overlap (computed only for a law with a rolling spring).
#[inline(always)]
fn finish<L: Lane, N: Normal<L>>(
    law: &ContactLaw,
    g: &LaneGeometry<N, L>,
    n: normal::NormalForce<L>,
    stiffness: Option<(L, L)>,
    history: &mut History<V3<L>>,
    mu_r: L,
    dt: f64,
) -> LaneForce<L> {
    let normal_raw = n.raw;
    let normal = normal_raw.max(L::splat(0.0));

    let tang = law.tangential.force_lanes(g, normal, &mut history.slide, dt);
    let stiffness = match stiffness {
        Some(s) => s,
        None if law.rolling.has_history() => law.normal.stiffness(g.overlap, g.overlap_rate, g.r_eff),
        None => (L::splat(0.0), L::splat(0.0)),
    };
    let load = RollingLoad { normal, stiffness, mu_r };
    let roll = law.rolling.torque_lanes(g, load, &mut history.roll, dt);

    let force = g.n.scaled(normal) + tang.force;
    let lever = g.n.cross(tang.force);
    let torque_i = lever.scale(-g.arm_i) + roll.torque;
    let torque_j = lever.scale(-g.arm_j) - roll.torque;

    let damping = normal - n.elastic;
    let drag = g.n.scaled(damping) + tang.force;
    let dissipation_rate = damping * g.overlap_rate + tang.dissipation_rate + roll.dissipation_rate;
    // (Decided per copy of the law: no addition of a zero for the laws without a spring.)
    let stored_energy = if law.rolling.has_history() {
        n.energy + tang.stored_energy + roll.stored_energy
    } else {
        n.energy + tang.stored_energy
    };
    LaneForce {
        force,
        torque_i,
        torque_j,
        normal_raw,
        normal,
        tangential: tang.force,
        drag,
        stored_energy,
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
        let (mut h, mut hs) = (History::default(), History::default());
        let f = evaluate(&law(), &g, &mut h, 1e-6);
        let fs = evaluate(&law(), &gs, &mut hs, 1e-6);
        assert!((f.force + fs.force).norm() < 1e-12 * f.force.norm());
        assert!((f.torque_i - fs.torque_j).norm() < 1e-12 * f.torque_i.norm());
        assert!((f.torque_j - fs.torque_i).norm() < 1e-12 * f.torque_i.norm());
    }

    #[test]
    fn total_angular_momentum_rate_vanishes() {
        let g = sample_geometry(false);
        let mut h = History::default();
        let f = evaluate(&law(), &g, &mut h, 1e-6);
        let d = g.n * (g.arm_i + g.arm_j); // r_i - r_j
        let total = d.cross(&f.force) + f.torque_i + f.torque_j;
        assert!(total.norm() < 1e-14 * d.norm() * f.force.norm(), "{total}");
    }

    #[test]
    fn coulomb_bound_and_no_attraction() {
        let g = sample_geometry(false);
        let mut h = History::sliding(Vec3::new(0.0, 1.0, 0.0)); // huge stored spring
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
            let (mut h_axis, mut h_general) = (History::default(), History::default());
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
                assert!(h_axis == h_general, "axis {axis} sign {sign} step {k}: {h_axis:?} != {h_general:?}");
                assert_eq!(h_axis.slide[axis], 0.0, "a wall's spring has no normal part");
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
