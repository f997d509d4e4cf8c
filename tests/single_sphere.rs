//! One sphere on the shaken floor with the thesis scene's own laws (thesis 3.3, Figs
//! 3.7-3.12): an uncapped floor (`wall_friction = inf`) rolls it without slip at every
//! frequency, a Coulomb floor (`mu = 0.7`) lets it slide above `Gamma = 7 mu / 2`, with the
//! amplitudes of the closed forms in `particles::experiment::single`.

use std::path::Path;

use particles::constants::GRAVITY;
use particles::contact::RollingLaw;
use particles::experiment::single::{self as sphere, Amplitudes, SphereOnFloor};
use particles::scene::{Scene, TimeStep};
use serde::Deserialize;

/// Thesis 3.3: A = 25 mm, nu = 5-29 Hz.
const AMPLITUDE: f64 = 0.025;

/// The thesis scene changed by `edit`; its grain of radius 0.5 mm (thesis 3.3) on the floor,
/// without rolling friction.
fn grain(edit: impl FnOnce(&mut Scene)) -> (Scene, SphereOnFloor) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thesis-reference.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut scene = Scene::deserialize(toml::from_str::<toml::Value>(&text).unwrap()).unwrap();
    edit(&mut scene);
    scene.validate().unwrap();
    let TimeStep::Seconds(dt) = scene.run.dt else {
        panic!("the thesis scene has an explicit step")
    };
    let mut g = SphereOnFloor::on_scene(&scene, scene.particles.radius_max, dt).unwrap();
    g.law.rolling = RollingLaw::None;
    (scene, g)
}

/// Amplitudes at `frequency` over the last half of a run of at least 10 periods and 1 s.
fn measure(g: &SphereOnFloor, frequency: f64) -> Amplitudes {
    let duration = (10.0 / frequency).max(1.0);
    let every = ((1.0 / frequency) / g.dt / 200.0).max(1.0) as u64;
    let samples = g.shake(AMPLITUDE, frequency, duration, every).unwrap();
    sphere::amplitudes(&samples, frequency).unwrap()
}

#[test]
fn an_uncapped_floor_rolls_the_sphere_without_slip_from_5_to_29_hz() {
    let (_, g) = grain(|s| s.contact.wall_friction = f64::INFINITY);
    let rolling = 2.0 * (2.0 / 7.0) * AMPLITUDE;
    for nu in (5..=29).step_by(2) {
        let a = measure(&g, nu as f64);
        println!("{nu} Hz: x peak-to-peak {:.4e} m (rolling {rolling:.4e} m)", a.x_peak_to_peak);
        // Measured within 0.2% (Haff-Werner's viscous branch needs a slip of F / gamma_t);
        // the issue asks for 10%.
        assert!((a.x_peak_to_peak / rolling - 1.0).abs() < 0.1, "{nu} Hz: {a:?}");
        // The velocity amplitude grows with nu as (2/7) A w: the thesis' Figs 3.7-3.8.
        let v = Amplitudes::rolling(AMPLITUDE, nu as f64).vx_amplitude;
        assert!((a.vx_amplitude / v - 1.0).abs() < 0.1, "{nu} Hz: {a:?} against {v}");
    }
}

#[test]
fn a_coulomb_floor_lets_the_sphere_slide_above_gamma_7_mu_over_2() {
    let (scene, g) = grain(|_| {});
    let mu = scene.contact.wall_friction;
    assert_eq!(mu, 0.7);
    // 5 Hz: Gamma = 2.47, just above 7 mu / 2 = 2.45; 5.5 and 6.5 Hz: between that and
    // continuous sliding (Gamma = 4.56, 6.8 Hz), where the sphere alternates; then sliding.
    for nu in [5.0, 5.5, 6.5, 7.0, 9.0, 13.0, 17.0, 21.0, 25.0, 29.0] {
        let gamma = sphere::gamma(AMPLITUDE, nu, GRAVITY);
        assert!(gamma > sphere::rolling_gamma(mu));
        let a = measure(&g, nu);
        let sliding = Amplitudes::sliding(mu, GRAVITY, nu);
        let (dx, dv) = (
            a.x_peak_to_peak / sliding.x_peak_to_peak - 1.0,
            a.vx_amplitude / sliding.vx_amplitude - 1.0,
        );
        println!(
            "{nu} Hz, Gamma {gamma:.2}: x p2p {:.4e} m ({dx:+.3} from sliding), v {:.4e} m/s ({dv:+.3})",
            a.x_peak_to_peak, a.vx_amplitude
        );
        if gamma >= sphere::continuous_sliding_gamma(mu) {
            // Continuous sliding: the closed forms are exact for Coulomb friction; measured
            // within 0.8% (x) and 0.5% (v).
            assert!(dx.abs() < 0.03 && dv.abs() < 0.03, "{nu} Hz: {a:?} against {sliding:?}");
        } else {
            // Stick-slip: the sphere alternates between rolling and sliding, and the closed
            // form of continuous sliding is only a guide: measured 18% above at 5 Hz, where
            // it still rolls (2 (2/7) A), 7% below at 5.5 Hz and 0.1% at 6.5 Hz.
            assert!(dx.abs() < 0.2, "{nu} Hz: {a:?} against {sliding:?}");
        }
    }
}
