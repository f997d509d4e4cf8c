//! `scenes/experiment.toml`, the experiment as run (thesis 2.2.1-2.2.5): it parses and
//! validates as the thesis' tray, grains and protocol, and a few hundred steps of its first
//! stage keep every grain inside the moving tray.

use particles::prepare::initial_state;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::{time_step, tray};
use serde::Deserialize;

fn experiment() -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/experiment.toml");
    let mut doc: toml::Table = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    doc.remove("automaton");
    let scene = Scene::deserialize(toml::Value::Table(doc)).unwrap();
    scene.validate().unwrap();
    scene
}

#[test]
fn the_experiment_scene_is_the_thesis_tray_grains_and_protocol() {
    let s = experiment();
    assert_eq!((s.tray.length, s.tray.width), (0.5, 0.1));
    assert!(s.tray.x_walls && s.toggles.walls, "end and side walls, not periodic");
    // About 4800 grains of mean diameter 2.14 mm, spread 0.22 mm (uniform: sd = width / sqrt 12).
    assert!((4700..=4900).contains(&s.particles.count));
    let (a, b) = (2.0 * s.particles.radius_min, 2.0 * s.particles.radius_max);
    assert!((0.5 * (a + b) - 2.14e-3).abs() < 0.01e-3, "mean diameter {}", 0.5 * (a + b));
    assert!(
        ((b - a) / 12f64.sqrt() - 0.22e-3).abs() < 0.01e-3,
        "spread {}",
        (b - a) / 12f64.sqrt()
    );
    assert!((s.packing() - 0.35).abs() < 0.01, "packing {}", s.packing());
    // The protocol: 5 Hz / 20 mm to fluidise, then 3 Hz / 10 mm for an hour; the analysis'
    // drive is the last stage's.
    let stages: Vec<(f64, f64, f64)> = s.drive.stages.iter().map(|x| (x.frequency, x.amplitude, x.duration)).collect();
    assert_eq!(stages.len(), 2);
    assert_eq!((stages[0].0, stages[0].1), (5.0, 0.02));
    assert_eq!(stages[1], (3.0, 0.01, 3600.0));
    assert_eq!((s.drive.frequency, s.drive.amplitude), (3.0, 0.01));
    assert_eq!(s.drive.schedule_duration(), Some(s.run.duration));
}

#[test]
fn the_experiment_scene_runs_with_every_grain_inside_the_moving_tray() {
    let scene = experiment();
    let dt = time_step::for_scene(&scene).unwrap();
    let motion = tray::drive(&scene);
    let setup = tray::setup(&scene, motion.clone(), dt).unwrap();
    // The lattice before relaxation (the prepared sample takes minutes): every grain on the floor.
    let mut sim = Simulation::new(setup, initial_state(&scene).unwrap()).unwrap();
    let (l, w) = (scene.tray.length, scene.tray.width);
    for k in 0..400 {
        sim.step().unwrap_or_else(|e| panic!("step {k}: {e}"));
    }
    let u = motion.displacement(sim.time).x;
    assert!(u > 0.0, "the tray has moved forwards");
    let state = sim.state();
    assert_eq!(state.len(), scene.particles.count);
    for (i, (x, r)) in state.pos.iter().zip(&state.radius).enumerate() {
        let inside = x.x > u + 0.5 * r && x.x < l + u - 0.5 * r && x.y > 0.5 * r && x.y < w - 0.5 * r && x.z > 0.0;
        assert!(inside, "grain {i} at {x:?}, the tray at {u}");
    }
}
