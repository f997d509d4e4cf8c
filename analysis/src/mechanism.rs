//! How grains move on the floor, inside and outside dense bands: the direct test of the
//! stripe mechanism of thesis 3.4 (frustration) and 3.5.
//!
//! The hypothesis: a free sphere on a floor shaken at `Gamma < 7 mu / 2` rolls without slip,
//! so its centre follows `2/7` of the floor's displacement and moves by `-5/7` of it relative
//! to the tray. Grains pressed against neighbours cannot all roll (two touching spheres that
//! roll the same way rub at their contact), so a dense cluster is held by the floor and moves
//! with it. Relative to the free grains the cluster then moves by `5/7` of the floor's
//! displacement, and sweeps them up at its front.
//!
//! Per grain on the floor (`z < R (1 + FLOOR_GAP)`), in the tray frame, with the floor
//! speed amplitude `U = A w`:
//! - `u = v - v_tray e_x`, its velocity relative to the tray;
//! - `s = u + omega x (-R e_z)`, the slip of its contact point on the floor (eq 3.11 with the
//!   floor as partner);
//! - **held**: `|u| < SLIP_FRACTION U` (moves with the floor);
//! - **rolling**: not held and `|s| < SLIP_FRACTION U` (moves on the floor without slip);
//! - **sliding**: `|s| >= SLIP_FRACTION U`.
//!
//! Grains off the floor are **airborne**. SLIP_FRACTION is 5 % (the threshold).
//!
//! The groups' motion is summarised by the slope `a` of the least-squares line
//! `u_x = a v_tray` through the samples of a period: `a = 0` for grains held by the floor,
//! `a = -5/7` for grains that roll without slip, `a = -1` for grains at rest in the lab.

use crate::stripes::Stripe;

/// Relative slip below which a grain counts as held or rolling (fraction of `A w`).
pub const SLIP_FRACTION: f64 = 0.05;
/// A grain is on the floor when its centre is below `R (1 + FLOOR_GAP)`: within 2 % of its
/// radius (10 um for the largest grains) of touching. Grains in dense bands hop by microns
/// all the time (with a gap of `1e-3 R`, 61 % of the band grains of the 3 Hz, 10 mm run were
/// off the floor at a given instant, yet their mean motion follows the floor); a grain
/// higher than that is climbing on its neighbours or flying.
pub const FLOOR_GAP: f64 = 0.02;

/// How a grain moves at one instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Motion {
    Held,
    Rolling,
    Sliding,
    Airborne,
}

impl Motion {
    pub const ALL: [Motion; 4] = [Motion::Held, Motion::Rolling, Motion::Sliding, Motion::Airborne];

    pub fn name(self) -> &'static str {
        match self {
            Motion::Held => "held",
            Motion::Rolling => "rolling",
            Motion::Sliding => "sliding",
            Motion::Airborne => "airborne",
        }
    }
}

/// One grain at one instant: centre (m), velocity (m/s), angular velocity (rad/s), radius (m).
#[derive(Clone, Copy, Debug)]
pub struct Grain {
    pub pos: [f64; 3],
    pub vel: [f64; 3],
    pub omega: [f64; 3],
    pub radius: f64,
}

/// The grain's motion on a floor moving at `v_tray` (m/s, along x) whose speed amplitude is
/// `floor_speed` (m/s); see the module docs.
pub fn motion(g: &Grain, v_tray: f64, floor_speed: f64) -> Motion {
    if g.pos[2] >= g.radius * (1.0 + FLOOR_GAP) {
        return Motion::Airborne;
    }
    let u = [g.vel[0] - v_tray, g.vel[1], g.vel[2]];
    // omega x (-R e_z) = -R (omega_y, -omega_x, 0)
    let s = [u[0] - g.radius * g.omega[1], u[1] + g.radius * g.omega[0]];
    let limit2 = (SLIP_FRACTION * floor_speed).powi(2);
    if u[0] * u[0] + u[1] * u[1] < limit2 {
        Motion::Held
    } else if s[0] * s[0] + s[1] * s[1] < limit2 {
        Motion::Rolling
    } else {
        Motion::Sliding
    }
}

/// Where a grain is: inside a dense band (a stripe of the instant's profile) or outside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    Band,
    Outside,
}

/// Counts of each motion and the least-squares sums of `u_x` against `v_tray`, for one place.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Grain-instants per motion, indexed by `Motion as usize` (the order of [`Motion::ALL`]).
    pub counts: [u64; 4],
    /// `sum v_tray u_x` and `sum v_tray^2` over grain-instants (for the slope `a`).
    pub vu: f64,
    pub vv: f64,
    /// `sum u_x` over grain-instants (for the mean velocity relative to the tray).
    pub u: f64,
}

impl Tally {
    pub fn add(&mut self, m: Motion, v_tray: f64, u_x: f64) {
        self.counts[m as usize] += 1;
        self.vu += v_tray * u_x;
        self.vv += v_tray * v_tray;
        self.u += u_x;
    }

    /// Adds another tally's grain-instants.
    pub fn merge(&mut self, other: &Tally) {
        for (c, o) in self.counts.iter_mut().zip(other.counts) {
            *c += o;
        }
        self.vu += other.vu;
        self.vv += other.vv;
        self.u += other.u;
    }

    /// Mean `u_x` (m/s; NaN without samples).
    pub fn mean_u(&self) -> f64 {
        self.u / self.total() as f64
    }

    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Fraction of grain-instants in motion `m` (NaN without any).
    pub fn fraction(&self, m: Motion) -> f64 {
        self.counts[m as usize] as f64 / self.total() as f64
    }

    /// Slope `a` of `u_x = a v_tray` (module docs; NaN without samples).
    pub fn slope(&self) -> f64 {
        self.vu / self.vv
    }
}

/// Upper edges of the local area-fraction classes of [`ByDensity`] (the last class is open).
pub const DENSITY_EDGES: [f64; 5] = [0.2, 0.35, 0.5, 0.65, 0.8];

/// Tallies by the local area fraction at each grain (the 1 mm cell it sits in), in the
/// classes `[0, 0.2), [0.2, 0.35), ..., [0.8, inf)`. The frustration hypothesis predicts a
/// slope that falls in magnitude as the local packing rises (crowded grains cannot all roll);
/// without pair friction it should not depend on the packing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ByDensity(pub [Tally; DENSITY_EDGES.len() + 1]);

impl ByDensity {
    /// Adds one instant; `phi` holds the area fraction of `phi.len()` equal cells over `length`.
    pub fn add_instant(&mut self, grains: &[Grain], phi: &[f64], length: f64, v_tray: f64, floor_speed: f64) {
        let cells = phi.len();
        for g in grains {
            let c = ((g.pos[0].rem_euclid(length) / length * cells as f64) as usize).min(cells - 1);
            let class = DENSITY_EDGES.iter().take_while(|&&e| phi[c] >= e).count();
            self.0[class].add(motion(g, v_tray, floor_speed), v_tray, g.vel[0] - v_tray);
        }
    }

    /// `(lower edge, upper edge)` of class `k`.
    pub fn class_range(k: usize) -> (f64, f64) {
        let lo = if k == 0 { 0.0 } else { DENSITY_EDGES[k - 1] };
        (lo, DENSITY_EDGES.get(k).copied().unwrap_or(f64::INFINITY))
    }
}

/// Tallies inside the dense bands and outside them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Split {
    pub band: Tally,
    pub outside: Tally,
}

impl Split {
    /// Adds one instant: each grain by its motion and by whether a stripe of `stripes` (on a
    /// periodic axis of length `length`) contains it.
    pub fn add_instant(&mut self, grains: &[Grain], stripes: &[Stripe], length: f64, v_tray: f64, floor_speed: f64) {
        for g in grains {
            let m = motion(g, v_tray, floor_speed);
            let inside = stripes.iter().any(|s| s.contains(g.pos[0], length));
            let t = if inside { &mut self.band } else { &mut self.outside };
            t.add(m, v_tray, g.vel[0] - v_tray);
        }
    }

    /// Adds another split's grain-instants.
    pub fn merge(&mut self, other: &Split) {
        self.band.merge(&other.band);
        self.outside.merge(&other.outside);
    }

    /// Slope of the bands' grains relative to the grains outside: `a_band - a_outside`,
    /// `5/7` when held clusters meet rolling grains (module docs).
    pub fn relative_slope(&self) -> f64 {
        self.band.slope() - self.outside.slope()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grain(z: f64, vx: f64, omega_y: f64) -> Grain {
        Grain {
            pos: [0.01, 0.01, z],
            vel: [vx, 0.0, 0.0],
            omega: [0.0, omega_y, 0.0],
            radius: 5e-4,
        }
    }

    #[test]
    fn held_rolling_sliding_and_airborne() {
        let (r, u) = (5e-4, 0.2);
        // With the floor: held.
        assert_eq!(motion(&grain(r, 0.3, 0.0), 0.3, u), Motion::Held);
        // Rolling without slip on a floor moving at 0.3: u = -0.1, omega_y = u / R gives zero
        // contact-point slip (u_x - R omega_y = 0).
        assert_eq!(motion(&grain(r, 0.2, -0.1 / r), 0.3, u), Motion::Rolling);
        // Sliding: the same translation without spin.
        assert_eq!(motion(&grain(r, 0.2, 0.0), 0.3, u), Motion::Sliding);
        // Off the floor.
        assert_eq!(motion(&grain(1.1 * r, 0.2, 0.0), 0.3, u), Motion::Airborne);
        assert_eq!(motion(&grain(1.01 * r, 0.2, 0.0), 0.3, u), Motion::Sliding, "a micron hop");
        // In contact with a slight overlap.
        assert_eq!(motion(&grain(0.999 * r, 0.3, 0.0), 0.3, u), Motion::Held);
    }

    #[test]
    fn slopes_of_held_and_rolling_groups() {
        // Rolling grains move -5/7 of the tray's velocity relative to it, held grains 0.
        let mut split = Split::default();
        let r = 5e-4;
        let stripes = [Stripe {
            start: 0.0,
            center: 0.005,
            width: 0.01,
            mass: 0.0,
        }];
        for k in 0..20 {
            let v_tray = 0.2 * (k as f64 * 0.3).cos();
            let held = Grain {
                pos: [0.004, 0.01, r],
                vel: [v_tray, 0.0, 0.0],
                omega: [0.0; 3],
                radius: r,
            };
            let u = -5.0 / 7.0 * v_tray;
            let rolling = Grain {
                pos: [0.05, 0.01, r],
                vel: [v_tray + u, 0.0, 0.0],
                omega: [0.0, u / r, 0.0],
                radius: r,
            };
            split.add_instant(&[held, rolling], &stripes, 0.1, v_tray, 0.2);
        }
        let Split { band, outside } = split;
        assert!((split.relative_slope() - 5.0 / 7.0).abs() < 1e-12);
        assert_eq!(band.mean_u(), 0.0, "held grains do not move on the tray");
        let mut twice = split;
        twice.merge(&split);
        assert_eq!(twice.band.total(), 40);
        assert_eq!(twice.outside.slope(), outside.slope());
        // By local packing: the held grain sits in a cell at 0.7, the rolling one at 0.1.
        let mut phi = vec![0.1; 100];
        phi[4] = 0.7;
        let mut by = ByDensity::default();
        let v_tray = 0.2;
        let held = Grain {
            pos: [0.0045, 0.01, r],
            vel: [v_tray, 0.0, 0.0],
            omega: [0.0; 3],
            radius: r,
        };
        let free = Grain {
            pos: [0.0505, 0.01, r],
            vel: [v_tray * 2.0 / 7.0, 0.0, 0.0],
            omega: [0.0, -5.0 / 7.0 * v_tray / r, 0.0],
            radius: r,
        };
        by.add_instant(&[held, free], &phi, 0.1, v_tray, 0.2);
        assert_eq!(by.0[4].total(), 1, "0.7 is in [0.65, 0.8)");
        assert_eq!(by.0[4].slope(), 0.0);
        assert!((by.0[0].slope() + 5.0 / 7.0).abs() < 1e-12);
        assert_eq!(ByDensity::class_range(0), (0.0, 0.2));
        assert_eq!(ByDensity::class_range(5), (0.8, f64::INFINITY));
        assert_eq!(band.total(), 20);
        assert!(band.slope().abs() < 1e-15);
        assert!((outside.slope() + 5.0 / 7.0).abs() < 1e-12);
        assert!(band.fraction(Motion::Held) > 0.75, "held except near v_tray = 0");
        assert_eq!(outside.fraction(Motion::Sliding), 0.0);
    }
}
