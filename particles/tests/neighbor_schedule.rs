//! The Verlet list and its rebuild schedule miss no contact in a shaken run: a tray stepped
//! with the list gives the same bits as the same tray with every pair tested every step
//! (partners are summed in increasing index order either way, and a candidate that does not
//! touch contributes nothing).

mod common;

use particles::neighbor::NeighborSearch;
use particles::prepare::initial_state;
use particles::scene::TimeStep;
use particles::sim::Simulation;
use particles::time_step;
use particles::tray;

/// The tray stepped 4000 times with `search` (the tray's own adaptive list if `None`), its
/// grains stirred at `speed` m/s (pinned to the floor unless `jumping`): the state's bits, steps with grain-grain contacts,
/// list builds and the final skin (m).
fn run(search: Option<NeighborSearch>, speed: f64, jumping: bool) -> (Vec<u64>, u64, u64, f64) {
    // 120 grains on 20 mm x 10 mm, stirred so that the list is rebuilt often.
    let scene = common::tray_scene(0.02, 0.01, 120, TimeStep::Seconds(8e-6), 5, |s| {
        s.prepare.speed = speed;
        s.toggles.jumping = jumping;
    });
    let mut setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap();
    if let Some(search) = search {
        setup.neighbors = search;
    }
    // All pairs have no grid to sort the grains by, and a sort changes the order in which a
    // grain adds its pair forces: neither run sorts.
    setup.sort = particles::scene::SortInterval::NONE;
    let mut sim = Simulation::new(setup, initial_state(&scene).unwrap()).unwrap();
    let mut pair_contact_steps = 0;
    for _ in 0..4000 {
        sim.step().unwrap();
        pair_contact_steps += (sim.contact_counts.0 > 0) as u64;
    }
    (
        common::state_bits(&sim),
        pair_contact_steps,
        sim.neighbor_builds(),
        sim.neighbor_skin(),
    )
}

#[test]
fn verlet_list_run_equals_all_pairs_run_bit_for_bit() {
    for jumping in [true, false] {
        let (list, contacts, builds, _) = run(None, 0.2, jumping);
        let (all, _, _, _) = run(Some(NeighborSearch::AllPairs), 0.2, jumping);
        assert!(
            contacts > 100,
            "jumping {jumping}: the test needs grain-grain contacts ({contacts} steps with some)"
        );
        assert!(builds > 3, "jumping {jumping}: the test needs rebuilds ({builds})");
        assert!(list == all, "jumping {jumping}: the Verlet-list run differs from the all-pairs run");
    }
}

/// A fast gas grows the adaptive skin, which then rebuilds less often than the smallest
/// skin fixed, and neither changes a bit of the run.
#[test]
fn adaptive_skin_grows_in_a_gas_and_changes_no_result() {
    let scene = common::tray_scene(0.02, 0.01, 120, TimeStep::Seconds(8e-6), 5, common::unchanged);
    let NeighborSearch::VerletList { skin, max_skin } = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap())
        .unwrap()
        .neighbors
    else {
        panic!("the tray uses a Verlet list");
    };
    let (adaptive, contacts, adaptive_builds, final_skin) = run(None, 1.0, true);
    let (fixed, _, fixed_builds, fixed_skin) = run(Some(NeighborSearch::verlet(skin)), 1.0, true);
    let (all, _, _, _) = run(Some(NeighborSearch::AllPairs), 1.0, true);
    assert!(contacts > 100, "the test needs grain-grain contacts ({contacts} steps with some)");
    assert_eq!(fixed_skin, skin);
    assert!(
        final_skin > 2.0 * skin && final_skin <= max_skin,
        "skin {final_skin:e} m: expected grown from {skin:e} towards {max_skin:e}"
    );
    assert!(
        2 * adaptive_builds < fixed_builds,
        "{adaptive_builds} adaptive builds against {fixed_builds} with the fixed skin"
    );
    assert!(adaptive == fixed, "the adaptive-skin run differs from the fixed-skin run");
    assert!(adaptive == all, "the adaptive-skin run differs from the all-pairs run");
}
