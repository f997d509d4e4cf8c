//! Issue 19, point 15: no shipped scene prints a warning. Every `scenes/*.toml` loads,
//! validates, gets its time step, and `tray::warnings` (what `stripes run` prints) is empty.

use particles::scene::Scene;
use particles::tray;

#[test]
fn no_shipped_scene_prints_a_warning() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        scene.validate().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let dt = tray::time_step(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let warnings = tray::warnings(&scene, dt);
        assert!(warnings.is_empty(), "{} at dt = {dt:e} s: {warnings:?}", path.display());
        checked += 1;
    }
    assert!(checked >= 2, "only {checked} scenes found");
}
