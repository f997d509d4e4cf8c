//! From the tray to the automaton's parameters.
//!
//! The automaton lives in the tray frame; a cell is one mean grain diameter `d`. Over one
//! half period a free grain slides relative to the tray by `D` (the peak-to-peak of its
//! displacement relative to the tray); that is the flight cap, `l = round(D / d_x)` cells
//! with `d_x` the cell length. `D` comes from the single-sphere DEM on the shaken plate
//! (`particles::experiment::single`, run by the CLI, which passes the measured
//! [`SlideMeasure`] here, so this crate does not depend on the DEM). [`coulomb_slide`] gives
//! the same quantities for a sliding Coulomb block, a closed check of the DEM value:
//! - sliding threshold: a grain at rest on the tray stays stuck while the tray's
//!   acceleration `a(t) = A (2 pi nu)^2 sin(2 pi nu t)` is within `mu g`, so grains slide at
//!   all only if `A (2 pi nu)^2 > mu g` (below: region (a) of Fig 3.30, nothing moves);
//! - far above it (thesis: 40 g against `mu g` = 0.7 g) the grain barely follows the tray;
//!   its velocity changes by at most `mu g / (2 nu)` per half period, so `D ~ 2 A`.
//!
//! The impact speed used by knock-through is the grain's peak sliding speed relative to the
//! tray, `v`; the far grain of a hit line is knocked loose with probability
//! `1 - exp(-(v / v_knock)^2)`: the impact's kinetic energy `m v^2 / 2` against an energy
//! scale `m v_knock^2 / 2` of the frictional lock of the line, with `v_knock` a free
//! parameter fitted to DEM runs (calibration).

use serde::{Deserialize, Serialize};

use crate::params::{Activation, FlightCap, Frustration, Knock, Lateral, Physical, Sideways, Threshold, Transport};
use crate::transport::{hold_share, Graded, SlopeTable};

/// The tray and the grains, SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrayDrive {
    /// nu (Hz).
    pub frequency: f64,
    /// A (m).
    pub amplitude: f64,
    /// Floor friction coefficient mu.
    pub mu: f64,
    /// g (m/s^2).
    pub gravity: f64,
}

impl TrayDrive {
    /// Peak tray acceleration `A (2 pi nu)^2` (m/s^2).
    pub fn tray_acceleration(&self) -> f64 {
        let w = 2.0 * std::f64::consts::PI * self.frequency;
        self.amplitude * w * w
    }

    /// Largest acceleration floor friction can transmit, `mu g` (m/s^2).
    pub fn friction_acceleration(&self) -> f64 {
        self.mu * self.gravity
    }
}

/// How a free grain slides on the tray, in its steady state.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlideMeasure {
    /// Peak-to-peak displacement relative to the tray over a period = sliding displacement per
    /// half period (m).
    pub displacement: f64,
    /// Peak speed relative to the tray (m/s).
    pub peak_speed: f64,
}

/// The slide of a grain from a sampled trajectory relative to the tray: `t` (s), relative
/// displacement `x` (m) and relative velocity `u` (m/s). The displacement per half period is
/// the mean `|x(t_k+1) - x(t_k)|` between the tray's turning points `t_k = (k/2 + 1/4) / nu`
/// (linear interpolation) over the last full period; the speed is the peak `|u|` over it.
pub fn slide_from_samples(frequency: f64, t: &[f64], x: &[f64], u: &[f64]) -> Option<SlideMeasure> {
    let end = *t.last()?;
    let half = 0.5 / frequency;
    // Last turning point inside the record, and the two before it.
    let k_last = ((end * frequency * 2.0 - 0.5).floor()) as i64;
    if k_last < 2 {
        return None;
    }
    let at = |tk: f64| -> f64 {
        let i = t.partition_point(|&s| s < tk).clamp(1, t.len() - 1);
        let (t0, t1) = (t[i - 1], t[i]);
        let w = if t1 > t0 { (tk - t0) / (t1 - t0) } else { 0.0 };
        x[i - 1] + w * (x[i] - x[i - 1])
    };
    let tk = |k: i64| (k as f64 + 0.5) * half;
    let (a, b, c) = (at(tk(k_last - 2)), at(tk(k_last - 1)), at(tk(k_last)));
    let peak = t
        .iter()
        .zip(u)
        .filter(|(s, _)| **s >= tk(k_last - 2))
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max);
    Some(SlideMeasure {
        displacement: 0.5 * ((b - a).abs() + (c - b).abs()),
        peak_speed: peak,
    })
}

/// A Coulomb block on the sinusoidal tray `x_tray = A sin(2 pi nu t)`, at rest in the lab at
/// `t = 0`: the relative velocity `u` obeys `du/dt = -a_tray(t) - mu g sgn(u)` while sliding
/// and sticks (`u = 0`) while `|a_tray| <= mu g`. Integrated with `steps_per_period` steps
/// for `periods` periods; measured by [`slide_from_samples`].
pub fn coulomb_slide(drive: &TrayDrive, periods: usize, steps_per_period: usize) -> SlideMeasure {
    let w = 2.0 * std::f64::consts::PI * drive.frequency;
    let dt = 1.0 / (drive.frequency * steps_per_period as f64);
    let f = drive.friction_acceleration();
    let (mut u, mut x) = (-drive.amplitude * w, 0.0f64);
    let n = periods.max(2) * steps_per_period;
    let (mut ts, mut xs, mut us) = (Vec::with_capacity(n + 1), Vec::with_capacity(n + 1), Vec::with_capacity(n + 1));
    ts.push(0.0);
    xs.push(0.0);
    us.push(u);
    for k in 0..n {
        let t = k as f64 * dt;
        let a = -drive.amplitude * w * w * (w * t).sin(); // tray acceleration
        if !(u == 0.0 && a.abs() <= f) {
            let dir = if u != 0.0 { u.signum() } else { -a.signum() };
            let un = u + (-a - f * dir) * dt;
            // Friction cannot reverse the slip within a step: it stops at zero.
            u = if un * dir < 0.0 { 0.0 } else { un };
        }
        x += u * dt;
        ts.push((k + 1) as f64 * dt);
        xs.push(x);
        us.push(u);
    }
    slide_from_samples(drive.frequency, &ts, &xs, &us).expect("at least two periods")
}

/// A free sphere on the shaken floor rolls without slip while `A (2 pi nu)^2 <= (7/2) mu g`
/// (its rolling needs only 2/7 of the floor's acceleration from friction; thesis 3.3.1):
/// up to there frustration and trains act.
pub const ROLLING_LIMIT: f64 = 3.5;

/// Whether a free sphere rolls without slip on this drive ([`ROLLING_LIMIT`]).
pub fn rolls_without_slip(drive: &TrayDrive) -> bool {
    drive.tray_acceleration() <= ROLLING_LIMIT * drive.friction_acceleration()
}

/// The parameters left free by the mapping, fitted by calibration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreeParams {
    /// Activation probability per half period (`None`: every grain flies).
    pub activation: Option<f64>,
    /// Knock-through speed scale `v_knock` (m/s) (`None`: no knock-through).
    pub knock_speed: Option<f64>,
    /// Sideways move probability per half period (`None`: no y moves).
    pub sideways: Option<f64>,
    /// Contacts with the neighbouring rows.
    pub lateral: Lateral,
    /// Apply the sliding threshold.
    pub threshold: bool,
    /// Free grains roll below the sliding threshold (see [`physical`]).
    pub rolling: bool,
    /// With `rolling`, up to the rolling limit ([`ROLLING_LIMIT`]): the probability that one occupied
    /// neighbouring cell holds a grain (`None`: crowded grains roll like free ones).
    pub frustration: Option<f64>,
    /// With `rolling`, up to the rolling limit: free grains move together as trains.
    pub trains: bool,
    /// Apply the flight cap.
    pub flight_cap: bool,
    /// With `rolling`, up to the rolling limit: graded transport in place of frustration
    /// (`None`: frustration as above).
    pub graded: Option<GradedChoice>,
}

/// The choices of graded transport ([`crate::transport`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GradedChoice {
    /// Which measured slope table.
    pub slope: SlopeTable,
    /// `Gamma_c` of the melt rule ([`hold_share`]); `None`: agitation leaves the whole hold.
    pub melt_gamma: Option<f64>,
    /// Length of the strip over which a grain's local packing is taken (m).
    pub window: f64,
}

/// The lattice's cells and grains, for the local packing of graded transport.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellShape {
    /// Cell length along x (m).
    pub length: f64,
    /// Cell width along y (m).
    pub width: f64,
    /// Rows across the tray.
    pub rows: usize,
    /// Mean projected area of a grain, `pi <r^2>` (m^2).
    pub grain_area: f64,
}

/// The graded-transport slot for a drive and lattice: the hold left by agitation at the
/// drive's `Gamma = A (2 pi nu)^2 / g`, and the area fraction one grain adds to its strip.
pub fn graded(drive: &TrayDrive, cell: &CellShape, choice: &GradedChoice) -> Graded {
    let gamma = drive.tray_acceleration() / drive.gravity;
    Graded {
        slope: choice.slope,
        hold: choice.melt_gamma.map_or(1.0, |gc| hold_share(gamma, gc)),
        grain_fraction: cell.grain_area / (choice.window * cell.width * cell.rows as f64),
        window_cells: choice.window / cell.length,
    }
}

/// The `physical` ingredients of a tray: cap `l = round(D / cell_length)` cells, threshold
/// `A (2 pi nu)^2 > mu g`, knock probability `1 - exp(-(v / v_knock)^2)`.
///
/// **Rolling** (`free.rolling`). A sphere does not need to slide to move: below the sliding
/// threshold the floor rolls a free sphere without slip as long as `A (2 pi nu)^2 <= (7/2) mu g`
/// (thesis 3.3.1, Figs 3.7-3.8; the rolling sphere's centre follows 2/7 of the floor), so it
/// moves `D = 2 (5/7) A` relative to the tray per half period, and `D` is what the
/// single-sphere DEM measures on the scene's own laws, rolling friction included. The jump is
/// then a rolling excursion of `round(D / cell_length)` cells, and Strassburger's rest is
/// frustration: a grain whose neighbour blocks its direction of motion cannot roll and rests
/// with the tray, which the jump rule already does. "Nothing moves" (region (a) of Fig 3.30)
/// is kept only where the free sphere itself does not get half a cell away, i.e. where
/// rolling friction or a pinned grain resist rolling: the cap is then 0 and the lattice
/// frozen. Without `rolling`, the Coulomb threshold freezes everything below `mu g`.
///
/// **Frustration** (`free.frustration`, rolling regime only). Two spheres touching and
/// rolling the same way rub at their contact, whose surfaces move in opposite directions
/// (thesis 3.4): a crowded grain cannot roll and rests with the tray. In the DEM the rolling
/// amplitude falls with the local packing (mechanism report, section 3); here each occupied
/// neighbouring cell holds a grain with probability `h`, so a grain with `n` neighbours flies
/// with probability `(1 - h)^n`. A free grain rolls its full excursion. Above the rolling
/// limit ([`ROLLING_LIMIT`]) every grain slides and crowding does not hold it back, so the
/// rule is off there.
///
/// **Trains** (`free.trains`, rolling regime only). Free grains all roll with the floor, at
/// 5/7 of its velocity, so they do not stop one another: only resting grains stop a flight.
///
/// **Graded transport** (`free.graded`, rolling regime only, in place of frustration): every
/// grain goes its own excursion against the packing of its strip, from the DEM's measured
/// slope, and agitation melts the hold ([`crate::transport`], [`graded`]).
pub fn physical(drive: &TrayDrive, slide: &SlideMeasure, cell: &CellShape, free: &FreeParams) -> Physical {
    let cell_length = cell.length;
    let rolling_regime = free.rolling && rolls_without_slip(drive);
    let transport = match &free.graded {
        Some(choice) if rolling_regime => Transport::Graded(graded(drive, cell, choice)),
        _ => Transport::Uniform,
    };
    Physical {
        threshold: if free.threshold && !free.rolling {
            Threshold::Coulomb {
                tray_acceleration: drive.tray_acceleration(),
                friction_acceleration: drive.friction_acceleration(),
            }
        } else {
            Threshold::None
        },
        cap: if free.flight_cap {
            FlightCap::Cells {
                cells: (slide.displacement / cell_length).round().max(0.0) as usize,
            }
        } else {
            FlightCap::None
        },
        activation: free.activation.map_or(Activation::None, |p| Activation::Bernoulli { p }),
        knock: free.knock_speed.map_or(Knock::None, |v| Knock::Bernoulli {
            p: if v > 0.0 {
                1.0 - (-(slide.peak_speed / v).powi(2)).exp()
            } else {
                1.0
            },
        }),
        lateral: free.lateral,
        sideways: free.sideways.map_or(Sideways::None, |p| Sideways::Bernoulli { p }),
        frustration: match free.frustration {
            Some(p) if rolling_regime && transport == Transport::Uniform => Frustration::Bernoulli { p },
            _ => Frustration::None,
        },
        trains: free.trains && rolling_regime,
        transport,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coulomb_block_sticks_below_the_threshold_and_slides_about_2a_far_above() {
        let weak = TrayDrive {
            frequency: 5.0,
            amplitude: 0.005,
            mu: 0.7,
            gravity: 10.0,
        };
        assert!(weak.tray_acceleration() < weak.friction_acceleration());
        let s = coulomb_slide(&weak, 4, 4000);
        assert!(s.displacement < 1e-12, "D = {}", s.displacement);
        let thesis = TrayDrive {
            frequency: 20.0,
            amplitude: 0.025,
            ..weak
        };
        let s = coulomb_slide(&thesis, 6, 20000);
        // |dv| <= mu g / (2 nu) = 0.175 m/s per half period against a tray at 3.14 m/s.
        assert!((s.displacement - 0.05).abs() < 0.05 * 0.1, "D = {}", s.displacement);
        assert!((s.peak_speed - std::f64::consts::PI).abs() < 0.3, "v = {}", s.peak_speed);
    }

    /// The experiment's drive (3 Hz, 10 mm, Gamma 0.36) is below the sliding threshold: the
    /// sliding reading freezes the lattice, the rolling reading jumps the free sphere's
    /// rolling excursion 2 (5/7) A = 14.3 mm, here 19 cells of 0.75 mm.
    #[test]
    fn below_the_sliding_threshold_free_grains_roll_their_excursion() {
        use crate::params::{Params, RuleSet, YBoundary};
        let drive = TrayDrive {
            frequency: 3.0,
            amplitude: 0.01,
            mu: 0.7,
            gravity: 9.81,
        };
        assert!(drive.tray_acceleration() < drive.friction_acceleration());
        let rolling = SlideMeasure {
            displacement: 2.0 * 5.0 / 7.0 * drive.amplitude,
            peak_speed: 5.0 / 7.0 * drive.amplitude * 2.0 * std::f64::consts::PI * drive.frequency,
        };
        let free = |rolling: bool| FreeParams {
            activation: None,
            knock_speed: None,
            sideways: None,
            lateral: Lateral::None,
            threshold: true,
            rolling,
            frustration: Some(0.1),
            trains: true,
            flight_cap: true,
            graded: None,
        };
        let cell = CellShape {
            length: 0.75e-3,
            width: 0.75e-3,
            rows: 10,
            grain_area: 0.4e-6,
        };
        let resolve = |ph: Physical| {
            Params {
                rule: RuleSet::Physical,
                physical: ph,
                y: YBoundary::Walls,
                x_walls: false,
                seed: 1,
                measured: None,
            }
            .resolve()
        };
        let rolls = resolve(physical(&drive, &rolling, &cell, &free(true)));
        assert!(!rolls.frozen);
        assert_eq!(rolls.cap, 19);
        assert_eq!(rolls.hold, crate::rng::quantise(0.1), "crowded grains are frustrated");
        let slides = resolve(physical(&drive, &rolling, &cell, &free(false)));
        assert!(slides.frozen, "the sliding reading: nothing moves below mu g");
        // Above the sliding threshold every grain slides: no frustration.
        let strong = TrayDrive {
            frequency: 20.0,
            amplitude: 0.025,
            ..drive
        };
        let sliding = resolve(physical(&strong, &rolling, &cell, &free(true)));
        assert_eq!(sliding.hold, 0);
        assert!(rolls.trains && !sliding.trains);
        // Above mu g but below (7/2) mu g a free sphere still rolls without slip.
        let brisk = TrayDrive {
            frequency: 4.0,
            amplitude: 0.018,
            ..drive
        };
        assert!(brisk.tray_acceleration() > brisk.friction_acceleration());
        let r = resolve(physical(&brisk, &rolling, &cell, &free(true)));
        assert!(r.hold > 0 && r.trains, "Gamma 1.16 still rolls");
        // Rolling resisted (the free sphere stays within half a cell): frozen either way.
        let held = SlideMeasure {
            displacement: 0.3e-3,
            peak_speed: 0.01,
        };
        assert!(resolve(physical(&drive, &held, &cell, &free(true))).frozen);
    }

    /// Graded transport takes frustration's place where grains roll, keeps the whole hold
    /// at the experiment's drive, melts it above `Gamma_c`, and is off where grains slide.
    #[test]
    fn graded_transport_replaces_frustration_and_melts_with_gamma() {
        let drive = TrayDrive {
            frequency: 3.0,
            amplitude: 0.01,
            mu: 0.7,
            gravity: 9.81,
        };
        let slide = SlideMeasure {
            displacement: 2.0 * 5.0 / 7.0 * drive.amplitude,
            peak_speed: 0.13,
        };
        let cell = CellShape {
            length: 0.6e-3,
            width: 0.6e-3,
            rows: 33,
            grain_area: 0.46e-6,
        };
        let free = FreeParams {
            activation: Some(1.0),
            knock_speed: None,
            sideways: None,
            lateral: Lateral::None,
            threshold: true,
            rolling: true,
            frustration: Some(0.25),
            trains: true,
            flight_cap: true,
            graded: Some(GradedChoice {
                slope: SlopeTable::InBands,
                melt_gamma: Some(1.2),
                window: 1e-3,
            }),
        };
        let ph = physical(&drive, &slide, &cell, &free);
        assert_eq!(ph.frustration, Frustration::None);
        let Transport::Graded(g) = ph.transport else {
            panic!("graded where grains roll")
        };
        assert_eq!(g.hold, 1.0, "Gamma 0.36 < Gamma_c");
        assert!((g.window_cells - 1e-3 / 0.6e-3).abs() < 1e-12);
        // N grains in the strip cover N pi <r^2> of its 1 mm x 33 rows.
        assert!((g.grain_fraction - 0.46e-6 / (1e-3 * 0.6e-3 * 33.0)).abs() < 1e-15);
        // Gamma 2.0 (5 Hz, 20 mm): the layer has lifted off, no hold is left.
        let brisk = TrayDrive {
            frequency: 5.0,
            amplitude: 0.02,
            ..drive
        };
        let Transport::Graded(g) = physical(&brisk, &slide, &cell, &free).transport else {
            panic!("Gamma 2 still rolls")
        };
        let gamma = brisk.tray_acceleration() / brisk.gravity;
        assert!(gamma > 1.2 && g.hold == 0.0);
        // Above the rolling limit every grain slides: neither rule.
        let sliding = TrayDrive {
            frequency: 20.0,
            amplitude: 0.025,
            ..drive
        };
        let ph = physical(&sliding, &slide, &cell, &free);
        assert_eq!((ph.transport, ph.frustration), (Transport::Uniform, Frustration::None));
    }
}
