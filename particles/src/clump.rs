//! Grains with flat sides: rigid clumps of two or three equal overlapping spheres (issue 39,
//! step 3), as LIGGGHTS' multisphere and DEM-Engine's clumps build them. This module holds
//! the shape: where the spheres sit in the body frame, and the mass and principal moments of
//! inertia of their union. The bodies' motion is [`crate::rigid`]'s.
//!
//! - **Dimer** (2 spheres): centres at `(+-d/2, 0, 0)`. A dimer lying on the floor rests on
//!   two points; across its axis it can only tip over one sphere, lifting its centre of mass,
//!   which needs a horizontal acceleration above `g d / (2 R)`; along its axis, though, it
//!   rolls as a cylinder does.
//! - **Trimer** (3 spheres): centres at the corners of an equilateral triangle of side `d` in
//!   the body's x-y plane, sphere 0 on the +y axis. Chosen over three spheres in a line
//!   because a triangle lying flat stands on three points and cannot roll in any direction
//!   without lifting its centre of mass (the seed's flat side of thesis 2.2.6 in every
//!   direction), where a line of spheres, like a dimer, rolls freely about its own axis.
//!
//! Both are planar and symmetric, so the centre of mass of the union is the mean of the
//! sphere centres (each member carries `1/n` of the body's mass for gravity, and the
//! members' mass-weighted positions and velocities are the body's), and the body axes are
//! principal axes.
//!
//! Mass and inertia of the union (overlaps counted once), in units of `rho R^3` and
//! `rho R^5`: the dimer's exactly, by slices across its axis (each half a sphere cut by the
//! mid-plane: polynomial integrals); the trimer's by a midpoint rule over the top view of the
//! exact column heights `max_k sqrt(R^2 - |p - c_k|^2)` (the union of spheres centred in one
//! plane covers, above each point of that plane, an interval symmetric about it), on
//! [`QUADRATURE_CELLS`]^2 cells. The same rule on the dimer misses the exact values by less
//! than 2e-5 relative (`the_quadrature_matches_the_dimer_s_closed_form`).

use crate::Vec3;

/// Cells per side of the midpoint rule of [`ClumpShape::mass_and_inertia`] for the trimer.
pub const QUADRATURE_CELLS: usize = 1200;

/// The most members a clump has (a triangle); the integrator keeps a body's member arms in
/// an array of this length.
pub const MAX_SPHERES: usize = 3;

/// The shape of a clump: `spheres` equal spheres of radius `R` whose neighbouring centres are
/// `spacing R` apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClumpShape {
    /// 2 (dimer) or 3 (trimer, a triangle).
    pub spheres: usize,
    /// Distance between neighbouring sphere centres over the radius, in (0, 2): below 2 the
    /// spheres overlap, so the clump is one body with a waist (and, lying down, flat sides).
    pub spacing: f64,
}

/// Why a clump shape is refused: the key and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeError {
    pub key: &'static str,
    pub message: String,
}

impl ClumpShape {
    /// A checked shape: `spheres` 2 or 3 (at most [`MAX_SPHERES`]), `spacing` in (0, 2).
    pub fn new(spheres: usize, spacing: f64) -> Result<Self, ShapeError> {
        if !(2..=MAX_SPHERES).contains(&spheres) {
            return Err(ShapeError {
                key: "particles.clump_spheres",
                message: format!("must be 2 (a dimer) or 3 (a triangle), got {spheres}"),
            });
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(ShapeError {
                key: "particles.clump_spacing",
                message: format!(
                    "must be a positive distance between sphere centres in radii, below 2 (spheres that overlap), got {spacing}"
                ),
            });
        }
        if spacing >= 2.0 {
            return Err(ShapeError {
                key: "particles.clump_spacing",
                message: format!(
                    "{spacing} radii between centres: the clump's spheres do not overlap (they must, to be one grain \
                     with flat sides): give a value below 2"
                ),
            });
        }
        Ok(Self { spheres, spacing })
    }

    /// The sphere centres in the body frame, in units of `R`, about the centre of mass.
    pub fn offsets(&self) -> Vec<Vec3> {
        let d = self.spacing;
        match self.spheres {
            2 => vec![Vec3::new(0.5 * d, 0.0, 0.0), Vec3::new(-0.5 * d, 0.0, 0.0)],
            _ => {
                let c = d / 3f64.sqrt();
                [90f64, 210.0, 330.0]
                    .iter()
                    .map(|a| Vec3::new(c * a.to_radians().cos(), c * a.to_radians().sin(), 0.0))
                    .collect()
            }
        }
    }

    /// Radius of the smallest circle about the centre of mass that holds the clump lying
    /// flat, in units of `R`: `1 + d/2` (dimer), `1 + d / sqrt(3)` (trimer).
    pub fn reach(&self) -> f64 {
        1.0 + self.offsets()[0].norm()
    }

    /// Mass `M / (rho R^3)` and principal moments `I / (rho R^5)` about the body axes.
    pub fn mass_and_inertia(&self) -> (f64, Vec3) {
        match self.spheres {
            2 => dimer_exact(0.5 * self.spacing),
            _ => planar_quadrature(&self.offsets(), QUADRATURE_CELLS),
        }
    }

    /// Area of the clump's top view lying flat (the union of its discs), in units of `R^2`,
    /// by the same midpoint rule (for the packing fraction: good to 1e-4 relative).
    pub fn projected_area(&self) -> f64 {
        let centres = self.offsets();
        let reach = self.reach();
        let n = 400;
        let h = 2.0 * reach / n as f64;
        let mut inside = 0usize;
        for a in 0..n {
            for b in 0..n {
                let p = Vec3::new(-reach + (a as f64 + 0.5) * h, -reach + (b as f64 + 0.5) * h, 0.0);
                if centres.iter().any(|c| (p - c).norm_squared() < 1.0) {
                    inside += 1;
                }
            }
        }
        inside as f64 * h * h
    }
}

/// The dimer of unit spheres at `(+-a, 0, 0)`, exactly: each half is a sphere cut at the
/// mid-plane `u = -a` (u along the axis from its own centre), integrated in discs of radius
/// `sqrt(1 - u^2)` over `u` in `[-a, 1]`:
/// `V/2 = pi int (1 - u^2)`, `I_axis/2 = pi/2 int (1 - u^2)^2`,
/// `I_perp/2 = pi int (1 - u^2) ((a + u)^2 + (1 - u^2)/4)`.
fn dimer_exact(a: f64) -> (f64, Vec3) {
    use std::f64::consts::PI;
    // Antiderivatives, evaluated from -a to 1.
    let vol = |u: f64| u - u.powi(3) / 3.0;
    let axis = |u: f64| u - 2.0 * u.powi(3) / 3.0 + u.powi(5) / 5.0;
    // (1 - u^2)(a + u)^2 = a^2 + 2 a u + (1 - a^2) u^2 - 2 a u^3 - u^4.
    let perp = |u: f64| a * a * u + a * u * u + (1.0 - a * a) * u.powi(3) / 3.0 - 0.5 * a * u.powi(4) - u.powi(5) / 5.0 + 0.25 * axis(u);
    let span = |f: &dyn Fn(f64) -> f64| f(1.0) - f(-a);
    let mass = 2.0 * PI * span(&vol);
    let i_axis = PI * span(&axis);
    let i_perp = 2.0 * PI * span(&perp);
    (mass, Vec3::new(i_axis, i_perp, i_perp))
}

/// Mass and moments about the coordinate axes of the union of unit spheres centred at
/// `centres` (all with z = 0, centre of mass at the origin), by the midpoint rule on
/// `cells`^2 cells of the top view: over a point p of the plane the union covers
/// `|z| <= s(p) = max_k sqrt(1 - |p - c_k|^2)`, so `dm = 2 s`, `int z^2 dm = 2 s^3 / 3`.
fn planar_quadrature(centres: &[Vec3], cells: usize) -> (f64, Vec3) {
    let reach = 1.0 + centres.iter().map(|c| c.norm()).fold(0.0, f64::max);
    let h = 2.0 * reach / cells as f64;
    let (mut m, mut xx, mut yy, mut zz) = (0.0, 0.0, 0.0, 0.0);
    for a in 0..cells {
        let x = -reach + (a as f64 + 0.5) * h;
        for b in 0..cells {
            let y = -reach + (b as f64 + 0.5) * h;
            let s2 = centres
                .iter()
                .map(|c| 1.0 - (x - c.x).powi(2) - (y - c.y).powi(2))
                .fold(0.0, f64::max);
            if s2 <= 0.0 {
                continue;
            }
            let s = s2.sqrt();
            let (dm, z2) = (2.0 * s, 2.0 * s * s2 / 3.0);
            m += dm;
            xx += dm * x * x;
            yy += dm * y * y;
            zz += z2;
        }
    }
    let area = h * h;
    (m * area, Vec3::new(yy + zz, xx + zz, xx + yy) * area)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn touching_spheres_give_two_spheres_and_the_parallel_axis_theorem() {
        // a = 1: two whole unit spheres, 4 pi / 3 each, I = 2/5 m about their own axes.
        let (m, i) = dimer_exact(1.0);
        let sphere = 4.0 * PI / 3.0;
        assert!((m - 2.0 * sphere).abs() < 1e-13);
        assert!((i.x - 2.0 * 0.4 * sphere).abs() < 1e-13);
        assert!((i.y - 2.0 * (0.4 * sphere + sphere)).abs() < 1e-13);
        // a = 0: one sphere.
        let (m, i) = dimer_exact(0.0);
        assert!((m - sphere).abs() < 1e-13 && (i.x - 0.4 * sphere).abs() < 1e-13 && (i.y - i.x).abs() < 1e-13);
    }

    #[test]
    fn the_dimer_s_mass_is_two_spheres_less_their_lens() {
        // Lens of two unit spheres at distance d: pi (4 + d) (2 - d)^2 / 12.
        for d in [0.5, 1.0, 1.5] {
            let (m, _) = ClumpShape::new(2, d).unwrap().mass_and_inertia();
            let lens = PI * (4.0 + d) * (2.0 - d).powi(2) / 12.0;
            assert!((m - (8.0 * PI / 3.0 - lens)).abs() < 1e-13, "d = {d}");
        }
    }

    #[test]
    fn the_quadrature_matches_the_dimer_s_closed_form() {
        for d in [0.5, 1.0, 1.5] {
            let shape = ClumpShape::new(2, d).unwrap();
            let (m, i) = dimer_exact(0.5 * d);
            let (mq, iq) = planar_quadrature(&shape.offsets(), QUADRATURE_CELLS);
            assert!(((mq - m) / m).abs() < 2e-5, "d = {d}: {mq} against {m}");
            for k in 0..3 {
                assert!(
                    ((iq[k] - i[k]) / i[k]).abs() < 2e-5,
                    "d = {d}, axis {k}: {} against {}",
                    iq[k],
                    i[k]
                );
            }
        }
    }

    #[test]
    fn the_triangle_is_a_symmetric_top_with_its_centre_at_the_origin() {
        let shape = ClumpShape::new(3, 1.0).unwrap();
        let c: Vec3 = shape.offsets().iter().sum();
        assert!(c.norm() < 1e-15);
        let o = shape.offsets();
        for k in 0..3 {
            assert!(((o[k] - o[(k + 1) % 3]).norm() - 1.0).abs() < 1e-15);
        }
        let (m, i) = shape.mass_and_inertia();
        // Equal by symmetry; the grid is not three-fold symmetric, so within the rule's error.
        assert!(((i.x - i.y) / i.x).abs() < 2e-5, "{i:?}");
        // Between one sphere and three whole ones; I_zz = I_xx + I_yy - 2 int z^2 dm.
        assert!(m > 4.0 * PI / 3.0 && m < 4.0 * PI);
        assert!(i.z > i.x && i.z < i.x + i.y);
    }

    #[test]
    fn spheres_that_do_not_overlap_and_other_counts_are_refused_by_key() {
        assert_eq!(ClumpShape::new(2, 2.0).unwrap_err().key, "particles.clump_spacing");
        assert!(ClumpShape::new(2, 2.0).unwrap_err().message.contains("do not overlap"));
        assert_eq!(ClumpShape::new(3, -0.5).unwrap_err().key, "particles.clump_spacing");
        assert_eq!(ClumpShape::new(2, f64::NAN).unwrap_err().key, "particles.clump_spacing");
        assert_eq!(ClumpShape::new(1, 1.0).unwrap_err().key, "particles.clump_spheres");
        assert_eq!(ClumpShape::new(4, 1.0).unwrap_err().key, "particles.clump_spheres");
    }

    #[test]
    fn the_projected_area_is_the_union_of_the_discs() {
        // Two unit discs at distance d overlap in 2 acos(d/2) - (d/2) sqrt(4 - d^2).
        let d: f64 = 1.0;
        let lens = 2.0 * (d / 2.0).acos() - 0.5 * d * (4.0 - d * d).sqrt();
        let a = ClumpShape::new(2, d).unwrap().projected_area();
        assert!((a - (2.0 * PI - lens)).abs() / a < 1e-3, "{a}");
    }
}
