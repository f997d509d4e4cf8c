//! The tray's results do not depend on the number of threads: one thread takes a serial path
//! (no rayon job), two threads split the force blocks; both must give the same bits,
//! including the contact histories and the energy ledger.

mod common;

use particles::contact::choice::TangentialKind;
use particles::prepare::initial_state;
use particles::scene::{Scene, TimeStep};
use particles::sim::Simulation;
use particles::time_step;
use particles::tray;

/// A change of the scene.
type Edit = fn(&mut Scene);

fn run(threads: usize, edit: Edit) -> (Vec<u64>, String) {
    // 400 grains at the thesis packing (four force blocks of 128), 1500 steps of shaking.
    let scene = common::tray_scene(0.04, 0.02, 400, TimeStep::Seconds(8e-6), 11, edit);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut sim = Simulation::new(
            tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap(),
            initial_state(&scene).unwrap(),
        )
        .unwrap();
        // Every step on the threads asked for, so that two threads test the parallel paths.
        sim.fix_team();
        for _ in 0..1500 {
            sim.step().unwrap();
        }
        let summary = format!("{:?} {:?} {:?}", sim.ledger, sim.stored_energy.to_bits(), sim.contact_counts);
        (common::state_bits(&sim), summary)
    })
}

#[test]
fn one_and_two_threads_give_the_same_bits() {
    let cases: [(&str, Edit); 3] = [
        ("the tray", common::unchanged),
        ("pinned 2D", |s| s.toggles.jumping = false),
        ("Cundall-Strack", |s| {
            s.contact.tangential = TangentialKind::CundallStrack;
            s.contact.tangential_stiffness = Some(50.0);
        }),
    ];
    for (name, edit) in cases {
        let (one, one_summary) = run(1, edit);
        let (two, two_summary) = run(2, edit);
        assert_eq!(one_summary, two_summary, "{name}");
        assert!(one == two, "{name}: states or histories differ");
    }
}

#[test]
fn two_simulations_sharing_the_thread_team_give_the_bits_of_one_thread() {
    // Two-thread simulations stepping at the same time contend for one team of threads: a
    // step that finds it busy runs its stages block by block on rayon's pool instead of in
    // the team's parallel region. The bits must not depend on which route a step took.
    let edit: Edit = common::unchanged;
    let (one, one_summary) = run(1, edit);
    let both = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..2).map(|_| scope.spawn(move || run(2, edit))).collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect::<Vec<_>>()
    });
    for (k, (two, two_summary)) in both.into_iter().enumerate() {
        assert_eq!(one_summary, two_summary, "simulation {k}");
        assert!(one == two, "simulation {k}: states or histories differ");
    }
}
