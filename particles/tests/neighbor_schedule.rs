//! The Verlet list and its rebuild schedule miss no contact in a shaken run: a tray stepped
//! with the list gives the same bits as the same tray with every pair tested every step
//! (partners are summed in increasing index order either way, and a candidate that does not
//! touch contributes nothing).

use particles::neighbor::NeighborSearch;
use particles::prepare::initial_state;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::tray;

const SCENE: &str = r#"
    [box]
    length = 0.02
    width = 0.01
    [drive]
    frequency = 20.0
    amplitude = 0.025
    [particles]
    count = 120
    radius_min = 0.25e-3
    radius_max = 0.5e-3
    [prepare]
    speed = 0.2
    [run]
    duration = 0.1
    dt = 8e-6
    seed = 5
"#;

fn run(all_pairs: bool, overrides: &[&str]) -> (Vec<u8>, u64, u64) {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let scene = Scene::parse(SCENE, &o, "test").unwrap();
    scene.validate().unwrap();
    let mut setup = tray::setup(&scene, tray::drive(&scene)).unwrap();
    if all_pairs {
        setup.neighbors = NeighborSearch::AllPairs;
    }
    let mut sim = Simulation::new(setup, initial_state(&scene)).unwrap();
    let mut pair_contact_steps = 0;
    for _ in 0..4000 {
        sim.step().unwrap();
        pair_contact_steps += (sim.contacts.0 > 0) as u64;
    }
    (sim.checkpoint(0, 0), pair_contact_steps, sim.neighbor_builds())
}

#[test]
fn verlet_list_run_equals_all_pairs_run_bit_for_bit() {
    for overrides in [&[][..], &["toggles.jumping=false"][..]] {
        let (list, contacts, builds) = run(false, overrides);
        let (all, _, _) = run(true, overrides);
        assert!(
            contacts > 100,
            "{overrides:?}: the test needs grain-grain contacts ({contacts} steps with some)"
        );
        assert!(builds > 3, "{overrides:?}: the test needs rebuilds ({builds})");
        assert!(list == all, "{overrides:?}: the Verlet-list run differs from the all-pairs run");
    }
}
