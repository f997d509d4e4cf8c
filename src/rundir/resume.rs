//! The one rule of `--resume`, for every model (`stripes run`, `stripes compare`,
//! `stripes events`): a resume continues only the run it finds. The scene given now (file and
//! `--set`, resolved) is compared key by key with the scene the run wrote (`scene.toml`);
//! every difference is refused, naming each key, except `run.duration` made longer (the run
//! is extended) and the keys that do not change a trajectory (`run.threads`,
//! `run.checkpoint_interval`). A shorter `run.duration` is refused too: the run on disk
//! already went further than asked. A scene that names input files (the event-driven
//! restitution tables) is also compared by their content: when every key agrees but the
//! content the run was written with does not, the files are named.
//!
//! Each model gives its scenes as [`Compared`] key/value tables ([`check`] for tray scenes,
//! with their `[automaton]` table; `crate::events::resume` for event-driven scenes).

use std::path::Path;

use crate::rundir::output::CliError;
use crate::scene::file::SceneFile;

/// The keys whose values may differ between the run's scene and the scene given: the
/// duration (which has its own rule, below) and the keys that do not change a trajectory.
pub const MAY_DIFFER: [&str; 3] = ["run.duration", "run.threads", "run.checkpoint_interval"];

/// A scene as the rule compares it: its tables as TOML values, each under the prefix of its
/// keys (`""` for the scene's own, `automaton` for a tray scene's `[automaton]`), and its
/// `run.duration` (s).
pub struct Compared {
    pub tables: Vec<(&'static str, toml::Value)>,
    pub duration: f64,
}

/// The input files a scene names, for a model whose scenes name them: each as `key = path`,
/// and whether their content is what the run was written with (a hash in its checkpoint).
pub struct Files {
    pub named: Vec<String>,
    pub content_matches: bool,
}

/// What the rule refuses, each as `key: found -> given` (or why): every key that differs but
/// those of [`MAY_DIFFER`], a shorter `run.duration`, and, when all keys agree, input files
/// whose content differs.
pub fn refused(found: &Compared, given: &Compared, files: Option<&Files>) -> Vec<String> {
    let free = |d: &String| MAY_DIFFER.iter().any(|k| d.starts_with(&format!("{k}:")));
    let mut refused: Vec<String> = found
        .tables
        .iter()
        .zip(&given.tables)
        .flat_map(|((prefix, f), (_, g))| crate::scene::file::table_differences(prefix, f, g))
        .filter(|d| !free(d))
        .collect();
    let (was, now) = (found.duration, given.duration);
    if now < was {
        refused.push(format!(
            "run.duration: {was} -> {now} (a resume may only extend a run; this one already holds {was} s)"
        ));
    }
    if let Some(files) = files.filter(|f| refused.is_empty() && !f.content_matches) {
        refused.push(if files.named.is_empty() {
            "the checkpoint was written by another scene".to_string()
        } else {
            format!(
                "the content of {} differs from the table(s) the run was written with",
                files.named.join(", ")
            )
        });
    }
    refused
}

/// Refuses a resume whose scene `given` differs from the run's `found` (read from `origin`),
/// naming everything [`refused`] finds; `what` names the run in messages (e.g.
/// `--resume out/x`). Nothing is written or removed.
pub fn decide(found: &Compared, given: &Compared, files: Option<&Files>, origin: &str, what: &str) -> Result<(), CliError> {
    let refused = refused(found, given, files);
    if refused.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{what}: the scene given differs from the run's ({origin}) in {} key(s) (its value -> the value given): {}. \
         A resume continues only the run it finds and may only make run.duration longer; nothing was changed. \
         Give the run's own scene{}, or --force (or another --out) to start a new run",
        refused.len(),
        refused.join("; "),
        if files.is_some() { " and tables" } else { "" }
    )
    .into())
}

/// A tray scene as the rule compares it: the DEM's tables, then `[automaton]`.
fn compared(file: &SceneFile) -> Compared {
    let value = |v: Result<toml::Value, toml::ser::Error>| v.unwrap_or(toml::Value::Table(Default::default()));
    Compared {
        tables: vec![
            ("", value(toml::Value::try_from(&file.dem))),
            ("automaton", value(toml::Value::try_from(&file.automaton))),
        ],
        duration: file.dem.run.duration,
    }
}

/// Refuses a resume of the tray run in `dir` (its `scene.toml`) with the scene `given`,
/// naming every key that differs; `what` names the run in messages (e.g. `--resume out/x`).
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
    decide(&compared(found), &compared(given), None, origin, what)
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

    /// One rule for both models: an event-driven scene's tables are compared by content only
    /// when every key agrees, and its refusal asks for the run's scene and tables.
    #[test]
    fn the_one_rule_compares_named_files_by_content_when_the_keys_agree() {
        let table = |x: f64| Compared {
            tables: vec![("", toml::from_str(&format!("[run]\nduration = {x:?}\nseed = 1")).unwrap())],
            duration: x,
        };
        let files = |matches: bool, named: &[&str]| Files {
            named: named.iter().map(|n| n.to_string()).collect(),
            content_matches: matches,
        };
        let (run, longer, shorter) = (table(3.0), table(5.0), table(2.0));
        assert!(decide(&run, &longer, Some(&files(true, &[])), "a", "--resume x").is_ok());
        let e = decide(&run, &run, Some(&files(false, &["rules.pair.table = t.csv"])), "a", "--resume x")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("the content of rules.pair.table = t.csv differs") && e.contains("own scene and tables"),
            "{e}"
        );
        let e = decide(&run, &run, Some(&files(false, &[])), "a", "--resume x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("written by another scene"), "{e}");
        // A key that differs is named; the files' content then goes unsaid.
        let r = refused(&run, &shorter, Some(&files(false, &["rules.pair.table = t.csv"])));
        assert_eq!(r.len(), 1, "{r:?}");
        assert!(r[0].starts_with("run.duration: 3 -> 2"), "{r:?}");
    }
}
