//! A sawtooth base (the ratchet paper, section III and Fig. 5): teeth of width `w`, height
//! `h` and asymmetry `a = l / w` (`l` the horizontal projection of a tooth's left side),
//! their tops rounded by arcs of radius `s` that join both sides smoothly. Valleys stand at
//! `z = 0` (the floor's mean position) and `x = k w`; the base repeats with period `w` and
//! oscillates vertically with the floor's motion.
//!
//! A tooth is three convex pieces: its left side (a segment), its tip (a disk of radius `s`
//! tangent to both sides) and its right side. The gap of a particle to a piece is its
//! distance to that convex set minus its radius. The distance to a convex set, taken along
//! a flight whose acceleration relative to the base is bounded by `K = g + A (2 pi f)^2`,
//! has a second derivative of at least `-K` (convexity only adds upward curvature), so the
//! same curvature-bound bracketing as for the flat walls ([`crate::wall::first_contact`])
//! finds the first contact with any piece without stepping over it (appendix B.3-B.4 of the
//! paper solve the same problem with its own brackets).

use crate::flight::fly;
use crate::wall::{first_contact, Motion};
use crate::Vec2;

/// The shape of the base's teeth (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sawtooth {
    /// Tooth width `w` (the period along x).
    pub width: f64,
    /// Tooth height `h` above the valleys.
    pub height: f64,
    /// Asymmetry `a = l / w` in `[0, 1]`: where the tip stands within the tooth.
    pub asymmetry: f64,
    /// Radius `s` of the arc that rounds each tip.
    pub tip_radius: f64,
}

/// One convex piece of tooth 0; tooth `k` is shifted by `k w` along x.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    /// A side, from `a` to `b`.
    Segment { a: Vec2, b: Vec2 },
    /// The rounded tip: a disk.
    Tip { centre: Vec2, radius: f64 },
}

impl Piece {
    /// Distance from `p` to the piece, and the unit normal from the piece towards `p`.
    pub fn distance(&self, p: Vec2) -> (f64, Vec2) {
        let (closest, extra) = match *self {
            Piece::Segment { a, b } => {
                let ab = b - a;
                let s = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
                (a + ab * s, 0.0)
            }
            Piece::Tip { centre, radius } => (centre, radius),
        };
        let d = p - closest;
        let norm = d.norm();
        let n = if norm > 0.0 { d / norm } else { Vec2::new(0.0, 1.0) };
        (norm - extra, n)
    }
}

impl Sawtooth {
    /// Checks the shape; the error names the field and why.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        let positive = |name: &'static str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err((name, format!("must be a positive number, got {x}")))
            }
        };
        positive("base.tooth_width", self.width)?;
        positive("base.tooth_height", self.height)?;
        if !(0.0..=1.0).contains(&self.asymmetry) {
            return Err(("base.asymmetry", format!("a = l / w must lie in [0, 1], got {}", self.asymmetry)));
        }
        positive("base.tip_radius", self.tip_radius)?;
        let [left, tip, right] = self.pieces();
        let short = |p: Piece| match p {
            Piece::Segment { a, b } => (b - a).norm() <= 0.0,
            Piece::Tip { .. } => false,
        };
        if short(left) || short(right) || matches!(tip, Piece::Tip { centre, .. } if !centre.y.is_finite()) {
            return Err((
                "base.tip_radius",
                format!(
                    "an arc of radius {} m does not fit on a tooth {} m wide and {} m high with asymmetry {}",
                    self.tip_radius, self.width, self.height, self.asymmetry
                ),
            ));
        }
        Ok(())
    }

    /// The peak (before rounding) of tooth 0.
    fn peak(&self) -> Vec2 {
        Vec2::new(self.asymmetry * self.width, self.height)
    }

    /// The three pieces of tooth 0: its left side, its tip and its right side. The arc of
    /// radius `s` is tangent to both sides: its centre lies on the bisector of the peak's
    /// angle `theta`, `s / sin(theta/2)` below the peak, and it meets each side
    /// `s / tan(theta/2)` from the peak, where the sides end.
    pub fn pieces(&self) -> [Piece; 3] {
        let peak = self.peak();
        let (left_valley, right_valley) = (Vec2::new(0.0, 0.0), Vec2::new(self.width, 0.0));
        let u1 = (left_valley - peak).normalize();
        let u2 = (right_valley - peak).normalize();
        let cos = u1.dot(&u2).clamp(-1.0, 1.0);
        let half = 0.5 * cos.acos();
        let s = self.tip_radius;
        let along = s / half.tan();
        let bisector = (u1 + u2).normalize();
        let centre = peak + bisector * (s / half.sin());
        let (t1, t2) = (peak + u1 * along, peak + u2 * along);
        let fits = |valley: Vec2| along < (valley - peak).norm();
        let nan = Vec2::new(f64::NAN, f64::NAN);
        [
            Piece::Segment {
                a: left_valley,
                b: if fits(left_valley) { t1 } else { left_valley },
            },
            Piece::Tip {
                centre: if fits(left_valley) && fits(right_valley) { centre } else { nan },
                radius: s,
            },
            Piece::Segment {
                a: if fits(right_valley) { t2 } else { right_valley },
                b: right_valley,
            },
        ]
    }

    /// Piece `piece` (0 left side, 1 tip, 2 right side) of tooth `tooth`.
    pub fn piece(&self, tooth: i64, piece: usize) -> Piece {
        let shift = Vec2::new(tooth as f64 * self.width, 0.0);
        match self.pieces()[piece] {
            Piece::Segment { a, b } => Piece::Segment {
                a: a + shift,
                b: b + shift,
            },
            Piece::Tip { centre, radius } => Piece::Tip {
                centre: centre + shift,
                radius,
            },
        }
    }

    /// The teeth whose pieces a particle of radius `radius` may touch while its centre
    /// stays within `[x_lo, x_hi]`.
    pub fn teeth(&self, x_lo: f64, x_hi: f64, radius: f64) -> std::ops::RangeInclusive<i64> {
        let lo = ((x_lo - radius) / self.width).floor() as i64;
        let hi = ((x_hi + radius) / self.width).floor() as i64;
        lo..=hi
    }

    /// Gap (m) and its rate (m/s) between a piece moving with `motion` and a particle at
    /// `(r, v)` of radius `radius` at time `t`, with the normal from the piece.
    pub fn gap(piece: &Piece, motion: &Motion, r: Vec2, v: Vec2, radius: f64, t: f64) -> (f64, f64, Vec2) {
        let lift = Vec2::new(0.0, motion.displacement(t));
        let (d, n) = piece.distance(r - lift);
        let rate = (v - Vec2::new(0.0, motion.velocity(t))).dot(&n);
        (d - radius, rate, n)
    }

    /// The first time `t >= t0` within `horizon` at which a particle at `(r, v)` at `t0`
    /// meets `piece` while approaching it, or `None`.
    #[allow(clippy::too_many_arguments)]
    pub fn contact_time(piece: &Piece, motion: &Motion, r: Vec2, v: Vec2, radius: f64, gravity: f64, t0: f64, horizon: f64) -> Option<f64> {
        let at = |t: f64| {
            let (rr, vv) = fly(r, v, gravity, t - t0);
            let (h, rate, _) = Self::gap(piece, motion, rr, vv, radius, t);
            (h, rate)
        };
        first_contact(at, gravity + motion.max_acceleration(), t0, t0 + horizon)
    }

    /// Whether a particle at `(r, v)` stays above every tooth's highest reach (`h + A`) for
    /// the next `span` seconds: a check without the base's phase.
    pub fn clear_of(&self, motion: &Motion, r: Vec2, v: Vec2, radius: f64, gravity: f64, span: f64) -> bool {
        if !span.is_finite() {
            return false;
        }
        let z_end = r.y + v.y * span - 0.5 * gravity * span * span;
        r.y.min(z_end) - radius > self.height + motion.amplitude.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tooth() -> Sawtooth {
        Sawtooth {
            width: 6e-3,
            height: 3e-3,
            asymmetry: 0.1,
            tip_radius: 2e-4,
        }
    }

    #[test]
    fn the_tip_arc_is_tangent_to_both_sides_and_the_sides_end_on_it() {
        let t = tooth();
        let [left, tip, right] = t.pieces();
        let (Piece::Segment { a: l0, b: l1 }, Piece::Tip { centre, radius }, Piece::Segment { a: r0, b: r1 }) = (left, tip, right) else {
            panic!("three pieces");
        };
        assert_eq!((l0, r1), (Vec2::new(0.0, 0.0), Vec2::new(6e-3, 0.0)));
        // Each side ends on the circle, and there the side is perpendicular to the radius.
        for (end, other) in [(l1, l0), (r0, r1)] {
            assert!(((end - centre).norm() - radius).abs() < 1e-15);
            assert!((end - centre).dot(&(other - end)).abs() < 1e-15);
        }
        // The rounded top is below the sharp peak by s (1/sin(theta/2) - 1).
        assert!(centre.y + radius < 3e-3 && centre.y + radius > 3e-3 - 2e-4 * 3.0);
        assert!(t.validate().is_ok());
    }

    #[test]
    fn a_too_large_arc_or_a_bad_asymmetry_is_refused_naming_the_field() {
        let big = Sawtooth {
            tip_radius: 5e-3,
            ..tooth()
        };
        assert_eq!(big.validate().unwrap_err().0, "base.tip_radius");
        let bad = Sawtooth { asymmetry: 1.5, ..tooth() };
        assert_eq!(bad.validate().unwrap_err().0, "base.asymmetry");
    }

    #[test]
    fn a_ball_dropped_on_a_fixed_side_lands_where_the_line_says() {
        // Falling from rest at x = 3 mm onto the right side of tooth 0, (0.6, 3) -> (6, 0) mm.
        let t = tooth();
        let right = t.piece(0, 2);
        let (r, radius, g) = (Vec2::new(3e-3, 4e-3), 1e-4, 9.81);
        let when = Sawtooth::contact_time(&right, &Motion::FIXED, r, Vec2::zeros(), radius, g, 0.0, 1.0).unwrap();
        // The side's height at x = 3 mm is 3 (6 - 3) / 5.4 mm; the centre stops R / cos above it.
        let slope: f64 = 3.0 / 5.4;
        let z_line = 3e-3 * (6.0 - 3.0) / 5.4;
        let z_contact = z_line + radius * (1.0 + slope * slope).sqrt();
        let expected = (2.0 * (4e-3 - z_contact) / g).sqrt();
        assert!((when - expected).abs() < 1e-11, "{when} vs {expected}");
    }

    #[test]
    fn a_ball_meets_an_oscillating_tip_at_contact_and_never_inside_before() {
        let t = tooth();
        let motion = Motion {
            amplitude: 2e-3,
            frequency: 25.0,
            phase: 0.3,
        };
        let tip = t.piece(1, 1);
        let Piece::Tip { centre, .. } = tip else { panic!() };
        let (r, v, radius, g) = (Vec2::new(centre.x + 1e-4, 9e-3), Vec2::new(0.01, 0.0), 1.1e-3, 9.81);
        let when = Sawtooth::contact_time(&tip, &motion, r, v, radius, g, 0.0, 1.0).unwrap();
        let (rt, vt) = fly(r, v, g, when);
        let (h, rate, _) = Sawtooth::gap(&tip, &motion, rt, vt, radius, when);
        assert!(h.abs() < 1e-10 && rate < 0.0, "gap {h} rate {rate}");
        for k in 0..20_000 {
            let s = when * k as f64 / 20_000.0;
            let (rs, vs) = fly(r, v, g, s);
            assert!(Sawtooth::gap(&tip, &motion, rs, vs, radius, s).0 > -1e-13, "inside at {s}");
        }
    }
}
