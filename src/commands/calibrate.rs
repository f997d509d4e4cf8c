//! `stripes automaton --calibrate RUN_DIR...`: fits the automaton's free parameters
//! (activation probability, knock-through speed scale) to DEM runs.
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
use analysis::stripes::{detect, StripeParams};
use serde_json::json;

use crate::cellular::{self, evolve, load_scene, setup, Cells};
use crate::output::{CliError, RunDir};

/// Activation probabilities of the grid.
pub const ACTIVATIONS: [f64; 5] = [0.2, 0.35, 0.5, 0.65, 0.8];
/// Knock-through speed scales of the grid (m/s).
pub const KNOCK_SPEEDS: [f64; 5] = [0.5, 1.0, 2.0, 4.0, 8.0];

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

pub fn run(args: &Calibration) -> Result<String, CliError> {
    let out = args.out.clone().unwrap_or_else(|| "out/automaton-calibration".into());
    let mut dir = RunDir::create(
        &out,
        &json!({ "args": args, "activations": ACTIVATIONS, "knock_speeds": KNOCK_SPEEDS }),
    )?;
    struct RunData {
        scene: crate::scene_file::SceneFile,
        dem: Metrics,
        setup: cellular::Setup,
    }
    let mut runs = Vec::new();
    for d in &args.runs {
        let scene = load_scene(&d.join("scene.toml"), &args.overrides)?;
        let dem = dem_metrics(&d.join("snapshots.bin"))?;
        let setup = setup(&scene, &args.samples, args.quiet)?;
        runs.push(RunData { scene, dem, setup });
    }
    let total = (ACTIVATIONS.len() * KNOCK_SPEEDS.len() * runs.len()) as u64;
    let b = crate::output::progress_bar(total, args.quiet, "calibrate");
    let mut rows = Vec::new();
    let mut best: Option<(f64, f64, f64, Vec<serde_json::Value>)> = None;
    let mut best_series: Vec<Vec<(f64, f64)>> = Vec::new();
    for &p in &ACTIVATIONS {
        for &v in &KNOCK_SPEEDS {
            let mut loss = 0.0;
            let mut per_run = Vec::new();
            let mut series = Vec::new();
            for r in &runs {
                let mut scene = r.scene.clone();
                scene.automaton.stochastic = true;
                scene.automaton.activation = p;
                scene.automaton.knock = true;
                scene.automaton.knock_speed = v;
                let params = cellular::params(&scene, scene.automaton.rule, &r.setup.slide_dem, &scene.automaton.free_params());
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
                per_run.push(
                    json!({ "e_count": ec, "e_contrast": ek, "contrast_automaton": m.contrast, "contrast_dem": r.dem.contrast,
                                      "count_final_automaton": m.counts.last(), "count_final_dem": r.dem.counts.last() }),
                );
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
    dir.csv("calibration.csv", &["activation", "knock_speed", "loss"], &rows)?;
    for (k, (r, s)) in runs.iter().zip(&best_series).enumerate() {
        let plot = LinePlot::new(&format!("Calibration, run {}: stripe count", k + 1), "t (s)", "stripes")
            .series(
                "DEM",
                r.dem.times.iter().zip(&r.dem.counts).map(|(t, c)| (*t, *c as f64)).collect(),
                Mark::LinePoints,
            )
            .series(&format!("automaton (activation {p}, v_knock {v} m/s)"), s.clone(), Mark::LinePoints);
        dir.plot(&format!("calibration_run{}", k + 1), &plot)?;
    }
    dir.finish(json!({
        "runs": args.runs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
        "grid_points": rows.len(),
        "best": { "activation": p, "knock_speed": v, "loss": loss },
        "fit": per_run,
        "use": format!("--set automaton.activation={p} --set automaton.knock_speed={v}"),
    }))
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
