//! A scene file as the commands read it: the DEM's scene ([`particles::scene::Scene`]) and
//! the automaton's optional `[automaton]` table ([`automaton::Spec`]), each owned by its
//! crate. `--set` overrides reach both tables ([`crate::scene::text::overrides`]).

use std::path::Path;

use particles::scene::{Scene, SceneError};
use serde::{Deserialize, Serialize};

use crate::scene::text::overrides;

/// Both models' view of one scene file. Serialises (for `config.json`) as the scene's
/// tables plus `automaton` unless it holds only defaults.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFile {
    #[serde(flatten)]
    pub dem: Scene,
    #[serde(skip_serializing_if = "automaton::Spec::is_default")]
    pub automaton: automaton::Spec,
}

/// Reads a scene file and applies `--set` overrides; errors name the file or the override.
pub fn load(path: &Path, set: &[String]) -> Result<SceneFile, SceneError> {
    let (text, origin) = read(path)?;
    parse(&text, set, &origin)
}

/// The text of a scene file and its name for messages; an unreadable file is named.
pub fn read(path: &Path) -> Result<(String, String), SceneError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        key: origin.clone(),
        message: format!("cannot read: {e}"),
    })?;
    Ok((text, origin))
}

/// Parses scene text (named `origin` in messages) with overrides.
pub fn parse(text: &str, set: &[String], origin: &str) -> Result<SceneFile, SceneError> {
    overrides::parse(text, set, origin, |mut doc| {
        if doc.get("model").and_then(|m| m.as_str()) == Some("events") {
            return Err("this is an event-driven scene (model = \"events\"): run it with `stripes events`".into());
        }
        let table = doc.remove("automaton");
        let dem = Scene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())?;
        let automaton = match table {
            None => automaton::Spec::default(),
            Some(t) => automaton::Spec::deserialize(t).map_err(|e| format!("[automaton]: {e}"))?,
        };
        Ok(SceneFile { dem, automaton })
    })
}

impl SceneFile {
    /// Checks both tables; errors name the key.
    pub fn validate(&self) -> Result<(), SceneError> {
        self.dem.validate()?;
        self.automaton.validate().map_err(|e| SceneError {
            key: e.key,
            message: e.message,
        })
    }

    /// The resolved scene as TOML: the DEM's tables, then `[automaton]` unless it holds
    /// only defaults.
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        let mut text = toml::to_string(&self.dem)?;
        if !self.automaton.is_default() {
            text.push_str("\n[automaton]\n");
            text.push_str(&toml::to_string(&self.automaton)?);
        }
        Ok(text)
    }
}

/// The dotted keys whose values differ between two DEM scenes, as `key: a -> b`, leaving out
/// the keys that do not change a trajectory (`run.threads`, `run.checkpoint_interval`).
pub fn differences(a: &Scene, b: &Scene) -> Vec<String> {
    let value = |s: &Scene| toml::Value::try_from(s).unwrap_or(toml::Value::Table(Default::default()));
    let mut differ = table_differences("", &value(a), &value(b));
    differ.retain(|d| !(d.starts_with("run.threads:") || d.starts_with("run.checkpoint_interval:")));
    differ
}

/// The dotted keys (under `prefix`) whose values differ between two TOML values, as
/// `key: a -> b`, a key missing on one side shown as `(unset)`.
pub fn table_differences(prefix: &str, a: &toml::Value, b: &toml::Value) -> Vec<String> {
    fn flat(prefix: &str, v: &toml::Value, out: &mut std::collections::BTreeMap<String, String>) {
        match v {
            toml::Value::Table(t) => {
                for (k, x) in t {
                    let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                    flat(&key, x, out);
                }
            }
            other => {
                out.insert(prefix.to_string(), other.to_string());
            }
        }
    }
    let table = |v: &toml::Value| {
        let mut m = std::collections::BTreeMap::new();
        flat(prefix, v, &mut m);
        m
    };
    let (ta, tb) = (table(a), table(b));
    let keys: std::collections::BTreeSet<&String> = ta.keys().chain(tb.keys()).collect();
    keys.into_iter()
        .filter(|k| ta.get(*k) != tb.get(*k))
        .map(|k| {
            let show = |m: &std::collections::BTreeMap<String, String>| m.get(k).cloned().unwrap_or_else(|| "(unset)".into());
            format!("{k}: {} -> {}", show(&ta), show(&tb))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::samples::sample_key;

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

    #[test]
    fn default_table_is_omitted_and_automaton_keys_never_change_the_sample() {
        let plain = parse(SCENE, &[], "test").unwrap();
        assert_eq!(plain.automaton.rule, automaton::RuleSet::Physical);
        assert_eq!(plain.automaton.lateral, automaton::Lateral::Clusters);
        assert!(!plain.to_toml().unwrap().contains("[automaton]"));
        let set = ["automaton.activation=0.3", "automaton.rule=strict", "automaton.lateral=none"];
        let tuned = parse(SCENE, &set.map(String::from), "test").unwrap();
        let text = tuned.to_toml().unwrap();
        assert!(text.contains("[automaton]"));
        assert_eq!(parse(&text, &[], "again").unwrap(), tuned, "the written scene reads back");
        assert_eq!(sample_key(&plain.dem), sample_key(&tuned.dem));
    }

    #[test]
    fn bad_automaton_values_name_their_key_and_overrides_are_blamed() {
        for (set, key) in [
            ("automaton.activation=1.5", "automaton.activation"),
            ("automaton.sideways_probability=-0.1", "automaton.sideways_probability"),
            ("automaton.knock_speed=0", "automaton.knock_speed"),
            ("automaton.cell=-1e-3", "automaton.cell"),
        ] {
            let s = parse(SCENE, &[set.into()], "test").unwrap();
            assert_eq!(s.validate().unwrap_err().key, key);
        }
        let e = parse(SCENE, &["automaton.flight=true".into()], "test").unwrap_err();
        assert!(e.message.contains("flight"), "{e}");
        assert_eq!(e.key, "--set automaton.flight=true");
        let e = parse(SCENE, &["run.durration=5".into()], "s/base.toml").unwrap_err();
        assert_eq!(e.key, "--set run.durration=5", "{e}");
    }

    /// Dotted keys of a TOML table (`table.key`), nested tables walked.
    fn keys(prefix: &str, table: &toml::Table, out: &mut Vec<String>) {
        for (k, v) in table {
            let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
            match v {
                toml::Value::Table(t) => keys(&key, t, out),
                // An array of tables (`[[drive.stages]]`): the array and each table's keys.
                toml::Value::Array(a) if a.iter().all(toml::Value::is_table) && !a.is_empty() => {
                    out.push(key.clone());
                    for t in a.iter().filter_map(toml::Value::as_table) {
                        keys(&key, t, out);
                    }
                }
                _ => out.push(key),
            }
        }
    }

    #[test]
    fn every_scene_key_is_documented() {
        // Every optional key set (and off its default where a default is left out of the
        // written scene), so that the written scene holds every key the parser accepts.
        let set = [
            "box.height=0.1",
            "contact.kn=1e3",
            "contact.gamma_n=0.1",
            "contact.tangential_stiffness=300",
            "contact.rolling_resistance=0.1",
            "contact.rolling_resistance_spread=0.05",
            "contact.rolling_stiffness=100",
            "contact.rolling_damping=0.01",
            "run.restitution_tolerance=1e-3",
            "run.integrator=thesis",
            "automaton.cell=1e-3",
            "automaton.activation=0.5",
        ];
        let file = parse(SCENE, &set.map(String::from), "test").unwrap();
        let doc: toml::Table = toml::from_str(&file.to_toml().unwrap()).unwrap();
        let mut all = Vec::new();
        keys("", &doc, &mut all);
        // A drive schedule's keys (arrays of tables cannot be set with --set).
        let staged = SCENE.replace(
            "frequency = 20.0\namplitude = 0.025\n",
            "[[drive.stages]]\nfrequency = 5.0\namplitude = 0.02\nduration = 2.0\n",
        );
        let file = parse(&staged, &[], "staged").unwrap();
        let doc: toml::Table = toml::from_str(&file.to_toml().unwrap()).unwrap();
        keys("", &doc, &mut all);
        assert!(all.iter().any(|k| k == "drive.stages.duration"), "{all:?}");
        // The clump's keys (a clump needs velocity Verlet, so not with the set above).
        let clump = ["particles.shape=clump", "particles.clump_spheres=2", "particles.clump_spacing=1.0"];
        let file = parse(SCENE, &clump.map(String::from), "clump").unwrap();
        let doc: toml::Table = toml::from_str(&file.to_toml().unwrap()).unwrap();
        keys("", &doc, &mut all);
        assert!(all.iter().any(|k| k == "particles.clump_spacing"), "{all:?}");
        assert!(all.len() > 40, "{all:?}");
        let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md")).unwrap();
        let missing: Vec<&String> = all.iter().filter(|k| !docs.contains(&format!("`{k}`"))).collect();
        assert!(missing.is_empty(), "docs/scenes.md does not document {missing:?}");
    }

    #[test]
    fn differences_name_each_changed_key_and_ignore_threads() {
        let a = parse(SCENE, &[], "a").unwrap().dem;
        let b = parse(SCENE, &["drive.frequency=10".into(), "run.threads=2".into()], "b")
            .unwrap()
            .dem;
        let d = differences(&a, &b);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(d[0].starts_with("drive.frequency: 20") && d[0].ends_with("-> 10.0"), "{d:?}");
        assert!(differences(&a, &a).is_empty());
    }
}
