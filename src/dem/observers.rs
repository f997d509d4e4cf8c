//! The outputs of a tray run, as observers ([`particles::advance`]): what `stripes run` writes and shows
//! while the DEM steps. The physics hands each of them the simulation after every step; the
//! file formats they write belong to `analysis` (snapshots, VTK) or are the simulation's own
//! checkpoint bytes.
//!
//! - [`Recorder`]: snapshots at the drive's turning points (and the ParaView series with
//!   `--vtk`), and checkpoints at `run.checkpoint_interval`. One observer, because a
//!   checkpoint records how many snapshots are in the file and must follow them.
//! - [`crate::dem::thermo::Thermo`]: the thermo table, in its own file.
//! - [`ContactMeans`]: mean live contacts per step, for the summary.
//! - [`Progress`]: the progress bar (or lines off a terminal).

use std::path::PathBuf;

use analysis::snapshot::{Header, SnapshotWriter};
use indicatif::ProgressBar;
use particles::advance::{Observer, ObserverError};
use particles::sim::Simulation;

use crate::dem::vtk::VtkSeries;

/// Positions as plain arrays, the analysis' frame type.
fn plain(v: &[particles::Vec3]) -> impl Iterator<Item = [f64; 3]> + '_ {
    v.iter().map(|p| [p.x, p.y, p.z])
}

/// Snapshots, VTK frames and checkpoints of one run directory.
pub struct Recorder {
    pub writer: SnapshotWriter,
    /// Snapshots written so far (frame 0 at t = 0 included).
    pub frames: u64,
    /// Time of snapshot `k >= 1`.
    snap_time: Box<dyn Fn(u64) -> f64>,
    /// With `--vtk`: every snapshot also goes to the ParaView series.
    pub vtk: Option<VtkSeries>,
    /// Checkpoint file, its fingerprint, and the steps between checkpoints; a checkpoint is
    /// also written at step `last`.
    pub checkpoint: PathBuf,
    fingerprint: u64,
    every: u64,
    last: u64,
    /// Until a first checkpoint is written: the wall-clock time by which one is written
    /// whatever `every` says, so that a run stopped early can be resumed.
    first_by: Option<std::time::Instant>,
    /// The step of the latest checkpoint written, for the observers whose files must follow
    /// it ([`crate::dem::thermo::Thermo::follow`]).
    pub checkpoints: std::rc::Rc<std::cell::Cell<u64>>,
}

/// Wall time after which a run writes its first checkpoint if none was due before.
pub const FIRST_CHECKPOINT_WALL: std::time::Duration = std::time::Duration::from_secs(3);

/// Where and when a [`Recorder`] writes.
pub struct RecorderPlan {
    pub header: Header,
    pub snapshots: PathBuf,
    /// Snapshots already in the file (a resumed run appends after them).
    pub frames: u64,
    pub snap_time: Box<dyn Fn(u64) -> f64>,
    pub vtk: Option<VtkSeries>,
    pub checkpoint: PathBuf,
    pub fingerprint: u64,
    pub every: u64,
    pub last: u64,
    /// Wall time after which the first checkpoint is written if none was due before.
    pub first_by: std::time::Duration,
}

impl Recorder {
    /// Opens the snapshot file (appending when `plan.frames > 0`).
    pub fn open(plan: RecorderPlan) -> Result<Self, ObserverError> {
        let writer = if plan.frames > 0 {
            SnapshotWriter::open_append(&plan.snapshots, plan.header, plan.frames)?
        } else {
            SnapshotWriter::create(&plan.snapshots, plan.header)?
        };
        Ok(Self {
            writer,
            frames: plan.frames,
            snap_time: plan.snap_time,
            vtk: plan.vtk,
            checkpoint: plan.checkpoint,
            fingerprint: plan.fingerprint,
            every: plan.every,
            last: plan.last,
            first_by: Some(std::time::Instant::now() + plan.first_by),
            checkpoints: Default::default(),
        })
    }

    /// Writes a snapshot of the current state now.
    pub fn snapshot(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        let state = sim.state();
        let s = &*state;
        self.writer.push(sim.time, plain(&s.pos), plain(&s.vel))?;
        if let Some(vtk) = &mut self.vtk {
            vtk.frame(sim, self.frames)?;
        }
        self.frames += 1;
        Ok(())
    }

    /// Writes the checkpoint after the snapshots it counts.
    fn checkpoint(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        self.writer.sync()?;
        analysis::io::write_atomic(
            &self.checkpoint,
            &crate::dem::checkpoint::encode(sim, self.fingerprint, self.frames),
        )?;
        self.first_by = None;
        self.checkpoints.set(sim.steps);
        Ok(())
    }
}

impl Observer for Recorder {
    fn observe(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        if sim.time >= (self.snap_time)(self.frames) - 0.5 * sim.setup.dt {
            self.snapshot(sim)?;
        }
        // The clock is read every 256 steps, and only until a first checkpoint is on disk.
        let early = self
            .first_by
            .is_some_and(|t| sim.steps.is_multiple_of(256) && std::time::Instant::now() >= t);
        if sim.steps.is_multiple_of(self.every) || sim.steps == self.last || early {
            self.checkpoint(sim)?;
        }
        Ok(())
    }
}

/// Sums of the live contacts over the steps observed.
#[derive(Default)]
pub struct ContactMeans {
    pair: f64,
    wall: f64,
    steps: u64,
}

impl ContactMeans {
    /// `(pair, wall)` means per step.
    pub fn means(&self) -> (f64, f64) {
        let n = self.steps.max(1) as f64;
        (self.pair / n, self.wall / n)
    }
}

impl Observer for ContactMeans {
    fn observe(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        self.pair += sim.contact_counts.0 as f64;
        self.wall += sim.contact_counts.1 as f64;
        self.steps += 1;
        Ok(())
    }
}

/// The progress bar (see [`crate::rundir::output::progress_bar`]), moved every 1000 steps, with the
/// simulated time of `duration` (s).
pub struct Progress<'a> {
    pub bar: &'a ProgressBar,
    pub duration: f64,
}

impl Observer for Progress<'_> {
    fn observe(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        if sim.steps.is_multiple_of(1000) {
            self.bar.set_position(sim.steps);
            self.bar.set_message(format!("t = {:.3} s of {} s", sim.time, self.duration));
        }
        Ok(())
    }
}
