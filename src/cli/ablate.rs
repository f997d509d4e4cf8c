//! `stripes ablate SCENE.toml --samples K`: the ablation study of thesis 3.5.4 (Figs 3.30-3.31,
//! Table 3.6) as a sweep of independent jobs (see `crate::studies::sweep`): the reference and the five
//! toggles (friction, jumping, dissipation, walls off, and rolling friction off, which the
//! thesis never ran) over K prepared samples, optionally a packing sweep (`--packing`), each
//! analysed by the shared analysis. `report.md` tabulates onset time, final stripe count
//! (mean +- std), MSD plateaus and phase per configuration beside the thesis' values, and shows
//! the density maps as a grid.

use std::path::PathBuf;

use crate::rundir::report::{report, Reported};
use crate::studies::sweep::ablate::{automaton_configs, dem_configs, jobs, pin_reference_step};
use crate::studies::sweep::{Model, Sweep, SweepKind, Which};

#[derive(clap::Args, Debug, serde::Serialize)]
pub struct Args {
    /// Scene file (TOML): the reference configuration.
    pub scene: PathBuf,
    /// Prepared samples (seeds) per configuration (seeds run.seed, run.seed + 1, ...).
    #[arg(long, value_name = "N", default_value_t = 1, visible_alias = "samples", value_parser = crate::cli::values::at_least_one)]
    pub seeds: usize,
    /// Also the packing sweep of Table 3.6: these particle counts in the same box.
    #[arg(long, value_delimiter = ',')]
    pub packing: Vec<usize>,
    /// Which model(s) to ablate: dem (`stripes run`), automaton (`stripes automaton`) or
    /// both, on the same samples.
    #[arg(long, value_enum, default_value = "dem")]
    pub model: Which,
    /// Sweep directory.
    #[arg(long, default_value = "out/ablate")]
    pub out: PathBuf,
    #[command(flatten)]
    pub sweep: crate::cli::args::SweepArgs,
}

pub fn run(args: Args) -> Reported {
    let file = crate::scene::file::load(&args.scene, &args.sweep.overrides)?;
    let scene = &file.dem;
    scene.validate()?;
    let mut all = Vec::new();
    if matches!(args.model, Which::Dem | Which::Both) {
        // One change at a time: each toggle keeps the reference's step where it is stable.
        let mut configs = dem_configs(&args.packing);
        pin_reference_step(&file, &mut configs)?;
        all.extend(jobs(&configs, Model::Dem, args.seeds.max(1), scene.run.seed));
    }
    if matches!(args.model, Which::Automaton | Which::Both) {
        all.extend(jobs(
            &automaton_configs(&args.packing),
            Model::Automaton,
            args.seeds.max(1),
            scene.run.seed,
        ));
    }
    let sweep = Sweep {
        kind: SweepKind::Ablate,
        scene: args.scene.clone(),
        overrides: args.sweep.overrides.clone(),
        jobs: all,
        resolved: String::new(),
    };
    report(
        args.sweep
            .engine()
            .execute(&args.out, &sweep, crate::studies::sweep::ablate::report)?,
    )
}
