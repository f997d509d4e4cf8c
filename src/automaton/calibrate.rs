//! `stripes automaton --calibrate RUN_DIR...`: fits the automaton's free parameters to DEM
//! runs: the activation probability and the knock-through speed scale where grains slide,
//! the activation probability and the frustration probability where they roll (while a free
//! sphere rolls, `Gamma <= 7 mu / 2`, where the knock-through probability is small).
//!
//! For every DEM run directory (its `scene.toml` and `snapshots.bin`) the automaton runs on
//! the same scene and the same sample for each point of a fixed grid; both are measured with
//! the same analysis functions as `stripes analyze` (exact area fraction in 1 mm cells,
//! default stripe detection):
//! - stripe count per frame, compared frame by frame: RMS difference `e_count`;
//! - density contrast `std(phi) / mean(phi)` averaged over the last quarter of the frames,
//!   compared as the relative difference `e_contrast`.
//!
//! The loss is `sum over runs of e_count^2 + e_contrast^2`; the grid point of least loss
//! wins (ties: first in grid order). Deterministic: same runs, same answer.

use std::path::Path;

use analysis::density::area_fraction_cells;
use analysis::plot::{LinePlot, Mark};
use analysis::snapshot::read_snapshots;
use analysis::stripes::{detect, onset, StripeParams};
use serde_json::json;

use crate::automaton::lattice::{self, evolve, load_scene, setup, Cells};
use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Summary};

/// Activation probabilities of the grid.
pub const ACTIVATIONS: [f64; 5] = [0.2, 0.35, 0.5, 0.65, 0.8];
/// Knock-through speed scales of the grid (m/s).
pub const KNOCK_SPEEDS: [f64; 5] = [0.5, 1.0, 2.0, 4.0, 8.0];
/// Activation probabilities of the grid in the rolling regime.
pub const ROLLING_ACTIVATIONS: [f64; 3] = [0.6, 0.8, 1.0];
/// Frustration probabilities (per occupied neighbouring cell) of the grid in the rolling regime.
pub const HOLDS: [f64; 6] = [0.1, 0.15, 0.2, 0.25, 0.3, 0.4];

/// The second free parameter of the grid.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// `automaton.knock_speed` (m/s), where grains slide.
    KnockSpeed,
    /// `automaton.frustration_probability`, where grains roll.
    FrustrationProbability,
}

impl Axis {
    fn key(self) -> &'static str {
        match self {
            Axis::KnockSpeed => "knock_speed",
            Axis::FrustrationProbability => "frustration_probability",
        }
    }

    fn set(self, scene: &mut crate::scene::file::SceneFile, v: f64) {
        match self {
            Axis::KnockSpeed => {
                scene.automaton.knock = true;
                scene.automaton.knock_speed = v;
            }
            Axis::FrustrationProbability => {
                scene.automaton.frustration = true;
                scene.automaton.frustration_probability = v;
            }
        }
    }
}

/// The grid of a calibration on `scene`: activation probabilities, and the second axis with
/// its values: the frustration probability where the scene's automaton reads the drive as
/// rolling, else the knock-through speed scale.
pub fn grid(scene: &crate::scene::file::SceneFile) -> (Vec<f64>, Axis, Vec<f64>) {
    if scene.automaton.rolling && automaton::mapping::rolls_without_slip(&lattice::tray_drive(&scene.dem)) {
        (ROLLING_ACTIVATIONS.to_vec(), Axis::FrustrationProbability, HOLDS.to_vec())
    } else {
        (ACTIVATIONS.to_vec(), Axis::KnockSpeed, KNOCK_SPEEDS.to_vec())
    }
}

/// Stripe counts per frame and the density contrast of a sequence of frames.
pub struct Metrics {
    pub times: Vec<f64>,
    pub counts: Vec<usize>,
    pub contrast: f64,
}

/// Measures frames given as x positions with radii, on a tray `length` x `width`.
pub struct Meter {
    length: f64,
    width: f64,
    cells: usize,
    params: StripeParams,
    contrasts: Vec<f64>,
    metrics: Metrics,
}

impl Meter {
    /// Analysis settings of `stripes analyze` for grains of radii `radii`.
    pub fn new(length: f64, width: f64, radii: &[f64]) -> Self {
        let n = radii.len() as f64;
        let mean_phi = radii.iter().map(|r| std::f64::consts::PI * r * r).sum::<f64>() / (length * width);
        let mean_d = 2.0 * radii.iter().sum::<f64>() / n;
        Self {
            length,
            width,
            cells: ((length / 1e-3).round() as usize).max(1),
            params: StripeParams::default_for(mean_phi, mean_d),
            contrasts: Vec::new(),
            metrics: Metrics {
                times: Vec::new(),
                counts: Vec::new(),
                contrast: 0.0,
            },
        }
    }

    pub fn frame(&mut self, t: f64, x: &[f64], radii: &[f64]) {
        let phi = area_fraction_cells(x, radii, self.length, self.width, self.cells);
        let mean = phi.iter().sum::<f64>() / phi.len() as f64;
        let var = phi.iter().map(|p| (p - mean) * (p - mean)).sum::<f64>() / phi.len() as f64;
        self.contrasts.push(if mean > 0.0 { var.sqrt() / mean } else { 0.0 });
        self.metrics.times.push(t);
        self.metrics.counts.push(detect(&phi, self.length, &self.params).len());
    }

    pub fn finish(mut self) -> Metrics {
        let n = self.contrasts.len();
        let tail = &self.contrasts[n - (n / 4).max(1)..];
        self.metrics.contrast = tail.iter().sum::<f64>() / tail.len() as f64;
        self.metrics
    }
}

/// `(e_count, e_contrast)` of a model against the DEM.
pub fn errors(dem: &Metrics, model: &Metrics) -> (f64, f64) {
    let n = dem.counts.len().min(model.counts.len()).max(1);
    let sq: f64 = dem
        .counts
        .iter()
        .zip(&model.counts)
        .map(|(a, b)| (*a as f64 - *b as f64).powi(2))
        .sum();
    let e_contrast = if dem.contrast > 0.0 {
        (model.contrast - dem.contrast).abs() / dem.contrast
    } else {
        model.contrast
    };
    ((sq / n as f64).sqrt(), e_contrast)
}

/// What `stripes automaton --calibrate` was asked for.
#[derive(Debug, serde::Serialize)]
pub struct Calibration {
    /// DEM run directories (each with scene.toml and snapshots.bin).
    pub runs: Vec<std::path::PathBuf>,
    /// Output directory (default: out/automaton-calibration).
    pub out: Option<std::path::PathBuf>,
    /// `--set` overrides applied to every run's scene.
    pub overrides: Vec<String>,
    /// Directory of prepared samples.
    pub samples: std::path::PathBuf,
    pub quiet: bool,
}

/// What a calibration found: `summary.json`, field for field.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CalibrationSummary {
    pub runs: Vec<String>,
    pub grid_points: usize,
    /// The best grid point: `activation`, the swept axis' key and `loss`.
    pub best: std::collections::BTreeMap<String, f64>,
    /// The best point's fit to each run.
    pub fit: Vec<Fit>,
    /// The `--set` options of the best point.
    #[serde(rename = "use")]
    pub use_: String,
    #[serde(flatten)]
    pub written: Written,
}

/// The automaton at one grid point against one DEM run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Fit {
    pub e_count: f64,
    pub e_contrast: f64,
    pub contrast_automaton: f64,
    pub contrast_dem: f64,
    pub count_final_automaton: Option<usize>,
    pub count_final_dem: Option<usize>,
    pub onset_automaton_s: Option<f64>,
    pub onset_dem_s: Option<f64>,
    pub spacing_automaton_m: Option<f64>,
    pub spacing_dem_m: Option<f64>,
}

impl Summary for CalibrationSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

pub fn run(args: &Calibration) -> Result<CalibrationSummary, CliError> {
    let out = args.out.clone().unwrap_or_else(|| "out/automaton-calibration".into());
    struct RunData {
        scene: crate::scene::file::SceneFile,
        dem: Metrics,
        setup: lattice::Setup,
    }
    let mut runs = Vec::new();
    for d in &args.runs {
        let scene = load_scene(&d.join("scene.toml"), &args.overrides)?;
        let dem = dem_metrics(&d.join("snapshots.bin"))?;
        let setup = setup(&scene, &args.samples, args.quiet)?;
        runs.push(RunData { scene, dem, setup });
    }
    let first = runs.first().ok_or("--calibrate needs at least one DEM run directory")?;
    let (activations, axis, values) = grid(&first.scene);
    let mut dir = RunDir::create(
        &out,
        &json!({ "args": args, "activations": activations, "axis": axis.key(), "values": values }),
    )?;
    let total = (activations.len() * values.len() * runs.len()) as u64;
    let b = crate::rundir::output::progress_bar(total, args.quiet, "calibrate");
    let mut rows = Vec::new();
    let mut best: Option<(f64, f64, f64, Vec<Fit>)> = None;
    let mut best_series: Vec<Vec<(f64, f64)>> = Vec::new();
    for &p in &activations {
        for &v in &values {
            let mut loss = 0.0;
            let mut per_run = Vec::new();
            let mut series = Vec::new();
            for r in &runs {
                let mut scene = r.scene.clone();
                scene.automaton.stochastic = true;
                scene.automaton.activation = p;
                axis.set(&mut scene, v);
                let params = lattice::params(&scene, scene.automaton.rule, &r.setup.slide_dem, &scene.automaton.free_params());
                let n = r.setup.lattice.mass() as usize;
                let radii = vec![r.setup.radius; n];
                let mut meter = Meter::new(scene.dem.tray.length, scene.dem.tray.width, &radii);
                let cells = Cells::of(&scene);
                let mut x = Vec::with_capacity(n);
                let hidden = indicatif::ProgressBar::hidden();
                evolve(&scene, r.setup.lattice.clone(), params, None, r.setup.radius, &hidden, |t, l| {
                    x.clear();
                    x.extend(l.grains().map(|(i, _, _)| (i as f64 + 0.5) * cells.dx));
                    meter.frame(t, &x, &radii);
                })?;
                let m = meter.finish();
                let (ec, ek) = errors(&r.dem, &m);
                loss += ec * ec + ek * ek;
                let spacing = |m: &Metrics| m.counts.last().filter(|&&c| c > 0).map(|&c| scene.dem.tray.length / c as f64);
                per_run.push(Fit {
                    e_count: ec,
                    e_contrast: ek,
                    contrast_automaton: m.contrast,
                    contrast_dem: r.dem.contrast,
                    count_final_automaton: m.counts.last().copied(),
                    count_final_dem: r.dem.counts.last().copied(),
                    onset_automaton_s: onset(&m.times, &m.counts),
                    onset_dem_s: onset(&r.dem.times, &r.dem.counts),
                    spacing_automaton_m: spacing(&m),
                    spacing_dem_m: spacing(&r.dem),
                });
                series.push(m.times.iter().zip(&m.counts).map(|(t, c)| (*t, *c as f64)).collect());
                b.inc(1);
            }
            rows.push(vec![p, v, loss]);
            if best.as_ref().is_none_or(|b| loss < b.2) {
                best = Some((p, v, loss, per_run));
                best_series = series;
            }
        }
    }
    b.finish_and_clear();
    let (p, v, loss, per_run) = best.ok_or("empty calibration grid")?;
    dir.csv("calibration.csv", &["activation", axis.key(), "loss"], &rows)?;
    for (k, (r, s)) in runs.iter().zip(&best_series).enumerate() {
        let plot = LinePlot::new(&format!("Calibration, run {}: stripe count", k + 1), "t (s)", "stripes")
            .series(
                "DEM",
                r.dem.times.iter().zip(&r.dem.counts).map(|(t, c)| (*t, *c as f64)).collect(),
                Mark::LinePoints,
            )
            .series(
                &format!("automaton (activation {p}, {} {v})", axis.key()),
                s.clone(),
                Mark::LinePoints,
            );
        dir.plot(&format!("calibration_run{}", k + 1), &plot)?;
    }
    let summary = CalibrationSummary {
        runs: args.runs.iter().map(|p| p.display().to_string()).collect(),
        grid_points: rows.len(),
        best: [("activation", p), (axis.key(), v), ("loss", loss)]
            .into_iter()
            .map(|(k, x)| (k.to_string(), x))
            .collect(),
        fit: per_run,
        use_: format!("--set automaton.activation={p} --set automaton.{}={v}", axis.key()),
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// Stripe counts and contrast of a DEM run's snapshots.
pub fn dem_metrics(path: &Path) -> Result<Metrics, CliError> {
    let (header, frames) = read_snapshots(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if frames.is_empty() {
        return Err(format!("{} holds no complete frame", path.display()).into());
    }
    let mut meter = Meter::new(header.length, header.width, &header.radii);
    for f in &frames {
        let x: Vec<f64> = f.pos.iter().map(|p| p[0]).collect();
        meter.frame(f.time, &x, &header.radii);
    }
    Ok(meter.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(name: &str) -> crate::scene::file::SceneFile {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
        crate::scene::file::load(&path, &[]).unwrap()
    }

    /// The stripe scene rolls (Gamma 0.36): the grid fits the frustration probability; the
    /// quick scene slides (20 Hz, 25 mm): the knock-through speed scale.
    #[test]
    fn the_grid_fits_what_the_regime_leaves_free() {
        let (acts, axis, values) = grid(&scene("stripes.toml"));
        assert_eq!(
            (acts, axis, values),
            (ROLLING_ACTIVATIONS.to_vec(), Axis::FrustrationProbability, HOLDS.to_vec())
        );
        let (acts, axis, values) = grid(&scene("quick.toml"));
        assert_eq!(
            (acts, axis, values),
            (ACTIVATIONS.to_vec(), Axis::KnockSpeed, KNOCK_SPEEDS.to_vec())
        );
    }
}
