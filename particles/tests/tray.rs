//! The shaken tray: periodic seam, pinned 2D mode, particle count, bad runtime input.

mod common;

use particles::boundary::Boundary;
use particles::prepare::initial_state;
use particles::scene::{Scene, TimeStep};
use particles::setup::Setup;
use particles::sim::Simulation;
use particles::state::State;
use particles::time_step;
use particles::tray;
use particles::{SimError, Vec3};

/// 100 grains on 20 mm x 10 mm, 0.1 s at the thesis' step, changed by `edit`.
fn scene(edit: impl FnOnce(&mut Scene)) -> Scene {
    common::tray_scene(0.02, 0.01, 100, TimeStep::Seconds(8e-6), 4, edit)
}

fn tray_sim(edit: impl FnOnce(&mut Scene)) -> Simulation {
    let s = scene(edit);
    Simulation::new(
        tray::setup(&s, tray::drive(&s), time_step::for_scene(&s).unwrap()).unwrap(),
        initial_state(&s).unwrap(),
    )
    .unwrap()
}

/// Two grains colliding obliquely on the floor at `x0` (m) in a periodic tray.
fn seam_pair(setup: &Setup, x0: f64) -> Simulation {
    let mut st = State::default();
    let r = 4e-4;
    let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    st.push(Vec3::new(x0, 0.005, r), Vec3::new(0.05, 0.01, 0.0), Vec3::new(0.0, 30.0, 0.0), r, m);
    st.push(
        Vec3::new(x0 + 2.0 * r - 1e-6, 0.0052, r),
        Vec3::new(-0.05, 0.0, 0.0),
        Vec3::zeros(),
        r,
        m,
    );
    for x in st.pos.iter_mut() {
        *x = setup.boundary.wrap(*x);
    }
    Simulation::new(setup.clone(), st).unwrap()
}

#[test]
fn a_contact_across_the_periodic_seam_equals_the_same_pair_shifted() {
    let s = scene(common::unchanged);
    let setup = tray::setup(&s, particles::wall::Motion::Fixed, time_step::for_scene(&s).unwrap()).unwrap();
    let l = s.tray.length;
    let mut middle = seam_pair(&setup, 0.5 * l);
    let mut seam = seam_pair(&setup, l - 4e-4); // the second grain lies across x = 0
    for _ in 0..2000 {
        middle.step().unwrap();
        seam.step().unwrap();
    }
    let b = Boundary {
        periodic: [Some(l), None, None],
    };
    for i in 0..2 {
        let shift = b.min_image(seam.state().pos[i] - middle.state().pos[i]);
        assert!(
            (shift.x - (l - 4e-4 - 0.5 * l)).abs() < 1e-12,
            "grain {i} moved differently: {shift}"
        );
        assert!(shift.y.abs() < 1e-12 && shift.z.abs() < 1e-12);
        assert!((seam.state().vel[i] - middle.state().vel[i]).norm() < 1e-12);
        assert!((seam.state().omega[i] - middle.state().omega[i]).norm() < 1e-9);
    }
    assert!(middle.state().vel[1].x > -0.05, "they did collide");
}

#[test]
fn pinned_mode_keeps_z_equal_to_the_radius_exactly() {
    // The prepared grains rest at z = R - overlap; pinning puts them at z = R.
    let mut sim = tray_sim(|s| s.toggles.jumping = false);
    for _ in 0..3000 {
        sim.step().unwrap();
    }
    for i in 0..sim.len() {
        assert_eq!(sim.state().pos[i].z, sim.state().radius[i], "grain {i}");
        assert_eq!(sim.state().vel[i].z, 0.0);
    }
    // The floor still drives: grains move.
    assert!(sim.state().vel.iter().any(|v| v.x.abs() > 1e-3));
}

#[test]
fn the_particle_count_is_conserved_and_grains_stay_in_the_box() {
    let mut sim = tray_sim(common::unchanged);
    let n = sim.len();
    for _ in 0..5000 {
        sim.step().unwrap();
    }
    assert_eq!(sim.len(), n);
    let s = scene(common::unchanged);
    for x in &sim.state().pos {
        assert!((0.0..s.tray.length).contains(&x.x) && (0.0..=s.tray.width).contains(&x.y) && x.z > 0.0);
    }
}

#[test]
fn bad_runtime_input_names_the_particle_and_the_step() {
    let base = tray_sim(common::unchanged);
    // Overlapping grains at the start.
    let mut st = base.state().into_owned();
    st.pos[7] = st.pos[3] + Vec3::new(1e-4, 0.0, 0.0);
    match Simulation::new(base.setup.clone(), st) {
        Err(SimError::InitialOverlap { i: 3, j: 7, .. }) => {}
        other => panic!("expected an overlap of grains 3 and 7, got {other:?}"),
    }
    // A NaN, and a grain outside the side walls, at the start.
    let mut st = base.state().into_owned();
    st.omega[11].x = f64::NAN;
    let e = Simulation::new(base.setup.clone(), st).unwrap_err();
    assert!(matches!(e, SimError::NonFinite { step: 0, particle: 11, .. }), "{e:?}");
    let mut st = base.state().into_owned();
    st.pos[9].y = -0.01;
    let e = Simulation::new(base.setup.clone(), st).unwrap_err();
    assert!(matches!(e, SimError::Escaped { step: 0, particle: 9, .. }), "{e:?}");
    // A NaN.
    let mut sim = base.clone();
    sim.step().unwrap();
    sim.state_mut().vel[42].y = f64::NAN;
    let e = sim.step().unwrap_err();
    assert!(matches!(e, SimError::NonFinite { step: 2, particle: 42, .. }), "{e:?}");
    assert!(e.to_string().contains("step 2: particle 42"), "{e}");
    // A grain shot through the side wall at y = 0 (it crosses the wall within one step).
    let mut sim = base.clone();
    sim.state_mut().vel[5] = Vec3::new(0.0, -2000.0, 0.0);
    let e = (0..1000).find_map(|_| sim.step().err()).expect("the grain escapes");
    assert!(matches!(e, SimError::Escaped { particle: 5, .. }), "{e:?}");
    assert!(e.to_string().contains("particle 5 left the box"), "{e}");
    // The top is open (thesis 3.5.3): a grain thrown up falls back, unless a ceiling is set.
    let mut sim = base.clone();
    sim.state_mut().vel[5] = Vec3::new(0.0, 0.0, 2.0);
    for _ in 0..12_500 {
        sim.step().unwrap();
    }
    let mut sim = tray_sim(|s| s.tray.height = Some(0.1));
    sim.state_mut().vel[5] = Vec3::new(0.0, 0.0, 2.0);
    let e = (0..12_500).find_map(|_| sim.step().err()).expect("the grain passes the ceiling");
    assert!(matches!(e, SimError::Escaped { particle: 5, .. }), "{e:?}");
}
