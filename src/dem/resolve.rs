//! A scene file resolved once: checked, with the DEM's laws, walls and step built, before any
//! run, study or check uses it.

use std::path::{Path, PathBuf};

use particles::measure;
use particles::setup::Setup;
use particles::time_step;
use particles::tray;

use crate::dem::samples::sample_key;
use crate::rundir::output::CliError as Error;
use crate::scene::file::SceneFile;

/// A scene checked and resolved for the DEM: the scene file (its `[automaton]` table kept
/// for the run directory's `scene.toml`), the setup its laws, walls, gravity and step give,
/// and the names of its sample and checkpoints. Built by [`resolve`], once per run.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// Where the scene was read (named in summaries and titles).
    pub path: PathBuf,
    pub file: SceneFile,
    /// Laws, walls, gravity, boundaries and the step (`run.dt`, chosen by the collision lab
    /// for `"auto"`).
    pub setup: Setup,
    /// The prepared sample the scene starts from ([`crate::dem::samples::sample_key`]).
    pub sample_key: u64,
    /// What a checkpoint must match to be resumed ([`checkpoint_fingerprint`]).
    pub fingerprint: u64,
    /// What a run of the scene must say at its start: the disk it will fill, a drive too weak
    /// to move anything ([`crate::scene::bounds::dem`]).
    pub warnings: Vec<String>,
}

impl Resolved {
    /// The DEM's scene.
    pub fn scene(&self) -> &particles::scene::Scene {
        &self.file.dem
    }

    /// The step (s).
    pub fn dt(&self) -> f64 {
        self.setup.dt
    }
}

/// Checks `file` (read from `path`) and builds its DEM setup: the laws and walls once, the
/// step once (`"auto"` runs the collision lab here, not in each consumer), and refuses
/// snapshots closer than two steps.
pub fn resolve(path: &Path, file: SceneFile) -> Result<Resolved, Error> {
    let scene = &file.dem;
    scene.validate()?;
    let setup = tray::setup(scene, tray::drive(scene), time_step::for_scene(scene)?)?;
    // The fastest stage of a schedule takes its snapshots closest together.
    let gap = 1.0 / (scene.run.snapshots_per_period as f64 * scene.drive.highest_frequency());
    if gap < 2.0 * setup.dt {
        return Err(format!(
            "scene `run.snapshots_per_period` = {}: snapshots {gap:e} s apart are closer than two steps of {:e} s; at most {} per period",
            scene.run.snapshots_per_period,
            setup.dt,
            (1.0 / (2.0 * setup.dt * scene.drive.highest_frequency())).floor()
        )
        .into());
    }
    // Sizes before anything is allocated or written (crate::scene::bounds).
    let warnings = crate::scene::bounds::dem(scene, setup.dt)?;
    Ok(Resolved {
        path: path.to_path_buf(),
        sample_key: sample_key(scene),
        fingerprint: checkpoint_fingerprint(scene)?,
        file,
        setup,
        warnings,
    })
}

/// What a checkpoint must match to be resumed: the scene and its sample, except the keys that
/// do not change the trajectory (`run.threads`, `run.checkpoint_interval`) or only say where
/// it stops (`run.duration`, so a finished run can be extended with `--resume`).
fn checkpoint_fingerprint(scene: &particles::scene::Scene) -> Result<u64, Error> {
    let mut s = scene.clone();
    s.run.threads = 0;
    s.run.checkpoint_interval = 0.0;
    s.run.duration = 1.0;
    Ok(measure::fnv1a(toml::to_string(&s)?.as_bytes()) ^ sample_key(scene))
}
