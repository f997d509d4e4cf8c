//! Free flight under gravity and the exact contact time of two flying disks.
//!
//! Between events a particle moves on a parabola, `r(t) = r0 + v0 s + 1/2 g s^2` with
//! `s = t - t0` and `g = (0, -g)`; its spin is constant. Two particles feel the same gravity,
//! so their separation moves on a straight line, `d(s) = d0 + u s`, and they touch when
//! `|d(s)| = R1 + R2`: the smaller root of `|u|^2 s^2 + 2 (d0 . u) s + |d0|^2 - sigma^2 = 0`,
//! written as `c / (-b + sqrt(b^2 - a c))` to keep its digits when the pair is close.
//!
//! Stability (Bannerman, Lue, Woodcock): a pair that round-off has left slightly inside
//! contact (`c <= 0`) collides at once if it approaches (`b < 0`), and never if it separates.
//! A pair is tested for its approach, not only for its overlap.

use crate::Vec2;

/// Position and velocity after `s` seconds of flight from `(r, v)` under `gravity` (m/s^2,
/// positive downwards).
#[inline]
pub fn fly(r: Vec2, v: Vec2, gravity: f64, s: f64) -> (Vec2, Vec2) {
    (
        Vec2::new(r.x + v.x * s, r.y + v.y * s - 0.5 * gravity * s * s),
        Vec2::new(v.x, v.y - gravity * s),
    )
}

/// The time from now at which two flying particles with separation `d = r1 - r2` and
/// relative velocity `u = v1 - v2` reach distance `sigma`, or `None` if they do not meet.
/// `Some(0.0)` when they touch or overlap (by round-off) and approach.
#[inline]
pub fn pair_time(d: Vec2, u: Vec2, sigma: f64) -> Option<f64> {
    let b = d.dot(&u);
    if b >= 0.0 {
        return None;
    }
    let c = d.norm_squared() - sigma * sigma;
    if c <= 0.0 {
        return Some(0.0);
    }
    let a = u.norm_squared();
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    Some(c / (-b + disc.sqrt()))
}

/// The first time `s > 0` at which `z0 + vz s - 1/2 g s^2` (g >= 0) reaches `level`, or `None`.
/// `upward`: the crossing from below (else from above).
pub fn height_time(z0: f64, vz: f64, gravity: f64, level: f64, upward: bool) -> Option<f64> {
    // z0 + vz s - 1/2 g s^2 = level: the roots are (vz -+ sqrt(vz^2 + 2 g c)) / g with
    // c = z0 - level; the earlier one is the way up through the level, the later one the way
    // down, each written where it keeps its digits.
    let c = z0 - level;
    if gravity == 0.0 {
        return match upward {
            true if vz > 0.0 && c < 0.0 => Some(-c / vz),
            false if vz < 0.0 && c > 0.0 => Some(c / -vz),
            _ => None,
        };
    }
    // Only from below (c < 0) while rising on the way up; from above (c > 0) while falling,
    // or after the apex, on the way down. Checked before the square root.
    if (upward && !(c < 0.0 && vz > 0.0)) || (!upward && vz < 0.0 && c <= 0.0) {
        return None;
    }
    let disc = vz * vz + 2.0 * gravity * c;
    if disc <= 0.0 {
        // Never reached, or only touched at the apex.
        return None;
    }
    let sq = disc.sqrt();
    if upward {
        Some(-2.0 * c / (vz + sq))
    } else if vz >= 0.0 {
        let s = (vz + sq) / gravity;
        (s > 0.0).then_some(s)
    } else {
        Some(2.0 * c / (sq - vz))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn the_pair_time_puts_the_pair_exactly_at_contact_and_never_inside(
            dx in -5.0f64..5.0, dz in -5.0f64..5.0, ux in -3.0f64..3.0, uz in -3.0f64..3.0, sigma in 0.1f64..1.0,
        ) {
            let d = Vec2::new(dx, dz);
            let u = Vec2::new(ux, uz);
            prop_assume!(d.norm() > sigma * 1.001);
            match pair_time(d, u, sigma) {
                Some(s) => {
                    let at = d + u * s;
                    prop_assert!((at.norm() - sigma).abs() <= 1e-12 * (1.0 + d.norm()));
                    // Before it, never closer than sigma: sample the way there.
                    for k in 0..50 {
                        let x = d + u * (s * k as f64 / 50.0);
                        prop_assert!(x.norm() >= sigma * (1.0 - 1e-12));
                    }
                    prop_assert!(at.dot(&u) <= 0.0, "approaching at contact");
                }
                None => {
                    // The closest approach stays outside.
                    let s = (-(d.dot(&u)) / u.norm_squared().max(1e-300)).max(0.0);
                    prop_assert!((d + u * s).norm() >= sigma * (1.0 - 1e-12));
                }
            }
        }
    }

    #[test]
    fn a_pair_inside_by_round_off_collides_now_if_it_approaches_and_never_if_it_separates() {
        let d = Vec2::new(1.0 - 1e-15, 0.0);
        assert_eq!(pair_time(d, Vec2::new(-1.0, 0.0), 1.0), Some(0.0));
        assert_eq!(pair_time(d, Vec2::new(1.0, 0.0), 1.0), None);
    }

    #[test]
    fn free_fall_matches_the_parabola_and_height_times_are_exact() {
        let (r, v) = fly(Vec2::new(0.1, 2.0), Vec2::new(0.3, 4.0), 10.0, 0.5);
        assert!((r.x - 0.25).abs() < 1e-15 && (r.y - (2.0 + 2.0 - 1.25)).abs() < 1e-14);
        assert!((v.y - -1.0).abs() < 1e-15);
        // Thrown up at 4 m/s from 2 m: reaches 2.5 m going up at s = (4 - sqrt(6)) / 10.
        let s = height_time(2.0, 4.0, 10.0, 2.5, true).unwrap();
        assert!((s - (4.0 - 6f64.sqrt()) / 10.0).abs() < 1e-14);
        let s = height_time(2.0, 4.0, 10.0, 2.5, false).unwrap();
        assert!((s - (4.0 + 6f64.sqrt()) / 10.0).abs() < 1e-14);
        // The top is at 2.8 m: 3 m is never reached.
        assert_eq!(height_time(2.0, 4.0, 10.0, 3.0, true), None);
        assert!((height_time(2.0, 0.0, 10.0, 0.0, false).unwrap() - (0.4f64).sqrt()).abs() < 1e-14);
        assert_eq!(height_time(1.0, 2.0, 0.0, 3.0, true), Some(1.0));
    }
}
