//! Issue 19, point 15: every `scenes/*.toml` loads, validates and gets its time step before a
//! run starts. (Until issue 41 `time_step::warnings` also said when the step left the
//! Haff-Werner viscous branch unstable; its implicit update is stable at any step.)

use particles::scene::Scene;
use particles::time_step;
use serde::Deserialize;

#[test]
fn every_shipped_scene_validates_and_gets_its_step() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        // The DEM's tables; the automaton's `[automaton]` table is the automaton's to check.
        let mut doc: toml::Table = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        if doc.get("model").and_then(|m| m.as_str()) == Some("events") {
            continue; // an event-driven scene: tests/cli_events.rs runs it
        }
        doc.remove("automaton");
        let origin = path.display().to_string();
        let scene = Scene::deserialize(toml::Value::Table(doc)).unwrap_or_else(|e| panic!("{origin}: {e}"));
        scene.validate().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let dt = time_step::for_scene(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(dt > 0.0 && dt.is_finite(), "{}: dt = {dt:e} s", path.display());
        checked += 1;
    }
    assert!(checked >= 2, "only {checked} scenes found");
}

/// `dt = "auto"` keeps the Haff-Werner viscous branch of the smallest grains within the ratio
/// at which the ledger was measured to close, however slow the drive
/// (`time_step::VISCOUS_RATIO_AUTO`): at 3 Hz and 2 mm, or 2 Hz and 1 mm, the impacts are slow
/// and the contacts long, and the restitution criterion alone would choose a longer step.
#[test]
fn auto_step_resolves_the_viscous_friction_at_the_slowest_drives() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stripes.toml");
    let mut doc: toml::Table = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    doc.remove("automaton");
    let stripes = Scene::deserialize(toml::Value::Table(doc)).unwrap();
    for (f, a) in [(3.0, 0.002), (2.0, 0.001), (20.0, 0.025)] {
        let mut scene = stripes.clone();
        scene.drive.frequency = f;
        scene.drive.amplitude = a;
        let dt = time_step::for_scene(&scene).unwrap();
        let ratio = time_step::viscous_friction_ratio(&scene, dt).unwrap().unwrap();
        assert!(
            ratio <= time_step::VISCOUS_RATIO_AUTO * (1.0 + 1e-12),
            "{f} Hz, {a} m: ratio {ratio}"
        );
    }
}
