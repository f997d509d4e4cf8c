//! `stripes collect DIR`: merges the results of a sweep's shards (`--shard I/N`, run anywhere
//! that shares `DIR`) into the sweep's tables, plots and report, exactly as a single run would.

use std::path::PathBuf;

use crate::rundir::report::{report, Reported};
use crate::studies::sweep::{self, SweepKind};

#[derive(clap::Args, Debug, serde::Serialize)]
pub struct Args {
    /// A sweep directory written by `stripes phase-map`, `stripes ablate` or `stripes events-sweep`.
    pub dir: PathBuf,
}

pub fn run(args: Args) -> Reported {
    let sweep = sweep::load(&args.dir)?;
    match sweep.kind {
        SweepKind::PhaseMap => report(sweep::phase_map::report(&args.dir, &sweep)?),
        SweepKind::Ablate => report(sweep::ablate::report(&args.dir, &sweep)?),
        SweepKind::EventsSweep => report(crate::studies::events_sweep::report(&args.dir, &sweep)?),
    }
}
