//! Particle-steps per second of the thesis scene (`scenes/thesis-reference.toml`, N = 4000
//! from the lattice, 5000 steps), with `dotted.key=value` overrides as arguments:
//! `cargo run --release --example speed -- toggles.jumping=false`.

#[path = "../src/scene/text/mod.rs"]
mod scene_text;

use particles::prepare::initial_state;
use particles::sim::Simulation;
use particles::time_step;
use particles::timescale;
use particles::tray;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let text = std::fs::read_to_string("scenes/thesis-reference.toml").unwrap();
    let scene = scene_text::parse_scene(&text, &args, "scenes/thesis-reference.toml").unwrap();
    scene.validate().unwrap();
    let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap();
    println!("dt {:e}, t_c {:e}", setup.dt, timescale::shortest_contact_time(&scene).unwrap());
    let mut sim = Simulation::new(setup, initial_state(&scene).unwrap()).unwrap();
    // `STEPS=500` for a short run (an instruction count under a profiler).
    let steps: usize = std::env::var("STEPS").ok().and_then(|s| s.parse().ok()).unwrap_or(5000);
    let t0 = Instant::now();
    for _ in 0..steps {
        sim.step().unwrap();
    }
    let wall = t0.elapsed().as_secs_f64();
    println!(
        "{} particle-steps/s, builds {}, contacts (pair, wall) {:?}",
        (steps * scene.particles.count) as f64 / wall,
        sim.neighbor_builds(),
        sim.contact_counts
    );
}
