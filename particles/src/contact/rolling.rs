//! Rolling resistance.

use super::geometry::{LaneGeometry, Normal};
use super::lane::{Lane, V3};
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
}

impl RollingLaw {
    /// Rolling torque on particle i (N m); particle j receives the opposite: one contact,
    /// [`Self::torque_lanes`] with one lane.
    #[inline(always)]
    pub fn torque<N: Normal>(&self, g: &ContactGeometry<N>, fn_: f64) -> Vec3 {
        self.torque_lanes(&g.lanes(), fn_).into()
    }

    /// The law over lanes.
    ///
    /// `v_omega / |omega_rel| = R_eff sqrt(|omega_rel x n|^2 / |omega_rel|^2)`: one root.
    #[inline(always)]
    pub fn torque_lanes<L: Lane, N: Normal<L>>(&self, g: &LaneGeometry<N, L>, fn_: L) -> V3<L> {
        match *self {
            RollingLaw::None => V3::zeros(),
            RollingLaw::BrilliantovPoschel { mu_r } => {
                let zero = L::splat(0.0);
                let spin2 = g.omega_rel.norm_squared();
                let still = L::equal(spin2, zero) | L::equal(fn_, zero);
                if L::all(still) {
                    return V3::zeros();
                }
                let v_omega_per_spin = g.r_eff * (g.n.cross_norm_squared(g.omega_rel) / spin2).sqrt();
                let m = g.omega_rel.scale(L::splat(-mu_r) * v_omega_per_spin * fn_);
                V3::select(still, V3::zeros(), m)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let m = RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 }.torque(&g, 1e-5);
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
        let m = RollingLaw::BrilliantovPoschel { mu_r: 1.0 }.torque(&g, 1.0);
        assert_eq!(m, Vec3::zeros());
    }
}
