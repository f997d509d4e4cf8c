//! The Verlet list and its rebuild schedule miss no contact in a shaken run: a tray stepped
//! with the list gives the same bits as the same tray with every pair tested every step
//! (partners are summed in increasing index order either way, and a candidate that does not
//! touch contributes nothing).

mod common;

use particles::neighbor::NeighborSearch;
use particles::prepare::initial_state;
use particles::sim::Simulation;
use particles::tray;

fn run(all_pairs: bool, overrides: &[&str]) -> (Vec<u8>, u64, u64) {
    // 120 grains on 20 mm x 10 mm, stirred at 0.2 m/s so that the list is rebuilt often.
    let scene = common::tray_scene(
        0.02,
        0.01,
        120,
        "[prepare]\nspeed = 0.2\n[run]\nduration = 0.1\ndt = 8e-6\nseed = 5\n",
        overrides,
    );
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
