//! `advance_to` with an `AtTimes` observer samples a run at the same steps, and leaves it in
//! the same state, as the hand-written loop it replaces in the studies (`while sim.time < t -
//! dt / 2 { sim.step() }`, then the sample).

mod common;

use particles::advance::{advance, advance_to, AtTimes};
use particles::scene::TimeStep;
use particles::sim::Simulation;
use particles::{prepare::initial_state, time_step, tray};

fn fresh() -> Simulation {
    let scene = common::tray_scene(0.01, 0.01, 20, TimeStep::Seconds(4e-6), 3, common::unchanged);
    let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap();
    Simulation::new(setup, initial_state(&scene).unwrap()).unwrap()
}

#[test]
fn samples_at_times_are_the_hand_loops_samples() {
    // Times that do not fall on step ends, one closer than a step to the next, and one
    // repeated: each is sampled once, in order, after the step that reaches it.
    let times = vec![1.31e-4, 1.33e-4, 5.0e-4, 5.0e-4, 1.011e-3, 2.0e-3];
    let mut by_hand = fresh();
    let mut want = Vec::new();
    for &t in &times {
        while by_hand.time < t - 0.5 * by_hand.setup.dt {
            by_hand.step().unwrap();
        }
        want.push((t, by_hand.steps, common::state_bits(&by_hand)));
    }
    let mut sim = fresh();
    let mut got = Vec::new();
    let mut sample = AtTimes::new(times.clone(), |s: &Simulation, t: f64| {
        got.push((t, s.steps, common::state_bits(s)));
        Ok(())
    });
    assert_eq!(sample.last(), Some(2.0e-3));
    advance_to(&mut sim, 2.0e-3, &mut [&mut sample]).unwrap();
    assert_eq!(got.len(), times.len());
    for (g, w) in got.iter().zip(&want) {
        assert_eq!((g.0, g.1), (w.0, w.1), "sampled at another step");
        assert!(g.2 == w.2, "the state at t = {} differs", g.0);
    }
    assert_eq!(sim.steps, by_hand.steps);
    assert_eq!(common::state_bits(&sim), common::state_bits(&by_hand));
}

#[test]
fn advance_runs_the_steps_asked_and_an_observer_error_stops_it() {
    let mut by_hand = fresh();
    for _ in 0..57 {
        by_hand.step().unwrap();
    }
    let mut sim = fresh();
    advance(&mut sim, 57, &mut []).unwrap();
    assert_eq!(sim.steps, 57);
    assert_eq!(common::state_bits(&sim), common::state_bits(&by_hand));
    let mut failing = AtTimes::new(vec![1e-4], |_: &Simulation, t: f64| Err(format!("sample at {t} refused").into()));
    let stop = advance_to(&mut sim, 1e-2, &mut [&mut failing]).unwrap_err();
    assert!(stop.to_string().contains("sample at 0.0001 refused"), "{stop}");
    // The sample was due at once (t = 1e-4 lies behind the run): one step, then the stop.
    assert_eq!(sim.steps, 58, "the run went on after the observer failed");
}
