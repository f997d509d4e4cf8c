//! Contact geometry: the quantities every force kernel needs, computed once per contact.

use super::lane::{Lane, V3};
use crate::Vec3;

/// Geometry and kinematics of a contact between particle i and a partner j (a particle or
/// a wall). Sign conventions:
/// - `n` is the unit normal pointing from j to i;
/// - `overlap` is `xi = R_i + R_j - |r_i - r_j|` (eq 3.5), or `R_i - (r_i - r_w) . n_w` for a
///   wall (eq 3.17); positive in contact;
/// - `overlap_rate` is `dxi/dt = -(v_i - v_j) . n` (eq 3.18 for walls);
/// - `v_t` is the tangential part of the contact-point velocity of i relative to j,
///   `v_c = (v_i - v_j) - (a_i omega_i + a_j omega_j) x n` (eq 3.11 with the lever arms below);
/// - `arm_i = R_i - xi/2`, `arm_j = R_j - xi/2`: distances from the centres to the contact
///   point at the middle of the overlap. They differ from the undeformed radii of eq 3.11 by
///   `xi/2` (a relative `1e-3` at rest on the floor) and make the torques conserve angular
///   momentum exactly. A wall is the limit `R_j -> infinity`, so `arm_i = R_i - xi/2` too.
/// - `omega_rel = omega_i - omega_j`; `r_eff` is the effective radius (eq 3.8);
/// - `mobility` (1/kg) is the tangential contact-point velocity a unit tangential impulse
///   gives, `1/m_t = sum_k (1/m_k + R_k^2/I_k)` over the grains of the contact (a wall adds
///   nothing); `7 / (2 m_eff)` for two solid spheres. The constructors leave it 0, the limit
///   of infinitely heavy grains, in which the implicit viscous friction of
///   [`super::TangentialLaw::HaffWerner`] is the explicit one; the force pass sets it
///   ([`ContactGeometry::with_mobility`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactGeometry<N = Vec3> {
    pub n: N,
    pub overlap: f64,
    pub overlap_rate: f64,
    pub v_t: Vec3,
    pub omega_rel: Vec3,
    pub arm_i: f64,
    pub arm_j: f64,
    pub r_eff: f64,
    pub mobility: f64,
}

/// One sphere of a contact: centre `x` (m), velocity `v` (m/s), spin `w` (rad/s), radius
/// `r` (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub x: Vec3,
    pub v: Vec3,
    pub w: Vec3,
    pub r: f64,
}

impl ContactGeometry {
    /// Geometry of two spheres; `None` when they are apart (or coincide). Exact touching
    /// (`xi = 0`) counts as contact, so a dashpot's force jump `gamma dxi/dt` at the onset of
    /// an impact that starts touching is seen by the first force evaluation.
    /// `b.x` must already be the periodic image nearest to `a.x`.
    #[inline]
    pub fn pair(a: Sphere, b: Sphere) -> Option<Self> {
        let d = a.x - b.x;
        let dist2 = d.norm_squared();
        let sum = a.r + b.r;
        if dist2 > sum * sum || dist2 == 0.0 {
            return None;
        }
        let g = LaneGeometry::<V3<f64>, f64>::pair(d.into(), dist2, (a.v.into(), b.v.into()), (a.w.into(), b.w.into()), (a.r, b.r));
        Some(Self::from_lane(g))
    }

    /// Geometry of a sphere against a flat wall with unit normal `normal` (pointing into the
    /// domain) through `origin`, moving with `v_wall`; `None` when apart (touching counts).
    #[inline]
    pub fn wall(xi: Vec3, vi: Vec3, wi: Vec3, ri: f64, origin: Vec3, normal: Vec3, v_wall: Vec3) -> Option<Self> {
        let overlap = ri - (xi - origin).dot(&normal);
        if overlap < 0.0 {
            return None;
        }
        let arm_i = ri - 0.5 * overlap;
        Some(Self::from_parts(
            normal,
            overlap,
            vi - v_wall,
            arm_i * wi,
            wi,
            (arm_i, f64::INFINITY),
            ri,
        ))
    }

    /// `arms`: the lever arms `(a_i, a_j)` of the contact point.
    #[inline]
    fn from_parts(n: Vec3, overlap: f64, v_rel: Vec3, spin_sum: Vec3, omega_rel: Vec3, arms: (f64, f64), r_eff: f64) -> Self {
        let (arm_i, arm_j) = arms;
        let v_t = tangential_velocity(n, v_rel, spin_sum);
        Self {
            n,
            overlap,
            overlap_rate: -v_rel.dot(&n),
            v_t,
            omega_rel,
            arm_i,
            arm_j,
            r_eff,
            mobility: 0.0,
        }
    }
}

/// A contact normal over lanes `L`: a unit vector, or a coordinate axis with a sign whose
/// products the compiler can collapse. The force kernels are generic over it, so an
/// axis-aligned wall runs the very same kernels with fewer operations; results are equal up
/// to the sign of zero components.
pub trait Normal<L: Lane = f64>: Copy + std::fmt::Debug + PartialEq {
    /// `s n`.
    fn scaled(&self, s: L) -> V3<L>;
    /// `n . v`.
    fn dot(&self, v: V3<L>) -> L;
    /// `n x v`.
    fn cross(&self, v: V3<L>) -> V3<L>;
    /// `|v x n|^2`.
    fn cross_norm_squared(&self, v: V3<L>) -> L;
    /// `v` without its part along the normal, `v - (n . v) n`. For an axis normal the
    /// component is set to zero (equal up to its sign), so the compiler knows it is zero in
    /// what follows.
    fn in_plane(&self, v: V3<L>) -> V3<L>;
}

impl Normal for Vec3 {
    #[inline(always)]
    fn scaled(&self, s: f64) -> V3<f64> {
        V3::from(*self).scale(s)
    }
    #[inline(always)]
    fn dot(&self, v: V3<f64>) -> f64 {
        V3::from(*self).dot(v)
    }
    #[inline(always)]
    fn cross(&self, v: V3<f64>) -> V3<f64> {
        V3::from(*self).cross(v)
    }
    #[inline(always)]
    fn cross_norm_squared(&self, v: V3<f64>) -> f64 {
        v.cross(V3::from(*self)).norm_squared()
    }
    #[inline(always)]
    fn in_plane(&self, v: V3<f64>) -> V3<f64> {
        let n = V3::from(*self);
        v - n.scale(n.dot(v))
    }
}

/// The normal `sign * e_AXIS` (`AXIS` 0, 1, 2 for x, y, z; `sign` +1 or -1) of an
/// axis-aligned wall such as the tray's floor and side walls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisNormal<const AXIS: usize> {
    pub sign: f64,
}

impl<const AXIS: usize> AxisNormal<AXIS> {
    /// The normal as a vector.
    pub fn vector(&self) -> Vec3 {
        let mut v = Vec3::zeros();
        v[AXIS] = self.sign;
        v
    }
}

/// A normal vector in lanes (particle pairs, several side by side).
impl<L: Lane> Normal<L> for V3<L> {
    #[inline(always)]
    fn scaled(&self, s: L) -> V3<L> {
        self.scale(s)
    }
    #[inline(always)]
    fn dot(&self, v: V3<L>) -> L {
        V3::dot(*self, v)
    }
    #[inline(always)]
    fn cross(&self, v: V3<L>) -> V3<L> {
        V3::cross(*self, v)
    }
    #[inline(always)]
    fn cross_norm_squared(&self, v: V3<L>) -> L {
        v.cross(*self).norm_squared()
    }
    #[inline(always)]
    fn in_plane(&self, v: V3<L>) -> V3<L> {
        v - self.scale(V3::dot(*self, v))
    }
}

impl<L: Lane, const AXIS: usize> Normal<L> for AxisNormal<AXIS> {
    #[inline(always)]
    fn scaled(&self, s: L) -> V3<L> {
        let mut v = V3::zeros();
        v.set(AXIS, L::splat(self.sign) * s);
        v
    }
    #[inline(always)]
    fn dot(&self, v: V3<L>) -> L {
        L::splat(self.sign) * v.get(AXIS)
    }
    #[inline(always)]
    fn cross(&self, v: V3<L>) -> V3<L> {
        // e_x x v = (0, -v_z, v_y), e_y x v = (v_z, 0, -v_x), e_z x v = (-v_y, v_x, 0)
        let z = L::splat(0.0);
        let c = match AXIS {
            0 => V3::new(z, -v.z, v.y),
            1 => V3::new(v.z, z, -v.x),
            _ => V3::new(-v.y, v.x, z),
        };
        c.scale(L::splat(self.sign))
    }
    #[inline(always)]
    fn cross_norm_squared(&self, v: V3<L>) -> L {
        let (a, b) = (v.get((AXIS + 1) % 3), v.get((AXIS + 2) % 3));
        a * a + b * b
    }
    #[inline(always)]
    fn in_plane(&self, v: V3<L>) -> V3<L> {
        let mut w = v;
        w.set(AXIS, L::splat(0.0));
        w
    }
}

/// [`ContactGeometry`] over lanes: what the force kernels read. The scalar geometry converts
/// to it at no cost ([`ContactGeometry::lanes`]); the floor pass builds it for four grains at
/// a time ([`LaneGeometry::axis_wall`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneGeometry<N, L> {
    pub n: N,
    pub overlap: L,
    pub overlap_rate: L,
    pub v_t: V3<L>,
    pub omega_rel: V3<L>,
    pub arm_i: L,
    pub arm_j: L,
    pub r_eff: L,
    pub mobility: L,
}

impl<N> ContactGeometry<N> {
    /// The contact of a one-lane geometry, its normal taken as an `N`.
    #[inline(always)]
    fn from_lane<M: Into<N>>(g: LaneGeometry<M, f64>) -> Self {
        Self {
            n: g.n.into(),
            overlap: g.overlap,
            overlap_rate: g.overlap_rate,
            v_t: g.v_t.into(),
            omega_rel: g.omega_rel.into(),
            arm_i: g.arm_i,
            arm_j: g.arm_j,
            r_eff: g.r_eff,
            mobility: g.mobility,
        }
    }
}

impl<N> ContactGeometry<N> {
    /// The same contact with the tangential mobility `mobility` (1/kg, see the fields).
    #[inline(always)]
    pub fn with_mobility(self, mobility: f64) -> Self {
        Self { mobility, ..self }
    }
}

impl<N, L> LaneGeometry<N, L> {
    /// The same contacts with the tangential mobilities `mobility` (1/kg, see
    /// [`ContactGeometry`]).
    #[inline(always)]
    pub fn with_mobility(self, mobility: L) -> Self {
        Self { mobility, ..self }
    }
}

impl<N: Normal> ContactGeometry<N> {
    /// The same geometry as one lane.
    #[inline(always)]
    pub fn lanes(&self) -> LaneGeometry<N, f64> {
        LaneGeometry {
            n: self.n,
            overlap: self.overlap,
            overlap_rate: self.overlap_rate,
            v_t: self.v_t.into(),
            omega_rel: self.omega_rel.into(),
            arm_i: self.arm_i,
            arm_j: self.arm_j,
            r_eff: self.r_eff,
            mobility: self.mobility,
        }
    }
}

impl<L: Lane> LaneGeometry<V3<L>, L> {
    /// The geometry of [`ContactGeometry::pair`] without its contact test, from the
    /// separation `d = x_i - x_j` (nearest image) and its square `dist2`, the velocities
    /// `(v_i, v_j)`, spins `(w_i, w_j)` and radii `(R_i, R_j)`. Lanes whose spheres are apart
    /// have a negative `overlap` and meaningless values elsewhere.
    #[inline(always)]
    pub fn pair(d: V3<L>, dist2: L, (vi, vj): (V3<L>, V3<L>), (wi, wj): (V3<L>, V3<L>), (ri, rj): (L, L)) -> Self {
        let sum = ri + rj;
        let dist = dist2.sqrt();
        let n = V3::new(d.x / dist, d.y / dist, d.z / dist);
        let overlap = sum - dist;
        let arm_i = ri - L::splat(0.5) * overlap;
        let arm_j = rj - L::splat(0.5) * overlap;
        let v_rel = vi - vj;
        let spin_sum = wi.scale(arm_i) + wj.scale(arm_j);
        // eq 3.11: v_c = v_rel - spin_sum x n, without its normal part.
        let v_c = v_rel - spin_sum.cross(n);
        Self {
            n,
            overlap,
            overlap_rate: -v_rel.dot(n),
            v_t: v_c - n.scale(v_c.dot(n)),
            omega_rel: wi - wj,
            arm_i,
            arm_j,
            r_eff: ri * rj / sum,
            mobility: L::splat(0.0),
        }
    }
}

impl<L: Lane, const AXIS: usize> LaneGeometry<AxisNormal<AXIS>, L> {
    /// The geometry of [`ContactGeometry::axis_wall`] without its gap test: for grains with
    /// centre coordinate `x_axis` along the wall's axis, velocities `vi`, spins `wi` and radii
    /// `ri`, against the wall through `origin_axis` with normal `sign * e_AXIS` moving with
    /// `v_wall`. Lanes whose grains are apart have a negative `overlap` and meaningless
    /// values elsewhere.
    #[inline(always)]
    pub fn axis_wall(x_axis: L, vi: V3<L>, wi: V3<L>, ri: L, origin_axis: f64, sign: f64, v_wall: Vec3) -> Self {
        let overlap = ri - L::splat(sign) * (x_axis - L::splat(origin_axis));
        let arm_i = ri - L::splat(0.5) * overlap;
        let v_rel = vi - V3::splat(v_wall);
        let s = wi.scale(arm_i);
        // s x e_AXIS
        let z = L::splat(0.0);
        let s_x_e = match AXIS {
            0 => V3::new(z, s.z, -s.y),
            1 => V3::new(-s.z, z, s.x),
            _ => V3::new(s.y, -s.x, z),
        };
        let mut v_t = v_rel - s_x_e.scale(L::splat(sign));
        v_t.set(AXIS, z);
        Self {
            n: AxisNormal { sign },
            overlap,
            overlap_rate: L::splat(-sign) * v_rel.get(AXIS),
            v_t,
            omega_rel: wi,
            arm_i,
            arm_j: L::splat(f64::INFINITY),
            r_eff: ri,
            mobility: L::splat(0.0),
        }
    }
}

impl<const AXIS: usize> ContactGeometry<AxisNormal<AXIS>> {
    /// [`ContactGeometry::wall`] for a wall whose normal is `sign * e_AXIS` (`AXIS` 0, 1, 2 for x, y, z;
    /// `sign` is +1 or -1), such as the tray's floor and side walls. The same geometry with
    /// the dot and cross products against the normal written out: it equals [`Self::wall`]
    /// bit for bit, up to the sign of components that are zero.
    #[inline(always)]
    pub fn axis_wall(xi: Vec3, vi: Vec3, wi: Vec3, ri: f64, origin: Vec3, sign: f64, v_wall: Vec3) -> Option<Self> {
        let g = LaneGeometry::<AxisNormal<AXIS>, f64>::axis_wall(xi[AXIS], vi.into(), wi.into(), ri, origin[AXIS], sign, v_wall);
        if g.overlap < 0.0 {
            return None;
        }
        Some(Self::from_lane(g))
    }
}

impl ContactGeometry<AxisNormal<2>> {
    /// [`ContactGeometry::axis_wall`] for a grain resting on a floor through `z = 0` with its
    /// centre at `z = R` and no vertical velocity (a pinned layer, eq 3.28): zero overlap,
    /// lever arm `R`. Equal to `axis_wall` for such a grain, without the gap test.
    #[inline(always)]
    pub fn resting_on_floor(vi: Vec3, wi: Vec3, ri: f64, v_wall: Vec3) -> Self {
        let v_rel = vi - v_wall;
        let s = ri * wi;
        let mut v_t = v_rel - Vec3::new(s.y, -s.x, 0.0);
        v_t.z = 0.0;
        Self {
            n: AxisNormal { sign: 1.0 },
            overlap: 0.0,
            overlap_rate: -v_rel.z,
            v_t,
            omega_rel: wi,
            arm_i: ri,
            arm_j: f64::INFINITY,
            r_eff: ri,
            mobility: 0.0,
        }
    }
}

/// Tangential part of the contact-point velocity of i relative to j (eq 3.11):
/// `v_c = v_rel - spin_sum x n`, `v_t = v_c - (v_c . n) n`, where `v_rel = v_i - v_j` and
/// `spin_sum = a_i omega_i + a_j omega_j` (lever arms times spins; a wall contributes 0).
#[inline]
pub fn tangential_velocity(n: Vec3, v_rel: Vec3, spin_sum: Vec3) -> Vec3 {
    let v_c = v_rel - spin_sum.cross(&n);
    v_c - n * v_c.dot(&n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rolling_without_slip_has_zero_tangential_velocity() {
        // Sphere of radius R rolling along +x on a floor: v = omega x (-a n) => omega_y = v / a.
        let r = 1e-3;
        let xi = Vec3::new(0.0, 0.0, r - 1e-6);
        let g0 = ContactGeometry::wall(xi, Vec3::zeros(), Vec3::zeros(), r, Vec3::zeros(), Vec3::z(), Vec3::zeros()).unwrap();
        let v = 0.1;
        let w = Vec3::new(0.0, v / g0.arm_i, 0.0);
        let g = ContactGeometry::wall(xi, Vec3::new(v, 0.0, 0.0), w, r, Vec3::zeros(), Vec3::z(), Vec3::zeros()).unwrap();
        assert!(g.v_t.norm() < 1e-15, "{}", g.v_t);
        assert!((g.overlap - 1e-6).abs() < 1e-18);
    }

    fn widen<const A: usize>(g: ContactGeometry<AxisNormal<A>>) -> ContactGeometry {
        ContactGeometry {
            n: g.n.vector(),
            overlap: g.overlap,
            overlap_rate: g.overlap_rate,
            v_t: g.v_t,
            omega_rel: g.omega_rel,
            arm_i: g.arm_i,
            arm_j: g.arm_j,
            r_eff: g.r_eff,
            mobility: g.mobility,
        }
    }

    #[test]
    fn axis_normals_match_vectors() {
        /// Every product of the normal `n` with `v` (and with 2.5).
        fn products<const A: usize>(n: AxisNormal<A>, v: &Vec3) -> (Vec3, Vec3, f64, Vec3, f64, Vec3) {
            (
                n.vector(),
                Normal::<f64>::scaled(&n, 2.5).into(),
                Normal::<f64>::dot(&n, (*v).into()),
                Normal::<f64>::cross(&n, (*v).into()).into(),
                Normal::<f64>::cross_norm_squared(&n, (*v).into()),
                Normal::<f64>::in_plane(&n, (*v).into()).into(),
            )
        }
        let v = Vec3::new(0.3, -1.7, 2.9);
        for sign in [1.0, -1.0] {
            for (vector, scaled, dot, cross, cn2, in_plane) in [
                products(AxisNormal::<0> { sign }, &v),
                products(AxisNormal::<1> { sign }, &v),
                products(AxisNormal::<2> { sign }, &v),
            ] {
                let v3 = V3::from(v);
                assert_eq!(scaled, vector * 2.5);
                assert_eq!(dot, Normal::dot(&vector, v3));
                assert_eq!(cross, Vec3::from(Normal::cross(&vector, v3)));
                assert!((cn2 - v.cross(&vector).norm_squared()).abs() < 1e-15);
                assert_eq!(in_plane, Vec3::from(Normal::in_plane(&vector, v3)));
            }
        }
    }

    #[test]
    fn axis_walls_equal_the_general_wall() {
        let (r, o) = (4e-4, Vec3::new(0.013, 0.02, 0.0));
        let v = Vec3::new(0.3, -0.2, 0.05);
        let w = Vec3::new(40.0, -25.0, 12.0);
        let vw = Vec3::new(1.7, 0.0, 0.0);
        for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let mut normal = Vec3::zeros();
            normal[axis] = sign;
            for depth in [-1e-6, 0.0, 2e-6] {
                let x = o + normal * (r - depth) + Vec3::new(1e-4, 2e-4, 3e-4) - normal * normal.dot(&Vec3::new(1e-4, 2e-4, 3e-4));
                let general = ContactGeometry::wall(x, v, w, r, o, normal, vw);
                let special = match axis {
                    0 => ContactGeometry::<AxisNormal<0>>::axis_wall(x, v, w, r, o, sign, vw).map(widen),
                    1 => ContactGeometry::<AxisNormal<1>>::axis_wall(x, v, w, r, o, sign, vw).map(widen),
                    _ => ContactGeometry::<AxisNormal<2>>::axis_wall(x, v, w, r, o, sign, vw).map(widen),
                };
                assert_eq!(general.is_some(), special.is_some(), "axis {axis} sign {sign} depth {depth}");
                if let (Some(g), Some(s)) = (general, special) {
                    // `==` treats -0 and +0 as equal, exactly the freedom the fast path takes.
                    assert!(g == s, "axis {axis} sign {sign}: {g:?} != {s:?}");
                }
            }
        }
    }

    #[test]
    fn resting_on_floor_equals_axis_wall() {
        let (r, v, w) = (4e-4, Vec3::new(0.3, -0.2, 0.0), Vec3::new(40.0, -25.0, 12.0));
        let (o, vw) = (Vec3::new(0.013, 0.0, 0.0), Vec3::new(1.7, 0.0, 0.0));
        let x = Vec3::new(0.1, 0.01, r);
        let g = ContactGeometry::<AxisNormal<2>>::axis_wall(x, v, w, r, o, 1.0, vw).unwrap();
        let f = ContactGeometry::resting_on_floor(v, w, r, vw);
        assert!(g == f, "{g:?} != {f:?}");
        assert_eq!((f.overlap, f.arm_i), (0.0, r));
    }

    #[test]
    fn pair_normal_points_from_j_to_i() {
        let z = Vec3::zeros();
        let a = Sphere {
            x: Vec3::new(1.5e-3, 0.0, 0.0),
            v: Vec3::new(-1.0, 0.0, 0.0),
            w: z,
            r: 1e-3,
        };
        let g = ContactGeometry::pair(a, Sphere { x: z, v: z, w: z, r: 1e-3 }).unwrap();
        assert_eq!(g.n, Vec3::x());
        assert!((g.overlap - 0.5e-3).abs() < 1e-15);
        assert_eq!(g.overlap_rate, 1.0); // approaching: overlap grows
        assert!((g.arm_i + g.arm_j - 1.5e-3).abs() < 1e-18);
    }

    #[test]
    fn separated_and_coincident_pairs_have_no_contact() {
        let z = Vec3::zeros();
        let at = |x: f64| Sphere {
            x: Vec3::new(x, 0.0, 0.0),
            v: z,
            w: z,
            r: 1.0,
        };
        assert!(ContactGeometry::pair(at(2.0 + 1e-12), at(0.0)).is_none());
        assert!(ContactGeometry::pair(at(2.0), at(0.0)).is_some());
        assert!(ContactGeometry::pair(at(0.0), at(0.0)).is_none());
    }
}
