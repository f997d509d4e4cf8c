//! `scenes/stripes.toml`, the DEM's stripe scene, stays what its comments promise: valid, at
//! a stable step with no warning, in the rolling regime (Gamma below 7 mu / 2), at packing
//! 0.46 on a box at least 0.1 m long.

use std::path::Path;

use particles::scene::Scene;
use particles::time_step;
use particles::tray;
use serde::Deserialize;

#[test]
fn the_stripe_scene_is_valid_warning_free_and_in_the_rolling_regime() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stripes.toml");
    // The DEM's tables only: `[automaton]` belongs to the automaton (read beside the scene
    // by the command line's scene_file).
    let mut doc: toml::Table = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    doc.remove("automaton");
    let scene = Scene::deserialize(toml::Value::Table(doc)).unwrap();
    scene.validate().unwrap();
    let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap();
    assert!(setup.dt > 0.0);
    assert!(scene.tray.length >= 0.1);
    assert!((scene.packing() - 0.46).abs() < 0.01, "packing {}", scene.packing());
    let w = 2.0 * std::f64::consts::PI * scene.drive.frequency;
    let gamma = scene.drive.amplitude * w * w / 10.0;
    assert!(
        gamma < 3.5 * scene.contact.wall_friction,
        "Gamma {gamma}: a free sphere must roll, not slide"
    );
    assert!((gamma - 0.355).abs() < 0.01, "the experiment's drive, Gamma {gamma}");
}
