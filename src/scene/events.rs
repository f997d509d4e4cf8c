//! The text side of the event-driven scene ([`events::scene::EventScene`], the `events`
//! crate's serde types): a scene file with `--set` overrides read into it (`model =
//! "events"`, told apart from a tray scene), the restitution tables its rules name read from
//! their CSV files, and the bytes of a run's snapshots bounded before anything is written.
//! `docs/scenes.md` documents every key.

use std::path::Path;

use events::scene::EventScene;
use events::{Config, Table};
use particles::scene::SceneError;
use serde::Deserialize;

use crate::scene::bounds::{DISK_NOTE_BYTES, MAX_SNAPSHOT_BYTES};
use crate::scene::text::overrides;

/// Reads an event-driven scene with `--set` overrides; errors name the file or override.
pub fn load(path: &Path, set: &[String]) -> Result<EventScene, SceneError> {
    let (text, origin) = crate::scene::file::read(path)?;
    let mut scene = parse_text(&text, set, &origin)?;
    // A table's path is read from the working directory; made absolute here, the run's
    // scene.toml (and a rerun or --resume from another directory) names the same file.
    if let Ok(cwd) = std::env::current_dir() {
        for (_, rule) in scene.rules.named_mut() {
            if let Some(p) = rule.table.as_mut().filter(|p| p.is_relative()) {
                *p = cwd.join(&*p);
            }
        }
    }
    Ok(scene)
}

/// The scene in `text` (named `origin` in messages) with `--set` overrides.
fn parse_text(text: &str, set: &[String], origin: &str) -> Result<EventScene, SceneError> {
    overrides::parse(text, set, origin, |doc| {
        // A tray scene (no `model`) would only be told of its first unknown table.
        match doc.get("model").and_then(|m| m.as_str()) {
            Some("events") => {}
            None if doc.get("model").is_none() => {
                return Err(
                    "this is a tray scene (no model = \"events\"), for `stripes run`, `automaton` or `compare`; \
                            `stripes events` and `events-sweep` take an event-driven scene such as scenes/mixture.toml"
                        .into(),
                )
            }
            _ => {}
        }
        EventScene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())
    })
}

/// Reads a restitution table (`g_n, g_t_over_g_n, eps_n, beta`, one header line) into the
/// engine's grid; every `(g_n, ratio)` pair of the grid must be present once.
pub fn read_table(path: &Path) -> Result<Table, String> {
    let (header, rows) = analysis::io::read_csv(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let want = ["g_n", "g_t_over_g_n", "eps_n", "beta"];
    if header.iter().map(|h| h.trim()).collect::<Vec<_>>() != want {
        return Err(format!(
            "{}: the columns must be {}, got {}",
            path.display(),
            want.join(", "),
            header.join(", ")
        ));
    }
    // Every value a finite number in its range, named by its line, before the grid is built
    // (a NaN would match no axis value, and a negative g_n is no speed).
    for (k, r) in rows.iter().enumerate() {
        let row = k + 1;
        for (c, name) in want.iter().enumerate() {
            if !r[c].is_finite() {
                return Err(format!("{}: row {row}: {name} is {}, not a finite number", path.display(), r[c]));
            }
        }
        let (lo, hi) = ([0.0, 0.0, 0.0, -1.0], [f64::INFINITY, f64::INFINITY, 1.0, 1.0]);
        for (c, name) in want.iter().enumerate() {
            if !(lo[c]..=hi[c]).contains(&r[c]) {
                let range = if hi[c].is_finite() {
                    format!("in [{}, {}]", lo[c], hi[c])
                } else {
                    format!(">= {}", lo[c])
                };
                return Err(format!("{}: row {row}: {name} = {} must be {range}", path.display(), r[c]));
            }
        }
    }
    let axis = |c: usize| {
        let mut v: Vec<f64> = rows.iter().map(|r| r[c]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (g_n, ratio) = (axis(0), axis(1));
    let mut eps_n = vec![vec![f64::NAN; ratio.len()]; g_n.len()];
    let mut beta = eps_n.clone();
    for r in &rows {
        let i = g_n.iter().position(|&x| x == r[0]).expect("on the axis");
        let j = ratio.iter().position(|&x| x == r[1]).expect("on the axis");
        if !eps_n[i][j].is_nan() {
            return Err(format!("{}: g_n = {}, g_t/g_n = {} appears twice", path.display(), r[0], r[1]));
        }
        (eps_n[i][j], beta[i][j]) = (r[2], r[3]);
    }
    if eps_n.iter().flatten().any(|x| x.is_nan()) {
        return Err(format!(
            "{}: not a full grid of {} g_n x {} ratios",
            path.display(),
            g_n.len(),
            ratio.len()
        ));
    }
    let t = Table { g_n, ratio, eps_n, beta };
    t.validate().map_err(|m| format!("{}: {m}", path.display()))?;
    Ok(t)
}

/// The engine's configuration of `scene` ([`EventScene::config`], its tables read by
/// [`read_table`]), with the bytes of the run's snapshots within their bound; errors name the
/// key.
pub fn config(scene: &EventScene) -> Result<Config, events::SceneError> {
    let config = scene.config(&read_table)?;
    let bytes = snapshot_bytes(scene);
    if bytes > MAX_SNAPSHOT_BYTES {
        return Err(events::SceneError::new(
            "run.samples_per_period",
            format!(
                "{} samples per period after run.transient is {:.1} GB of snapshots.bin; at most {:.0} GB are allowed: \
                 fewer samples per period or a shorter run",
                scene.run.samples_per_period,
                bytes / 1e9,
                MAX_SNAPSHOT_BYTES / 1e9
            ),
        ));
    }
    Ok(config)
}

/// What a run of this (valid) scene must say at its start: the disk its snapshots will fill
/// when that is more than a gigabyte, then what its physics says ([`EventScene::warnings`]:
/// a drive too weak to move anything).
pub fn warnings(scene: &EventScene) -> Vec<String> {
    let mut out = Vec::new();
    let bytes = snapshot_bytes(scene);
    if bytes > DISK_NOTE_BYTES {
        out.push(format!(
            "this run writes about {:.1} GB of snapshots ({} samples per period after run.transient); make sure --out has the room",
            bytes / 1e9,
            scene.run.samples_per_period
        ));
    }
    out.extend(scene.warnings());
    out
}

/// Bytes of the run's `snapshots.bin` (the snapshot format of the DEM's runs,
/// [`crate::scene::bounds::snapshot_bytes`]): a frame per sample after `run.transient`.
fn snapshot_bytes(scene: &EventScene) -> f64 {
    let grains: f64 = scene.particles.species.iter().map(|s| s.count as f64).sum();
    let frames = ((scene.run.duration - scene.run.transient) * scene.drive.frequency * f64::from(scene.run.samples_per_period))
        .max(0.0)
        .floor();
    crate::scene::bounds::snapshot_bytes(frames, grains)
}

#[cfg(test)]
mod tests {
    use super::*;
    use events::scene::EventRule;
    use events::Rule;

    fn mixture() -> String {
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mixture.toml")).unwrap()
    }

    fn ratchet() -> String {
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml")).unwrap()
    }

    #[test]
    fn the_ratchet_scene_maps_onto_the_paper_and_a_bad_base_names_its_key() {
        let c = config(&parse(&ratchet(), &[]).unwrap()).unwrap();
        let base = c.base.unwrap();
        assert_eq!((base.width, base.height, base.asymmetry), (6e-3, 3e-3, 0.1));
        assert!((c.width / base.width - 24.0).abs() < 1e-9);
        assert_eq!(c.q, 0.5);
        let key = |set: &[&str]| refused(&ratchet(), set).0;
        assert_eq!(key(&["base.tooth_width=0.007"]), "base.tooth_width");
        assert_eq!(key(&["base.tip_radius=0.004"]), "base.tip_radius");
        assert_eq!(key(&["base.asymmetry=-0.1"]), "base.asymmetry");
        // A name that is none of the key's is refused as the scene is read, blamed on the
        // override (or the file) and naming the key in its message.
        let (blamed, message) = refused(&ratchet(), &["base.shape=\"sine\""]);
        assert_eq!(blamed, "--set base.shape=\"sine\"");
        assert!(
            message.starts_with("base.shape (leave [base] out for a flat floor) must be \"sawtooth\""),
            "{message}"
        );
        assert_eq!(key(&["base.tooth_height=0.06"]), "base.tooth_height");
    }

    /// The key a scene with these overrides is refused by (as it is read, or by its check)
    /// and the message; "accepted" if none.
    fn refused(text: &str, set: &[&str]) -> (String, String) {
        match parse(text, set) {
            Err(e) => (e.key, e.message),
            Ok(s) => match config(&s) {
                Err(e) => (e.key, e.message),
                Ok(_) => ("accepted".into(), String::new()),
            },
        }
    }

    fn parse(text: &str, set: &[&str]) -> Result<EventScene, SceneError> {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        overrides::parse(text, &set, "test", |doc| {
            EventScene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())
        })
    }

    fn keys(prefix: &str, v: &toml::Value, out: &mut Vec<String>) {
        match v {
            toml::Value::Table(t) => {
                for (k, x) in t {
                    keys(&if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") }, x, out);
                }
            }
            toml::Value::Array(a) if a.iter().all(|x| x.is_table()) => {
                for x in a {
                    keys(prefix, x, out);
                }
            }
            _ => out.push(prefix.to_string()),
        }
    }

    #[test]
    fn every_event_scene_key_is_documented() {
        let mut all = Vec::new();
        let vibrated_box = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml")).unwrap();
        for text in [mixture(), ratchet(), vibrated_box] {
            let scene = parse(
                &text,
                &[
                    "guard.min_rebound_speed=1e-4",
                    "guard.tc=1e-6",
                    "guard.collapse_speed=1e-3",
                    "particles.q=0.5",
                    "run.phase=0.5",
                    "run.phase_resolved=true",
                ],
            )
            .unwrap();
            keys("", &toml::Value::try_from(&scene).unwrap(), &mut all);
        }
        all.sort();
        all.dedup();
        assert!(all.len() > 25, "{all:?}");
        let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md")).unwrap();
        let section = &docs[docs.find("## Event-driven scenes").expect("the events section")..];
        let missing: Vec<&String> = all
            .iter()
            .filter(|k| {
                // A wall rule's keys are documented with the pair's ("likewise for each wall").
                let k = k
                    .replace("rules.floor.", "rules.pair.")
                    .replace("rules.side.", "rules.pair.")
                    .replace("rules.lid.", "rules.pair.");
                !section.contains(&format!("`{k}`"))
            })
            .collect();
        assert!(missing.is_empty(), "docs/scenes.md does not document {missing:?}");
    }

    #[test]
    fn the_mixture_scene_maps_onto_the_paper_and_bad_values_name_their_key() {
        let c = config(&parse(&mixture(), &[]).unwrap()).unwrap();
        assert_eq!(c.species.len(), 2);
        assert_eq!(c.species[0].count + c.species[1].count, 300);
        assert!((c.width / 1.6e-3 - 48.0).abs() < 1e-9 && (c.height / 1.6e-3 - 32.0).abs() < 1e-9);
        assert_eq!(c.floor.unwrap().frequency, 50.0);
        let key = |set: &[&str]| refused(&mixture(), set).0;
        assert_eq!(key(&["rules.pair.e=[1.2, 0.8, 0.7]"]), "rules.pair[0].e");
        assert_eq!(key(&["rules.pair.beta0=1.5"]), "rules.pair[0].beta0");
        assert_eq!(key(&["rules.floor.mu=-1"]), "rules.floor[0].mu");
        assert_eq!(key(&["drive.amplitude=0.03"]), "drive.amplitude");
        assert_eq!(key(&["rules.pair.e=[0.9, 0.8]"]), "rules.pair.e");
        // Names that are none of their key's are refused as the scene is read, blamed on the
        // override and naming the key and the accepted names.
        for (set, says) in [
            (
                "box.side_walls=round",
                "box.side_walls must be \"fixed\", \"periodic\" or \"with-floor\", got \"round\"",
            ),
            (
                "model=tray",
                "model (`stripes events` takes an event-driven scene) must be \"events\", got \"tray\"",
            ),
            ("drive.floor=none", "drive.floor must be \"vibrated\" or \"fixed\", got \"none\""),
            (
                "drive.lid=open",
                "drive.lid must be \"vibrated\", \"fixed\" or \"none\", got \"open\"",
            ),
            (
                "particles.shape=cube",
                "particles.shape must be \"sphere\" or \"disk\", got \"cube\"",
            ),
        ] {
            let (key, message) = refused(&mixture(), &[set]);
            assert_eq!(key, format!("--set {set}"));
            assert!(message.contains(says), "{set}: {message}");
        }
        // 1e9 Hz sampled 4 times a period for 10 s: 4e10 samples, a run that would never end.
        assert_eq!(key(&["drive.frequency=1e9"]), "run.samples_per_period");
        assert_eq!(key(&["run.duration=6e4"]), "run.samples_per_period");
        // The papers' observables and the inertia factor.
        for phase in ["1.0", "-0.25", "1.5"] {
            assert_eq!(key(&[&format!("run.phase={phase}")]), "run.phase");
        }
        assert_eq!(key(&["run.samples_per_period=4", "run.phase=0.3"]), "run.phase");
        for q in ["0.0", "-0.4", "1.01"] {
            assert_eq!(key(&[&format!("particles.q={q}")]), "particles.q");
        }
        assert_eq!(key(&["guard.collapse_speed=0.0"]), "guard.collapse_speed");
        assert_eq!(key(&["run.duration=4e4"]), "accepted");
        assert_eq!(key(&["run.transient=20"]), "run.transient");
        assert_eq!(key(&["rules.floor.e=[1.0, 1.0]", "rules.floor.table=x.csv"]), "rules.floor.table");
        assert_eq!(key(&["drive.peak_speed=0.5"]), "drive.peak_speed");
    }

    #[test]
    fn a_peak_speed_sets_the_amplitude_at_the_scene_frequency() {
        let box_scene = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml")).unwrap();
        for f in [40.0, 100.0, 500.0] {
            let s = parse(&box_scene, &[&format!("drive.frequency={f}"), "drive.peak_speed=0.8"]).unwrap();
            let a = config(&s).unwrap().floor.unwrap().amplitude;
            assert!((a * 2.0 * std::f64::consts::PI * f - 0.8).abs() < 1e-12, "{f} Hz: A = {a}");
        }
        let both = config(&parse(&box_scene, &["drive.amplitude=0.001"]).unwrap()).unwrap_err();
        assert_eq!(both.key, "drive.peak_speed");
        let mut neither = parse(&box_scene, &[]).unwrap();
        neither.drive.peak_speed = None;
        assert_eq!(config(&neither).unwrap_err().key, "drive.amplitude");
        assert_eq!(
            config(&parse(&box_scene, &["drive.peak_speed=-1"]).unwrap()).unwrap_err().key,
            "drive.peak_speed"
        );
    }

    #[test]
    fn a_restitution_table_is_read_as_a_full_grid_and_used_as_the_rule() {
        let d = std::env::temp_dir().join(format!("stripes-events-table-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("restitution.csv");
        std::fs::write(
            &p,
            "g_n,g_t_over_g_n,eps_n,beta\n0.1,0,0.9,-0.5\n0.1,2,0.8,-1\n1,0,0.7,0.5\n1,2,0.6,0\n",
        )
        .unwrap();
        let t = read_table(&p).unwrap();
        assert_eq!(t.at(0.55, 1.0).0, 0.75);
        let set = format!("rules.pair.table={}", p.display());
        let c = parse(&mixture(), &["rules.pair.e=[]", &set]);
        assert!(c.is_err() || config(&c.unwrap()).is_err(), "e beside a table is refused");
        let mut scene = parse(&mixture(), &[]).unwrap();
        scene.rules.pair = EventRule {
            e: None,
            table: Some(p.clone()),
            mu: 0.0,
            beta0: -1.0,
            v0: None,
        };
        let c = config(&scene).unwrap();
        assert!(matches!(c.rules.pair[0], Rule::Table(_)) && c.rules.pair.len() == 3);
        std::fs::write(&p, "g_n,g_t_over_g_n,eps_n,beta\n0.1,0,0.9,-0.5\n1,2,0.6,0\n").unwrap();
        assert!(read_table(&p).unwrap_err().contains("not a full grid"));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_drive_waveform_is_a_sine_or_a_sawtooth_and_anything_else_names_its_key() {
        let key = |set: &[&str]| match parse(&mixture(), set) {
            Err(e) => e.key,
            Ok(s) => match config(&s) {
                Err(e) => e.key,
                Ok(c) => format!("{:?}", c.waveform),
            },
        };
        assert_eq!(key(&[]), "Sine");
        assert_eq!(key(&["drive.waveform=sawtooth"]), "Sawtooth");
        assert_eq!(key(&["drive.waveform=square"]), "--set drive.waveform=square");
        // The engine's refusal (sides that move with the floor) names the scene key.
        assert_eq!(key(&["drive.waveform=sawtooth", "box.side_walls=with-floor"]), "drive.waveform");
        // The default leaves the scene's fingerprint (and its checkpoints) as they were.
        let scene = parse(&mixture(), &[]).unwrap();
        assert!(!serde_json::to_string(&scene.drive).unwrap().contains("waveform"));
    }
}
