//! `stripes compare SCENE.toml`: both models on the same scene and the same sample, analysed
//! alike, side by side in `report.md` (the study: [`crate::studies::compare`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::report::{report, Reported};
use crate::studies::compare::{compare_scene, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Reuse this DEM run directory instead of running the DEM (it must start from the
    /// same sample as the scene).
    #[arg(long)]
    pub dem_run: Option<PathBuf>,
    /// A second DEM run of the same scene with another seed (a run directory): the pattern
    /// distance between the two seeds is the scale of the distance between the models.
    #[arg(long, value_name = "RUN_DIR")]
    pub seed_scale_run: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub samples: crate::cli::args::SampleCache,
    #[command(flatten)]
    #[serde(flatten)]
    pub run: crate::cli::args::SceneRun,
    /// Vibrated box only (`drive.direction = "z"`): runs per model, seeds run.seed, run.seed + 1, ...
    #[arg(long, default_value_t = 3)]
    pub seeds: u64,
    /// Vibrated box only: simulated time discarded before sampling (s).
    #[arg(long, default_value_t = 1.0, value_parser = crate::cli::values::not_nan)]
    pub transient: f64,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            scene: self.run.scene.clone(),
            overrides: self.run.set.overrides.clone(),
            out: self.run.out.clone(),
            force: self.run.force,
            resume: self.run.resume,
            quiet: self.run.quiet,
            dem_run: self.dem_run.clone(),
            seed_scale_run: self.seed_scale_run.clone(),
            sample_cache: self.samples.sample_cache.clone(),
            seeds: self.seeds,
            transient: self.transient,
        }
    }
}

pub fn run(args: Args) -> Reported {
    report(compare_scene(&args.options())?)
}
