//! `stripes seeds`: several analysed runs of one scene side by side: pooled structure with errors, pattern distances, spacing and band count over time (the study: [`crate::studies::seeds`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::report::{report, Reported};
use crate::studies::seeds::{seeds, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Analysed runs: run directories holding analysis/, or analysis directories (at least 2).
    #[arg(required = true, num_args = 2..)]
    pub runs: Vec<PathBuf>,
    /// Output directory (default: out/seeds).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            runs: self.runs.clone(),
            out: self.out.clone(),
            force: self.writing.force,
            quiet: self.writing.quiet,
        }
    }
}

pub fn run(args: Args) -> Reported {
    report(seeds(&args.options())?)
}
