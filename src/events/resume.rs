//! `--resume` of event-driven runs (`stripes events`) by the one rule of
//! [`crate::rundir::resume`]: the scene given now (file and `--set`) against the run's
//! `scene.toml`, key by key, and the restitution tables a scene names by content (a hash in
//! the checkpoint's fingerprint), so an edited table is refused even under the same path.

use std::path::Path;

use events::scene::EventScene;

use crate::rundir::output::CliError;
use crate::rundir::resume::{decide, Compared, Files};

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

/// The scene as the rule of `--resume` compares it ([`crate::rundir::resume`]).
fn compared(scene: &EventScene) -> Compared {
    Compared {
        tables: vec![("", toml::Value::try_from(scene).unwrap_or(toml::Value::Table(Default::default())))],
        duration: scene.run.duration,
    }
}

/// Refuses a resume of the run in `dir` with the scene `given` by the one rule of `--resume`
/// ([`crate::rundir::resume::decide`]), its tables compared by content: the checkpoint's
/// fingerprint, which hashes them, matches (`fingerprint_matches`) or not. Nothing is
/// written or removed.
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
    let files = Files {
        named: tables(given).iter().map(|(k, p)| format!("{k} = {}", p.display())).collect(),
        content_matches: fingerprint_matches,
    };
    decide(
        &compared(&found),
        &compared(given),
        Some(&files),
        &path.display().to_string(),
        &format!("--resume {}", dir.display()),
    )
}
