//! Closed forms of the spring-dashpot-slider rolling resistance (`contact.rolling = "sds"`,
//! SPEC section 7), for a sphere of radius R on the floor with enough sliding friction
//! (Cundall-Strack, mu = 1), run through the whole step pipeline:
//! - on an incline it stays at rest for `tan(theta) <= mu_r` and rolls above, accelerating at
//!   `(5/7) g (sin(theta) - mu_r cos(theta))`;
//! - started rolling without slip at v0 on a flat floor, it stops after `7 v0^2 / (10 mu_r g)`;
//! - the rolling spring's energy `k_r |theta|^2 / 2` is in the stored energy, and the energy
//!   ledger closes with it.

mod common;

use particles::boundary::Boundary;
use particles::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::integrate::Integrator;
use particles::neighbor::NeighborSearch;
use particles::setup::{Setup, Vertical};
use particles::sim::Simulation;
use particles::state::State;
use particles::wall::{Motion, Wall};
use particles::Vec3;

const R: f64 = 5e-4;
const G: f64 = 10.0;
const MU_R: f64 = 0.1;
/// Reduced modulus (Pa): stiff enough that the static overlap (about 1e-6 m) leaves the
/// lever arm `R - xi/2` within 0.1 % of R.
const Y_STAR: f64 = 1.1e9;
/// 25 steps per period of the grain bouncing on its static overlap.
const DT: f64 = 2e-6;

fn mass() -> f64 {
    common::mass(R)
}

/// Hertz with dissipation (the bounce settles), Cundall-Strack with mu = 1, and the
/// spring-dashpot-slider at `MU_R` with its default stiffness (`normal`: Hertz) or
/// `k_roll` given, damped at half its critical rate.
fn law(normal: NormalLaw) -> ContactLaw {
    ContactLaw {
        normal,
        tangential: TangentialLaw::CundallStrack { kt: 2e4, mu: 1.0 },
        rolling: RollingLaw::SpringDashpotSlider {
            mu_r: MU_R,
            k_roll: None,
            gamma_roll: 0.03,
        },
    }
}

fn hertz() -> NormalLaw {
    NormalLaw::hertz(Y_STAR, 2e-6)
}

/// One sphere resting (in its static overlap) on a fixed floor, gravity tilted by `tilt`
/// (rad) towards +x: the floor is an incline of that angle. Velocity `v0` along x and spin
/// `w0` about y.
fn on_incline(law: ContactLaw, tilt: f64, v0: f64, w0: f64) -> Simulation {
    lifted(law, tilt, v0, w0, 0.0)
}

/// [`on_incline`], the sphere `lift` (m) above its rest height.
fn lifted(law: ContactLaw, tilt: f64, v0: f64, w0: f64, lift: f64) -> Simulation {
    let m = mass();
    let load = m * G * tilt.cos();
    let sink = law.normal.static_overlap(load, R);
    let mut state = State::default();
    state.push(
        Vec3::new(0.0, 0.0, R - sink + lift),
        Vec3::new(v0, 0.0, 0.0),
        Vec3::new(0.0, w0, 0.0),
        R,
        m,
    );
    let setup = Setup {
        pair_law: law,
        wall_law: law,
        walls: vec![Wall::new("floor", Vec3::zeros(), Vec3::z(), Motion::Fixed)],
        gravity: Vec3::new(G * tilt.sin(), 0.0, -G * tilt.cos()),
        dt: DT,
        integrator: Integrator::VelocityVerlet,
        boundary: Boundary::open(),
        neighbors: NeighborSearch::AllPairs,
        vertical: Vertical::Free,
        container: None,
        sort: particles::scene::SortInterval::NONE,
        rolling_mu: Vec::new(),
        clump: None,
    };
    Simulation::new(setup, state).unwrap()
}

fn run(sim: &mut Simulation, duration: f64) {
    for _ in 0..(duration / DT).round() as usize {
        sim.step().unwrap();
    }
}

#[test]
fn a_sphere_on_an_incline_stays_at_rest_below_the_critical_angle_and_rolls_above() {
    // Below: tan(theta) = 0.8 mu_r. The grain creeps only while its springs load (a few
    // 1e-8 m), then holds.
    let below = (0.8 * MU_R).atan();
    let mut sim = on_incline(law(hertz()), below, 0.0, 0.0);
    run(&mut sim, 0.05);
    let x_settled = sim.state().pos[0].x;
    run(&mut sim, 0.15);
    let s = sim.state();
    println!(
        "below: x {:e} m after 0.05 s, {:e} m after 0.2 s, v {:e} m/s",
        x_settled, s.pos[0].x, s.vel[0].x
    );
    assert!(s.pos[0].x.abs() < 1e-6, "moved {:e} m down the incline", s.pos[0].x);
    assert!((s.pos[0].x - x_settled).abs() < 1e-8, "still moving after 0.05 s");
    assert!(s.vel[0].norm() < 1e-5, "speed {:e} m/s", s.vel[0].norm());

    // Above: tan(theta) = 1.2 mu_r. The spring sits at its limit mu_r R F_n and the grain
    // rolls without slip: (m + I/R^2) a = m g sin(theta) - mu_r m g cos(theta).
    let above = (1.2 * MU_R).atan();
    let mut sim = on_incline(law(hertz()), above, 0.0, 0.0);
    let duration = 0.2;
    run(&mut sim, duration);
    let s = sim.state();
    let a = 5.0 / 7.0 * G * (above.sin() - MU_R * above.cos());
    let (x, v) = (s.pos[0].x, s.vel[0].x);
    println!(
        "above: x {x:e} m (closed form {:e}), v {v:e} m/s (closed form {:e})",
        0.5 * a * duration * duration,
        a * duration
    );
    assert!((v / (a * duration) - 1.0).abs() < 0.01, "speed {v} against {}", a * duration);
    assert!(
        (x / (0.5 * a * duration * duration) - 1.0).abs() < 0.01,
        "distance {x} against {}",
        0.5 * a * duration * duration
    );
    // Rolling, not sliding: the contact point is at rest.
    let slip = v - s.omega[0].y * R;
    assert!(slip.abs() < 1e-2 * v, "slip {slip} at speed {v}");
}

#[test]
fn a_sphere_rolling_on_a_flat_floor_stops_in_the_distance_of_the_closed_form() {
    // Decelerating at (5/7) mu_r g once the spring is at its limit (after a rotation of
    // mu_r R F_n / k_r, about 1e-5 rad here): it stops after 7 v0^2 / (10 mu_r g) and holds.
    let v0 = 0.05;
    let mut sim = on_incline(law(hertz()), 0.0, v0, v0 / R);
    let stop_time = v0 / (5.0 / 7.0 * MU_R * G);
    run(&mut sim, 1.5 * stop_time);
    let s = sim.state();
    let distance = 7.0 * v0 * v0 / (10.0 * MU_R * G);
    println!("stopped at {:e} m (closed form {distance:e}), v {:e} m/s", s.pos[0].x, s.vel[0].x);
    assert!((s.pos[0].x / distance - 1.0).abs() < 0.005, "{} against {distance}", s.pos[0].x);
    assert!(s.vel[0].norm() < 1e-4 * v0 && s.omega[0].norm() * R < 1e-4 * v0, "not at rest");
}

#[test]
fn the_rolling_springs_energy_is_stored_and_the_ledger_closes() {
    // A grain released on an incline below the critical angle settles with its rolling
    // spring holding `M = m g sin(theta) (R - xi/2)`; the stored energy holds that spring's
    // `M^2 / (2 k_r)`, and `E(t) - E(0) + dissipated` stays zero. Linear normal law: `k_r`
    // is constant. Then Hertz, whose default `k_r` changes with the overlap.
    let kn = 2e4;
    let tilt = (0.8 * MU_R).atan();
    let mut sim = on_incline(law(NormalLaw::Linear { kn, gamma_n: 2e-3 }), tilt, 0.0, 0.0);
    let e0 = sim.total_energy();
    run(&mut sim, 0.1);
    let e = sim.total_energy();
    let saved = sim.export_state();
    let theta = saved.wall_rolls[0];
    let kr = 2.25 * kn * MU_R * MU_R * R * R;
    let spring = 0.5 * kr * theta.norm_squared();
    let xi = R - sim.state().pos[0].z;
    let held = mass() * G * tilt.sin() * (R - 0.5 * xi);
    println!(
        "linear: rolling spring {:e} N m (torque balance {held:e}), energy {spring:e} J; stored {:e} J; miss {:e} J",
        kr * theta.norm(),
        sim.stored_energy,
        e - e0 + sim.ledger.dissipated
    );
    assert!(
        (kr * theta.norm() / held - 1.0).abs() < 1e-3,
        "{} against {held}",
        kr * theta.norm()
    );
    assert!(spring > 0.0 && spring < sim.stored_energy);
    let miss = (e - e0 + sim.ledger.dissipated).abs();
    assert!(
        miss < 0.02 * spring,
        "ledger misses {miss:e} J; the rolling spring holds {spring:e} J"
    );

    // Hertz: dropped from 2 um above its rest height on an incline above the critical angle:
    // the overlap, so k_r, changes while the spring is loaded and at its limit; the slider
    // dissipates `mu_r R F_n` times the rolling angle (about 2e-9 J here). The miss is that of
    // the same run without rolling resistance (a few 1e-12 J: the step's first-order
    // booking). (A spin at the start makes the Cundall-Strack spring slide, whose truncation
    // books more than the friction's work when a step's slip exceeds the spring's range:
    // 1e-10 J here, with or without the rolling spring.)
    let tilt = (1.5 * MU_R).atan();
    let mut sim = lifted(law(hertz()), tilt, 0.0, 0.0, 2e-6);
    let e0 = sim.total_energy();
    let mut worst: f64 = 0.0;
    for _ in 0..50 {
        run(&mut sim, 0.002);
        worst = worst.max((sim.total_energy() - e0 + sim.ledger.dissipated).abs());
    }
    let scale = sim.ledger.dissipated;
    println!("hertz: dissipated {scale:e} J, worst miss {worst:e} J");
    assert!(
        scale > 1e-9 && worst < 5e-3 * scale,
        "ledger misses {worst:e} J of {scale:e} J dissipated"
    );
}
