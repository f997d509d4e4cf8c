//! The whole analysis of one run, as one library call: [`analyze`] (frames in memory) or
//! [`Analyzer`] (frames streamed in batches, for runs too large to hold). The CLI
//! (`stripes analyze`) and other studies (`stripes compare`, phase maps) call this and only
//! write and plot what it returns.
//!
//! Per frame: the exact cell-averaged area fraction ([`crate::density`]) forming the
//! space-time map, its stripes ([`crate::stripes`]), coarsening point and contrast. Over
//! frames: the stripe onset, `D` per period with plateau fits ([`crate::msd`]), its
//! autocorrelation ([`crate::autocorr`]), the tracer ([`crate::tracer`]), the radius
//! distribution inside the stripes of the final-state frames ([`crate::segregation`]) and the phase
//! ([`crate::classify`]).
//!
//! Frames are analysed in parallel (rayon) within a batch; every per-frame quantity is
//! computed by one thread in a fixed order, so results do not depend on the thread count.

use std::collections::VecDeque;

use rayon::prelude::*;
use serde::Serialize;

use crate::autocorr;
use crate::classify::{
    cell_std, classify, persistence_window, random_layer_sigma, same_phase, sensitivity, time_average, Classification, ClassifyParams,
    Evidence, Phase, Sensitivity,
};
use crate::density::{add_area_fraction_cells, mean_area_fraction};
use crate::msd::{flat_plateau, half_msd, median_spacing, MsdPoint, Plateau, PLATEAU_FLATNESS};
use crate::segregation::{RadiusBins, RadiusDistribution, RadiusTally};
use crate::snapshot::{Frame, Header};
use crate::stripes::{detect, dominant_spacing, onset, Coarsening, Stripe, StripeParams};
use crate::structure::{in_band_fraction, peak, structure_factor, widths_and_gaps, Peak, Structure};
use crate::tracer::Tracer;

/// Settings of the analysis. [`Options::default`] gives the documented defaults.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Options {
    /// Cell width of the area-fraction map (m) [1e-3]; rounded so cells tile `L`.
    pub cell: f64,
    /// Stripe threshold on the area fraction [None: [`StripeParams::default_for`]].
    pub threshold: Option<f64>,
    /// Minimum stripe width (m) [None: [`StripeParams::default_for`]].
    pub min_width: Option<f64>,
    /// Drive period `T` (s) for `D` [None: the median spacing of the snapshots].
    pub period: Option<f64>,
    /// Two frames are one period apart when their spacing is within this fraction of `T` [0.1].
    pub period_tolerance: f64,
    /// Whether y is periodic too (walls off) for displacements [false].
    pub periodic_y: bool,
    /// Index of the tracer grain [0].
    pub tracer: usize,
    /// Fraction of the frames, at the end, that make the final state [0.1].
    pub tail_fraction: f64,
    /// Window of the plateau `a1` of `D` (s) [None: the first three quarters of the time
    /// before the stripe onset (the rise of `D` ahead of the onset left out), or the first
    /// half of the run without onset].
    pub plateau_before: Option<(f64, f64)>,
    /// Window of the plateau `a2` (s) [None: from the onset plus a quarter of the time left
    /// to the end, or the second half of the run without onset].
    pub plateau_after: Option<(f64, f64)>,
    /// Bins of the radius histograms [20].
    pub radius_bins: usize,
    /// Largest lag of the autocorrelation, in samples [None: half the series].
    pub max_lag: Option<usize>,
    /// Classifier thresholds.
    pub classify: ClassifyParams,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            cell: 1e-3,
            threshold: None,
            min_width: None,
            period: None,
            period_tolerance: 0.1,
            periodic_y: false,
            tracer: 0,
            tail_fraction: 0.1,
            plateau_before: None,
            plateau_after: None,
            radius_bins: 20,
            max_lag: None,
            classify: ClassifyParams::default(),
        }
    }
}

/// One lag of the autocorrelation of `D`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AutocorrPoint {
    /// Lag in samples and in seconds (`lag * T`).
    pub lag: usize,
    pub lag_s: f64,
    /// Eq 3.32 summed over the available pairs (m^4).
    pub raw: f64,
    /// Autocorrelation coefficient (1 at lag 0).
    pub normalised: f64,
}

/// Everything the analysis finds in a run.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub particles: usize,
    pub frames: usize,
    /// Box length L (m, periodic x) and width W (m).
    pub length: f64,
    pub width: f64,
    /// `sum pi r^2 / (L W)`.
    pub mean_area_fraction: f64,
    /// Mean grain diameter (m).
    pub mean_diameter: f64,
    /// Cell width actually used (m) and number of cells.
    pub cell: f64,
    pub cells: usize,
    pub stripe_params: StripeParams,
    /// Drive period used for `D` (s; None with a single frame).
    pub period: Option<f64>,
    /// Frame times (s).
    pub times: Vec<f64>,
    /// Space-time map of the area fraction: `density_map[frame][cell]`.
    pub density_map: Vec<Vec<f64>>,
    /// Stripes of each frame.
    pub stripes: Vec<Vec<Stripe>>,
    /// Coarsening curve, one point per frame.
    pub coarsening: Vec<Coarsening>,
    /// Stripe onset (s), see [`crate::stripes::onset`].
    pub onset: Option<f64>,
    /// Stripe spacing (m): the dominant wavelength of the time-averaged profile over the
    /// persistence window ([`crate::stripes::dominant_spacing`], at most twice as many bands
    /// as it holds stationary stripes), when it holds any.
    pub spacing: Option<f64>,
    /// Contrast of each frame (see [`crate::classify`]).
    pub contrast_series: Vec<f64>,
    /// `D` per period (eq 3.30).
    pub msd: Vec<MsdPoint>,
    pub plateau_before: Option<Plateau>,
    pub plateau_after: Option<Plateau>,
    /// Why there is no `plateau_before` / `plateau_after` (not flat, too few points, no window).
    pub plateau_before_note: Option<String>,
    pub plateau_after_note: Option<String>,
    /// Autocorrelation of `D` (eq 3.32).
    pub autocorrelation: Vec<AutocorrPoint>,
    pub tracer: Tracer,
    /// Radii inside the stripes of the final-state (tail) frames against the whole layer.
    pub radii: RadiusDistribution,
    pub classification: Classification,
    /// The phase under thresholds around the given ones ([`crate::classify::sensitivity`]).
    pub sensitivity: Sensitivity,
    /// The structure of every frame: S(k) peak and fraction of grains in bands.
    pub structure: Vec<StructurePoint>,
    /// The late-time structure (the tail frames): S(k) averaged, band widths pooled.
    pub late: Structure,
    /// Gaps between neighbouring bands of the tail frames, pooled (m).
    pub late_gaps: Vec<f64>,
}

impl Report {
    /// The phase, or None with the reason when the frames cannot tell it: without two frames
    /// one drive period apart there is no mobility, and `nothing` cannot be told from `gas`.
    pub fn phase(&self) -> Result<Phase, ReportError> {
        if self.msd.is_empty() {
            return Err(ReportError::NoMobility { frames: self.frames });
        }
        Ok(self.classification.phase)
    }
}

/// How many threshold sets of the sensitivity sweep give each phase.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, serde::Deserialize)]
pub struct PhaseVotes {
    pub nothing: usize,
    pub stripes: usize,
    pub gas: usize,
}

/// The scalar results, as written to `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub particles: usize,
    pub frames: usize,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub period_s: Option<f64>,
    pub mean_area_fraction: f64,
    pub stripe_params: StripeParams,
    pub stripe_count_final: usize,
    pub stripe_onset_s: Option<f64>,
    pub stripe_mean_width_final_m: Option<f64>,
    /// Dominant wavelength of the stationary bands (m), see [`Report::spacing`].
    pub stripe_spacing_m: Option<f64>,
    /// None when the frames cannot tell it; `phase_note` says why.
    pub phase: Option<Phase>,
    pub phase_note: Option<String>,
    pub contrast: f64,
    pub mobility: f64,
    pub tail_stripe_count: usize,
    pub stationary_stripe_count: usize,
    pub classify_params: ClassifyParams,
    /// Whether the phase is the same under every threshold set of the sensitivity sweep
    /// (`phase_sensitivity.csv`), and how many of its 27 sets give each phase.
    pub phase_robust: bool,
    pub phase_votes: PhaseVotes,
    pub msd_plateau_before: Option<f64>,
    pub msd_plateau_before_stderr: Option<f64>,
    pub msd_plateau_before_window_s: Option<(f64, f64)>,
    pub msd_plateau_before_note: Option<String>,
    pub msd_plateau_after: Option<f64>,
    pub msd_plateau_after_stderr: Option<f64>,
    pub msd_plateau_after_window_s: Option<(f64, f64)>,
    pub msd_plateau_after_note: Option<String>,
    pub tracer: usize,
    pub radius_mean_m: f64,
    pub radius_mean_in_stripes_m: Option<f64>,
    pub radius_relative_change: Option<f64>,
    /// The late-time S(k) peak: spacing (m), height and full width at half maximum (rad/m).
    pub spacing_m: Option<f64>,
    pub structure_peak_height: Option<f64>,
    pub structure_peak_width_per_m: Option<f64>,
    /// Mean width of the tail frames' bands and of the gaps between them (m).
    pub band_width_m: Option<f64>,
    pub band_gap_m: Option<f64>,
    /// Mean fraction of grains in bands over the tail frames.
    pub in_band_fraction: f64,
}

impl Report {
    /// The scalars of the report (see [`Summary`]).
    pub fn summary(&self) -> Summary {
        let last = self.coarsening.last();
        let finite = |v: f64| v.is_finite().then_some(v);
        Summary {
            particles: self.particles,
            frames: self.frames,
            t_start_s: self.times.first().copied().unwrap_or(f64::NAN),
            t_end_s: self.times.last().copied().unwrap_or(f64::NAN),
            period_s: self.period,
            mean_area_fraction: self.mean_area_fraction,
            stripe_params: self.stripe_params,
            stripe_count_final: last.map_or(0, |c| c.count),
            stripe_onset_s: self.onset,
            stripe_mean_width_final_m: last.and_then(|c| finite(c.mean_width)),
            stripe_spacing_m: self.spacing,
            phase: self.phase().ok(),
            phase_note: self.phase().err().map(|e| e.to_string()),
            contrast: self.classification.contrast,
            mobility: self.classification.mobility,
            tail_stripe_count: self.classification.tail_stripe_count,
            stationary_stripe_count: self.classification.stationary_stripe_count,
            classify_params: self.classification.params,
            phase_robust: self.sensitivity.robust(),
            phase_votes: PhaseVotes {
                nothing: self.sensitivity.count(Phase::Nothing),
                stripes: self.sensitivity.count(Phase::Stripes),
                gas: self.sensitivity.count(Phase::Gas),
            },
            msd_plateau_before: self.plateau_before.map(|p| p.value),
            msd_plateau_before_stderr: self.plateau_before.map(|p| p.stderr),
            msd_plateau_before_window_s: self.plateau_before.map(|p| (p.from, p.to)),
            msd_plateau_before_note: self.plateau_before_note.clone(),
            msd_plateau_after: self.plateau_after.map(|p| p.value),
            msd_plateau_after_stderr: self.plateau_after.map(|p| p.stderr),
            msd_plateau_after_window_s: self.plateau_after.map(|p| (p.from, p.to)),
            msd_plateau_after_note: self.plateau_after_note.clone(),
            tracer: self.tracer.index,
            radius_mean_m: self.radii.mean_whole,
            radius_mean_in_stripes_m: finite(self.radii.mean_stripes),
            radius_relative_change: finite(self.radii.relative_change),
            spacing_m: peak(&self.late.s).map(|p| p.spacing),
            structure_peak_height: peak(&self.late.s).map(|p| p.height),
            structure_peak_width_per_m: peak(&self.late.s).map(|p| p.width),
            band_width_m: mean(&self.late.band_widths),
            band_gap_m: mean(&self.late_gaps),
            in_band_fraction: {
                let tail = &self.structure[self.structure.len() - self.structure.len().div_ceil(10)..];
                tail.iter().map(|p| p.in_band_fraction).sum::<f64>() / tail.len().max(1) as f64
            },
        }
    }
}

fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// Analyses frames in memory: [`Analyzer`] with the period taken from the snapshot
/// spacing unless given, fed in batches.
pub fn analyze(header: &Header, frames: &[Frame], opts: &Options) -> Result<Report, ReportError> {
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    let period = opts.period.or_else(|| median_spacing(&times));
    let mut a = Analyzer::new(header, opts, period)?;
    for batch in frames.chunks(64) {
        a.push(batch)?;
    }
    a.finish()
}

/// Input the analysis refuses, or a result the frames cannot give; each names the field,
/// grain or frame at fault.
#[derive(Clone, Debug, PartialEq)]
pub enum ReportError {
    /// The box length L (m) is not positive.
    BoxLength { length: f64 },
    /// The box width W (m) is not positive.
    BoxWidth { width: f64 },
    /// The header lists no grain.
    NoGrains,
    /// A grain's radius (m) lies outside (0, L/2).
    Radius { grain: usize, radius: f64 },
    /// The density cell (m) lies outside (0, L].
    Cell { cell: f64, length: f64 },
    /// The density cell gives more than 1e7 cells.
    TooManyCells { cell: f64, cells: usize },
    /// The drive period (s) is not positive.
    Period { period: f64 },
    /// `tail_fraction` lies outside (0, 1].
    TailFraction { value: f64 },
    /// `period_tolerance` lies outside (0, 0.5).
    PeriodTolerance { value: f64 },
    /// The tracer's index is not a grain of the run.
    Tracer { tracer: usize, grains: usize },
    /// The stripe threshold or minimum width (m) is not finite, or the width is negative.
    StripeParams { threshold: f64, min_width: f64 },
    /// A frame does not hold one position and one velocity per grain.
    FrameSize {
        frame: usize,
        time: f64,
        positions: usize,
        velocities: usize,
        grains: usize,
    },
    /// A grain's position in a frame is NaN or infinite.
    NonFinitePosition {
        frame: usize,
        time: f64,
        grain: usize,
        position: [f64; 3],
    },
    /// A frame's time (s) is not finite or does not come after the previous frame's.
    TimeOrder { frame: usize, time: f64 },
    /// No frame was given.
    NoFrames,
    /// No two frames lie one drive period apart, so there is no mobility and no phase.
    NoMobility { frames: usize },
}

impl std::fmt::Display for ReportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReportError::BoxLength { length } => write!(f, "box length L = {length} m must be positive"),
            ReportError::BoxWidth { width } => write!(f, "box width W = {width} m must be positive"),
            ReportError::NoGrains => f.write_str("the run holds no grains"),
            ReportError::Radius { grain, radius } => write!(f, "grain {grain}: radius {radius} m must lie in (0, L/2)"),
            ReportError::Cell { cell, length } => write!(f, "cell = {cell} m must lie in (0, L = {length} m]"),
            ReportError::TooManyCells { cell, cells } => {
                write!(f, "cell = {cell} m gives {cells} cells; use at least L / 1e7")
            }
            ReportError::Period { period } => write!(f, "period = {period} s must be positive"),
            ReportError::TailFraction { value } => write!(f, "tail_fraction = {value} must lie in (0, 1]"),
            ReportError::PeriodTolerance { value } => write!(f, "period_tolerance = {value} must lie in (0, 0.5)"),
            ReportError::Tracer { tracer, grains } => {
                write!(f, "tracer = {tracer} but the run has {grains} grains (0-based index)")
            }
            ReportError::StripeParams { threshold, min_width } => write!(
                f,
                "stripe threshold {threshold} and min_width {min_width} m must be finite, min_width >= 0"
            ),
            ReportError::FrameSize {
                frame,
                time,
                positions,
                velocities,
                grains,
            } => write!(
                f,
                "frame {frame} (t = {time} s) holds {positions} positions and {velocities} velocities for {grains} grains"
            ),
            ReportError::NonFinitePosition {
                frame,
                time,
                grain,
                position,
            } => write!(
                f,
                "frame {frame} (t = {time} s): grain {grain} has a non-finite position {position:?}"
            ),
            ReportError::TimeOrder { frame, time } => {
                write!(f, "frame {frame}: time {time} s does not follow the previous frame's")
            }
            ReportError::NoFrames => f.write_str("no frame to analyse"),
            ReportError::NoMobility { frames } => write!(
                f,
                "too few frames for a phase: {frames} frame(s) and no two one drive period apart, so no mobility"
            ),
        }
    }
}

impl std::error::Error for ReportError {}

/// Per-frame results computed in parallel.
struct FrameResult {
    phi: Vec<f64>,
    stripes: Vec<Stripe>,
    std: f64,
    radii: RadiusTally,
    s: Vec<(f64, f64)>,
    in_band: f64,
}

/// The structure of one frame ([`crate::structure`]).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct StructurePoint {
    pub time: f64,
    /// The peak of S(k), if any mode rises above the independent level.
    pub peak: Option<Peak>,
    /// Fraction of the grains inside bands.
    pub in_band_fraction: f64,
}

/// Streaming analysis: feed frames in time order with [`Analyzer::push`], then
/// [`Analyzer::finish`].
pub struct Analyzer {
    header: Header,
    opts: Options,
    period: Option<f64>,
    cells: usize,
    mean_phi: f64,
    mean_d: f64,
    params: StripeParams,
    sigma_random: f64,
    times: Vec<f64>,
    map: Vec<Vec<f64>>,
    stripes: Vec<Vec<Stripe>>,
    contrast: Vec<f64>,
    msd: Vec<MsdPoint>,
    recent: VecDeque<(f64, Vec<[f64; 3]>)>,
    tracer: Tracer,
    radius_bins: RadiusBins,
    radius_tallies: Vec<RadiusTally>,
    modes: usize,
    structure: Vec<StructurePoint>,
    spectra: Vec<Vec<(f64, f64)>>,
}

impl Analyzer {
    /// Checks the header and options (errors name the field or grain) and prepares the
    /// analysis; `period` (s) is the drive period for `D` (None: no `D`).
    pub fn new(header: &Header, opts: &Options, period: Option<f64>) -> Result<Self, ReportError> {
        let (l, w) = (header.length, header.width);
        if !(l.is_finite() && l > 0.0) {
            return Err(ReportError::BoxLength { length: l });
        }
        if !(w.is_finite() && w > 0.0) {
            return Err(ReportError::BoxWidth { width: w });
        }
        if header.radii.is_empty() {
            return Err(ReportError::NoGrains);
        }
        for (i, &r) in header.radii.iter().enumerate() {
            if !(r.is_finite() && r > 0.0 && 2.0 * r < l) {
                return Err(ReportError::Radius { grain: i, radius: r });
            }
        }
        if !(opts.cell.is_finite() && opts.cell > 0.0 && opts.cell <= l) {
            return Err(ReportError::Cell {
                cell: opts.cell,
                length: l,
            });
        }
        let cells = (l / opts.cell).round().max(1.0) as usize;
        if cells > 10_000_000 {
            return Err(ReportError::TooManyCells { cell: opts.cell, cells });
        }
        if let Some(p) = period {
            if !(p.is_finite() && p > 0.0) {
                return Err(ReportError::Period { period: p });
            }
        }
        if !(opts.tail_fraction > 0.0 && opts.tail_fraction <= 1.0) {
            return Err(ReportError::TailFraction { value: opts.tail_fraction });
        }
        if !(opts.period_tolerance > 0.0 && opts.period_tolerance < 0.5) {
            return Err(ReportError::PeriodTolerance {
                value: opts.period_tolerance,
            });
        }
        if opts.tracer >= header.radii.len() {
            return Err(ReportError::Tracer {
                tracer: opts.tracer,
                grains: header.radii.len(),
            });
        }
        let mean_phi = mean_area_fraction(&header.radii, l, w);
        let mean_d = 2.0 * header.radii.iter().sum::<f64>() / header.radii.len() as f64;
        let mut params = StripeParams::default_for(mean_phi, mean_d);
        if let Some(t) = opts.threshold {
            params.threshold = t;
        }
        if let Some(m) = opts.min_width {
            params.min_width = m;
        }
        if !(params.threshold.is_finite() && params.min_width.is_finite() && params.min_width >= 0.0) {
            return Err(ReportError::StripeParams {
                threshold: params.threshold,
                min_width: params.min_width,
            });
        }
        Ok(Self {
            header: header.clone(),
            opts: opts.clone(),
            period,
            cells,
            mean_phi,
            mean_d,
            params,
            sigma_random: random_layer_sigma(&header.radii, l, w, cells),
            times: Vec::new(),
            map: Vec::new(),
            stripes: Vec::new(),
            contrast: Vec::new(),
            msd: Vec::new(),
            recent: VecDeque::new(),
            tracer: Tracer::new(opts.tracer, header.radii[opts.tracer]),
            radius_bins: RadiusBins::of(&header.radii, opts.radius_bins),
            radius_tallies: Vec::new(),
            // Wavelengths down to two mean diameters, at most 400 modes.
            modes: ((l / (2.0 * mean_d)).floor() as usize).clamp(1, 400),
            structure: Vec::new(),
            spectra: Vec::new(),
        })
    }

    /// Analyses the next frames (in time order, after those already pushed).
    pub fn push(&mut self, frames: &[Frame]) -> Result<(), ReportError> {
        let n = self.header.radii.len();
        for (k, f) in frames.iter().enumerate() {
            let index = self.times.len() + k;
            if f.pos.len() != n || f.vel.len() != n {
                return Err(ReportError::FrameSize {
                    frame: index,
                    time: f.time,
                    positions: f.pos.len(),
                    velocities: f.vel.len(),
                    grains: n,
                });
            }
            if let Some(i) = f.pos.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
                return Err(ReportError::NonFinitePosition {
                    frame: index,
                    time: f.time,
                    grain: i,
                    position: f.pos[i],
                });
            }
            let before = if k > 0 {
                Some(frames[k - 1].time)
            } else {
                self.times.last().copied()
            };
            if !f.time.is_finite() || before.is_some_and(|b| f.time <= b) {
                return Err(ReportError::TimeOrder {
                    frame: index,
                    time: f.time,
                });
            }
        }
        let (l, w, cells) = (self.header.length, self.header.width, self.cells);
        let radii = &self.header.radii;
        let params = self.params;
        let bins = self.radius_bins;
        let modes = self.modes;
        let results: Vec<FrameResult> = frames
            .par_iter()
            .map(|f| {
                let x: Vec<f64> = f.pos.iter().map(|p| p[0]).collect();
                let mut phi = vec![0.0; cells];
                add_area_fraction_cells(&x, radii, l, w, &mut phi);
                let stripes = detect(&phi, l, &params);
                let std = cell_std(&phi);
                let mut tally = RadiusTally::new(&bins);
                tally.add_frame_on_cells(&x, radii, &stripes, l, cells, &bins);
                let s = structure_factor(&x, l, modes);
                let in_band = in_band_fraction(&x, &stripes, l);
                FrameResult {
                    phi,
                    stripes,
                    std,
                    radii: tally,
                    s,
                    in_band,
                }
            })
            .collect();
        for (f, r) in frames.iter().zip(results) {
            self.times.push(f.time);
            self.contrast.push(if self.sigma_random > 0.0 {
                r.std / self.sigma_random
            } else {
                f64::NAN
            });
            self.map.push(r.phi);
            self.structure.push(StructurePoint {
                time: f.time,
                peak: peak(&r.s),
                in_band_fraction: r.in_band,
            });
            self.spectra.push(r.s);
            self.stripes.push(r.stripes);
            self.radius_tallies.push(r.radii);
            let t = self.opts.tracer;
            self.tracer.push(f.time, f.pos[t], f.vel[t], l);
            if let Some(period) = self.period {
                let tol = self.opts.period_tolerance * period;
                while self.recent.front().is_some_and(|(s, _)| *s < f.time - period - tol) {
                    self.recent.pop_front();
                }
                let partner = self
                    .recent
                    .iter()
                    .filter(|(s, _)| (f.time - s - period).abs() <= tol)
                    .min_by(|a, b| (f.time - a.0 - period).abs().total_cmp(&(f.time - b.0 - period).abs()));
                if let Some((_, old)) = partner {
                    let d = half_msd(old, &f.pos, l, w, self.opts.periodic_y);
                    self.msd.push(MsdPoint { time: f.time, d });
                }
                self.recent.push_back((f.time, f.pos.clone()));
            }
        }
        Ok(())
    }

    /// Completes the analysis; fails when no frame was pushed.
    pub fn finish(self) -> Result<Report, ReportError> {
        let m = self.times.len();
        if m == 0 {
            return Err(ReportError::NoFrames);
        }
        let (l, t0, t_end) = (self.header.length, self.times[0], self.times[m - 1]);
        let counts: Vec<usize> = self.stripes.iter().map(Vec::len).collect();
        let onset_s = onset(&self.times, &counts);
        let coarsening: Vec<Coarsening> = self
            .times
            .iter()
            .zip(&self.stripes)
            .map(|(&t, s)| Coarsening::of(t, s, self.mean_phi, l))
            .collect();

        // Final state: the tail frames.
        let tail_from = ((m as f64 * (1.0 - self.opts.tail_fraction)).floor() as usize).min(m - 1);
        let t_tail = self.times[tail_from];
        let tail_n = (m - tail_from) as f64;
        let late_s: Vec<(f64, f64)> = (0..self.spectra[0].len())
            .map(|j| {
                (
                    self.spectra[0][j].0,
                    self.spectra[tail_from..].iter().map(|sp| sp[j].1).sum::<f64>() / tail_n,
                )
            })
            .collect();
        let (mut late_widths, mut late_gaps) = (Vec::new(), Vec::new());
        for st in &self.stripes[tail_from..] {
            let (w, g) = widths_and_gaps(st, l);
            late_widths.extend(w);
            late_gaps.extend(g);
        }
        let late = Structure {
            s: late_s,
            band_widths: late_widths,
        };
        let contrast = self.contrast[tail_from..].iter().sum::<f64>() / (m - tail_from) as f64;
        let mut tail_counts = counts[tail_from..].to_vec();
        tail_counts.sort_unstable();
        let tail_count = tail_counts[tail_counts.len() / 2];
        let tail_d: Vec<f64> = self.msd.iter().filter(|p| p.time >= t_tail).map(|p| p.d).collect();
        let tail_d = if tail_d.is_empty() {
            self.msd.iter().map(|p| p.d).collect()
        } else {
            tail_d
        };
        let mobility = if tail_d.is_empty() {
            f64::NAN
        } else {
            (2.0 * tail_d.iter().sum::<f64>() / tail_d.len() as f64).sqrt() / self.mean_d
        };
        // The persistence window's frames at the last frame's phase of the drive (see
        // [`same_phase`]).
        let averaged_over = |periods: f64| {
            persistence_window(&self.times, tail_from, self.period, periods).map(|from| {
                let frames: Vec<Vec<f64>> = same_phase(&self.times, from, self.period)
                    .into_iter()
                    .map(|i| self.map[i].clone())
                    .collect();
                time_average(&frames)
            })
        };
        let averaged = averaged_over(self.opts.classify.persistence_periods);
        let stationary = averaged.as_ref().map_or(0, |p| detect(p, l, &self.params).len());
        let spacing = averaged
            .as_ref()
            .filter(|_| stationary > 0)
            .and_then(|p| dominant_spacing(p, l, 2 * stationary));
        let evidence = Evidence {
            contrast,
            mobility,
            tail_stripe_count: tail_count,
            stationary_stripe_count: stationary,
        };
        let classification = classify(evidence, self.opts.classify);
        let sensitivity = sensitivity(self.opts.classify, evidence, |periods| {
            averaged_over(periods).map_or(0, |p| detect(&p, l, &self.params).len())
        });

        // Plateaus of D.
        let (before, after) = match onset_s {
            Some(on) => {
                let before = (on > t0).then_some((t0, on - 0.25 * (on - t0)));
                (before, Some((on + 0.25 * (t_end - on), t_end)))
            }
            None => {
                let mid = t0 + 0.5 * (t_end - t0);
                (Some((t0, mid)), Some((mid, t_end)))
            }
        };
        let window = |given: Option<(f64, f64)>, auto: Option<(f64, f64)>| match given.or(auto) {
            None => (None, Some("no window: the stripes are there from the first frame".to_string())),
            Some((a, b)) => match flat_plateau(&self.msd, a, b, PLATEAU_FLATNESS) {
                Ok(p) => (Some(p), None),
                Err(e) => (None, Some(e.to_string())),
            },
        };
        let (plateau_before, plateau_before_note) = window(self.opts.plateau_before, before);
        let (plateau_after, plateau_after_note) = window(self.opts.plateau_after, after);

        let d: Vec<f64> = self.msd.iter().map(|p| p.d).collect();
        let max_lag = self.opts.max_lag.unwrap_or(d.len() / 2);
        let (raw, norm) = (autocorr::raw(&d, max_lag), autocorr::normalised(&d, max_lag));
        let autocorrelation = raw
            .iter()
            .zip(&norm)
            .enumerate()
            .map(|(lag, (&raw, &normalised))| AutocorrPoint {
                lag,
                lag_s: lag as f64 * self.period.unwrap_or(f64::NAN),
                raw,
                normalised,
            })
            .collect();
        let mut tally = RadiusTally::new(&self.radius_bins);
        for t in &self.radius_tallies[tail_from..] {
            tally.merge(t);
        }
        let radii = RadiusDistribution::from_tally(&self.header.radii, &self.radius_bins, &tally, m - tail_from);
        Ok(Report {
            particles: self.header.radii.len(),
            frames: m,
            length: l,
            width: self.header.width,
            mean_area_fraction: self.mean_phi,
            mean_diameter: self.mean_d,
            cell: l / self.cells as f64,
            cells: self.cells,
            stripe_params: self.params,
            period: self.period,
            times: self.times,
            density_map: self.map,
            stripes: self.stripes,
            coarsening,
            onset: onset_s,
            spacing,
            contrast_series: self.contrast,
            msd: self.msd,
            plateau_before,
            plateau_after,
            plateau_before_note,
            plateau_after_note,
            autocorrelation,
            tracer: self.tracer,
            radii,
            classification,
            sensitivity,
            structure: self.structure,
            late,
            late_gaps,
        })
    }
}
