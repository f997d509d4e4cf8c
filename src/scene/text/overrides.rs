//! `--set dotted.key=value` overrides: the one parser of them, for every command and for
//! every table of a scene file (the DEM's, the automaton's and the event-driven model's).
//!
//! A value is read as a TOML value (number, bool, string, array, `inf`) or, failing that, as
//! a bare string, so `--set contact.rolling=none` needs no quotes. An error is blamed on what
//! caused it: the scene file when the file alone is wrong, else the first override after
//! which the scene no longer reads (`scene `--set run.durration=5`: unknown field ...`).

use particles::scene::SceneError;

fn err(key: &str, message: impl Into<String>) -> SceneError {
    SceneError {
        key: key.into(),
        message: message.into(),
    }
}

/// Applies `key=value` to a TOML document; errors name the override.
pub fn apply(doc: &mut toml::Table, assignment: &str) -> Result<(), SceneError> {
    let blame = format!("--set {assignment}");
    let (key, raw) = assignment
        .split_once('=')
        .ok_or_else(|| err(&blame, "an override must look like dotted.key=value"))?;
    let key = key.trim();
    let value = match toml::from_str::<toml::Table>(&format!("v = {}", raw.trim())) {
        Ok(mut t) => t.remove("v").unwrap_or_else(|| toml::Value::String(raw.trim().to_string())),
        Err(_) => toml::Value::String(raw.trim().to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(err(&blame, format!("empty component in dotted key `{key}`")));
    }
    let (last, tables) = parts.split_last().expect("split yields at least one part");
    let mut table = doc;
    let mut k = 0;
    while k < tables.len() {
        let part = tables[k];
        let mut entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        // An array of tables takes an index: `particles.species.0.count=49`.
        if let toml::Value::Array(items) = entry {
            let len = items.len();
            let index = tables
                .get(k + 1)
                .and_then(|i| i.parse::<usize>().ok())
                .filter(|&i| i < len)
                .ok_or_else(|| {
                    err(
                        &blame,
                        format!("`{part}` is a list of {len}: give an index below {len}, e.g. {part}.0.key"),
                    )
                })?;
            entry = &mut items[index];
            k += 1;
        }
        table = entry
            .as_table_mut()
            .ok_or_else(|| err(&blame, format!("`{part}` is a value, not a table")))?;
        k += 1;
    }
    if table.get(*last).is_some_and(|v| v.is_table()) && !value.is_table() {
        let keys: Vec<&str> = table[*last].as_table().map_or(vec![], |t| t.keys().map(|k| k.as_str()).collect());
        return Err(err(
            &blame,
            format!(
                "`{key}` is a table of keys ({}), not a value: set one of them, e.g. --set {key}.{}=...",
                keys.join(", "),
                keys.first().copied().unwrap_or("key")
            ),
        ));
    }
    table.insert(last.to_string(), value);
    Ok(())
}

/// Parses `text` (named `origin` in messages), applies `overrides` in order and reads the
/// document with `read`. A failure of `read` is blamed on the file if the file alone fails
/// the same way, else on the first override after which it does.
pub fn parse<T>(text: &str, overrides: &[String], origin: &str, read: impl Fn(toml::Table) -> Result<T, String>) -> Result<T, SceneError> {
    let file: toml::Table = toml::from_str(text).map_err(|e| err(origin, format!("not valid TOML: {e}")))?;
    let mut doc = file.clone();
    for o in overrides {
        apply(&mut doc, o)?;
    }
    let message = match read(doc) {
        Ok(t) => return Ok(t),
        Err(message) => message,
    };
    let mut partial = file;
    let mut culprit = origin.to_string();
    for k in 0..=overrides.len() {
        if k > 0 {
            apply(&mut partial, &overrides[k - 1])?;
        }
        if read(partial.clone()).err().as_ref() == Some(&message) {
            if k > 0 {
                culprit = format!("--set {}", overrides[k - 1]);
            }
            break;
        }
    }
    Err(err(&culprit, plain_words(&message)))
}

/// A deserialisation message in the user's words, not Rust's: type names (`usize`, `f64`,
/// ...) and the untagged `run.dt` become what a scene file may hold.
pub(crate) fn plain_words(message: &str) -> String {
    let mut m = message
        .replace(
            "data did not match any variant of untagged enum TimeStep",
            "expected a number of seconds or \"auto\"",
        )
        .replace(
            "data did not match any variant of untagged enum SortInterval",
            "expected a whole number of steps >= 1 or \"none\"",
        );
    for (rust, words) in [
        ("usize", "a whole number >= 0"),
        ("u64", "a whole number >= 0"),
        ("u32", "a whole number >= 0"),
        ("i64", "a whole number"),
        ("f64", "a number"),
    ] {
        m = m.replace(&format!("expected {rust}"), &format!("expected {words}"));
    }
    // `expected struct TrayBox`: a table of the scene, not a Rust type.
    if let Some(at) = m.find("expected struct ") {
        let end = m[at + 16..].find(|c: char| !c.is_alphanumeric()).map_or(m.len(), |e| at + 16 + e);
        m.replace_range(at..end, "expected a table of keys");
    }
    m
}
