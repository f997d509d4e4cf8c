//! The small tray scenes of the particle tests: the thesis' grains and drive on a short box.
#![allow(dead_code)] // each test file uses a part

use particles::boundary::Boundary;
use particles::contact::ContactLaw;
use particles::integrate::Integrator;
use particles::neighbor::NeighborSearch;
use particles::scene::Scene;
use particles::sim::{Setup, Vertical};
use particles::Vec3;

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

/// Mass (kg) of a grain of radius `r` (m) at the thesis' density, 2500 kg/m^3.
pub fn mass(r: f64) -> f64 {
    2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// Grains in free space under `law` for pairs and walls: no walls, no gravity, every pair
/// tested, velocity Verlet at step `dt`.
pub fn free_setup(law: ContactLaw, boundary: Boundary, dt: f64) -> Setup {
    Setup {
        pair_law: law,
        wall_law: law,
        walls: Vec::new(),
        gravity: Vec3::zeros(),
        dt,
        integrator: Integrator::VelocityVerlet,
        boundary,
        neighbors: NeighborSearch::AllPairs,
        vertical: Vertical::Free,
        container: None,
    }
}
