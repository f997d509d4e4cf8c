//! `stripes collect DIR`: merges the results of a sweep's shards (`--shard I/N`, run anywhere
//! that shares `DIR`) into the sweep's tables, plots and report, exactly as a single run would.

use std::path::PathBuf;

use crate::rundir::output::CliError;
use crate::studies::sweep::{self, SweepKind};

#[derive(clap::Args, Debug, serde::Serialize)]
pub struct Args {
    /// A sweep directory written by `stripes phase-map`, `stripes ablate` or `stripes events-sweep`.
    pub dir: PathBuf,
}

pub fn run(args: Args) -> Result<String, CliError> {
    let sweep = sweep::load(&args.dir)?;
    let summary = match sweep.kind {
        SweepKind::PhaseMap => sweep::phase_map::report(&args.dir, &sweep)?,
        SweepKind::Ablate => sweep::ablate::report(&args.dir, &sweep)?,
        SweepKind::EventsSweep => crate::studies::events_sweep::report(&args.dir, &sweep)?,
    };
    Ok(serde_json::to_string(&summary)?)
}
