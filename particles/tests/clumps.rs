//! Rigid clumps (issue 39, step 3): a free clump keeps its energy and angular momentum, a
//! pair of clumps colliding keeps its momenta, a dimer dropped onto the floor comes to rest
//! with the energy ledger closed, and a dimer lying on an incline below its tipping angle
//! stays where a sphere of the same material rolls.

mod common;

use particles::boundary::Boundary;
use particles::clump::ClumpShape;
use particles::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::sim::Simulation;
use particles::state::State;
use particles::wall::{Motion, Wall};
use particles::Vec3;

const R: f64 = 5e-4;
const RHO: f64 = 2500.0;
const G: f64 = 10.0;

/// The thesis' laws (Hertz with dissipation, Haff-Werner, Brilliantov-Pöschel).
fn thesis_law() -> ContactLaw {
    ContactLaw {
        normal: NormalLaw::hertz(1e6 / (1.0 - 0.09), 8.5e-6),
        tangential: TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 },
        rolling: RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 },
    }
}

/// Clumps of `shape` with spheres of radius `R` at density `RHO`: one per `(centre, axis)`,
/// the body's x axis along `axis`, its y axis horizontal.
fn clumps(shape: &ClumpShape, bodies: &[(Vec3, Vec3)]) -> State {
    let (unit_mass, _) = shape.mass_and_inertia();
    let m = RHO * unit_mass * R.powi(3) / shape.spheres as f64;
    let mut s = State::default();
    for &(c, axis) in bodies {
        let e1 = axis.normalize();
        let side = if e1.z.abs() < 0.9 { Vec3::z().cross(&e1) } else { Vec3::y() };
        let e2 = (side - e1 * side.dot(&e1)).normalize();
        for b in shape.offsets() {
            s.push(c + (e1 * b.x + e2 * b.y) * R, Vec3::zeros(), Vec3::zeros(), R, m);
        }
    }
    s
}

fn simulation(shape: ClumpShape, law: ContactLaw, state: State, dt: f64, edit: impl FnOnce(&mut particles::setup::Setup)) -> Simulation {
    let mut setup = common::free_setup(law, Boundary::open(), dt);
    setup.clump = Some(shape);
    edit(&mut setup);
    Simulation::new(setup, state).unwrap()
}

/// Total linear momentum and angular momentum about the origin of the bodies.
fn momenta(sim: &Simulation) -> (Vec3, Vec3) {
    let b = sim.bodies().unwrap();
    let (mut p, mut l) = (Vec3::zeros(), Vec3::zeros());
    for g in 0..b.len() {
        p += b.v[g] * b.mass[g];
        l += b.x[g].cross(&b.v[g]) * b.mass[g] + b.angular_momentum(g);
    }
    (p, l)
}

#[test]
fn a_free_tumbling_triangle_keeps_its_energy_angular_momentum_and_shape() {
    // A trimer spun about a tilted axis in free space: a symmetric top (I1 = I2 < I3)
    // precessing torque-free; its members must follow it rigidly.
    let shape = ClumpShape::new(3, 1.2).unwrap();
    let state = clumps(&shape, &[(Vec3::zeros(), Vec3::x())]);
    let mut sim = simulation(shape, thesis_law(), state, 1e-5, |_| {});
    sim.set_body_motion(0, Vec3::new(0.01, 0.0, 0.0), Vec3::new(60.0, 25.0, 200.0));
    let (e0, (p0, l0)) = (sim.total_energy(), momenta(&sim));
    let i = sim.bodies().unwrap().inertia[0];
    // Precession of the body-frame spin at (I3 - I1) / I1 omega_3: run five of its periods.
    let period = 2.0 * std::f64::consts::PI / ((i.z - i.x) / i.x * 200.0);
    let steps = (5.0 * period / 1e-5) as usize;
    let (mut de, mut dl, mut shape_error) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..steps {
        sim.step().unwrap();
        let (p, l) = momenta(&sim);
        de = de.max((sim.total_energy() - e0).abs() / e0);
        dl = dl.max((l - l0).norm() / l0.norm());
        assert!((p - p0).norm() < 1e-15 * p0.norm());
        let s = sim.state();
        for k in 0..3 {
            shape_error = shape_error.max(((s.pos[k] - s.pos[(k + 1) % 3]).norm() / R - 1.2).abs());
        }
    }
    println!(
        "{steps} steps ({} precession periods): energy {de:.2e}, angular momentum {dl:.2e}, shape {shape_error:.2e}",
        5
    );
    assert!(de < 1e-6, "energy drift {de:e}");
    assert!(dl < 1e-9, "angular momentum drift {dl:e}");
    assert!(shape_error < 1e-12, "members moved apart by {shape_error:e} R");
    assert_eq!(sim.contact_counts, (0, 0), "a clump's own members never touch as a pair");
}

#[test]
fn two_dimers_colliding_keep_their_linear_and_angular_momentum() {
    // An off-centre frictional impact of a spinning dimer on a resting one turned by 60
    // degrees, in free space: contacts between members of different bodies only.
    let shape = ClumpShape::new(2, 1.0).unwrap();
    let turned = Vec3::new(0.5, 0.75f64.sqrt(), 0.0);
    let state = clumps(
        &shape,
        &[(Vec3::zeros(), Vec3::x()), (Vec3::new(3.6 * R, 0.7 * R, 0.2 * R), turned)],
    );
    let mut sim = simulation(shape, thesis_law(), state, 2e-7, |_| {});
    sim.set_body_motion(0, Vec3::new(0.5, 0.02, 0.0), Vec3::new(0.0, 30.0, -200.0));
    let (p0, l0) = momenta(&sim);
    let e0 = sim.total_energy();
    let (mut touched, mut apart) = (false, false);
    for _ in 0..200_000 {
        sim.step().unwrap();
        touched |= sim.contact_counts.0 > 0;
        if touched && sim.contact_counts.0 == 0 {
            apart = true;
            break;
        }
    }
    assert!(touched && apart, "the dimers met and separated");
    let (p, l) = momenta(&sim);
    let b = sim.bodies().unwrap();
    let scale_l = b.x[1].norm() * p0.norm() + l0.norm();
    println!(
        "momentum {:.2e}, angular momentum {:.2e} (of {scale_l:e}), energy {:e} -> {:e} J, v1 {:?}",
        (p - p0).norm() / p0.norm(),
        (l - l0).norm() / scale_l,
        e0,
        sim.total_energy(),
        b.v[1]
    );
    assert!(b.v[1].x > 0.1, "the second dimer was pushed");
    assert!((p - p0).norm() < 1e-13 * p0.norm(), "momentum changed by {:e}", (p - p0).norm());
    assert!(
        (l - l0).norm() < 1e-12 * scale_l,
        "angular momentum changed by {:e}",
        (l - l0).norm()
    );
    assert!(sim.total_energy() < e0);
}

#[test]
fn a_dimer_dropped_onto_the_floor_comes_to_rest_and_the_ledger_closes() {
    // Dropped from 0.5 R above the floor, its axis tilted by 10 degrees and moving sideways:
    // one sphere lands first, the dimer rocks, slides and comes to rest lying flat.
    let shape = ClumpShape::new(2, 1.0).unwrap();
    let axis = Vec3::new(10f64.to_radians().cos(), 0.0, 10f64.to_radians().sin());
    let state = clumps(&shape, &[(Vec3::new(0.0, 0.0, 1.6 * R), axis)]);
    let floor = Wall::new("floor", Vec3::zeros(), Vec3::z(), Motion::Fixed);
    let mut sim = simulation(shape, thesis_law(), state, 4e-6, |s| {
        s.walls = vec![floor];
        s.gravity = Vec3::new(0.0, 0.0, -G);
    });
    sim.set_body_motion(0, Vec3::new(0.05, 0.0, 0.0), Vec3::zeros());
    let e0 = sim.total_energy();
    let mut worst: f64 = 0.0;
    for _ in 0..100 {
        for _ in 0..1000 {
            sim.step().unwrap();
        }
        worst = worst.max((sim.total_energy() - e0 + sim.ledger.dissipated).abs());
    }
    let lost = e0 - sim.total_energy();
    let b = sim.bodies().unwrap();
    let m = b.mass[0];
    let s = sim.state();
    let rest = thesis_law().normal.static_overlap(0.5 * m * G, R);
    println!(
        "after 0.4 s: v {:e} m/s, omega {:e} rad/s, heights {:e} {:e} (rest {:e}); lost {lost:e} J, worst ledger miss {worst:e} J",
        b.v[0].norm(),
        b.omega(0).norm(),
        s.pos[0].z,
        s.pos[1].z,
        R - rest
    );
    assert!(b.v[0].norm() < 1e-4 && b.omega(0).norm() * R < 1e-4, "not at rest");
    for k in 0..2 {
        assert!(
            (s.pos[k].z - (R - rest)).abs() < 0.05 * rest,
            "sphere {k} does not lie on the floor"
        );
    }
    assert_eq!(sim.contact_counts, (0, 2));
    // The tolerance of the spheres' dropped stack (extreme_contacts.rs): 1e-2 of the loss.
    assert!(worst < 1e-2 * lost, "ledger misses {worst:e} J of {lost:e} J lost");
}

/// A grain (a sphere, or a dimer with its axis down the slope) released at rest on a floor
/// tilted by `tilt`, with static friction (Cundall-Strack, mu 0.9) and no rolling
/// resistance; its displacements down the slope after `t` and `2 t` seconds. The normal
/// dissipation is six times the thesis', so that a dimer's rocking on its two contacts (it
/// starts with equal loads on both) dies out within `t`.
fn on_incline(dimer: bool, tilt: f64, t: f64) -> (f64, f64) {
    let law = ContactLaw {
        normal: NormalLaw::hertz(1e6 / (1.0 - 0.09), 5e-5),
        tangential: TangentialLaw::CundallStrack { kt: 100.0, mu: 0.9 },
        rolling: RollingLaw::None,
    };
    let gravity = Vec3::new(G * tilt.sin(), 0.0, -G * tilt.cos());
    let floor = Wall::new("floor", Vec3::zeros(), Vec3::z(), Motion::Fixed);
    let dt = 4e-6;
    let mut sim = if dimer {
        let shape = ClumpShape::new(2, 1.0).unwrap();
        let m = RHO * shape.mass_and_inertia().0 * R.powi(3) / 2.0;
        let z = R - law.normal.static_overlap(m * G * tilt.cos(), R);
        let state = clumps(&shape, &[(Vec3::new(0.0, 0.0, z), Vec3::x())]);
        simulation(shape, law, state, dt, |s| {
            s.walls = vec![floor];
            s.gravity = gravity;
        })
    } else {
        let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
        let mut state = State::default();
        let z = R - law.normal.static_overlap(m * G * tilt.cos(), R);
        state.push(Vec3::new(0.0, 0.0, z), Vec3::zeros(), Vec3::zeros(), R, m);
        let mut setup = common::free_setup(law, Boundary::open(), dt);
        setup.walls = vec![floor];
        setup.gravity = gravity;
        Simulation::new(setup, state).unwrap()
    };
    let n = sim.len() as f64;
    let x = |sim: &Simulation| sim.state().pos.iter().map(|x| x.x).sum::<f64>() / n;
    let x0 = x(&sim);
    let mut out = [0.0; 2];
    for o in &mut out {
        for _ in 0..(t / dt).round() as usize {
            sim.step().unwrap();
        }
        *o = x(&sim) - x0;
    }
    (out[0], out[1])
}

#[test]
fn a_dimer_lying_on_an_incline_below_its_tipping_angle_stays_where_a_sphere_rolls() {
    // A dimer of spacing d = R lying down the slope tips over its lower sphere once
    // tan(theta) > d / (2 R) = 0.5 (its weight's line leaves the contact); a sphere with
    // no rolling resistance rolls from any tilt, at (5/7) g sin(theta).
    let t = 0.2;
    let below = 0.4f64.atan();
    let (sphere, _) = on_incline(false, below, t);
    let rolled = 0.5 * 5.0 / 7.0 * G * below.sin() * t * t;
    let (dimer, later) = on_incline(true, below, t);
    let (tipped, _) = on_incline(true, 0.6f64.atan(), t);
    println!(
        "tan 0.4: sphere {sphere:e} m (closed form {rolled:e}), dimer {dimer:e} m at {t} s, {later:e} m at {} s; \
         tan 0.6: dimer {tipped:e} m",
        2.0 * t
    );
    assert!((sphere / rolled - 1.0).abs() < 0.01, "the sphere rolled {sphere} m, not {rolled} m");
    // The dimer settles within a micrometre (it starts with equal loads on both spheres and
    // rocks at first; a sphere that lifts loses its tangential spring), then holds still.
    assert!(dimer.abs() < 1e-2 * R, "the dimer moved {dimer:e} m below its tipping angle");
    assert!((later - dimer).abs() < 1e-4 * R, "the dimer crept by {:e} m", later - dimer);
    assert!(tipped > 2.0 * R, "the dimer moved only {tipped:e} m above its tipping angle");
}

#[test]
fn a_tray_of_clumps_is_prepared_without_overlaps_and_its_ledger_closes() {
    // 40 triangles (d = 1.2 R) on the thesis' tray, shaken for 0.05 s from their lattice
    // with random orientations in the plane.
    use particles::{prepare::initial_state, scene::Shape, time_step, tray};
    let scene = common::tray_scene(0.01, 0.01, 40, particles::scene::TimeStep::Seconds(4e-6), 3, |s| {
        s.particles.shape = Shape::Clump;
        s.particles.clump_spheres = Some(3);
        s.particles.clump_spacing = Some(1.2);
    });
    let state = initial_state(&scene).unwrap();
    assert_eq!(state.len(), 120);
    let mut closest = f64::INFINITY;
    for i in 0..state.len() {
        for j in i + 1..state.len() {
            if i / 3 != j / 3 {
                let gap = (state.pos[i] - state.pos[j]).norm() - state.radius[i] - state.radius[j];
                closest = closest.min(gap);
            }
        }
        assert!(state.pos[i].y > state.radius[i] && state.pos[i].y < 0.01 - state.radius[i]);
    }
    assert!(closest > 0.0, "clumps overlap by {:e} m", -closest);
    let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap();
    let mut sim = Simulation::new(setup, state).unwrap();
    assert_eq!(sim.bodies().unwrap().len(), 40);
    let e0 = sim.total_energy();
    for _ in 0..(0.05 / 4e-6) as usize {
        sim.step().unwrap();
    }
    let l = sim.ledger;
    let miss = (sim.total_energy() - e0 - (l.injected - l.dissipated)).abs();
    println!(
        "injected {:e} J, dissipated {:e} J, miss {:.2e} of injected",
        l.injected,
        l.dissipated,
        miss / l.injected
    );
    assert!(l.injected > 0.0 && l.dissipated > 0.0);
    // The spheres' bound on their shaken tray at this step (extreme_contacts.rs): 1e-4.
    assert!(miss < 1e-4 * l.injected, "the ledger misses by {miss:e} J");
}

#[test]
fn a_clump_run_continued_from_its_saved_state_goes_on_bit_for_bit() {
    use particles::{prepare::initial_state, scene::Shape, time_step, tray};
    let scene = common::tray_scene(0.01, 0.01, 40, particles::scene::TimeStep::Seconds(4e-6), 5, |s| {
        s.particles.shape = Shape::Clump;
        s.particles.clump_spheres = Some(2);
        s.particles.clump_spacing = Some(0.8);
    });
    let fresh = || {
        let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).unwrap()).unwrap();
        Simulation::new(setup, initial_state(&scene).unwrap()).unwrap()
    };
    let mut whole = fresh();
    for _ in 0..3000 {
        whole.step().unwrap();
    }
    let saved = whole.export_state();
    assert_eq!(saved.bodies.len(), 40);
    for _ in 0..3000 {
        whole.step().unwrap();
    }
    let mut resumed = fresh();
    resumed.import_state(saved).unwrap();
    for _ in 0..3000 {
        resumed.step().unwrap();
    }
    let b = whole.bodies().unwrap();
    assert!(whole.contact_counts.1 > 0, "the clumps touch the tray: {:?}", whole.contact_counts);
    assert!((0..b.len()).all(|g| b.v[g].norm() > 1e-3), "the tray moves them");
    assert_eq!(common::state_bits(&resumed), common::state_bits(&whole));
    assert_eq!(resumed.export_state().bodies, whole.export_state().bodies);
    // A state of spheres, or of another number of clumps, is refused by name.
    let mut spheres = whole.export_state();
    spheres.bodies.clear();
    let e = fresh().import_state(spheres).unwrap_err();
    assert!(e.to_string().contains("0 rigid clumps, the scene 40"), "{e}");
}
