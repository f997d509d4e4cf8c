//! The vertically vibrated floor (`drive.direction = "z"`) against closed forms: a sphere
//! resting on it lifts off where the floor's downward acceleration first reaches g, and a
//! sphere hitting it rebounds, relative to the moving floor, with the restitution and the
//! contact time the collision lab measures for the same law against a fixed wall. The floor
//! contact is the walls' one kernel with the floor's height and velocity; these tests pin
//! that the vertical drive feeds both in.

mod common;

use particles::constants::GRAVITY;
use particles::experiment::collide::{Collision, Impact, StepSize, Target};
use particles::integrate::Integrator;
use particles::scene::{ContactSpec, DriveDirection, Scene, TimeStep};
use particles::sim::Simulation;
use particles::state::State;
use particles::{tray, Vec3};
use std::f64::consts::PI;

/// One sphere of radius 0.5 mm in a 10 mm x 1.2 mm box with end walls, its floor vibrated at
/// `frequency` (Hz) and `amplitude` (m); linear spring-dashpot, k_n = 1e4 N/m, smooth walls.
fn box_scene(frequency: f64, amplitude: f64) -> Scene {
    common::tray_scene(0.01, 0.0012, 1, TimeStep::Seconds(2.5e-7), 1, |s| {
        s.tray.x_walls = true;
        s.drive = particles::scene::Drive {
            frequency,
            amplitude,
            direction: DriveDirection::Z,
            stages: Vec::new(),
        };
        s.particles.radius_min = 0.5e-3;
        s.particles.radius_max = 0.5e-3;
        s.contact = ContactSpec {
            normal: particles::contact::choice::NormalKind::Linear,
            kn: Some(1e4),
            gamma_n: Some(5.4e-3),
            tangential: particles::contact::choice::TangentialKind::None,
            rolling: particles::contact::choice::RollingKind::None,
            wall_friction: 0.0,
            ..ContactSpec::default()
        };
    })
}

/// A simulation of `scene` with its one sphere at height `z`, vertical velocity `vz`.
fn one_sphere(scene: &Scene, z: f64, vz: f64) -> Simulation {
    let r = scene.particles.radius_min;
    let m = scene.material().sphere_mass(r);
    let mut state = State::default();
    state.push(Vec3::new(0.005, 0.0006, z), Vec3::new(0.0, 0.0, vz), Vec3::zeros(), r, m);
    let dt = match scene.run.dt {
        TimeStep::Seconds(dt) => dt,
        TimeStep::Auto(_) => unreachable!(),
    };
    Simulation::new(tray::setup(scene, tray::drive(scene), dt).unwrap(), state).unwrap()
}

/// The floor's height at time `t`.
fn floor(scene: &Scene, t: f64) -> f64 {
    scene.drive.amplitude * (2.0 * PI * scene.drive.frequency * t).sin()
}

#[test]
fn a_resting_sphere_rides_the_floor_below_one_g_and_lifts_off_where_it_first_pulls_g() {
    let r = 0.5e-3;
    // Below Gamma = 1 the sphere never leaves the floor: Gamma = 0.47 at 20 Hz, 0.3 mm.
    for (amplitude, gamma) in [(0.3e-3, 0.474), (1.0e-3, 1.579)] {
        let scene = box_scene(20.0, amplitude);
        let w = 2.0 * PI * 20.0;
        assert!((amplitude * w * w / GRAVITY - gamma).abs() < 1e-3);
        let (_, wall) = scene.laws().unwrap();
        let m = scene.material().sphere_mass(r);
        // At rest on the floor at t = 0, moving with it (the floor rises at A w).
        let mut sim = one_sphere(&scene, r - wall.normal.static_overlap(m * GRAVITY, r), amplitude * w);
        let mut lift_off = None;
        while sim.time < 1.0 / 20.0 {
            sim.step().unwrap();
            let gap = sim.state().pos[0].z - r - floor(&scene, sim.time);
            if gap > 0.0 && lift_off.is_none() {
                lift_off = Some(sim.time);
            }
            if gamma < 1.0 {
                // Pressed on the floor: the overlap stays within a few static overlaps.
                assert!(
                    gap < 0.0 && gap > -4.0 * wall.normal.static_overlap(m * GRAVITY, r),
                    "t = {}: gap {gap:e}",
                    sim.time
                );
            }
        }
        if gamma > 1.0 {
            // Hard contact: lift-off at sin(w t) = 1 / Gamma. The soft contact releases a little
            // later (its spring unloads over part of its period, about 0.01 period here).
            let expected = (1.0 / gamma).asin() / w;
            let t = lift_off.expect("the sphere lifts off");
            assert!(
                t > expected && t - expected < 0.02 / 20.0,
                "lift-off at {t:e} s, closed form {expected:e} s"
            );
        } else {
            assert!(lift_off.is_none());
        }
    }
}

#[test]
fn an_impact_on_the_moving_floor_rebounds_with_the_fixed_walls_restitution_relative_to_the_floor() {
    // The floor at 100 Hz, V = A w = 0.4 m/s; the impact is centred on t = 10 ms, where the
    // floor passes its mean position at its peak speed and does not accelerate, so its
    // velocity is constant over the contact to second order.
    let scene = box_scene(100.0, 0.4 / (2.0 * PI * 100.0));
    let r = 0.5e-3;
    let m = scene.material().sphere_mass(r);
    let (_, wall_law) = scene.laws().unwrap();
    let lab = |g_n: f64| {
        Collision {
            law: wall_law,
            r1: r,
            m1: m,
            omega1: Vec3::zeros(),
            target: Target::Wall,
            impact: Impact::Components { vn: g_n, vt: 0.0 },
            step: StepSize::Dt(2.5e-7),
            integrator: Integrator::VelocityVerlet,
        }
        .run()
        .unwrap()
    };
    let t_c = lab(1.0).t_c;
    // Thrown down at 0.5 m/s from the height that makes the contact start at
    // t_s = 10 ms - t_c / 2.
    let v0 = -0.5;
    let t_s = 0.01 - 0.5 * t_c;
    let z0 = r + floor(&scene, t_s) - v0 * t_s + 0.5 * GRAVITY * t_s * t_s;
    let mut sim = one_sphere(&scene, z0, v0);
    let (mut start, mut end) = (None, None);
    let mut v_in = 0.0;
    let v_floor = |t: f64| 0.4 * (2.0 * PI * 100.0 * t).cos();
    let mut g_in = 0.0;
    while end.is_none() && sim.time < 0.02 {
        let before = sim.state().vel[0].z;
        sim.step().unwrap();
        let touching = sim.state().pos[0].z - r - floor(&scene, sim.time) <= 0.0;
        if touching && start.is_none() {
            start = Some(sim.time);
            v_in = before;
            g_in = v_floor(sim.time) - v_in;
        }
        if !touching && start.is_some() {
            end = Some(sim.time);
        }
    }
    let (start, end) = (start.expect("an impact"), end.expect("a rebound"));
    assert!(
        (0.5 * (start + end) - 0.01).abs() < 0.1 * t_c,
        "contact centred on {:e} s",
        0.5 * (start + end)
    );
    // The approach speed relative to the floor: the fall plus the floor rising at 0.4 m/s.
    assert!((g_in - (0.5 + GRAVITY * t_s + 0.4)).abs() < 1e-3, "g_in {g_in}");
    let lab = lab(g_in);
    // Gravity acts over the contact too: add back g t_c to the rebound.
    let g_out = sim.state().vel[0].z + GRAVITY * (end - start) - v_floor(end);
    let eps = g_out / g_in;
    assert!(
        (eps - lab.eps_n).abs() < 2e-3,
        "rebound relative to the floor {eps}, fixed wall {}",
        lab.eps_n
    );
    assert!(
        ((end - start) - lab.t_c).abs() < 4.0 * 2.5e-7,
        "contact {:e} s, fixed wall {:e} s",
        end - start,
        lab.t_c
    );
    // And the floor did work on the sphere: it leaves faster than it came in.
    assert!(sim.state().vel[0].z > -v_in, "{} after {v_in}", sim.state().vel[0].z);
}

#[test]
fn the_vertical_drive_moves_only_the_floor_and_lowers_the_container_by_the_amplitude() {
    let scene = box_scene(100.0, 1e-3);
    let setup = tray::setup(&scene, tray::drive(&scene), 1e-6).unwrap();
    let names: Vec<&str> = setup.walls.iter().map(|w| w.name.as_str()).collect();
    assert_eq!(names, ["floor", "side y=0", "side y=W", "end x=0", "end x=L"]);
    let t = 1.3e-3;
    assert!((setup.walls[0].origin_at(t).z - floor(&scene, t)).abs() < 1e-18);
    assert_eq!(setup.walls[0].origin_at(t).x, 0.0);
    for w in &setup.walls[1..] {
        assert_eq!(w.origin_at(t), w.origin, "{} moved", w.name);
    }
    assert_eq!(setup.boundary.periodic, [None, None, None]);
    let lo = setup.container.unwrap().lo;
    assert!((lo.z + 1e-3 + 0.5e-3).abs() < 1e-15, "{lo}");
    // The horizontal tray: every wall moves along x, x is periodic without end walls.
    let mut tray_scene = scene.clone();
    tray_scene.drive.direction = DriveDirection::X;
    tray_scene.tray.x_walls = false;
    let setup = tray::setup(&tray_scene, tray::drive(&tray_scene), 1e-6).unwrap();
    assert_eq!(setup.walls.len(), 3);
    for w in &setup.walls {
        assert!((w.origin_at(t).x - w.origin.x - floor(&scene, t)).abs() < 1e-18);
    }
    assert_eq!(setup.boundary.periodic[0], Some(0.01));
    // A pinned layer cannot follow a vertical floor.
    let mut pinned = scene;
    pinned.toggles.jumping = false;
    let e = pinned.validate().unwrap_err();
    assert_eq!(e.key, "toggles.jumping");
}
