//! The run measured as the experiment's camera measured it (thesis 2.2.5-2.2.6): a picture of
//! the tray from above at the shaker's turning point, its brightness averaged over y as the
//! density profile along x, and the stripes counted on that profile.
//!
//! - **Stroboscopic frames** ([`strobe`]): the experiment filmed "at every second turning
//!   point of the shaker", one picture per period at the same end of the stroke. Here: per
//!   drive period, the frame nearest the `+A` turning point of [`TrayDrive`] (`x_tray = +A`,
//!   phase `pi/2` of `A sin(2 pi nu t)`); how far each chosen frame is from it is kept
//!   ([`StrobeFrame::offset`], a fraction of the period) and summarised. The DEM's stripe
//!   scene writes 4 frames per period at phases 0, pi/2, pi, 3 pi/2, so its second frame of
//!   each period is exactly at the turning point; the automaton writes one state per period
//!   at the turning point. Without a drive every frame is kept.
//! - **Tray frame**: positions are taken relative to the tray, `x - x_tray(t)`, so that a band
//!   at rest on the floor stays at one x (the lab frame swings it by `+-A`).
//! - **Profile**: the exact cell average of the projected area fraction
//!   ([`crate::density::add_area_fraction_cells`]): the y-average of the covered width, the
//!   analogue of the camera's column-averaged brightness. Its smoothing length is the cell.
//! - **Count**: stripes of the profile with the analyzer's detector and thresholds
//!   ([`crate::stripes::detect`], [`crate::stripes::StripeParams::default_for`]): runs of
//!   cells above `k` times the layer's mean area fraction (`k = 1.5`, capped halfway to the
//!   jammed 0.82 at high packing), at least five mean grain diameters wide. The thesis counted
//!   by eye on such profiles "based on a density threshold" (3.3: 0.03/m; 3.4: 0.003-0.004/m),
//!   a fixed level in units that do not carry over between packings; the rule here is the
//!   one the classifier uses, so a run's label and its count come from one detector.
//! - **Onsets**: the *onset of clusters* is the first stroboscopic frame from which on the
//!   profile's contrast (cell standard deviation over that of a random layer,
//!   [`crate::classify::random_layer_sigma`]) stays at or above [`CLUSTER_CONTRAST`]: the
//!   layer is no longer a random one (thesis 2.2.6: "irregular clusters ... after about
//!   1 second"). The *onset of stripes* is the first stroboscopic frame from which on every
//!   frame holds at least one stripe ([`crate::stripes::onset`]).
//! - **Coarsening law** ([`crate::coarsening_law`]) on the count from its peak on (the first
//!   frame after the onset of stripes holding the most stripes: coarsening is the decay
//!   that follows the stripes' formation), and **lifetimes** ([`crate::lifetime`]) of the stripes tracked in the tray frame.

use serde::Serialize;

use crate::classify::{cell_std, random_layer_sigma};
use crate::coarsening_law::{compare, LawComparison};
use crate::density::{add_area_fraction_cells, mean_area_fraction};
use crate::drive::TrayDrive;
use crate::lifetime::{lifetimes, profile_correlation, track, CorrelationPoint, Lifetimes, Track};
use crate::snapshot::{Frame, Header};
use crate::stripes::{detect, onset, Stripe, StripeParams};

/// Contrast (x a random layer's) from which on a profile holds clusters. A random layer gives
/// at most about 1; the contrast of one random frame of 100 cells scatters by about
/// `1/sqrt(2 x 100) = 7 %`, so 1.5 lies seven of those above it.
pub const CLUSTER_CONTRAST: f64 = 1.5;

/// One frame of the stroboscopic series.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StrobeFrame {
    /// Index among the run's frames.
    pub frame: usize,
    pub time: f64,
    /// The tray's displacement at that time (m), subtracted from every x.
    pub tray_x: f64,
    /// Time from the nearest `+A` turning point, as a fraction of the drive period (None
    /// without a moving drive).
    pub offset: Option<f64>,
}

/// Frames farther than this from every `+A` turning point (in periods) are not used: at the
/// opposite end of the stroke the tray is `2 A` away.
pub const MAX_STROBE_OFFSET: f64 = 0.25;

/// The frames at the drive's `+A` turning points, one per period (the nearest to each, within
/// [`MAX_STROBE_OFFSET`]), or every frame when the drive does not move the tray at their times.
pub fn strobe(times: &[f64], drive: Option<&TrayDrive>) -> Vec<StrobeFrame> {
    let mut out: Vec<StrobeFrame> = Vec::new();
    let mut last_key = None;
    for (frame, &time) in times.iter().enumerate() {
        let tp = drive.and_then(|d| d.turning_point(time));
        if tp.is_some_and(|p| p.offset.abs() > MAX_STROBE_OFFSET + 1e-9) {
            continue;
        }
        let tray_x = drive.map_or(0.0, |d| d.displacement(time));
        let here = StrobeFrame {
            frame,
            time,
            tray_x,
            offset: tp.map(|p| p.offset),
        };
        let key = tp.map(|p| (p.stage, p.index));
        match (key, last_key) {
            (Some(k), Some(Some(l))) if k == l => {
                let prev = out.last_mut().expect("a frame of this period was kept");
                if here.offset.unwrap_or(0.0).abs() < prev.offset.unwrap_or(0.0).abs() {
                    *prev = here;
                }
            }
            _ => out.push(here),
        }
        last_key = Some(key);
    }
    out
}

/// The counting rule as stated in the output.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CountRule {
    /// Area-fraction threshold and minimum width (m).
    pub threshold: f64,
    pub min_width_m: f64,
    /// The threshold over the layer's mean area fraction (`k`).
    pub threshold_over_mean: f64,
    /// The profile's smoothing length (m): its cell.
    pub smoothing_m: f64,
    /// The contrast from which on a profile holds clusters.
    pub cluster_contrast: f64,
}

/// Everything the camera measures on a run.
#[derive(Clone, Debug, Serialize)]
pub struct Camera {
    pub rule: CountRule,
    /// The drive used for the tray frame and the turning points (None: none known).
    pub drive: Option<TrayDrive>,
    pub frames: Vec<StrobeFrame>,
    /// Tray-frame profiles of the stroboscopic frames: `profiles[k][cell]`.
    pub profiles: Vec<Vec<f64>>,
    pub stripes: Vec<Vec<Stripe>>,
    pub contrast: Vec<f64>,
    pub cluster_onset: Option<f64>,
    pub stripe_onset: Option<f64>,
    pub law: LawComparison,
    /// Time (s) of the first frame of the coarsening fit (None: no stripes).
    pub law_from: Option<f64>,
    pub tracks: Vec<Track>,
    pub lifetimes: Lifetimes,
    pub correlation: Vec<CorrelationPoint>,
    pub correlation_time: Option<f64>,
}

/// The tray-frame area-fraction profile of `frame` (positions less `tray_x`) on `cells` cells.
pub fn tray_profile(frame: &Frame, header: &Header, tray_x: f64, cells: usize) -> Vec<f64> {
    let x: Vec<f64> = frame.pos.iter().map(|p| p[0] - tray_x).collect();
    let mut phi = vec![0.0; cells];
    add_area_fraction_cells(&x, &header.radii, header.length, header.width, &mut phi);
    phi
}

/// The camera's measures of a run: `frames` (in time order) of a tray of `header`, its
/// `drive`, counted with `params` on `cells` cells over the tray's length.
pub fn measure(header: &Header, frames: &[Frame], drive: Option<&TrayDrive>, params: &StripeParams, cells: usize) -> Camera {
    let (l, w) = (header.length, header.width);
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    let chosen = strobe(&times, drive);
    let profiles: Vec<Vec<f64>> = chosen
        .iter()
        .map(|s| tray_profile(&frames[s.frame], header, s.tray_x, cells))
        .collect();
    let stripes: Vec<Vec<Stripe>> = profiles.iter().map(|p| detect(p, l, params)).collect();
    let sigma = random_layer_sigma(&header.radii, l, w, cells);
    let contrast: Vec<f64> = profiles
        .iter()
        .map(|p| if sigma > 0.0 { cell_std(p) / sigma } else { f64::NAN })
        .collect();
    let t: Vec<f64> = chosen.iter().map(|s| s.time).collect();
    let counts: Vec<usize> = stripes.iter().map(Vec::len).collect();
    let clustered: Vec<usize> = contrast.iter().map(|c| usize::from(*c >= CLUSTER_CONTRAST)).collect();
    let cluster_onset = if t.is_empty() { None } else { onset(&t, &clustered) };
    let (stripe_onset, from) = coarsening_start(&t, &counts);
    let law = compare(&t[from..], &counts[from..].iter().map(|&c| c as f64).collect::<Vec<_>>());
    let tracks = track(&t, &stripes, l);
    let lifetimes = lifetimes(&tracks, &t);
    let (correlation, correlation_time) = profile_correlation(&t, &profiles, t.len() / 2);
    let mean = mean_area_fraction(&header.radii, l, w);
    Camera {
        rule: CountRule {
            threshold: params.threshold,
            min_width_m: params.min_width,
            threshold_over_mean: params.threshold / mean,
            smoothing_m: l / cells as f64,
            cluster_contrast: CLUSTER_CONTRAST,
        },
        drive: drive.cloned(),
        frames: chosen,
        profiles,
        stripes,
        contrast,
        cluster_onset,
        stripe_onset,
        law,
        law_from: t.get(from).copied(),
        tracks,
        lifetimes,
        correlation,
        correlation_time,
    }
}

/// The onset of stripes of a count series (the first frame from which on every frame holds
/// one; `None` if none does) and the index the coarsening law is fitted from: coarsening is
/// the count's decay, fitted from the first frame after the onset holding the most stripes
/// to the end (`t.len()`, an empty fit, without an onset).
pub fn coarsening_start(t: &[f64], counts: &[usize]) -> (Option<f64>, usize) {
    let stripe_onset = if t.is_empty() { None } else { onset(t, counts) };
    let onset_at = stripe_onset.map_or(t.len(), |on| t.partition_point(|&x| x < on));
    let most = counts[onset_at..].iter().copied().max().unwrap_or(0);
    let from = onset_at + counts[onset_at..].iter().position(|&c| c == most).unwrap_or(0);
    (stripe_onset, from)
}

/// The camera's scalars, as written under `camera` in `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct CameraSummary {
    /// How the frames were chosen, in words.
    pub strobe: String,
    pub strobe_frames: usize,
    /// Largest and mean distance of a chosen frame from the turning point (fraction of a
    /// period; None without a drive).
    pub strobe_offset_max_periods: Option<f64>,
    pub strobe_offset_mean_periods: Option<f64>,
    pub drive: Option<TrayDrive>,
    pub rule: CountRule,
    pub stripe_count_first: usize,
    pub stripe_count_last: usize,
    pub stripe_count_max: usize,
    pub cluster_onset_s: Option<f64>,
    pub stripe_onset_s: Option<f64>,
    pub coarsening_law: LawComparison,
    /// Time (s) from which on the coarsening law is fitted (the count's peak).
    pub coarsening_from_s: Option<f64>,
    pub lifetimes: Lifetimes,
    /// Time (s) for the tray-frame profile's autocorrelation to fall below 1/e (None: it
    /// stays above over half the run).
    pub profile_correlation_time_s: Option<f64>,
}

impl Camera {
    pub fn summary(&self) -> CameraSummary {
        let offsets: Vec<f64> = self.frames.iter().filter_map(|f| f.offset.map(f64::abs)).collect();
        let counts: Vec<usize> = self.stripes.iter().map(Vec::len).collect();
        let strobe = match (&self.drive, offsets.is_empty()) {
            (Some(_), false) => {
                "one frame per drive period, the nearest to the +A turning point (x_tray = +A), positions relative to the tray".to_string()
            }
            _ => "every frame (no moving drive known), positions as stored".to_string(),
        };
        CameraSummary {
            strobe,
            strobe_frames: self.frames.len(),
            strobe_offset_max_periods: offsets.iter().copied().max_by(f64::total_cmp),
            strobe_offset_mean_periods: (!offsets.is_empty()).then(|| offsets.iter().sum::<f64>() / offsets.len() as f64),
            drive: self.drive.clone(),
            rule: self.rule,
            stripe_count_first: counts.first().copied().unwrap_or(0),
            stripe_count_last: counts.last().copied().unwrap_or(0),
            stripe_count_max: counts.iter().copied().max().unwrap_or(0),
            cluster_onset_s: self.cluster_onset,
            stripe_onset_s: self.stripe_onset,
            coarsening_law: self.law.clone(),
            coarsening_from_s: self.law_from,
            lifetimes: self.lifetimes,
            profile_correlation_time_s: self.correlation_time,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const L: f64 = 0.1;
    const W: f64 = 0.02;
    const R: f64 = 0.4e-3;

    /// A tray of `n` grains of radius R: `bands` (centre, width) in the tray frame take
    /// `fill` of the grains on a hexagonal-ish grid, the rest spread evenly; the frame is in
    /// the lab frame, shifted by `tray_x`.
    fn frame(time: f64, tray_x: f64, bands: &[(f64, f64)], n: usize) -> Frame {
        let mut pos = Vec::with_capacity(n);
        let d = 2.0 * R;
        let rows = (W / d).floor() as usize;
        for &(c, w) in bands {
            let cols = (w / d).floor() as usize;
            for i in 0..cols {
                for j in 0..rows {
                    pos.push([c - 0.5 * w + (i as f64 + 0.5) * d + tray_x, (j as f64 + 0.5) * d, R]);
                }
            }
        }
        let rest = n.saturating_sub(pos.len());
        for k in 0..rest {
            // Spread evenly over the tray, off the bands' centres.
            let x = (k as f64 + 0.5) * L / rest as f64;
            let y = ((k * 7) % rows) as f64 * d + R;
            pos.push([x + tray_x, y, R]);
        }
        pos.truncate(n);
        Frame {
            time,
            vel: vec![[0.0; 3]; pos.len()],
            pos,
        }
    }

    #[test]
    fn strobe_keeps_the_turning_point_of_each_period() {
        let drive = TrayDrive::harmonic(0.01, 3.0).unwrap();
        // Four frames per period at phases 0, pi/2, pi, 3 pi/2: the second of each.
        let times: Vec<f64> = (0..12).map(|k| k as f64 / 12.0).collect();
        let s = strobe(&times, Some(&drive));
        assert_eq!(s.iter().map(|f| f.frame).collect::<Vec<_>>(), vec![1, 5, 9]);
        assert!(s.iter().all(|f| f.offset.unwrap().abs() < 1e-12 && (f.tray_x - 0.01).abs() < 1e-12));
        // One frame per period at phase 0: all kept, a quarter period from the turning point.
        let times: Vec<f64> = (0..5).map(|k| k as f64 / 3.0).collect();
        let s = strobe(&times, Some(&drive));
        assert_eq!(s.len(), 5);
        assert!(s.iter().all(|f| (f.offset.unwrap() + 0.25).abs() < 1e-9));
        // No drive: every frame, unshifted.
        assert_eq!(strobe(&times, None).len(), 5);
    }

    #[test]
    fn bands_shifted_by_the_tray_are_counted_in_the_tray_frame_with_their_onsets() {
        let drive = TrayDrive::harmonic(0.01, 3.0).unwrap();
        let n = 1600;
        let bands = [(0.02, 0.012), (0.055, 0.010), (0.085, 0.014)];
        // Four frames per period over 8 periods: homogeneous for the first 3 periods, then a
        // three narrow dense spots from period 3 (clusters, narrower than a stripe), then three
        // bands from period 5 (stripes).
        let frames: Vec<Frame> = (0..32)
            .map(|k| {
                let t = k as f64 / 12.0;
                let x = drive.displacement(t);
                match k / 4 {
                    0..=2 => frame(t, x, &[], n),
                    3 | 4 => frame(t, x, &[(0.02, 0.0024), (0.05, 0.0024), (0.08, 0.0024)], n),
                    _ => frame(t, x, &bands, n),
                }
            })
            .collect();
        let header = Header {
            length: L,
            width: W,
            radii: vec![R; n],
        };
        let mean = mean_area_fraction(&header.radii, L, W);
        let params = StripeParams::default_for(mean, 2.0 * R);
        let cam = measure(&header, &frames, Some(&drive), &params, 100);
        assert_eq!(cam.frames.len(), 8);
        let counts: Vec<usize> = cam.stripes.iter().map(Vec::len).collect();
        assert_eq!(counts, vec![0, 0, 0, 0, 0, 3, 3, 3], "{:?}", cam.stripes);
        for (s, (c, w)) in cam.stripes[7].iter().zip(bands) {
            assert!((s.center - c).abs() < 1e-3 && (s.width - w).abs() <= 2e-3, "{s:?} vs {c}, {w}");
        }
        let t = |period: usize| (period as f64 + 0.25) / 3.0;
        assert!((cam.stripe_onset.unwrap() - t(5)).abs() < 1e-12);
        assert!((cam.cluster_onset.unwrap() - t(3)).abs() < 1e-12, "{:?}", cam.contrast);
        // In the lab frame the same frames' bands would sit 10 mm off.
        let lab = detect(&tray_profile(&frames[29], &header, 0.0, 100), L, &params);
        assert!((lab[0].center - bands[0].0 - 0.01).abs() < 1e-3, "{lab:?}");
        let sum = cam.summary();
        assert_eq!((sum.stripe_count_first, sum.stripe_count_last), (0, 3));
        assert!(sum.strobe_offset_max_periods.unwrap() < 1e-12);
        assert!((sum.rule.threshold_over_mean - params.threshold / mean).abs() < 1e-12);
        // Three stripes from period 5 to the end: censored, no complete lifetime.
        assert_eq!((sum.lifetimes.tracks, sum.lifetimes.complete), (3, 0));
    }
}
