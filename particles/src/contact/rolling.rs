//! Rolling resistance.

use super::geometry::{LaneGeometry, Normal};
use super::lane::{Lane, V3};
use super::tangential::turn_into_plane;
use super::ContactGeometry;
use crate::Vec3;

/// Rolling-resistance law of one kind of contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RollingLaw {
    /// No rolling resistance.
    None,
    /// Brilliantov-Pöschel (eq 3.15-3.16): a torque `M_i = -mu_r v_omega F_n e_omega` on i
    /// and `-M_i` on j, with `mu_r` in s.
    ///
    /// - `e_omega` is the direction of the relative spin `omega_i - omega_j`; against a wall
    ///   (which does not spin) it is `omega_i/|omega_i|`, exactly eq 3.15.
    /// - `v_omega = |R_eff (omega_i - omega_j) x n|` is the rolling velocity at the contact.
    ///   Against a wall it is `R |omega_i x n|`, the thesis' `|omega_i x R_i|`. For a pair it
    ///   is the objective rolling velocity; counter-rotating equal spheres give `R omega`.
    ///
    /// Equal and opposite torques keep the total angular momentum conserved. A grain rolling
    /// without slip on the floor slows down as `dv/dt = -(5/7) (mu_r g / R) v`: a rate that
    /// depends on size, unlike sliding friction.
    BrilliantovPoschel { mu_r: f64 },
    /// Spring-dashpot-slider, the elastic-plastic spring-dashpot of Ai, Chen, Rotter & Ooi
    /// (Powder Technology 206, 2011, model C; LAMMPS `pair granular ... rolling sds`): a
    /// rolling spring that holds a grain at rest up to a static limit.
    ///
    /// - **Spring.** The rolling spring `theta` (rad, per-contact history) integrates the
    ///   relative rolling rotation, the part of `omega_i - omega_j` across the normal:
    ///   `dtheta = (omega_rel - (omega_rel . n) n) dt` (twisting is free). Its torque on i is
    ///   `M_k = -k_r theta`, on j `-M_k`.
    /// - **Slider.** `|M_k| <= mu_r R_eff F_n` (`mu_r` dimensionless, `F_n` the clamped normal
    ///   force); beyond it the spring is truncated to the limit and the energy it loses is
    ///   dissipated.
    /// - **Dashpot.** While the spring is below its limit a viscous torque
    ///   `M_d = -gamma_roll R_eff^2 omega_roll` acts as well (`gamma_roll` in N s/m, LAMMPS'
    ///   `gamma_roll`); at the limit it is off (Ai et al.'s `f = 0`), and so it is without a limit
    ///   (`mu_r R_eff F_n = 0`). It is not itself capped: below the limit it may exceed
    ///   `mu_r R_eff F_n` (LAMMPS caps spring and dashpot together).
    /// - **Stiffness.** `k_r = k_roll R_eff^2` (N m/rad) with `k_roll` in N/m (LAMMPS'
    ///   `k_roll`), or by default `k_roll = 2.25 mu_r^2 k_n`, i.e. `k_r = 2.25 k_n mu_r^2
    ///   R_eff^2` (Ai et al. eq 21, after Iwashita & Oda), with `k_n` the normal law's tangent
    ///   stiffness at the current overlap ([`super::NormalLaw::stiffness`]).
    ///
    /// `mu_r` here is the law's (the scene's mean); a contact may be given its own (the mean
    /// of its grains' per-grain values). Integration mirrors the Cundall-Strack spring (the
    /// trapezoid rule: the history holds the spring half a step ahead). A grain rolling
    /// without slip on the floor with the spring at its limit decelerates at
    /// `(5/7) mu_r g`, whatever its size; on an incline it stays at rest while
    /// `tan(theta) <= mu_r`.
    SpringDashpotSlider {
        /// Rolling resistance coefficient (dimensionless), the law's mean.
        mu_r: f64,
        /// `k_roll` (N/m); `None`: `2.25 mu_r^2 k_n`.
        k_roll: Option<f64>,
        /// `gamma_roll` (N s/m).
        gamma_roll: f64,
    },
}

/// Result of a rolling kernel (per lane: `RollingTorque<V3<L>, L>`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingTorque<F = Vec3, L = f64> {
    /// Torque on particle i (N m); j receives the opposite.
    pub torque: F,
    /// Elastic energy held in the rolling spring, `k_r |theta|^2 / 2` (J).
    pub stored_energy: L,
    /// Dissipated power (W): `-M . omega_rel` (Brilliantov-Pöschel); for the
    /// spring-dashpot-slider the dashpot's power, the slider's work per time step (its slip
    /// times the limit torque), and minus the power a changing stiffness puts into the
    /// spring, `-(|theta|^2 / 2) dk_r/dt`.
    pub dissipation_rate: L,
}

/// The normal side of a contact, as the rolling laws need it (per lane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingLoad<L = f64> {
    /// Clamped normal force `F_n >= 0` (N).
    pub normal: L,
    /// Normal stiffness `k_n` (N/m) and its rate (N/m/s), see [`super::NormalLaw::stiffness`]
    /// (only the spring-dashpot-slider reads them).
    pub stiffness: (L, L),
    /// The contact's rolling coefficient `mu_r` (only the spring-dashpot-slider reads it).
    pub mu_r: L,
}

impl RollingLaw {
    /// True if the law keeps a per-contact spring (the spring-dashpot-slider).
    pub fn has_history(&self) -> bool {
        matches!(self, RollingLaw::SpringDashpotSlider { .. })
    }

    /// The law's rolling coefficient: `mu_r` (s) of Brilliantov-Pöschel, `mu_r`
    /// (dimensionless) of the spring-dashpot-slider, 0 without rolling resistance.
    pub fn mu_r(&self) -> f64 {
        match *self {
            RollingLaw::None => 0.0,
            RollingLaw::BrilliantovPoschel { mu_r } | RollingLaw::SpringDashpotSlider { mu_r, .. } => mu_r,
        }
    }

    /// Rolling torque on particle i (N m) under the clamped normal force `fn_`; particle j
    /// receives the opposite: one contact without history, [`Self::torque_lanes`] with one
    /// lane (the law's own `mu_r` and a normal stiffness of 0).
    #[inline(always)]
    pub fn torque<N: Normal>(&self, g: &ContactGeometry<N>, fn_: f64, theta: &mut Vec3, dt: f64) -> RollingTorque {
        let load = RollingLoad {
            normal: fn_,
            stiffness: (0.0, 0.0),
            mu_r: self.mu_r(),
        };
        let mut t = V3::from(*theta);
        let r = self.torque_lanes(&g.lanes(), load, &mut t, dt);
        *theta = t.into();
        RollingTorque {
            torque: r.torque.into(),
            stored_energy: r.stored_energy,
            dissipation_rate: r.dissipation_rate,
        }
    }

    /// The law over lanes; `theta` is the rolling spring (rad) of the spring-dashpot-slider
    /// (unused by the others), advanced by `dt`.
    ///
    /// Brilliantov-Pöschel: `v_omega / |omega_rel| = R_eff sqrt(|omega_rel x n|^2 /
    /// |omega_rel|^2)`: one root.
    #[inline(always)]
    pub fn torque_lanes<L: Lane, N: Normal<L>>(
        &self,
        g: &LaneGeometry<N, L>,
        load: RollingLoad<L>,
        theta: &mut V3<L>,
        dt: f64,
    ) -> RollingTorque<V3<L>, L> {
        let zero = L::splat(0.0);
        match *self {
            RollingLaw::None => RollingTorque {
                torque: V3::zeros(),
                stored_energy: zero,
                dissipation_rate: zero,
            },
            RollingLaw::BrilliantovPoschel { mu_r } => {
                let fn_ = load.normal;
                let spin2 = g.omega_rel.norm_squared();
                let still = L::equal(spin2, zero) | L::equal(fn_, zero);
                if L::all(still) {
                    return RollingTorque {
                        torque: V3::zeros(),
                        stored_energy: zero,
                        dissipation_rate: zero,
                    };
                }
                let v_omega_per_spin = g.r_eff * (g.n.cross_norm_squared(g.omega_rel) / spin2).sqrt();
                let m = g.omega_rel.scale(L::splat(-mu_r) * v_omega_per_spin * fn_);
                let torque = V3::select(still, V3::zeros(), m);
                RollingTorque {
                    torque,
                    stored_energy: zero,
                    dissipation_rate: -torque.dot(g.omega_rel),
                }
            }
            RollingLaw::SpringDashpotSlider { k_roll, gamma_roll, .. } => {
                let mu_r = load.mu_r;
                let r2 = g.r_eff * g.r_eff;
                let (kn, kn_rate) = load.stiffness;
                // k_r = k_roll R^2, or 2.25 mu_r^2 k_n R^2; its rate with k_n's.
                let (kr, kr_rate) = match k_roll {
                    Some(k) => (L::splat(k) * r2, zero),
                    None => {
                        let c = L::splat(2.25) * mu_r * mu_r * r2;
                        (c * kn, c * kn_rate)
                    }
                };
                // The rolling rotation rate: the relative spin across the normal.
                let roll = g.n.in_plane(g.omega_rel);
                let s = turn_into_plane(&g.n, *theta);
                // The spring now: the second half of the trapezoid over the last step.
                let half = roll.scale(L::splat(0.5 * dt));
                let mut th = s + half;
                let limit = mu_r * g.r_eff * load.normal;
                let len2 = th.norm_squared();
                let mut stored = L::splat(0.5) * kr * len2;
                let mut lost = zero;
                // At the limit (compared in squares): truncate, and the dashpot is off. The
                // slider slips by `|theta| - limit / k_r` at the limit torque: that work is
                // dissipated. (Not the spring energy above the limit, `k_r (|theta|^2 -
                // (limit / k_r)^2) / 2`: where a step's rotation exceeds the spring's elastic
                // range `limit / k_r`, that would book the energy of a spring stretched far
                // past its limit, which the grains never gave.)
                let sliding = L::lt(limit * limit, kr * kr * len2);
                if L::any(sliding) {
                    let len = len2.sqrt();
                    let scale = limit / (kr * len);
                    th = V3::select(sliding, th.scale(scale), th);
                    lost = L::select(sliding, limit * len * (L::splat(1.0) - scale), zero);
                    stored = L::select(sliding, stored * (scale * scale), stored);
                }
                // The first half of the trapezoid over the next step.
                *theta = th + half;
                // Without a limit (`mu_r` = 0, or no normal force) nothing holds the contact:
                // the dashpot is off as at the limit. (With `mu_r` = 0 the default stiffness is
                // 0 too, so the spring never exceeded the zero limit, and the dashpot acted
                // alone, uncapped.)
                let held = L::lt(zero, limit);
                let damping = L::select(sliding, zero, L::select(held, L::splat(gamma_roll) * r2, zero));
                let torque = th.scale(-kr) - roll.scale(damping);
                let th2 = th.norm_squared();
                RollingTorque {
                    torque,
                    stored_energy: stored,
                    dissipation_rate: damping * roll.norm_squared() + lost * L::splat(1.0 / dt) - L::splat(0.5) * th2 * kr_rate,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::geometry::Sphere;
    use crate::contact::{evaluate_with, ContactLaw, History, NormalLaw, TangentialLaw};
    use proptest::prelude::*;

    fn sds(mu_r: f64, k_roll: Option<f64>, gamma_roll: f64) -> ContactLaw {
        ContactLaw {
            normal: NormalLaw::hertz(1.1e6, 8.5e-6),
            tangential: TangentialLaw::CundallStrack { kt: 50.0, mu: 0.7 },
            rolling: RollingLaw::SpringDashpotSlider { mu_r, k_roll, gamma_roll },
        }
    }

    fn v3() -> impl Strategy<Value = Vec3> {
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    proptest! {
        /// Any pair, any spins, any stored springs: evaluated from either grain (the other's
        /// spring is the negation) the contact gives equal and opposite rolling torques and
        /// springs, the total angular momentum (orbital + spin) does not change, and the
        /// spring never exceeds its limit `mu_r R_eff F_n`.
        #[test]
        fn pair_torques_are_equal_and_opposite_and_the_spring_is_capped(
            (ri, rj) in (2e-4f64..6e-4, 2e-4f64..6e-4),
            dir in v3(),
            depth in 0.001f64..0.05,
            (vi, vj, wi, wj) in (v3(), v3(), v3(), v3()),
            (slide, roll) in (v3(), v3()),
            mu_r in 0.0f64..1.0,
            k_roll in prop::option::of(0.1f64..1e3),
        ) {
            prop_assume!(dir.norm() > 0.1);
            let d = dir.normalize() * (ri + rj) * (1.0 - depth);
            let xi = Vec3::zeros();
            let sphere = |x, v: Vec3, w: Vec3, r| Sphere { x, v: v * 0.1, w: w * 300.0, r };
            let g = ContactGeometry::pair(sphere(xi, vi, wi, ri), sphere(xi - d, vj, wj, rj)).unwrap();
            let gs = ContactGeometry::pair(sphere(xi - d, vj, wj, rj), sphere(xi, vi, wi, ri)).unwrap();
            let dt = 1e-6;
            for gamma_roll in [0.0, 0.05] {
                let law = sds(mu_r, k_roll, gamma_roll);
                let mut h = History { slide: slide * 1e-5, roll: roll * 1e-2 };
                let mut hs = History { slide: -h.slide, roll: -h.roll };
                let c = evaluate_with(&law, &g, None, &mut h, mu_r, dt);
                let cs = evaluate_with(&law, &gs, None, &mut hs, mu_r, dt);
                let scale = c.torque_i.norm() + c.torque_j.norm() + 1e-300;
                prop_assert!((c.torque_i - cs.torque_j).norm() <= 1e-12 * scale);
                prop_assert!((c.torque_j - cs.torque_i).norm() <= 1e-12 * scale);
                prop_assert!((h.roll + hs.roll).norm() <= 1e-12 * h.roll.norm());
                let total = d.cross(&c.force) + c.torque_i + c.torque_j;
                prop_assert!(total.norm() <= 1e-12 * (d.norm() * c.force.norm() + scale), "{total}");
                if gamma_roll == 0.0 {
                    // The rolling torque alone: the torques minus the friction's lever.
                    let lever = g.n.cross(&c.tangential);
                    let m = c.torque_i + lever * g.arm_i;
                    // Subtracting the friction's lever leaves its rounding in `m`: the
                    // tolerances scale with the larger of the two torques.
                    let round = 1e-12 * (m.norm() + (lever * g.arm_i).norm()) + 1e-300;
                    let cap = mu_r * g.r_eff * c.normal;
                    prop_assert!(m.norm() <= cap * (1.0 + 1e-12) + round, "|M| {} > cap {cap}", m.norm());
                    prop_assert!(m.dot(&g.n).abs() <= round, "torque along the normal");
                }
            }
        }
    }

    #[test]
    fn without_a_limit_the_law_gives_no_rolling_torque() {
        // mu_r = 0, with the default stiffness (0) or a given one, and a dashpot: a sphere
        // rolling on a wall feels only the friction's lever, whatever the dashpot.
        let r = 5e-4;
        let g = ContactGeometry::wall(
            Vec3::new(0.0, 0.0, r - 1e-5),
            Vec3::zeros(),
            Vec3::new(0.0, 30.0, 0.0),
            r,
            Vec3::zeros(),
            Vec3::z(),
            Vec3::zeros(),
        )
        .unwrap();
        for k_roll in [None, Some(10.0)] {
            let law = sds(0.0, k_roll, 0.05);
            let mut h = History::default();
            for _ in 0..5 {
                let c = evaluate_with(&law, &g, None, &mut h, 0.0, 1e-6);
                let m = c.torque_i + g.n.cross(&c.tangential) * g.arm_i;
                assert!(m.norm() <= 1e-15 * (g.n.cross(&c.tangential) * g.arm_i).norm(), "{k_roll:?}: {m}");
            }
        }
    }

    #[test]
    fn the_spring_accumulates_the_rolling_rotation_below_its_limit() {
        // A sphere on a wall rolling at omega about y for k steps from zero: the spring is
        // `-omega k dt` (the trapezoid from rest: half a step at the first evaluation), its
        // torque `-k_r theta`, its energy `k_r theta^2 / 2`; a spin about the normal (twist)
        // adds nothing.
        let r = 5e-4;
        let k_roll = 1.0;
        let law = sds(0.5, Some(k_roll), 0.0);
        let (w, dt) = (Vec3::new(0.0, 3.0, 7.0), 1e-6);
        let g = ContactGeometry::wall(
            Vec3::new(0.0, 0.0, r - 1e-5),
            Vec3::zeros(),
            w,
            r,
            Vec3::zeros(),
            Vec3::z(),
            Vec3::zeros(),
        )
        .unwrap();
        let mut h = History::default();
        let mut last = None;
        for _ in 0..10 {
            last = Some(evaluate_with(&law, &g, None, &mut h, 0.5, dt));
        }
        let c = last.unwrap();
        let theta = 9.5 * 3.0 * dt;
        let kr = k_roll * r * r;
        let lever = g.n.cross(&c.tangential) * g.arm_i;
        let m = c.torque_i + lever;
        assert!((m.y + kr * theta).abs() <= 1e-12 * kr * theta, "{m}");
        assert!(m.x.abs() <= 1e-20 && m.z.abs() <= 1e-20, "{m}");
        let normal = NormalLaw::hertz(1.1e6, 8.5e-6).evaluate(1e-5, 0.0, r);
        assert!(kr * theta < 0.5 * r * normal.elastic, "below the limit");
        let tangential = 0.5 * 50.0 * (h.slide - (g.v_t * 0.5 * dt)).norm_squared();
        let expected = normal.energy + tangential + 0.5 * kr * theta * theta;
        assert!(
            (c.stored_energy - expected).abs() <= 1e-9 * expected,
            "{} against {expected}",
            c.stored_energy
        );
    }

    #[test]
    fn wall_rolling_torque_matches_eq_3_15() {
        let r = 5e-4;
        let w = Vec3::new(0.0, 20.0, 0.0);
        let g = ContactGeometry::wall(
            Vec3::new(0.0, 0.0, r - 1e-6),
            Vec3::zeros(),
            w,
            r,
            Vec3::zeros(),
            Vec3::z(),
            Vec3::zeros(),
        )
        .unwrap();
        let m = RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 }
            .torque(&g, 1e-5, &mut Vec3::zeros(), 1e-6)
            .torque;
        let expect = -8.5e-6 * (r * 20.0) * 1e-5;
        assert!((m.y - expect).abs() < 1e-12 * expect.abs());
        assert_eq!(m.x, 0.0);
        assert_eq!(m.z, 0.0);
    }

    #[test]
    fn no_spin_no_torque() {
        let g = ContactGeometry::wall(
            Vec3::new(0.0, 0.0, 0.9),
            Vec3::x(),
            Vec3::zeros(),
            1.0,
            Vec3::zeros(),
            Vec3::z(),
            Vec3::zeros(),
        )
        .unwrap();
        let m = RollingLaw::BrilliantovPoschel { mu_r: 1.0 }
            .torque(&g, 1.0, &mut Vec3::zeros(), 1e-6)
            .torque;
        assert_eq!(m, Vec3::zeros());
    }
}
