//! The one rule of `--resume` for tray scenes (`stripes run`, `stripes compare`): a resume
//! continues only the run it finds. The resolved scene given now (file and `--set`) is compared
//! key by key with the scene the run wrote (`scene.toml`, with its `[automaton]` table); every
//! difference is refused, naming each key, except `run.duration` made longer (the run is
//! extended) and the keys that do not change a trajectory (`run.threads`,
//! `run.checkpoint_interval`). A shorter `run.duration` is refused too: the run on disk
//! already went further than asked.
//!
//! Tray scenes name no input files (tables); the event-driven model's own resume check covers
//! its tables by content hash.

use std::path::Path;

use crate::rundir::output::CliError;
use crate::scene::file::SceneFile;

/// The dotted keys that differ between the scene of the run on disk (`found`) and the scene
/// given now, as `key: found -> given`, leaving out `run.duration` and the keys that do not
/// change a trajectory.
pub fn refused_differences(found: &SceneFile, given: &SceneFile) -> Vec<String> {
    let mut differ = crate::scene::file::differences(&found.dem, &given.dem);
    differ.retain(|d| !d.starts_with("run.duration:"));
    differ.extend(crate::scene::file::table_differences(
        "automaton",
        &toml_of(&found.automaton),
        &toml_of(&given.automaton),
    ));
    differ
}

fn toml_of(spec: &automaton::Spec) -> toml::Value {
    toml::Value::try_from(spec).unwrap_or(toml::Value::Table(Default::default()))
}

/// Refuses a resume of the run in `dir` (its `scene.toml`) with the scene `given`, naming
/// every key that differs; `what` names the run in messages (e.g. `--resume: out/x`).
/// Nothing is written or removed.
pub fn check(dir: &Path, given: &SceneFile, what: &str) -> Result<(), CliError> {
    let path = dir.join("scene.toml");
    let found = crate::scene::file::load(&path, &[]).map_err(|e| {
        format!("{what}: cannot read the scene of the run it continues ({e}); nothing was changed; --force starts the run again")
    })?;
    check_scenes(&found, given, &path.display().to_string(), what)
}

/// [`check`] on a scene already read (`origin` names where it came from).
pub fn check_scenes(found: &SceneFile, given: &SceneFile, origin: &str, what: &str) -> Result<(), CliError> {
    let mut refused = refused_differences(found, given);
    let (was, now) = (found.dem.run.duration, given.dem.run.duration);
    if now < was {
        refused.push(format!(
            "run.duration: {was} -> {now} (a resume may only extend a run; this one already holds {was} s)"
        ));
    }
    if refused.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{what}: the scene given differs from the run's ({origin}) in {} key(s) (its value -> the value given): {}. \
         A resume continues only the run it finds and may only make run.duration longer; nothing was changed. \
         Give the run's own scene, or --force (or another --out) to start a new run",
        refused.len(),
        refused.join("; ")
    )
    .into())
}

/// Why a directory cannot be resumed, in words that are true of what it holds: nothing, or
/// files written before a first checkpoint was due.
pub fn no_checkpoint(out: &Path) -> String {
    let (mut files, mut bytes) = (0u64, 0u64);
    let mut walk = vec![out.to_path_buf()];
    while let Some(d) = walk.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk.push(p);
            } else if e.file_name() != ".lock" {
                files += 1;
                bytes += e.metadata().map_or(0, |m| m.len());
            }
        }
    }
    if files == 0 {
        format!(
            "{} holds no checkpoint.bin to continue from (nothing was written); start the run without --resume",
            out.display()
        )
    } else {
        format!(
            "{} holds no checkpoint.bin to continue from: its {files} file(s) ({:.3} MB) were written before a first checkpoint; \
             --force starts the run again",
            out.display(),
            bytes as f64 / 1e6
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = r#"
[box]
length = 0.1
width = 0.02
[drive]
frequency = 20.0
amplitude = 0.025
[particles]
count = 1000
radius_min = 0.25e-3
radius_max = 0.5e-3
[run]
duration = 3.0
dt = 8e-6
seed = 1
"#;

    fn scene(set: &[&str]) -> SceneFile {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        crate::scene::file::parse(SCENE, &set, "test").unwrap()
    }

    /// Issue 43, findings 1 and 2: a resume with another scene, or with one key changed by
    /// `--set`, is refused naming each key; a longer duration extends, a shorter is refused.
    #[test]
    fn a_resume_refuses_every_changed_key_but_a_longer_duration() {
        let run = scene(&[]);
        assert!(check_scenes(&run, &run, "a", "--resume").is_ok());
        assert!(check_scenes(&run, &scene(&["run.duration=5", "run.threads=2"]), "a", "--resume").is_ok());
        let e = check_scenes(&run, &scene(&["contact.friction=0.5"]), "a", "--resume")
            .unwrap_err()
            .to_string();
        assert!(e.contains("1 key(s)") && e.contains("contact.friction: 0.7 -> 0.5"), "{e}");
        let e = check_scenes(&run, &scene(&["run.duration=1"]), "a", "--resume")
            .unwrap_err()
            .to_string();
        assert!(e.contains("run.duration: 3 -> 1") && e.contains("only extend"), "{e}");
        let other = scene(&["particles.count=2000", "drive.frequency=3", "automaton.activation=0.3"]);
        let e = check_scenes(&run, &other, "a", "--resume").unwrap_err().to_string();
        for key in [
            "particles.count: 1000 -> 2000",
            "drive.frequency: 20.0 -> 3",
            "automaton.activation",
        ] {
            assert!(e.contains(key), "{key} not named: {e}");
        }
        assert!(e.contains("3 key(s)"), "{e}");
    }
}
