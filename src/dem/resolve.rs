//! A scene file resolved once: checked, with the DEM's laws, walls and step built, before any
//! run, study or check uses it.

use std::path::{Path, PathBuf};

use particles::measure;
use particles::prepare::SAMPLE_REVISION;
use particles::setup::Setup;
use particles::time_step;
use particles::tray;

use crate::dem::samples::{sample_key, sample_key_at};
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
    Ok(trajectory_key(scene)? ^ sample_key(scene))
}

/// The scene's keys that a checkpoint must match, hashed (the fingerprint without the sample).
fn trajectory_key(scene: &particles::scene::Scene) -> Result<u64, Error> {
    let mut s = scene.clone();
    s.run.threads = 0;
    s.run.checkpoint_interval = 0.0;
    s.run.duration = 1.0;
    Ok(measure::fnv1a(toml::to_string(&s)?.as_bytes()))
}

/// Why a checkpoint of fingerprint `found` does not belong to `scene`, where it can be told:
/// the same scene's checkpoint written by a version of an older sample revision (whose
/// prepared samples differ, so its checkpoints are refused as another scene's). `None`: a
/// key of the scene differs, or the file is not this scene's at all.
pub fn refusal_reason(scene: &particles::scene::Scene, found: u64) -> Option<String> {
    let keys = trajectory_key(scene).ok()?;
    let revision = (0..SAMPLE_REVISION).rev().find(|&r| keys ^ sample_key_at(scene, r) == found)?;
    Some(format!(
        "it is this scene's checkpoint, written by a version of sample revision {revision} (this one is of \
         revision {SAMPLE_REVISION}, whose prepared samples differ): continue it with a build of revision \
         {revision}: `git log -S 'SAMPLE_REVISION: u64 = {revision};' -- particles/src/prepare.rs` names the commit \
         that brought it and the one that ended it; build the latter's parent"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(set: &[&str]) -> particles::scene::Scene {
        let text = "[box]\nlength = 0.1\nwidth = 0.02\n[drive]\nfrequency = 20.0\namplitude = 0.025\n\
                    [particles]\ncount = 100\nradius_min = 0.25e-3\nradius_max = 0.5e-3\n[run]\nduration = 1.0\ndt = 8e-6\nseed = 1\n";
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        crate::scene::file::parse(text, &set, "test").expect("a valid scene").dem
    }

    #[test]
    fn a_checkpoint_of_an_older_sample_revision_is_named_as_such() {
        let s = scene(&[]);
        let keys = trajectory_key(&s).unwrap();
        let older = keys ^ sample_key_at(&s, SAMPLE_REVISION - 1);
        assert_ne!(older, checkpoint_fingerprint(&s).unwrap());
        let why = refusal_reason(&s, older).expect("an older revision is recognised");
        assert!(why.contains(&format!("sample revision {}", SAMPLE_REVISION - 1)), "{why}");
        // Another scene's checkpoint (a key differs), or this revision's own: no such reason.
        let other = scene(&["run.seed=7"]);
        let theirs = trajectory_key(&other).unwrap() ^ sample_key_at(&other, SAMPLE_REVISION - 1);
        assert_eq!(refusal_reason(&s, theirs), None);
        assert_eq!(refusal_reason(&s, checkpoint_fingerprint(&s).unwrap()), None);
    }
}
