//! `stripes windows`: one long run's analysed windows joined over time: the count on log axes, the coarsening law on the joined count, each window's lifetimes (the study: [`crate::studies::windows`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::report::{report, Reported};
use crate::studies::windows::{windows, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Analysed windows of one run: directories holding camera_count.csv and summary.json, or
    /// run directories with them under analysis/.
    #[arg(required = true, num_args = 1..)]
    pub windows: Vec<PathBuf>,
    /// Output directory (default: out/windows).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A reference count T:S (time since the last drive stage began, s; count), drawn beside
    /// the run's and listed with the run's counts within 1 s; repeat or separate with commas.
    #[arg(long, value_delimiter = ',', value_parser = crate::cli::values::time_count)]
    pub reference: Vec<(f64, f64)>,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
}

pub fn run(args: Args) -> Reported {
    report(windows(&Options {
        windows: args.windows.clone(),
        out: args.out.clone(),
        reference: args.reference.clone(),
        force: args.writing.force,
        quiet: args.writing.quiet,
    })?)
}
