//! Conservation laws of the whole DEM (issue 7), as properties over random many-grain
//! systems run through the full step pipeline (`Simulation::step`):
//! - friction and dissipation off: the energy error is bounded and shrinks like dt^2;
//! - free space: total momentum is conserved, whatever the laws;
//! - free space with friction and rolling resistance on: total angular momentum is conserved;
//! - the shaken tray keeps every grain: the particle count is conserved, all finite.
//!
//! (The automaton's mass conservation belongs to the automaton crate.)

mod common;

use particles::boundary::Boundary;
use particles::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::measure;
use particles::prepare::initial_state;
use particles::scene::{TimeStep, Toggles};
use particles::sim::Simulation;
use particles::state::State;
use particles::time_step;
use particles::tray;
use particles::Vec3;
use proptest::prelude::*;

const R: f64 = 5e-4;

use common::mass;

/// `n` grains of radii in `[0.6 R, R]` on a loose cubic lattice of spacing `2.4 R` with
/// random velocities up to `v` (m/s) and spins up to `w` (rad/s), from `draws` in [0, 1).
fn cluster(n: usize, draws: &[f64], v: f64, w: f64, converge: bool) -> State {
    let mut s = State::default();
    let side = (n as f64).cbrt().ceil() as usize;
    let centre = Vec3::repeat(1.2 * R * (side as f64 - 1.0));
    for i in 0..n {
        let d = &draws[7 * i..7 * i + 7];
        let r = R * (0.6 + 0.4 * d[0]);
        let x = Vec3::new((i % side) as f64, ((i / side) % side) as f64, (i / (side * side)) as f64) * 2.4 * R;
        let mut vel = Vec3::new(d[1] - 0.5, d[2] - 0.5, d[3] - 0.5) * (2.0 * v);
        if converge {
            // Towards the centre, so that the grains meet in free space.
            vel -= (x - centre) * (v / (2.4 * R * side as f64));
        }
        let omega = Vec3::new(d[4] - 0.5, d[5] - 0.5, d[6] - 0.5) * (2.0 * w);
        s.push(x, vel, omega, r, mass(r));
    }
    s
}

use common::free_setup as setup;

/// Contact time of two of the largest grains at 1 m/s under `law` (s).
fn contact_time(law: &ContactLaw) -> f64 {
    law.normal.undamped_contact_time(0.5 * mass(R), 0.5 * R, 1.0)
}

/// Largest `|E(t) - E(0)| / E(0)` over a run of `duration` s with `steps` per contact time,
/// and the number of contacts seen.
fn energy_error(law: ContactLaw, state: &State, steps: f64, duration: f64) -> (f64, u64) {
    let box_len = 2.4 * R * 3.0;
    let b = Boundary {
        periodic: [Some(box_len); 3],
    };
    let dt = contact_time(&law) / steps;
    let mut sim = Simulation::new(setup(law, b, dt), state.clone()).unwrap();
    let e0 = sim.total_energy();
    let (mut worst, mut contacts) = (0.0f64, 0);
    while sim.time < duration {
        sim.step().unwrap();
        worst = worst.max((sim.total_energy() - e0).abs() / e0);
        contacts += sim.contact_counts.0;
    }
    (worst, contacts)
}

fn draws(n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(0.0f64..1.0, 7 * n)
}

fn frictional() -> impl Strategy<Value = ContactLaw> {
    let tangential = prop_oneof![
        (1e-4f64..1e-2, 0.1f64..1.0).prop_map(|(gamma_t, mu)| TangentialLaw::HaffWerner { gamma_t, mu }),
        (10f64..300.0, 0.1f64..1.0).prop_map(|(kt, mu)| TangentialLaw::CundallStrack { kt, mu }),
    ];
    let rolling = prop_oneof![
        Just(RollingLaw::None),
        (1e-6f64..1e-4).prop_map(|mu_r| RollingLaw::BrilliantovPoschel { mu_r }),
        (0.01f64..0.5, prop::option::of(1.0f64..100.0), 0.0f64..1e-3)
            .prop_map(|(mu_r, k_roll, gamma_roll)| { RollingLaw::SpringDashpotSlider { mu_r, k_roll, gamma_roll } })
    ];
    (tangential, rolling, 0.0f64..2e-5).prop_map(|(tangential, rolling, a)| ContactLaw {
        normal: NormalLaw::hertz(1.1e6, a),
        tangential,
        rolling,
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// 27 grains in a periodic box, Hertz without dissipation or friction: the largest energy
    /// error over the run (about 1e-3 at 20 steps per contact) falls by about 16 when the
    /// step shrinks 4 times.
    #[test]
    fn elastic_energy_error_is_bounded_and_shrinks_like_dt_squared(d in draws(27)) {
        let law = ContactLaw {
            normal: NormalLaw::hertz(1.1e6, 0.0),
            tangential: TangentialLaw::None,
            rolling: RollingLaw::None,
        };
        let state = cluster(27, &d, 0.5, 0.0, false);
        let duration = 20.0 * contact_time(&law);
        let (coarse, contacts) = energy_error(law, &state, 20.0, duration);
        let (fine, _) = energy_error(law, &state, 80.0, duration);
        prop_assume!(contacts > 0);
        println!("energy error {coarse:.3e} -> {fine:.3e} (ratio {:.2}, order {:.2}), {contacts} contact-steps", coarse / fine, (coarse / fine).log2() / 2.0);
        prop_assert!(coarse < 1e-2, "energy error {coarse:e} at 20 steps per contact");
        // dt^2 gives a factor 16 for dt / 4; measured 9 to 21 (orders 1.6 to 2.2, median 2.1):
        // contacts that start or end between steps cost a little order. At least 7 (1.4).
        prop_assert!(fine < coarse / 7.0 || fine < 1e-12, "error {coarse:e} -> {fine:e} when dt shrinks 4 times");
    }

    /// The same grains with any frictional, dissipative laws: momentum is conserved to
    /// round-off (pair forces are exactly antisymmetric).
    #[test]
    fn momentum_is_conserved_in_free_space(d in draws(27), law in frictional()) {
        let state = cluster(27, &d, 0.5, 300.0, true);
        let p0 = measure::momentum(&state);
        let scale: f64 = (0..state.len()).map(|i| state.mass(i) * state.vel[i].norm()).sum();
        let dt = contact_time(&law) / 30.0;
        let mut sim = Simulation::new(setup(law, Boundary::open(), dt), state).unwrap();
        let mut contacts = 0;
        for _ in 0..3000 {
            sim.step().unwrap();
            contacts += sim.contact_counts.0;
        }
        prop_assert!(contacts > 0, "the grains never met");
        let dp = (measure::momentum(&sim.state()) - p0).norm();
        println!("momentum: {dp:.2e} of {scale:.2e}, {contacts} contact-steps");
        prop_assert!(dp < 1e-13 * scale, "momentum changed by {dp:e} (scale {scale:e})");
    }

    /// Free space with friction and rolling resistance on: orbital plus spin angular momentum
    /// about the origin is conserved (torques act at the middle of the overlap).
    #[test]
    fn angular_momentum_is_conserved_with_friction_on(d in draws(27), law in frictional()) {
        let state = cluster(27, &d, 0.5, 300.0, true);
        let l0 = measure::angular_momentum(&state);
        let extent = 2.4 * R * 3.0;
        let scale: f64 = (0..state.len())
            .map(|i| state.mass(i) * state.vel[i].norm() * extent + state.inertia(i) * state.omega[i].norm())
            .sum();
        let dt = contact_time(&law) / 30.0;
        let mut sim = Simulation::new(setup(law, Boundary::open(), dt), state).unwrap();
        let mut friction_acted = false;
        for _ in 0..3000 {
            sim.step().unwrap();
            friction_acted |= sim.contact_counts.0 > 0;
        }
        prop_assert!(friction_acted);
        let dl = (measure::angular_momentum(&sim.state()) - l0).norm();
        println!("angular momentum: {dl:.2e} of {scale:.2e}");
        prop_assert!(dl < 1e-12 * scale, "angular momentum changed by {dl:e} (scale {scale:e})");
    }

    /// A small shaken tray with any toggles: no grain is lost or duplicated, all stay finite
    /// and inside the tray.
    #[test]
    fn the_shaken_tray_keeps_every_grain(
        seed in 0u64..1000,
        friction in any::<bool>(),
        jumping in any::<bool>(),
        walls in any::<bool>(),
        rolling in any::<bool>(),
    ) {
        let toggles = Toggles { friction, jumping, dissipation: true, walls, rolling };
        let scene = common::tray_scene(0.01, 0.008, 40, TimeStep::Seconds(4e-6), seed, |s| s.toggles = toggles);
        let mut sim = Simulation::new(tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap(), initial_state(&scene).unwrap()).unwrap();
        let n = sim.len();
        for _ in 0..2500 {
            sim.step().unwrap();
        }
        prop_assert_eq!(sim.len(), n);
        prop_assert_eq!(n, 40);
        for (i, x) in sim.state().pos.iter().enumerate() {
            prop_assert!(x.iter().all(|c| c.is_finite()), "grain {} not finite", i);
            prop_assert!((0.0..scene.tray.length).contains(&x.x) && (0.0..=scene.tray.width).contains(&x.y), "grain {} at {}", i, x);
        }
    }
}
