//! `stripes mechanism RUN_DIR`: the stripe mechanism measured directly (thesis 3.4 and 3.5;
//! [`analysis::mechanism`]). It continues a finished `stripes run` from its checkpoint for a
//! few more drive periods, sampling every grain many times per period, and reports which
//! grains are held by the floor, roll or slide, inside the dense bands of each instant and
//! outside them, and how fast the bands' grains move relative to the others.
//!
//! First it measures, on the run's own frames, what the coarse model needs
//! ([`crate::studies::coarse`]): `automaton.toml` and `coarse.json`.
//!
//! Writes `mechanism.csv` (one row per sample), `mechanism.png/svg` (the mean velocity
//! relative to the tray of each group against the tray's velocity) and `summary.json`.
//! The run directory itself is left untouched.

use std::path::PathBuf;

use analysis::density::{area_fraction_cells, mean_area_fraction};
use analysis::mechanism::{ByDensity, Grain, Motion, Split, Tally};
use analysis::plot::{LinePlot, Mark};
use analysis::stripes::{detect, StripeParams};
use particles::advance::{advance_to, AtTimes};
use particles::sim::Simulation;
use particles::tray;
use serde::Serialize;
use serde_json::json;

use crate::rundir::output::Written;
use crate::rundir::output::{progress_bar, CliError, RunDir};
use crate::rundir::report::{Headline, Summary};

/// What the study is given (the command's arguments, without the command line); serialised
/// as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// A finished `stripes run` directory (scene.toml and checkpoint.bin).
    pub run: PathBuf,
    /// Drive periods to continue and sample.
    pub periods: u32,
    /// Samples per drive period.
    pub per_period: u32,
    pub sample_cache: PathBuf,
    /// Output directory (default: <RUN>/mechanism).
    pub out: Option<PathBuf>,
    pub force: bool,
    pub quiet: bool,
    /// Only the coarse model's measures from the run's frames (`automaton.toml`,
    /// `coarse.json`): no continuation, so no checkpoint is read and no DEM step is taken.
    pub coarse_only: bool,
    /// The swing field over the half periods that start before this time (s); None: the
    /// whole run.
    pub swing_until: Option<f64>,
    /// A DEM phase map's `phase_map.csv`, for the lift-off and melting thresholds.
    pub phase_map: Option<PathBuf>,
}

/// What `stripes mechanism` found: `summary.json`, field for field.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum MechanismSummary {
    /// `--coarse-only`: the coarse model's parameters alone.
    CoarseOnly(CoarseOnly),
    Full(Box<Full>),
}

#[derive(Debug, Serialize)]
pub struct CoarseOnly {
    pub run: String,
    pub coarse_only: bool,
    pub coarse: CoarseFile,
    #[serde(flatten)]
    pub written: Written,
}

/// The grains' motions inside and outside the bands, continued from the run's checkpoint.
#[derive(Debug, Serialize)]
pub struct Full {
    pub run: String,
    pub from_s: f64,
    pub periods: u32,
    pub per_period: u32,
    pub gamma: f64,
    pub floor_speed_m_s: f64,
    pub slip_fraction: f64,
    pub band: Fractions,
    pub outside: Fractions,
    pub relative_slope: f64,
    pub by_density: Vec<DensityClass>,
    pub relative_slope_hypothesis: f64,
    pub coarse: Coarse,
    #[serde(flatten)]
    pub written: Written,
}

/// Each motion's share of the grain instants of a group, their number and the slope.
#[derive(Debug, Serialize)]
pub struct Fractions {
    #[serde(flatten)]
    pub motions: std::collections::BTreeMap<&'static str, f64>,
    pub grain_instants: u64,
    pub slope: f64,
}

/// One class of local packing (`phi_hi` infinite, written as null, for the last).
#[derive(Debug, Serialize)]
pub struct DensityClass {
    pub phi_lo: f64,
    pub phi_hi: f64,
    pub grain_instants: f64,
    pub slope: f64,
}

/// The coarse model's parameter file and its cell.
#[derive(Debug, Serialize)]
pub struct CoarseFile {
    pub file: &'static str,
    pub cell_m: Option<f64>,
    pub half_periods: usize,
}

/// The coarse model's file with the measures it holds.
#[derive(Debug, Serialize)]
pub struct Coarse {
    #[serde(flatten)]
    pub file: CoarseFile,
    pub before_s: Option<f64>,
    pub excursion_mean_m: f64,
    pub excursion_sd_m: f64,
    pub sideways_mean_m: f64,
    pub core_packing: Option<f64>,
    pub escape_per_period: Option<f64>,
    pub edge_escape_per_period: Option<f64>,
    pub residence_mean_periods: f64,
}

impl Summary for MechanismSummary {
    fn headline(&self) -> Headline {
        match self {
            MechanismSummary::CoarseOnly(c) => Headline::written(0, &c.written),
            MechanismSummary::Full(f) => Headline::written(0, &f.written),
        }
    }
}

pub fn mechanism(args: &Options) -> Result<MechanismSummary, CliError> {
    if args.periods == 0 || args.per_period == 0 {
        return Err("--periods and --per-period must be at least 1".into());
    }
    let scene_path = args.run.join("scene.toml");
    let resolved = crate::dem::resolve(&scene_path, crate::scene::file::load(&scene_path, &[])?)?;
    let scene = resolved.scene();
    // The checkpoint first (a full run continues from it), so that a missing one writes nothing.
    let ckpt_path = args.run.join("checkpoint.bin");
    let bytes = if args.coarse_only {
        Vec::new()
    } else {
        std::fs::read(&ckpt_path).map_err(|e| format!("{}: cannot read ({e}); run `stripes run` to the end first", ckpt_path.display()))?
    };
    let out = args.out.clone().unwrap_or_else(|| args.run.join("mechanism"));
    crate::rundir::output::claim(&out, args.force)?;
    let mut dir = RunDir::create(&out, &json!({ "args": &args, "scene": scene }))?;
    // The coarse model's parameters, from the run's own frames (issue 40).
    let coarse = crate::studies::coarse::write(
        &args.run,
        !scene.tray.x_walls,
        args.swing_until,
        args.phase_map.as_deref(),
        &mut dir,
    )?;
    if args.coarse_only {
        let summary = CoarseOnly {
            run: args.run.display().to_string(),
            coarse_only: true,
            coarse: CoarseFile {
                file: "automaton.toml",
                cell_m: coarse.cell.size_m,
                half_periods: coarse.excursion.half_periods,
            },
            written: dir.written(),
        };
        dir.finish_typed(&summary)?;
        return Ok(MechanismSummary::CoarseOnly(summary));
    }

    let (state, _) = crate::dem::samples::load_or_prepare(scene, &args.sample_cache, |_| {})?;
    let mut sim = Simulation::new(resolved.setup.clone(), state)?;
    crate::dem::checkpoint::restore(&mut sim, &bytes, resolved.fingerprint).map_err(|e| format!("{}: {e}", ckpt_path.display()))?;
    let start = sim.time;

    let (l, w) = (scene.tray.length, scene.tray.width);
    let (nu, a) = (scene.drive.frequency, scene.drive.amplitude);
    let floor_speed = 2.0 * std::f64::consts::PI * nu * a;
    let motion = tray::drive(scene);
    let radii = sim.state().radius.clone();
    let mean_d = 2.0 * radii.iter().sum::<f64>() / radii.len() as f64;
    let params = StripeParams::default_for(mean_area_fraction(&radii, l, w), mean_d);
    let cells = (l / 1e-3).round().max(1.0) as usize;

    let samples = args.periods as u64 * args.per_period as u64;
    let every = 1.0 / (nu * args.per_period as f64);
    let bar = progress_bar(samples, args.quiet, "mechanism");
    let mut total = Split::default();
    let mut by_density = ByDensity::default();
    let mut rows = Vec::new();
    let times = (1..=samples).map(|k| start + k as f64 * every).collect();
    let mut sample = AtTimes::new(times, |sim: &Simulation, _| {
        let state = sim.state();
        let s = &*state;
        let grains: Vec<Grain> = (0..s.len())
            .map(|i| Grain {
                pos: [s.pos[i].x.rem_euclid(l), s.pos[i].y, s.pos[i].z],
                vel: [s.vel[i].x, s.vel[i].y, s.vel[i].z],
                omega: [s.omega[i].x, s.omega[i].y, s.omega[i].z],
                radius: s.radius[i],
            })
            .collect();
        let x: Vec<f64> = grains.iter().map(|g| g.pos[0]).collect();
        let phi = area_fraction_cells(&x, &radii, l, w, cells);
        let stripes = detect(&phi, l, &params);
        let v_tray = motion.velocity(sim.time).x;
        by_density.add_instant(&grains, &phi, l, v_tray, floor_speed);
        let mut instant = Split::default();
        instant.add_instant(&grains, &stripes, l, v_tray, floor_speed);
        let mut row = vec![
            sim.time - start,
            v_tray,
            stripes.len() as f64,
            instant.band.mean_u(),
            instant.outside.mean_u(),
        ];
        for t in [&instant.band, &instant.outside] {
            row.push(t.total() as f64);
            row.extend(Motion::ALL.iter().map(|&m| t.fraction(m)));
        }
        rows.push(row);
        total.merge(&instant);
        bar.inc(1);
        Ok(())
    });
    if let Some(end) = sample.last() {
        advance_to(&mut sim, end, &mut [&mut sample])?;
    }
    bar.finish_and_clear();

    let mut header: Vec<String> = ["t", "v_tray", "stripes", "u_band", "u_outside"].map(String::from).to_vec();
    for place in ["band", "outside"] {
        header.push(format!("n_{place}"));
        header.extend(Motion::ALL.iter().map(|m| format!("{place}_{}", m.name())));
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    dir.csv("mechanism.csv", &header, &rows)?;
    let series = |col: usize| rows.iter().map(|r| (r[0], r[col])).collect::<Vec<_>>();
    let plot = LinePlot::new(
        "Mean velocity relative to the tray, u_x (m/s)",
        "time since the checkpoint (s)",
        "u_x (m/s)",
    )
    .series("grains in dense bands", series(3), Mark::Line)
    .series("grains outside bands", series(4), Mark::Line)
    .series("held by the floor: 0", rows.iter().map(|r| (r[0], 0.0)).collect(), Mark::Dashed)
    .series(
        "rolling without slip: -5/7 v_tray",
        rows.iter().map(|r| (r[0], -5.0 / 7.0 * r[1])).collect(),
        Mark::Dashed,
    );
    dir.plot("mechanism", &plot)?;
    let density_rows: Vec<Vec<f64>> = by_density
        .0
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let (lo, hi) = ByDensity::class_range(k);
            let mut row = vec![lo, hi, t.total() as f64, t.slope()];
            row.extend(Motion::ALL.iter().map(|&m| t.fraction(m)));
            row
        })
        .collect();
    dir.csv(
        "mechanism_by_density.csv",
        &[
            "phi_lo",
            "phi_hi",
            "grain_instants",
            "slope",
            "held",
            "rolling",
            "sliding",
            "airborne",
        ],
        &density_rows,
    )?;
    let by_phi = LinePlot::new(
        "Velocity relative to the tray against local packing: u_x = a v_tray",
        "local area fraction (class centre; 1 mm cells)",
        "slope a",
    )
    .series(
        "this run",
        density_rows
            .iter()
            .filter(|r| r[2] >= 100.0)
            .map(|r| (if r[1].is_finite() { 0.5 * (r[0] + r[1]) } else { r[0] + 0.05 }, r[3]))
            .collect(),
        Mark::LinePoints,
    )
    .series(
        "rolling without slip: -5/7",
        vec![(0.0, -5.0 / 7.0), (0.9, -5.0 / 7.0)],
        Mark::Dashed,
    )
    .series("held by the floor: 0", vec![(0.0, 0.0), (0.9, 0.0)], Mark::Dashed);
    dir.plot("mechanism_by_density", &by_phi)?;

    let fractions = |t: &Tally| Fractions {
        motions: Motion::ALL.iter().map(|&k| (k.name(), t.fraction(k))).collect(),
        grain_instants: t.total(),
        slope: t.slope(),
    };
    let summary = Full {
        run: args.run.display().to_string(),
        from_s: start,
        periods: args.periods,
        per_period: args.per_period,
        gamma: floor_speed * 2.0 * std::f64::consts::PI * nu / sim.setup.gravity.norm(),
        floor_speed_m_s: floor_speed,
        slip_fraction: analysis::mechanism::SLIP_FRACTION,
        band: fractions(&total.band),
        outside: fractions(&total.outside),
        relative_slope: total.relative_slope(),
        by_density: density_rows
            .iter()
            .map(|r| DensityClass {
                phi_lo: r[0],
                phi_hi: r[1],
                grain_instants: r[2],
                slope: r[3],
            })
            .collect(),
        relative_slope_hypothesis: 5.0 / 7.0,
        coarse: Coarse {
            file: CoarseFile {
                file: "automaton.toml",
                cell_m: coarse.cell.size_m,
                half_periods: coarse.excursion.half_periods,
            },
            before_s: coarse.excursion.before_s,
            excursion_mean_m: coarse.excursion.all.excursion.mean,
            excursion_sd_m: coarse.excursion.all.excursion.sd,
            sideways_mean_m: coarse.excursion.all.sideways.mean,
            core_packing: coarse.bands.core_packing,
            escape_per_period: coarse.bands.escape_per_period,
            edge_escape_per_period: coarse.bands.edge_escape_per_period,
            residence_mean_periods: coarse.bands.residence_periods.mean,
        },
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(MechanismSummary::Full(Box::new(summary)))
}
