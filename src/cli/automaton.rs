//! `stripes automaton SCENE.toml`: the Strassburger cellular automaton (thesis 3.1) on the
//! same scene file and the same prepared sample as `stripes run`, written as snapshots that
//! `stripes analyze` reads, and analysed by it. `--bench` measures its speed, `--calibrate`
//! fits its free parameters to DEM runs (see [`crate::automaton::calibrate`]). The run itself is the
//! pipeline's ([`crate::automaton::run_automaton`]).
//!
//! Time: one drive period is two half steps (a flight towards +x, then towards -x, the
//! grains' slide relative to the tray between the turning points). Frame 0 is the sample at
//! t = 0; frame k >= 1 follows k periods and carries the DEM's snapshot time
//! `t_k = 1/(4 nu) + (k - 1)/nu`, so both models' curves share one time axis. The lattice is
//! the tray frame: positions are written shifted by the tray's displacement at that phase.

use std::path::{Path, PathBuf};
use std::time::Instant;

use automaton::RuleSet;
use automaton::{Automaton, Direction};
use serde::Serialize;
use serde_json::json;

use crate::automaton::lattice::{self, Cells};
use crate::automaton::{resolve_lattice, run_automaton, AutomatonOptions};
use crate::host::clock::Stopwatch;
use crate::rundir::output::{json_line, CliError, RunDir};
use crate::scene::file::SceneFile;

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Scene file (TOML), the same as for `stripes run` (optional table [automaton]); not
    /// with --calibrate, which uses each DEM run's own scene.toml.
    #[arg(required_unless_present = "calibrate", conflicts_with = "calibrate")]
    pub scene: Option<PathBuf>,
    /// Output directory (default: out/automaton-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub replace: crate::cli::args::Force,
    #[command(flatten)]
    #[serde(flatten)]
    pub set: crate::cli::args::Overrides,
    /// Rule set: strict (thesis 3.1 exactly), physical (plus what a shaken tray supplies,
    /// the scene's [automaton] table) or measured (every number from a DEM run's parameter
    /// file, automaton.parameters). Default: the scene's automaton.rule, itself physical.
    #[arg(long, value_parser = rule_parser())]
    pub rule: Option<RuleSet>,
    #[command(flatten)]
    #[serde(flatten)]
    pub samples: crate::cli::args::SampleCache,
    /// Measure the speed (cell updates per second, one core) on the scene's tray with a
    /// random layer of its grain count instead of running it.
    #[arg(long)]
    pub bench: bool,
    /// Wall-clock seconds per benchmark case.
    #[arg(long, default_value_t = 3.0)]
    pub bench_seconds: f64,
    /// Fit the free parameters to these DEM run directories (each holding scene.toml and
    /// snapshots.bin) and report the fit.
    #[arg(long, num_args = 1.., value_name = "RUN_DIR")]
    pub calibrate: Vec<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub progress: crate::cli::args::Quiet,
}

pub fn run(args: Args) -> Result<String, CliError> {
    if !args.calibrate.is_empty() {
        return crate::automaton::calibrate::run(&crate::automaton::calibrate::Calibration {
            runs: args.calibrate.clone(),
            out: args.out.clone(),
            overrides: args.set.overrides.clone(),
            samples: args.samples.sample_cache.clone(),
            quiet: args.progress.quiet,
        });
    }
    let path = args.scene.clone().ok_or("a scene file is needed")?;
    let scene = resolve_lattice(&path, crate::scene::file::load(&path, &args.set.overrides)?)?;
    if args.bench {
        return bench(&args, &path, &scene.file);
    }
    json_line(&run_automaton(&scene, &args.options(&path))?)
}

/// `--rule`: the automaton's own rule-set type, by its scene-file names.
fn rule_parser() -> impl clap::builder::TypedValueParser<Value = RuleSet> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(RuleSet::NAMES).map(|s| s.parse::<RuleSet>().expect("one of the names"))
}

impl Args {
    /// The pipeline's options these arguments select for the scene at `path`.
    fn options(&self, path: &Path) -> AutomatonOptions {
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        AutomatonOptions {
            out: self.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/automaton-{name}"))),
            force: self.replace.force,
            rule: self.rule,
            sample_cache: self.samples.sample_cache.clone(),
            quiet: self.progress.quiet,
        }
    }
}

/// Speed on the scene's tray: a random layer of the scene's grain count, `strict` and
/// `physical`, each for about `bench_seconds`.
fn bench(args: &Args, path: &Path, file: &SceneFile) -> Result<String, CliError> {
    crate::automaton::lattice::validate_lattice(file)?;
    let scene = &file.dem;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out/automaton-bench"));
    crate::rundir::output::claim(&out, args.replace.force)?;
    let mut dir = RunDir::create(&out, &json!({ "args": args, "scene": scene }))?;
    let cells = Cells::of(file);
    // Grain positions from a SplitMix64 stream of the scene's seed.
    let mut s = scene.run.seed;
    let mut uniform = || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let pos: Vec<[f64; 2]> = (0..scene.particles.count)
        .map(|_| [uniform() * scene.tray.length, uniform() * scene.tray.width])
        .collect();
    let (lattice, _, _) = lattice::lattice_from_positions(&cells, scene.tray.length, &pos);
    let slide = lattice::slide_dem(scene)?;
    let mut rows = Vec::new();
    let mut cases = serde_json::Map::new();
    for (name, rule) in [("strict", RuleSet::Strict), ("physical", RuleSet::Physical)] {
        let params = lattice::params(file, rule, &slide, &file.automaton.free_params());
        let mut a = Automaton::new(lattice.clone(), params, Direction::Plus)?;
        // Warm up, then time batches until the budget is spent.
        for _ in 0..100 {
            a.half_step();
        }
        let (start, watch, mut steps) = (Instant::now(), Stopwatch::start(true), 0u64);
        while start.elapsed().as_secs_f64() < args.bench_seconds {
            for _ in 0..1000 {
                a.half_step();
            }
            steps += 1000;
        }
        let wall = start.elapsed().as_secs_f64();
        // On a shared machine the wall clock counts other processes' time slices too; the
        // thread's own CPU time measures one core's throughput.
        let cpu = watch.seconds();
        let cells_per_step = (cells.nx * cells.ny) as f64;
        let cell_rate = cells_per_step * steps as f64 / cpu;
        let grain_rate = lattice.mass() as f64 * steps as f64 / cpu;
        rows.push(vec![cell_rate, grain_rate, steps as f64, cpu, wall]);
        cases.insert(
            name.into(),
            json!({ "cell_updates_per_s": cell_rate, "grain_updates_per_s": grain_rate,
                    "cell_updates_per_wall_s": cells_per_step * steps as f64 / wall,
                    "half_steps": steps, "cpu_s": cpu, "wall_s": wall, "frozen": a.frozen(), "params": params }),
        );
    }
    dir.csv(
        "bench.csv",
        &["cell_updates_per_s", "grain_updates_per_s", "half_steps", "cpu_s", "wall_s"],
        &rows,
    )?;
    dir.finish(json!({
        "scene": path.display().to_string(),
        "grains": lattice.mass(),
        "cells": cells,
        "threads": 1,
        "cases": cases,
        "flight_cap_cells": (slide.displacement / cells.dx).round(),
    }))
}
