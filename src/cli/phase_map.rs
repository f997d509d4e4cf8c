//! `stripes phase-map SCENE.toml --frequency LO:HI:N --amplitude LO:HI:N`: the (nu, A) phase
//! diagram of thesis Figs 3.30-3.31 for the DEM, the automaton, or both, as a sweep of
//! independent jobs (see `crate::studies::sweep`).
//!
//! The jobs and the report are the sweep's ([`crate::studies::sweep::phase_map`]).

use std::path::PathBuf;

use crate::rundir::report::{report, Reported};
use crate::studies::sweep::{self, phase_map, Sweep, SweepKind, Which};

#[derive(clap::Args, Debug, serde::Serialize)]
pub struct Args {
    /// Scene file (TOML); every job is this scene with the drive (and seed) changed.
    pub scene: PathBuf,
    /// Drive frequencies, LO:HI:N or a list such as 2,3,5,8,13,20 (Hz).
    #[arg(long, default_value = "5:29:7")]
    pub frequency: String,
    /// Drive amplitudes, LO:HI:N or a list such as 0.002,0.005,0.01 (m).
    #[arg(long, default_value = "0.005:0.04:8")]
    pub amplitude: String,
    /// Which model(s) to run: dem (`stripes run`), automaton (`stripes automaton`) or both,
    /// on the same samples.
    #[arg(long, value_enum, default_value = "both")]
    pub model: Which,
    /// Prepared samples (seeds run.seed, run.seed + 1, ...) per cell.
    #[arg(long, value_name = "N", default_value_t = 1, visible_alias = "samples", value_parser = crate::cli::values::at_least_one)]
    pub seeds: usize,
    /// Sweep directory.
    #[arg(long, default_value = "out/phase-map")]
    pub out: PathBuf,
    #[command(flatten)]
    pub sweep: crate::cli::args::SweepArgs,
}

pub fn run(args: Args) -> Reported {
    let freqs = sweep::parse_range(&args.frequency, "frequency")?;
    let amps = sweep::parse_range(&args.amplitude, "amplitude")?;
    let scene = crate::scene::file::load(&args.scene, &args.sweep.overrides)?.dem;
    scene.validate()?;
    let sweep = Sweep {
        kind: SweepKind::PhaseMap,
        scene: args.scene.clone(),
        overrides: args.sweep.overrides.clone(),
        jobs: phase_map::jobs(&freqs, &amps, &args.model.models(), args.seeds.max(1), scene.run.seed),
        resolved: String::new(),
    };
    report(
        args.sweep
            .engine()
            .execute(&args.out, &sweep, crate::studies::sweep::phase_map::report)?,
    )
}
