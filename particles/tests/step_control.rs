//! The error-controlled time step (`run.dt = "auto"`, `run.restitution_tolerance`).

mod common;

use particles::experiment::step_control::{choose, restitution_error, run_all, scene_probes, REFERENCE_STEPS};
use particles::integrate::Integrator;
use particles::scene::Scene;
use particles::time_step;
use particles::timescale;
use particles::SimError;

/// 50 grains on 20 mm x 10 mm with the error-controlled step, at least 8 steps per
/// contact, changed by `edit`.
fn scene(edit: impl FnOnce(&mut Scene)) -> Scene {
    common::tray_scene(0.02, 0.01, 50, common::AUTO, 1, |s| {
        s.run.steps_per_contact = 8.0;
        edit(s)
    })
}

#[test]
fn the_chosen_step_meets_the_tolerance_and_a_coarser_one_does_not() {
    let s = scene(common::unchanged);
    let reference = run_all(&scene_probes(&s, REFERENCE_STEPS, Integrator::VelocityVerlet).unwrap()).unwrap();
    for tol in [3e-2, 1e-2, 1e-3] {
        let c = choose(&s, tol, 8.0).unwrap();
        println!(
            "tolerance {tol:e}: {} steps per contact, error {:.2e}",
            c.steps_per_contact, c.restitution_error
        );
        assert!(c.restitution_error <= tol);
        assert!((c.dt - c.contact_time / c.steps_per_contact).abs() < 1e-18);
        // The measured error is what the probes give at that step.
        let at = restitution_error(
            &run_all(&scene_probes(&s, c.steps_per_contact, Integrator::VelocityVerlet).unwrap()).unwrap(),
            &reference,
        );
        assert_eq!(at, c.restitution_error);
    }
    // Tighter tolerances never give coarser steps.
    let steps: Vec<f64> = [3e-2, 1e-2, 1e-3]
        .iter()
        .map(|&t| choose(&s, t, 8.0).unwrap().steps_per_contact)
        .collect();
    assert!(steps.windows(2).all(|w| w[0] <= w[1]), "{steps:?}");
}

#[test]
fn auto_uses_the_tolerance_and_never_fewer_than_steps_per_contact() {
    let t_c = timescale::shortest_contact_time(&scene(common::unchanged)).unwrap();
    let default = time_step::for_scene(&scene(common::unchanged)).unwrap();
    // 25 with the explicit viscous friction; 50 with backward Euler for it (first order in
    // eps_t); 30 with the explicit force capped at two thirds of the slip per step.
    assert_eq!(t_c / default, 30.0, "thesis material at the default tolerance 1e-2");
    let floored = time_step::for_scene(&scene(|s| s.run.steps_per_contact = 80.0)).unwrap();
    assert!((t_c / floored - 80.0).abs() < 1e-9);
}

#[test]
fn an_unreachable_tolerance_is_refused_naming_the_key() {
    let e = time_step::for_scene(&scene(|s| s.run.restitution_tolerance = 1e-9)).unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidParameter { field, .. } if field == "run.restitution_tolerance"),
        "{e:?}"
    );
    assert!(e.to_string().contains("cannot be met"), "{e}");
}
