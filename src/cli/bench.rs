//! `stripes bench`: speed against error of every accuracy-for-speed choice (the study: [`crate::studies::tradeoff::bench`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::report::{report, Reported};
use crate::studies::tradeoff::bench::{bench, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Small and short: under a minute on a loaded two-core machine.
    #[arg(long)]
    pub quick: bool,
    /// Output directory.
    #[arg(long, default_value = "out/bench")]
    pub out: PathBuf,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
    /// Grains in the tray study (default: 200 quick, 400 full); the tray is count/10000 m
    /// long and 2 cm wide (thesis packing 0.23).
    #[arg(long)]
    pub tray_count: Option<usize>,
    /// Simulated seconds of each tray run (default: 0.05 quick, 0.15 full).
    #[arg(long)]
    pub tray_duration: Option<f64>,
    /// Steps of the dense-packing hard case, 8000 grains (default: 600 quick, 3000 full; 0 skips it).
    #[arg(long)]
    pub dense_steps: Option<u64>,
    /// Worker threads (speed ratios are measured on this many; default 1, timed by the
    /// worker's on-CPU time, which is the wall time on an idle core; more: wall time).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            quick: self.quick,
            out: self.out.clone(),
            force: self.writing.force,
            quiet: self.writing.quiet,
            tray_count: self.tray_count,
            tray_duration: self.tray_duration,
            dense_steps: self.dense_steps,
            threads: self.threads,
        }
    }
}

pub fn run(args: Args) -> Reported {
    report(bench(&args.options())?)
}
