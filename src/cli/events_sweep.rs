//! `stripes events-sweep`: the event-driven model over a grid of scene values and seeds (the study: [`crate::studies::events_sweep`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::output::CliError;
use crate::studies::events_sweep::{events_sweep, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Event-driven scene file (model = "events"), e.g. scenes/ratchet.toml.
    pub scene: PathBuf,
    /// A key and the numbers it takes, e.g. --vary base.asymmetry=0,0.25,0.5 (repeatable:
    /// every combination runs). An array of tables takes an index: particles.species.0.count.
    #[arg(long = "vary", value_name = "KEY=V1,V2,...", required = true)]
    pub vary: Vec<String>,
    /// Override a scene key for every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
    /// Seeds per grid point: run.seed = 1..=N.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub seeds: u64,
    /// Worker threads (default: every core). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory (default: out/events-sweep-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the files of an output directory that already holds some (default: refuse it).
    #[arg(long)]
    pub force: bool,
    /// Draw the plots on a logarithmic x axis, and H and K/R on a logarithmic y axis too
    /// (a power law shows as a line).
    #[arg(long)]
    pub log: bool,
    #[command(flatten)]
    #[serde(flatten)]
    pub progress: crate::cli::args::Quiet,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            scene: self.scene.clone(),
            vary: self.vary.clone(),
            overrides: self.overrides.clone(),
            seeds: self.seeds,
            threads: self.threads,
            out: self.out.clone(),
            force: self.force,
            log: self.log,
            quiet: self.progress.quiet,
        }
    }
}

pub fn run(args: Args) -> Result<String, CliError> {
    events_sweep(&args.options())
}
