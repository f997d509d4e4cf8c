//! `stripes run SCENE.toml`: the tray-driven DEM.
//!
//! Writes into the run directory: `scene.toml` (the resolved scene, with its `[automaton]`
//! table), `config.json`,
//! `snapshots.bin` (see `analysis::snapshot`; a frame at t = 0 and then at the chosen phase of
//! every period), `thermo.csv` and `thermo.{png,svg}` (see `crate::dem::thermo`), `checkpoint.bin`
//! (at `run.checkpoint_interval`), with `--vtk` a ParaView series `vtk/series.pvd` (see
//! `crate::dem::vtk`), and `summary.json`. `--resume` continues from `checkpoint.bin`, bit
//! for bit.
//!
//! A directory that already holds a run is refused unless `--resume` (continue it) or
//! `--force` (replace it) is given. Everything that can be checked (the scene, the time step,
//! the checkpoint of `--resume`) is checked before anything is written, and a start that
//! fails before the first step removes what it created.

use std::path::PathBuf;

use serde::Serialize;

use crate::dem::{resolve, run_dem, RunOptions};
use crate::rundir::report::{report, Reported};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    #[command(flatten)]
    #[serde(flatten)]
    pub run: crate::cli::args::SceneRun,
    /// Also write every snapshot for ParaView: vtk/series.pvd (open it) with one .vtp of the
    /// grains (id, radius, velocity, angular velocity) and one of the tray per snapshot.
    #[arg(long)]
    pub vtk: bool,
    /// Simulated seconds between rows of thermo.csv (default: a tenth of the drive period).
    #[arg(long, value_name = "SECONDS")]
    pub thermo_interval: Option<f64>,
    #[command(flatten)]
    #[serde(flatten)]
    pub samples: crate::cli::args::SampleCache,
    /// Also write the state the run starts from (the prepared sample, or the checkpoint with
    /// --resume) as a LAMMPS data file (atom_style sphere, units si), to run the same grains
    /// in LAMMPS (bench/lammps/in.tray).
    #[arg(long, value_name = "FILE")]
    pub lammps_data: Option<PathBuf>,
    /// Die after this many steps as `kill -9` would (a test hook for checkpoints and --resume).
    #[arg(long, hide = true)]
    pub stop_after: Option<u64>,
    /// Wall seconds by which the first checkpoint is written (default 3; a test hook).
    #[arg(long, hide = true, value_parser = crate::cli::values::not_nan)]
    pub first_checkpoint_after: Option<f64>,
}

impl Args {
    /// The pipeline's options these arguments select (the scene is read apart).
    pub fn options(&self) -> RunOptions {
        let name = self
            .run
            .scene
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        RunOptions {
            out: self.run.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/run-{name}"))),
            resume: self.run.resume,
            force: self.run.force,
            vtk: self.vtk,
            thermo_interval: self.thermo_interval,
            sample_cache: self.samples.sample_cache.clone(),
            lammps_data: self.lammps_data.clone(),
            stop_after: self.stop_after,
            first_checkpoint_after: self.first_checkpoint_after,
            quiet: self.run.quiet,
        }
    }
}

pub fn run(args: Args) -> Reported {
    let file = crate::scene::file::load(&args.run.scene, &args.run.set.overrides)?;
    let resolved = resolve(&args.run.scene, file)?;
    report(run_dem(&resolved, &args.options())?)
}
