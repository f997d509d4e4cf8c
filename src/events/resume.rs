//! The one rule of `--resume` for event-driven runs (`stripes events`), as
//! [`crate::rundir::resume`] is for tray scenes: a resume continues only the run it finds. The
//! scene given now (file and `--set`) is compared key by key with the run's `scene.toml`;
//! every difference is refused naming each key, except `run.duration` made longer (the run is
//! extended). A shorter `run.duration` is refused: the run on disk already went further. The
//! restitution tables a scene names are compared by content (a hash in the checkpoint's
//! fingerprint), so an edited table is refused even under the same path.

use std::path::Path;

use crate::rundir::output::CliError;
use events::scene::EventScene;

/// The tables a scene names, as `(key, path)`.
pub fn tables(scene: &EventScene) -> Vec<(String, std::path::PathBuf)> {
    scene
        .rules
        .named()
        .into_iter()
        .filter_map(|(key, rule)| rule.table.clone().map(|p| (format!("{key}.table"), p)))
        .collect()
}

/// A hash of the content of every table the scene names, with its key; 0 without tables (so
/// the fingerprint of a scene without tables is what it was before tables were hashed).
pub fn tables_hash(scene: &EventScene) -> Result<u64, CliError> {
    let mut h = 0u64;
    for (key, path) in tables(scene) {
        let bytes = std::fs::read(&path).map_err(|e| format!("{key}: cannot read {}: {e}", path.display()))?;
        let mut named = key.into_bytes();
        named.extend_from_slice(&bytes);
        h ^= crate::rundir::bytes::fnv1a(&named).rotate_left(1);
    }
    Ok(h)
}

/// The keys of `given` that differ from `found` (`key: found -> given`), `run.duration` left
/// out, and a shorter `run.duration` refused.
pub fn refused_differences(found: &EventScene, given: &EventScene) -> Vec<String> {
    let value = |s: &EventScene| toml::Value::try_from(s).unwrap_or(toml::Value::Table(Default::default()));
    let mut differ = crate::scene::file::table_differences("", &value(found), &value(given));
    differ.retain(|d| !d.starts_with("run.duration:"));
    let (was, now) = (found.run.duration, given.run.duration);
    if now < was {
        differ.push(format!(
            "run.duration: {was} -> {now} (a resume may only extend a run; this one already holds {was} s)"
        ));
    }
    differ
}

/// Refuses a resume of the run in `dir` with the scene `given`, naming every key that differs
/// from the run's `scene.toml`, a shorter `run.duration`, or, when the keys agree but the
/// checkpoint's fingerprint does not (`fingerprint_matches`), the tables whose content
/// changed. Nothing is written or removed.
pub fn check(dir: &Path, given: &EventScene, fingerprint_matches: bool) -> Result<(), CliError> {
    let path = dir.join("scene.toml");
    let found: EventScene = std::fs::read_to_string(&path)
        .map_err(|e| e.to_string())
        .and_then(|t| toml::from_str(&t).map_err(|e| e.to_string()))
        .map_err(|e| {
            format!(
                "--resume: cannot read the scene of the run it continues, {} ({e}); nothing was changed; --force starts the run again",
                path.display()
            )
        })?;
    let mut refused = refused_differences(&found, given);
    if refused.is_empty() && !fingerprint_matches {
        let names: Vec<String> = tables(given).iter().map(|(k, p)| format!("{k} = {}", p.display())).collect();
        refused.push(if names.is_empty() {
            "the checkpoint was written by another scene".to_string()
        } else {
            format!(
                "the content of {} differs from the table(s) the run was written with",
                names.join(", ")
            )
        });
    }
    if refused.is_empty() {
        return Ok(());
    }
    Err(format!(
        "--resume {}: the scene given differs from the run's ({}) in {} key(s) (its value -> the value given): {}. \
         A resume continues only the run it finds and may only make run.duration longer; nothing was changed. \
         Give the run's own scene and tables, or --force (or another --out) to start a new run",
        dir.display(),
        path.display(),
        refused.len(),
        refused.join("; ")
    )
    .into())
}
