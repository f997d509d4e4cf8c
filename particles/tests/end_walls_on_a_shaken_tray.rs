//! Regression: end walls on a horizontally shaken tray (the known defect of 2026-11-28).
//!
//! `stripes run scenes/stripes.toml --set box.x_walls=true` stopped within 1000-2000 steps
//! with "particle left the box at (L + 3e-7 m, ...)": the walls at x = u(t) and x = L + u(t)
//! moved with the tray, but the escape check's box stayed at [0, L], so a grain carried
//! forwards by the floor past x = L, still inside the moving tray, stopped the run. The
//! container now moves with the side and end walls ([`particles::setup::Container`]).

mod common;

use particles::prepare::initial_state;
use particles::scene::{Scene, TimeStep};
use particles::sim::Simulation;
use particles::state::State;
use particles::tray;
use particles::Vec3;

/// 5 Hz / 20 mm, the experiment's fluidising drive, on a 10 mm x 5 mm tray with end walls.
fn shaken_box(count: usize, edit: impl FnOnce(&mut Scene)) -> Scene {
    common::tray_scene(0.01, 0.005, count, TimeStep::Seconds(4e-6), 3, |s| {
        s.tray.x_walls = true;
        s.drive.frequency = 5.0;
        s.drive.amplitude = 0.02;
        edit(s);
    })
}

#[test]
fn end_walls_on_a_shaken_tray_keep_every_grain_inside_and_the_run_going() {
    let scene = shaken_box(60, common::unchanged);
    let setup = tray::setup(&scene, tray::drive(&scene), 4e-6).unwrap();
    let motion = tray::drive(&scene);
    let mut sim = Simulation::new(setup, initial_state(&scene).unwrap()).unwrap();
    let l = scene.tray.length;
    let (mut beyond_l, mut below_0) = (false, false);
    // Half a period: the tray goes forwards by 20 mm and back, twice the tray's length.
    let steps = (0.1 / 4e-6) as usize;
    for k in 0..steps {
        sim.step().unwrap_or_else(|e| panic!("step {k}: {e}"));
        let u = motion.displacement(sim.time).x;
        let state = sim.state();
        for (i, (x, r)) in state.pos.iter().zip(&state.radius).enumerate() {
            // Inside the moving walls, overlapping them by less than the half radius the
            // simulation accepts (particles::setup::MAX_OVERLAP_FRACTION).
            assert!(
                x.x > u + 0.5 * r && x.x < l + u - 0.5 * r,
                "step {k}: grain {i} at x = {} with the tray at {u}",
                x.x
            );
            beyond_l |= x.x > l;
            below_0 |= x.x < 0.0;
        }
    }
    // The floor carried grains past where the old, fixed check put the end of the box.
    assert!(beyond_l, "no grain went past x = L: the test does not reach the bug");
    assert!(!below_0 || beyond_l);
}

#[test]
fn a_grain_is_pushed_by_the_moving_end_wall() {
    // One grain at rest on a frictionless floor, 2 mm from the end wall at x = 0: only the
    // end wall can move it. The wall (the tray at 5 Hz / 20 mm, u = A sin(w t)) reaches it
    // at u = 2 mm, moving at V = A w cos(w t); an infinite mass hitting a grain at rest
    // sends it off at (1 + e) V with restitution 0 < e <= 1.
    let scene = shaken_box(1, |s| {
        s.tray.length = 0.2; // the grain flies off: room for it
        s.contact.wall_friction = 0.0;
        s.toggles.rolling = false;
    });
    let dt = 4e-6;
    let setup = tray::setup(&scene, tray::drive(&scene), dt).unwrap();
    let motion = tray::drive(&scene);
    let r = 0.5e-3;
    let gap = 2e-3;
    let mut state = State::default();
    state.push(Vec3::new(r + gap, 0.0025, r), Vec3::zeros(), Vec3::zeros(), r, common::mass(r));
    let mut sim = Simulation::new(setup, state).unwrap();
    let (w, a) = (2.0 * std::f64::consts::PI * 5.0, 0.02);
    let t_hit = (gap / a).asin() / w;
    let v_wall = a * w * (w * t_hit).cos();
    let mut touched = false;
    while sim.time < 0.05 {
        sim.step().unwrap();
        let u = motion.displacement(sim.time).x;
        let x = sim.state().pos[0].x;
        assert!(x - u > 0.5 * r, "t = {}: the grain at {x} is behind the wall at {u}", sim.time);
        if x - u < r {
            assert!(
                sim.time > t_hit - dt,
                "touched at {} before the wall could reach it ({t_hit})",
                sim.time
            );
            touched = true;
        } else if touched {
            break; // the contact is over
        } else {
            assert_eq!(sim.state().vel[0].x, 0.0, "t = {}: moved before the wall came", sim.time);
        }
    }
    assert!(touched, "the wall never reached the grain");
    let v = sim.state().vel[0].x;
    assert!(
        v > v_wall && v <= 2.0 * v_wall * (1.0 + 1e-3),
        "grain leaves at {v} m/s; the wall hit it at {v_wall} m/s (expected (1 + e) V)"
    );
}
