//! The tray's results do not depend on the number of threads: one thread takes a serial path
//! (no rayon job), two threads split the force blocks; both must give the same bits,
//! including the contact histories and the energy ledger.

mod common;

use particles::prepare::initial_state;
use particles::sim::Simulation;
use particles::tray;

fn run(threads: usize, overrides: &[&str]) -> (Vec<u8>, String) {
    // 400 grains at the thesis packing (four force blocks of 128), 1500 steps of shaking.
    let scene = common::tray_scene(0.04, 0.02, 400, "[run]\nduration = 0.1\ndt = 8e-6\nseed = 11\n", overrides);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut sim = Simulation::new(tray::setup(&scene, tray::drive(&scene)).unwrap(), initial_state(&scene).unwrap()).unwrap();
        for _ in 0..1500 {
            sim.step().unwrap();
        }
        let summary = format!("{:?} {:?} {:?}", sim.ledger, sim.stored_energy.to_bits(), sim.contacts);
        (sim.checkpoint(0, 0), summary)
    })
}

#[test]
fn one_and_two_threads_give_the_same_bits() {
    for overrides in [
        &[][..],
        &["toggles.jumping=false"][..],
        &["contact.tangential=cundall-strack", "contact.tangential_stiffness=50"][..],
    ] {
        let (one, one_summary) = run(1, overrides);
        let (two, two_summary) = run(2, overrides);
        assert_eq!(one_summary, two_summary, "{overrides:?}");
        assert!(one == two, "{overrides:?}: states or histories differ");
    }
}
