//! The small tray scenes of the particle tests: the thesis' grains and drive on a short box.
#![allow(dead_code)] // each test file uses a part

use particles::scene::Scene;

/// A tray of `count` grains with the thesis' radii (0.25-0.5 mm) and drive (20 Hz, 25 mm) on
/// `length` x `width` m, followed by the TOML tables in `extra` (at least `[run]`).
pub fn tray_toml(length: f64, width: f64, count: usize, extra: &str) -> String {
    format!(
        "[box]\nlength = {length}\nwidth = {width}\n\
         [drive]\nfrequency = 20.0\namplitude = 0.025\n\
         [particles]\ncount = {count}\nradius_min = 0.25e-3\nradius_max = 0.5e-3\n{extra}"
    )
}

/// [`tray_toml`] parsed with `--set`-style `overrides` and validated.
pub fn tray_scene(length: f64, width: f64, count: usize, extra: &str, overrides: &[&str]) -> Scene {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let scene = Scene::parse(&tray_toml(length, width, count, extra), &o, "test").unwrap();
    scene.validate().unwrap();
    scene
}
