//! Walls: straight lines of infinite mass, fixed or oscillating with the drive, and the
//! time at which a flying particle meets one (appendix B of the sawtooth paper).
//!
//! Every wall moves, if at all, vertically with the drive: `d(t) = A sin(2 pi f t + phi)`.
//! A horizontal wall (the floor, the lid) moves along its normal; a vertical side wall that
//! moves with the floor keeps its place and only lends its velocity to friction. A sawtooth
//! wall ([`Waveform::Sawtooth`]) stands still and lends a fixed speed along its normal to
//! every grain that strikes it.
//!
//! The gap of a particle of radius `R` to a horizontal wall is a parabola minus a sinusoid,
//! with a curvature bounded by `K = g + A (2 pi f)^2`. From any time with gap `h >= 0` and
//! rate `h'`, the gap stays positive for at least `s = (h' + sqrt(h'^2 + 2 K h)) / K`: the
//! root of the bound `h + h' s - K s^2 / 2`. Stepping by such `s` brackets the first contact
//! from below without ever stepping over it; it converges where the particle meets the wall
//! at an angle, and the last bracket is bisected to [`TIME_TOLERANCE`]. A contact counts only
//! while the particle approaches the wall (`h' < 0`), so round-off that leaves a particle a
//! hair inside a wall makes it bounce at once and never sink.

use crate::flight::{fly, height_time};
use crate::Vec2;

/// Bisection width of a wall contact (s).
pub const TIME_TOLERANCE: f64 = 1e-12;

/// Where a wall stands and which side the particles are on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallKind {
    /// A horizontal line with the particles above it (the vibrated bottom).
    Floor,
    /// A horizontal line with the particles below it.
    Lid,
    /// A vertical line with the particles to its right (x > x0).
    Left,
    /// A vertical line with the particles to its left.
    Right,
}

/// Vertical oscillation `d(t) = amplitude sin(2 pi frequency t + phase)` (m, Hz, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub amplitude: f64,
    pub frequency: f64,
    pub phase: f64,
}

impl Motion {
    /// A wall that does not move.
    pub const FIXED: Motion = Motion {
        amplitude: 0.0,
        frequency: 0.0,
        phase: 0.0,
    };

    pub fn is_fixed(&self) -> bool {
        self.amplitude == 0.0
    }

    fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency
    }

    /// Displacement at `t` (m).
    pub fn displacement(&self, t: f64) -> f64 {
        if self.is_fixed() {
            0.0
        } else {
            self.amplitude * (self.omega() * t + self.phase).sin()
        }
    }

    /// Velocity at `t` (m/s).
    pub fn velocity(&self, t: f64) -> f64 {
        if self.is_fixed() {
            0.0
        } else {
            self.amplitude * self.omega() * (self.omega() * t + self.phase).cos()
        }
    }

    /// Largest acceleration (m/s^2).
    pub fn max_acceleration(&self) -> f64 {
        self.amplitude.abs() * self.omega().powi(2)
    }
}

/// How a vibrated floor or lid moves (`drive.waveform` of a scene: `sine` or `sawtooth`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Waveform {
    /// `A sin(2 pi f t + phi)`: the wall's position and velocity follow the sinusoid, so a
    /// grain meets it at whatever velocity the phase of its impact gives.
    #[default]
    Sine,
    /// Barrat and Trizac's sawtooth of negligible excursion (the limit of a sawtooth whose
    /// amplitude goes to zero at fixed speed): the wall stands at its mean line, and every
    /// grain that strikes it meets it moving into the box at the sinusoid's peak speed
    /// `V = A 2 pi f`. Every impact sees the same wall velocity.
    Sawtooth,
}

/// One wall: its kind, its mean position (z for horizontal walls, x for vertical ones), its
/// motion, and the speed it lends to the grains that strike it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    pub kind: WallKind,
    pub position: f64,
    pub motion: Motion,
    /// Speed (m/s) at which the wall moves into the box, along its normal, whenever a grain
    /// strikes it, over and above `motion`: a sawtooth wall's `V`, 0 for any other wall. It
    /// takes part in the collision only; where the wall stands, and so when a grain meets
    /// it, is `motion`'s.
    pub push: f64,
}

impl Wall {
    /// Unit normal pointing into the particles' side.
    pub fn normal(&self) -> Vec2 {
        match self.kind {
            WallKind::Floor => Vec2::new(0.0, 1.0),
            WallKind::Lid => Vec2::new(0.0, -1.0),
            WallKind::Left => Vec2::new(1.0, 0.0),
            WallKind::Right => Vec2::new(-1.0, 0.0),
        }
    }

    fn horizontal(&self) -> bool {
        matches!(self.kind, WallKind::Floor | WallKind::Lid)
    }

    /// The wall's line at `t` (z or x, m).
    pub fn line(&self, t: f64) -> f64 {
        if self.horizontal() {
            self.position + self.motion.displacement(t)
        } else {
            self.position
        }
    }

    /// The wall's velocity at `t` (m/s): always vertical.
    pub fn velocity(&self, t: f64) -> Vec2 {
        Vec2::new(0.0, self.motion.velocity(t))
    }

    /// The velocity a grain that strikes the wall at `t` collides with (m/s): the wall's own,
    /// plus its push along the normal.
    pub fn strike_velocity(&self, t: f64) -> Vec2 {
        self.velocity(t) + self.normal() * self.push
    }

    /// Gap between the wall and a particle at `r` with radius `radius` at time `t` (m;
    /// negative inside).
    pub fn gap(&self, r: Vec2, radius: f64, t: f64) -> f64 {
        let n = self.normal();
        let along = if self.horizontal() { r.y } else { r.x };
        let sign = if self.horizontal() { n.y } else { n.x };
        sign * (along - self.line(t)) - radius
    }

    /// Rate of the gap (m/s) for a particle of velocity `v`.
    fn gap_rate(&self, v: Vec2, t: f64) -> f64 {
        (v - self.velocity(t)).dot(&self.normal())
    }

    /// Whether a particle at `(r, v)` stays clear of every position the horizontal wall can
    /// take (its mean line +- amplitude) for the next `span` seconds: a check without the
    /// wall's phase, so without trigonometry. The height `z(s)` is a parabola that opens
    /// downwards, so its lowest point on `[0, span]` is at an end, and its highest at an end
    /// or at the apex.
    fn clear_of(&self, r: Vec2, v: Vec2, radius: f64, gravity: f64, span: f64) -> bool {
        if !span.is_finite() {
            return false;
        }
        let reach = self.motion.amplitude.abs() + radius;
        let z_end = r.y + v.y * span - 0.5 * gravity * span * span;
        match self.kind {
            WallKind::Floor => r.y.min(z_end) - reach > self.position,
            WallKind::Lid => {
                let apex = if gravity > 0.0 && v.y > 0.0 && v.y / gravity < span {
                    r.y + 0.5 * v.y * v.y / gravity
                } else {
                    r.y.max(z_end)
                };
                apex.max(r.y.max(z_end)) + reach < self.position
            }
            WallKind::Left | WallKind::Right => false,
        }
    }

    /// Whether the wall moves along its normal (a vibrated floor or lid), so that finding a
    /// contact with it takes a bounded search.
    pub fn moves_along_normal(&self) -> bool {
        self.horizontal() && !self.motion.is_fixed()
    }

    /// The time from now (s) until a particle at `(r, v)` first comes within reach of any
    /// position the horizontal wall can take (its mean line +- amplitude): 0 if it is within
    /// reach now, infinite if it never comes; 0 for a side wall. No contact can come before it.
    pub fn reach(&self, r: Vec2, v: Vec2, radius: f64, gravity: f64) -> f64 {
        let reach = self.motion.amplitude.abs() + radius;
        let (level, upward) = match self.kind {
            WallKind::Floor if r.y > self.position + reach => (self.position + reach, false),
            WallKind::Lid if r.y < self.position - reach => (self.position - reach, true),
            _ => return 0.0,
        };
        height_time(r.y, v.y, gravity, level, upward).unwrap_or(f64::INFINITY)
    }

    /// The first time `t >= t0` before `t0 + horizon` at which a particle at `(r, v)` at `t0`
    /// meets the wall while approaching it, or `None` (also when the search of a moving wall
    /// gave up: see [`Wall::search`]).
    pub fn contact_time(&self, r: Vec2, v: Vec2, radius: f64, gravity: f64, t0: f64, horizon: f64) -> Option<f64> {
        match self.search(r, v, radius, gravity, t0, horizon) {
            Search::At(t) => Some(t),
            Search::Clear | Search::GaveUp(_) => None,
        }
    }

    /// The same search, telling a wall that is clear up to `t0 + horizon` from a search of a
    /// moving wall that gave up before it.
    pub fn search(&self, r: Vec2, v: Vec2, radius: f64, gravity: f64, t0: f64, horizon: f64) -> Search {
        let found = |t: Option<f64>| t.map_or(Search::Clear, Search::At);
        if self.horizontal() && self.clear_of(r, v, radius, gravity, horizon) {
            return Search::Clear;
        }
        let h0 = self.gap(r, radius, t0);
        let rate0 = self.gap_rate(v, t0);
        if h0 <= 0.0 && rate0 < 0.0 {
            // Touching or inside by round-off, and approaching: bounce now.
            return Search::At(t0);
        }
        // Touching and separating: gravity or the wall may bring them together again.
        let h0 = h0.max(0.0);
        let end = t0 + horizon;
        if !self.horizontal() {
            // Linear in x.
            let s = match self.kind {
                WallKind::Left if v.x < 0.0 => h0 / -v.x,
                WallKind::Right if v.x > 0.0 => h0 / v.x,
                _ => return Search::Clear,
            };
            return found((t0 + s <= end).then_some(t0 + s));
        }
        let n = self.normal().y;
        if self.motion.is_fixed() {
            // A parabola against a fixed line: h(s) = h0 + rate s + a s^2 / 2, with a = -g on
            // a floor and +g under a lid; the first root where h falls, in stable forms.
            let a = -gravity * n;
            let s = if a < 0.0 {
                let root = (rate0 * rate0 - 2.0 * a * h0).sqrt();
                if rate0 < 0.0 {
                    2.0 * h0 / (-rate0 + root)
                } else {
                    (rate0 + root) / -a
                }
            } else if a > 0.0 {
                let disc = rate0 * rate0 - 2.0 * a * h0;
                if rate0 >= 0.0 || disc < 0.0 {
                    return Search::Clear;
                }
                2.0 * h0 / (-rate0 + disc.sqrt())
            } else if rate0 < 0.0 {
                h0 / -rate0
            } else {
                return Search::Clear;
            };
            return found((t0 + s <= end).then_some(t0 + s));
        }
        let at = |t: f64| {
            let (rr, vv) = fly(r, v, gravity, t - t0);
            (self.gap(rr, radius, t), self.gap_rate(vv, t))
        };
        search_contact(at, gravity + self.motion.max_acceleration(), t0, end)
    }
}

/// The first time in `[t0, end]` at which a gap `h(t)` (m), given with its rate by `at(t)`,
/// closes while closing, for a gap whose second derivative is at least `-k` (m/s^2); or
/// `None`. From a time with gap `h >= 0` and rate `h'`, the gap stays positive for at least
/// `s = (h' + sqrt(h'^2 + 2 k h)) / k`, the root of the bound `h + h' s - k s^2 / 2`:
/// stepping by `s` brackets the first contact from below without stepping over it, and the
/// last bracket is bisected to [`TIME_TOLERANCE`]. A gap closed by round-off at `t0` while
/// closing is a contact now; one closed while opening is not, so nothing sinks.
pub fn first_contact(at: impl Fn(f64) -> (f64, f64), k: f64, t0: f64, end: f64) -> Option<f64> {
    match search_contact(at, k, t0, end) {
        Search::At(t) => Some(t),
        Search::Clear | Search::GaveUp(_) => None,
    }
}

/// What a search for a contact found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Search {
    /// The first contact, at this time.
    At(f64),
    /// No contact up to the end of the search.
    Clear,
    /// The iteration budget ran out at this time, before the end of the search, with no
    /// contact before it.
    GaveUp(f64),
}

/// [`first_contact`], telling a gap that stays open to `end` from a search that gave up.
pub fn search_contact(at: impl Fn(f64) -> (f64, f64), k: f64, t0: f64, end: f64) -> Search {
    let (h0, rate0) = at(t0);
    if h0 <= 0.0 && rate0 < 0.0 {
        return Search::At(t0);
    }
    let (mut t, mut h, mut rate) = (t0, h0.max(0.0), rate0);
    for _ in 0..100_000 {
        let s = (rate + (rate * rate + 2.0 * k * h.max(0.0)).sqrt()) / k;
        let next = t + s.max(TIME_TOLERANCE);
        if next > end {
            return Search::Clear;
        }
        let (hn, rn) = at(next);
        if hn <= 0.0 {
            // The gap closed within (t, next] (round-off, or a touching particle that the
            // wall catches up with): bisect to the first closing.
            let (mut lo, mut hi) = (t, next);
            while hi - lo > TIME_TOLERANCE {
                let mid = 0.5 * (lo + hi);
                if at(mid).0 > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let (_, rate_hi) = at(hi);
            if rate_hi < 0.0 {
                return Search::At(hi);
            }
            // Touching but not approaching there: go on from the contact, gap zero.
            (t, h, rate) = (hi, 0.0, rate_hi);
            continue;
        }
        (t, h, rate) = (next, hn, rn);
        if h <= 1e-15 && rate < 0.0 {
            return Search::At(t);
        }
    }
    // A grazing approach that never quite touches within the iteration budget: the caller
    // looks again from where the search stopped.
    Search::GaveUp(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floor(a: f64, f: f64) -> Wall {
        Wall {
            kind: WallKind::Floor,
            position: 0.0,
            motion: Motion {
                amplitude: a,
                frequency: f,
                phase: 0.0,
            },
            push: 0.0,
        }
    }

    #[test]
    fn a_ball_dropped_on_a_fixed_floor_lands_at_the_free_fall_time() {
        let w = floor(0.0, 0.0);
        let t = w.contact_time(Vec2::new(0.0, 1.0), Vec2::zeros(), 0.1, 10.0, 0.0, 10.0).unwrap();
        assert!((t - (2.0 * 0.9 / 10.0f64).sqrt()).abs() < 1e-14);
    }

    #[test]
    fn a_ball_meets_an_oscillating_floor_at_the_root_and_never_inside() {
        // A ball falling from 5 mm onto a floor oscillating with 1 mm at 50 Hz.
        let w = floor(1e-3, 50.0);
        for z0 in [5e-3, 3.3e-3, 2.1e-3] {
            let (r, v) = (Vec2::new(0.0, z0), Vec2::new(0.0, 0.0));
            let t = w.contact_time(r, v, 5e-4, 9.81, 0.0, 1.0).unwrap();
            let (rt, vt) = fly(r, v, 9.81, t);
            assert!(w.gap(rt, 5e-4, t).abs() < 1e-12, "gap {}", w.gap(rt, 5e-4, t));
            assert!(w.gap_rate(vt, t) < 0.0);
            // Densely sampled, the gap stays positive before the contact.
            for k in 0..10_000 {
                let s = t * k as f64 / 10_000.0;
                let (rs, _) = fly(r, v, 9.81, s);
                assert!(w.gap(rs, 5e-4, s) > -1e-15, "inside at {s}");
            }
        }
    }

    #[test]
    fn no_contact_comes_before_a_particle_reaches_the_band_the_wall_sweeps() {
        // The floor sweeps z in [-1, 1] mm; a grain of radius 0.5 mm dropped from 5 mm comes
        // within reach when its centre falls to 1.5 mm, after sqrt(2 (3.5 mm) / g).
        let w = floor(1e-3, 50.0);
        let (r, g) = (Vec2::new(0.0, 5e-3), 10.0);
        let entry = w.reach(r, Vec2::zeros(), 5e-4, g);
        assert!((entry - (2.0 * 3.5e-3 / g).sqrt()).abs() < 1e-15, "{entry}");
        let contact = w.contact_time(r, Vec2::zeros(), 5e-4, g, 0.0, 1.0).unwrap();
        assert!(contact >= entry);
        // Within reach now: 0; thrown up without gravity: never.
        assert_eq!(w.reach(Vec2::new(0.0, 1e-3), Vec2::zeros(), 5e-4, g), 0.0);
        assert_eq!(w.reach(r, Vec2::new(0.0, 1.0), 5e-4, 0.0), f64::INFINITY);
        // A lid at 10 mm sweeping [9, 11] mm: reached rising at 1 m/s from 5 mm when the
        // centre passes 8.5 mm.
        let lid = Wall {
            kind: WallKind::Lid,
            position: 1e-2,
            motion: Motion {
                amplitude: 1e-3,
                frequency: 50.0,
                phase: 0.0,
            },
            push: 0.0,
        };
        let up = lid.reach(r, Vec2::new(0.0, 1.0), 5e-4, g);
        let z = r.y + up - 0.5 * g * up * up;
        assert!((z - 8.5e-3).abs() < 1e-15, "{z}");
        assert_eq!(lid.reach(r, Vec2::new(0.0, 0.1), 5e-4, g), f64::INFINITY);
    }

    #[test]
    fn a_search_that_runs_out_of_steps_says_where_it_stopped() {
        // A gap that never closes but shrinks forever: the bound's steps shrink with it.
        let at = |t: f64| (1e-3 * (-1e3 * t).exp(), -(-1e3 * t).exp());
        match search_contact(at, 1e9, 0.0, 1.0) {
            Search::GaveUp(t) => assert!(t > 0.0 && t < 1.0),
            other => panic!("{other:?}"),
        }
        assert_eq!(first_contact(at, 1e9, 0.0, 1.0), None);
        assert_eq!(search_contact(|_| (1.0, 0.0), 1.0, 0.0, 1.0), Search::Clear);
    }

    #[test]
    fn a_particle_a_hair_inside_bounces_now_only_if_it_approaches() {
        let w = floor(0.0, 0.0);
        let r = Vec2::new(0.0, 0.1 - 1e-16);
        assert_eq!(w.contact_time(r, Vec2::new(0.0, -1.0), 0.1, 10.0, 2.0, 1.0), Some(2.0));
        // Leaving at 1 m/s, it comes back down after 2 v / g = 0.2 s.
        let back = w.contact_time(r, Vec2::new(0.0, 1.0), 0.1, 10.0, 2.0, 1.0).unwrap();
        assert!((back - 2.2).abs() < 1e-12, "{back}");
        // A side wall it leaves is never met again.
        let side = Wall {
            kind: WallKind::Left,
            position: 0.0,
            motion: Motion::FIXED,
            push: 0.0,
        };
        assert_eq!(
            side.contact_time(Vec2::new(0.1 - 1e-16, 0.5), Vec2::new(1.0, 0.0), 0.1, 10.0, 0.0, 10.0),
            None
        );
    }
}
