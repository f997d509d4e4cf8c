//! The tray's results do not depend on the number of threads: one thread takes a serial path
//! (no rayon job), two threads split the force blocks; both must give the same bits,
//! including the contact histories and the energy ledger.

use particles::prepare::initial_state;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::tray;

/// 400 grains at the thesis packing (four force blocks of 128), 1500 steps of shaking.
const SCENE: &str = r#"
    [box]
    length = 0.04
    width = 0.02
    [drive]
    frequency = 20.0
    amplitude = 0.025
    [particles]
    count = 400
    radius_min = 0.25e-3
    radius_max = 0.5e-3
    [run]
    duration = 0.1
    dt = 8e-6
    seed = 11
"#;

fn run(threads: usize, overrides: &[&str]) -> (Vec<u8>, String) {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let scene = Scene::parse(SCENE, &o, "test").unwrap();
    scene.validate().unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut sim = Simulation::new(tray::setup(&scene, tray::drive(&scene)).unwrap(), initial_state(&scene)).unwrap();
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
