//! `stripes events-sweep`: the event-driven model over a grid of scene values and seeds, a
//! sweep of the one engine (the study: [`crate::studies::events_sweep`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::cli::args::SweepArgs;
use crate::rundir::report::{report, Reported};
use crate::studies::events_sweep::{events_sweep, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Event-driven scene file (model = "events"), e.g. scenes/ratchet.toml.
    pub scene: PathBuf,
    /// A key and the numbers it takes, e.g. --vary base.asymmetry=0,0.25,0.5 (repeatable:
    /// every combination runs). An array of tables takes an index: particles.species.0.count.
    #[arg(long = "vary", value_name = "KEY=V1,V2,...", required = true)]
    pub vary: Vec<String>,
    /// Seeds per grid point: run.seed = 1..=N.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub seeds: u64,
    /// Sweep directory (default: out/events-sweep-<scene name>); a re-run continues the same
    /// sweep there (its finished runs are kept) and refuses a different one.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Draw the plots on a logarithmic x axis, and H and K/R on a logarithmic y axis too
    /// (a power law shows as a line).
    #[arg(long)]
    pub log: bool,
    #[command(flatten)]
    pub sweep: SweepArgs,
}

pub fn run(args: Args) -> Reported {
    let options = Options {
        scene: args.scene.clone(),
        vary: args.vary.clone(),
        seeds: args.seeds,
        out: args.out.clone(),
        log: args.log,
    };
    report(events_sweep(&options, &args.sweep.engine())?)
}
