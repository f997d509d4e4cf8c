//! Run classifier: `nothing | stripes | gas` (thesis Fig 3.30-3.31, regions a, b, c), from
//! two continuous metrics that a phase map can also plot directly.
//!
//! Both metrics are taken over the *tail* of the run (by default its last 10 % of frames,
//! at least one), i.e. its final state.
//!
//! - **`contrast`** (dimensionless): the standard deviation of the area fraction over the
//!   analysis cells, divided by the standard deviation the same grains would give if placed
//!   independently and uniformly along x ([`random_layer_sigma`]). A homogeneous random
//!   layer gives about 1 (a bit less, since grains cannot overlap); an ordered lattice less;
//!   stripes, which concentrate the area in a few dense bands, give several times more.
//!   Normalising by the random layer makes the number independent of the packing and of the
//!   cell width, which raw `std/mean` is not (it grows as cells shrink).
//! - **`mobility`** (mean grain diameters per period): `sqrt(2 D) / d`, the root mean square
//!   displacement per drive period relative to the tray (eq 3.30: `2 D = <r_i^2>`), divided
//!   by the mean diameter `d`. Grains that stick to the floor (region a: the tray's
//!   acceleration is below what friction can transmit) return to the same place every
//!   period and give 0 up to numerical creep; sliding grains drift.
//!
//! - **`stationary_stripes`**: the stripes of the run's *time-averaged* profile over its
//!   last `persistence_periods` drive periods (or its tail frames, if those span more), found
//!   with the same detector as every frame. A band that holds its place for that long
//!   survives the average, whatever the grains between the bands do; the fluctuations of a
//!   gas, and bands that form and dissolve or sweep across the tray, average out (the cell
//!   noise of `K` independent frames falls like `1/sqrt(K)`). 0 when the run is shorter than
//!   the window: persistence cannot be shown.
//!
//! Decision ([`ClassifyParams`], defaults in brackets):
//! 1. `mobility < mobility_min` [0.1 diameters per period] -> **nothing**: the grains
//!    do not move relative to the tray enough to rearrange the layer (whatever pattern the
//!    initial state had stays);
//! 2. else, at least one stationary stripe over `persistence_periods` [10] -> **stripes**;
//! 3. else, `contrast >= contrast_min` [2] and at least one stripe in the median tail
//!    frame -> **stripes** (strong bands that move);
//! 4. else -> **gas**: mobile grains without a lasting density contrast.
//!
//! Why rule 2: the DEM's stripes at 3 Hz, 10 mm and packing 0.46 are three
//! bands that hold their places for 30 s between grains that roll freely; the contrast is
//! 1.8-1.9 there, because a band cannot be denser than a jammed layer (0.8), and rule 3
//! alone called every such run `gas`.
//!
//! Why 0.1 diameters per period: grains never stand perfectly still in a DEM of the tray.
//! Measured with `stripes run` (N = 1000, L = 0.1 m, thesis packing) and `stripes analyze`:
//! at 3 Hz, 10 mm (peak tray acceleration 3.6 m/s^2, below mu g = 7 m/s^2, region a) the
//! grains still creep 0.05 diameters per period (a sphere can roll on an accelerating
//! floor without sliding); at 20 Hz, 25 mm they drift 0.03 diameters per period, without
//! contacts and with an unchanged density profile (as a single sphere, which drifts
//! 0.02 diameters per period). Nothing happens in either. The thesis' plateau
//! `a1 ~ 1.6e-4 m^2` is 25 diameters per period, a LAMMPS run of the tray gives 1.9, and
//! independent steps of +-0.2 mm per period give 0.2: all mobile.

use crate::density::chord_primitive;

/// The phase of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    /// Region (a): grains immobile relative to the tray.
    Nothing,
    /// Region (b): dense stripes across the tray.
    Stripes,
    /// Region (c): mobile grains, no density contrast.
    Gas,
}

impl Phase {
    /// Lower-case name, as written in `summary.json` and phase-map CSVs.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Nothing => "nothing",
            Phase::Stripes => "stripes",
            Phase::Gas => "gas",
        }
    }
}

/// Thresholds of the classifier.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ClassifyParams {
    /// Below this mobility (mean diameters per period) a run is `nothing`.
    pub mobility_min: f64,
    /// At or above this contrast (and with stripes detected) a mobile run is `stripes`.
    pub contrast_min: f64,
    /// Drive periods over which a band must hold its place to count as a stationary stripe.
    pub persistence_periods: f64,
}

impl Default for ClassifyParams {
    fn default() -> Self {
        Self {
            mobility_min: 0.1,
            contrast_min: 2.0,
            persistence_periods: 10.0,
        }
    }
}

/// Metrics and verdict.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Classification {
    pub phase: Phase,
    /// See the module docs (dimensionless).
    pub contrast: f64,
    /// See the module docs (mean diameters per period; NaN when no two frames are a
    /// period apart, in which case the run is classified without it).
    pub mobility: f64,
    /// Median stripe count over the tail frames.
    pub tail_stripe_count: usize,
    /// Stripes of the time-averaged profile over the persistence window (module docs).
    pub stationary_stripe_count: usize,
    pub params: ClassifyParams,
}

/// What the classifier reads of a run's final state (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evidence {
    pub contrast: f64,
    pub mobility: f64,
    pub tail_stripe_count: usize,
    pub stationary_stripe_count: usize,
}

/// Applies the decision rule of the module docs.
pub fn classify(e: Evidence, params: ClassifyParams) -> Classification {
    let phase = if e.mobility < params.mobility_min {
        Phase::Nothing
    } else if e.stationary_stripe_count > 0 || (e.contrast >= params.contrast_min && e.tail_stripe_count > 0) {
        Phase::Stripes
    } else {
        Phase::Gas
    };
    Classification {
        phase,
        contrast: e.contrast,
        mobility: e.mobility,
        tail_stripe_count: e.tail_stripe_count,
        stationary_stripe_count: e.stationary_stripe_count,
        params,
    }
}

/// Factors by which [`sensitivity`] scales each threshold: half and twice the mobility and
/// the persistence, and the contrast threshold 20 % either way (contrasts of stripes and gases
/// lie within a factor 2-3 of each other, so a factor 2 there would say nothing).
pub const SENSITIVITY_FACTORS: [(&str, [f64; 3]); 3] = [
    ("mobility_min", [0.5, 1.0, 2.0]),
    ("contrast_min", [0.8, 1.0, 1.25]),
    ("persistence_periods", [0.5, 1.0, 2.0]),
];

/// The phase under one set of thresholds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Variant {
    pub params: ClassifyParams,
    pub stationary_stripe_count: usize,
    pub phase: Phase,
}

/// How the phase depends on the classifier's thresholds: the verdict under every
/// combination of the factors of [`SENSITIVITY_FACTORS`] (27 sets, the given one among them).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Sensitivity {
    pub variants: Vec<Variant>,
}

impl Sensitivity {
    /// How many of the variants give `phase`.
    pub fn count(&self, phase: Phase) -> usize {
        self.variants.iter().filter(|v| v.phase == phase).count()
    }

    /// Whether every variant gives the same phase.
    pub fn robust(&self) -> bool {
        self.variants.windows(2).all(|w| w[0].phase == w[1].phase)
    }
}

/// The verdicts around `base` (see [`Sensitivity`]). `e` is the evidence at `base`; the
/// stationary stripe count depends on the persistence window and comes from
/// `stationary_at(persistence_periods)`.
pub fn sensitivity(base: ClassifyParams, e: Evidence, stationary_at: impl Fn(f64) -> usize) -> Sensitivity {
    let [(_, fm), (_, fc), (_, fp)] = SENSITIVITY_FACTORS;
    let mut variants = Vec::with_capacity(27);
    for p in fp {
        let persistence_periods = base.persistence_periods * p;
        let stationary = if p == 1.0 {
            e.stationary_stripe_count
        } else {
            stationary_at(persistence_periods)
        };
        for m in fm {
            for c in fc {
                let params = ClassifyParams {
                    mobility_min: base.mobility_min * m,
                    contrast_min: base.contrast_min * c,
                    persistence_periods,
                };
                let evidence = Evidence {
                    stationary_stripe_count: stationary,
                    ..e
                };
                variants.push(Variant {
                    params,
                    stationary_stripe_count: stationary,
                    phase: classify(evidence, params).phase,
                });
            }
        }
    }
    Sensitivity { variants }
}

/// The frames from `from` on that are a whole number of drive periods before the last one
/// (to a hundredth of a period): the frames at the last frame's phase of the drive. All of
/// them without a period. Positions are in the laboratory frame, where a band that rests on
/// the tray moves with it by the drive's amplitude within a period: an average over frames
/// at several phases smears it, one over frames at one phase does not.
pub fn same_phase(times: &[f64], from: usize, period: Option<f64>) -> Vec<usize> {
    let Some(&last) = times.last() else {
        return Vec::new();
    };
    (from..times.len())
        .filter(|&i| {
            period.is_none_or(|p| {
                let k = (last - times[i]) / p;
                (k - k.round()).abs() < 0.01
            })
        })
        .collect()
}

/// The cell-wise mean of equally long profiles (empty input: empty profile).
pub fn time_average(profiles: &[Vec<f64>]) -> Vec<f64> {
    let Some(first) = profiles.first() else {
        return Vec::new();
    };
    let mut mean = vec![0.0; first.len()];
    for p in profiles {
        for (m, v) in mean.iter_mut().zip(p) {
            *m += v;
        }
    }
    let k = profiles.len() as f64;
    mean.iter_mut().for_each(|m| *m /= k);
    mean
}

/// First frame of the persistence window: the frames of the last `periods` drive periods
/// of `period` (s), or from `tail_from` if that reaches back further. `None` when the
/// frames span less than the window. Without a period, the tail frames, if there are at
/// least two.
pub fn persistence_window(times: &[f64], tail_from: usize, period: Option<f64>, periods: f64) -> Option<usize> {
    let (first, last) = (*times.first()?, *times.last()?);
    let Some(period) = period else {
        // Persistence needs frames: one frame says nothing about whether a band stays.
        return (times.len() >= tail_from + 2).then_some(tail_from);
    };
    let span = periods * period;
    // A relative slack of 1e-9 absorbs the round-off of snapshot times.
    if last - first < span * (1.0 - 1e-9) {
        return None;
    }
    let from = times.partition_point(|&t| t < last - span * (1.0 + 1e-9));
    Some(from.min(tail_from))
}

/// Standard deviation over cells of the area fraction, `std_c(phi_c)`.
pub fn cell_std(phi: &[f64]) -> f64 {
    if phi.is_empty() {
        return 0.0;
    }
    let n = phi.len() as f64;
    let mean = phi.iter().sum::<f64>() / n;
    (phi.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt()
}

/// The standard deviation of a cell's area fraction when every grain sits at an independent
/// uniform position along x: `sigma^2 = sum_i Var(c_i)`, where `c_i(u)` is the cell average
/// of grain i at offset u from the cell's centre (cell width `h = length / cells`). With
/// `E[c_i] = pi r_i^2 / (L W)` and `E[c_i^2] = (1/L) integral c_i(u)^2 du`, the integral is
/// taken by the midpoint rule on 64 points over `|u| < r_i + h/2`. The fixed total (the
/// cells' mean is known) multiplies the variance by `1 - 1/cells`.
pub fn random_layer_sigma(radii: &[f64], length: f64, width: f64, cells: usize) -> f64 {
    let h = length / cells as f64;
    const POINTS: usize = 64;
    let var: f64 = radii
        .iter()
        .map(|&r| {
            let half = r + 0.5 * h;
            let du = 2.0 * half / POINTS as f64;
            let sq: f64 = (0..POINTS)
                .map(|k| {
                    let u = -half + (k as f64 + 0.5) * du;
                    let c = (chord_primitive(0.5 * h - u, r) - chord_primitive(-0.5 * h - u, r)) / (h * width);
                    c * c
                })
                .sum::<f64>()
                * du;
            let mean = std::f64::consts::PI * r * r / (length * width);
            (sq / length - mean * mean).max(0.0)
        })
        .sum();
    (var * (1.0 - 1.0 / cells as f64)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::density::area_fraction_cells;
    use rand::{Rng, SeedableRng};

    /// Four frames a period: the window's average takes every fourth, counted back from the
    /// last; one frame a period, or no period: all of them.
    #[test]
    fn the_persistence_average_keeps_the_last_frames_phase() {
        let four: Vec<f64> = (0..20).map(|k| 0.25 + k as f64 * 0.25 + 1e-6 * (k % 3) as f64).collect();
        assert_eq!(same_phase(&four, 8, Some(1.0)), vec![11, 15, 19]);
        let one: Vec<f64> = (0..6).map(|k| 0.25 + k as f64).collect();
        assert_eq!(same_phase(&one, 2, Some(1.0)), vec![2, 3, 4, 5]);
        assert_eq!(same_phase(&four, 17, None), vec![17, 18, 19]);
        assert!(same_phase(&[], 0, Some(1.0)).is_empty());
    }

    /// One frame holds no evidence of persistence: no stationary stripes, with or without a
    /// known period.
    #[test]
    fn a_single_frame_has_no_persistence_window() {
        assert_eq!(persistence_window(&[2.0], 0, None, 10.0), None);
        assert_eq!(persistence_window(&[2.0], 0, Some(0.1), 10.0), None);
        assert_eq!(persistence_window(&[1.0, 2.0], 1, None, 10.0), None);
        assert_eq!(persistence_window(&[1.0, 2.0], 0, None, 10.0), Some(0));
    }

    fn evidence(contrast: f64, mobility: f64, tail: usize, stationary: usize) -> Evidence {
        Evidence {
            contrast,
            mobility,
            tail_stripe_count: tail,
            stationary_stripe_count: stationary,
        }
    }

    /// Far from every threshold the phase is robust; a run whose contrast sits just above
    /// the threshold and whose bands hold their place only over the shorter window is not,
    /// and the variants say which thresholds decide it.
    #[test]
    fn the_sensitivity_names_the_thresholds_that_decide() {
        let base = ClassifyParams::default();
        let strong = sensitivity(base, evidence(5.0, 3.0, 4, 4), |_| 4);
        assert_eq!(strong.variants.len(), 27);
        assert!(strong.robust());
        assert_eq!(strong.count(Phase::Stripes), 27);
        assert!(strong.variants.contains(&Variant {
            params: base,
            stationary_stripe_count: 4,
            phase: Phase::Stripes
        }));

        // Contrast 2.1: stripes unless the threshold rises to 2.5; bands stationary over 5
        // periods but not over 10 or 20.
        let edge = sensitivity(base, evidence(2.1, 3.0, 3, 0), |p| usize::from(p < 10.0));
        assert!(!edge.robust());
        for v in &edge.variants {
            let expect = if v.params.persistence_periods < 10.0 || v.params.contrast_min <= 2.1 {
                Phase::Stripes
            } else {
                Phase::Gas
            };
            assert_eq!(v.phase, expect, "{v:?}");
        }
        assert_eq!(edge.count(Phase::Gas), 6);
        assert_eq!(edge.count(Phase::Stripes), 21);

        // Mobility 0.15: `nothing` once the threshold doubles to 0.2.
        let slow = sensitivity(base, evidence(1.0, 0.15, 0, 0), |_| 0);
        assert_eq!(slow.count(Phase::Nothing), 9);
        assert_eq!(slow.count(Phase::Gas), 18);
    }

    #[test]
    fn the_decision_rule() {
        let p = ClassifyParams::default();
        let c = |contrast, mobility, tail, stationary| classify(evidence(contrast, mobility, tail, stationary), p).phase;
        assert_eq!(c(5.0, 0.001, 3, 3), Phase::Nothing);
        assert_eq!(c(1.0, 0.05, 0, 0), Phase::Nothing, "creep of a DEM below mu g");
        assert_eq!(c(5.0, 0.5, 3, 0), Phase::Stripes, "strong bands that move");
        assert_eq!(
            c(1.8, 0.5, 3, 3),
            Phase::Stripes,
            "bands that hold their place at a contrast below 2"
        );
        assert_eq!(c(1.8, 3.0, 0, 2), Phase::Stripes, "stationary bands whatever the grains between do");
        assert_eq!(c(5.0, 0.5, 0, 0), Phase::Gas);
        assert_eq!(c(1.0, 0.5, 2, 0), Phase::Gas, "short-lived bands");
        assert_eq!(c(1.0, f64::NAN, 0, 0), Phase::Gas, "unknown mobility: not `nothing`");
        assert_eq!(Phase::Stripes.name(), "stripes");
    }

    #[test]
    fn the_persistence_window_covers_the_last_periods_or_the_tail() {
        let t: Vec<f64> = (0..30).map(|k| 0.1 * k as f64).collect(); // 2.9 s, period 0.1 s
        assert_eq!(persistence_window(&t, 27, Some(0.1), 10.0), Some(19), "t >= 1.9 s");
        assert_eq!(persistence_window(&t, 5, Some(0.1), 10.0), Some(5), "a longer tail wins");
        assert_eq!(persistence_window(&t, 27, Some(0.1), 29.0), Some(0), "exactly the run");
        assert_eq!(persistence_window(&t, 27, Some(0.1), 30.0), None, "run too short");
        assert_eq!(persistence_window(&t, 27, None, 10.0), Some(27));
        assert_eq!(persistence_window(&[], 0, Some(0.1), 10.0), None);
        assert_eq!(time_average(&[vec![1.0, 2.0], vec![3.0, 6.0]]), vec![2.0, 4.0]);
    }

    #[test]
    fn independent_uniform_grains_have_the_reference_sigma() {
        // Overlapping grains at independent uniform positions: the measured std over cells,
        // averaged over layers, matches the closed form.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (l, w, cells) = (0.4, 0.02, 400);
        let r: Vec<f64> = (0..4000).map(|_| rng.gen_range(2.5e-4..5e-4)).collect();
        let sigma = random_layer_sigma(&r, l, w, cells);
        let mut var = 0.0;
        let layers = 40;
        for _ in 0..layers {
            let x: Vec<f64> = (0..r.len()).map(|_| rng.gen_range(0.0..l)).collect();
            var += cell_std(&area_fraction_cells(&x, &r, l, w, cells)).powi(2) / layers as f64;
        }
        let ratio = var.sqrt() / sigma;
        assert!((ratio - 1.0).abs() < 0.02, "measured / closed form = {ratio}");
    }
}
