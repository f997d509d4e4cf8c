//! `stripes mechanism`: held, rolling and sliding grains inside and outside the bands of a finished run, and the coarse model's measurements (the study: [`crate::studies::mechanism`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::report::{report, Reported};
use crate::studies::mechanism::{mechanism, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// A finished `stripes run` directory (scene.toml and checkpoint.bin).
    pub run: PathBuf,
    /// Drive periods to continue and sample.
    #[arg(long, default_value_t = 2)]
    pub periods: u32,
    /// Samples per drive period.
    #[arg(long, default_value_t = 24)]
    pub per_period: u32,
    #[command(flatten)]
    #[serde(flatten)]
    pub samples: crate::cli::args::SampleCache,
    /// Output directory (default: <RUN>/mechanism).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
    /// Only the coarse model's measures from the run's frames (automaton.toml, coarse.json):
    /// no continuation, no checkpoint read, no DEM step.
    #[arg(long)]
    pub coarse_only: bool,
    /// The swing field (the automaton's `swing` rule) over the half periods that start
    /// before this simulated time (s), e.g. the bands' formation; default: the whole run.
    #[arg(long)]
    pub swing_until: Option<f64>,
    /// A DEM phase map's phase_map.csv (`stripes phase-map --model dem`): the lift-off and
    /// melting thresholds of the drive, written into automaton.toml's [thresholds].
    #[arg(long)]
    pub phase_map: Option<PathBuf>,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            run: self.run.clone(),
            periods: self.periods,
            per_period: self.per_period,
            sample_cache: self.samples.sample_cache.clone(),
            out: self.out.clone(),
            force: self.writing.force,
            quiet: self.writing.quiet,
            coarse_only: self.coarse_only,
            swing_until: self.swing_until,
            phase_map: self.phase_map.clone(),
        }
    }
}

pub fn run(args: Args) -> Reported {
    report(mechanism(&args.options())?)
}
