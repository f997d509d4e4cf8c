//! The small tray scenes of the particle tests: the thesis' grains and drive on a short box.
#![allow(dead_code)] // each test file uses a part

use particles::boundary::Boundary;
use particles::contact::ContactLaw;
use particles::integrate::Integrator;
use particles::material::Material;
use particles::neighbor::NeighborSearch;
use particles::scene::{
    AutoDt, ContactSpec, Drive, Particles, Prepare, Run, Scene, TimeStep, Toggles, TrayBox, DEFAULT_CHECKPOINT_INTERVAL,
    DEFAULT_RESTITUTION_TOLERANCE, DEFAULT_SORT_INTERVAL, DEFAULT_STEPS_PER_CONTACT,
};
use particles::setup::{Setup, Vertical};
use particles::sim::Simulation;
use particles::Vec3;

/// A tray of `count` grains with the thesis' radii (0.25-0.5 mm), drive (20 Hz, 25 mm) and
/// defaults on `length` x `width` m, run for 0.1 s at step `dt` from sample `seed`, then
/// changed by `edit` and validated.
pub fn tray_scene(length: f64, width: f64, count: usize, dt: TimeStep, seed: u64, edit: impl FnOnce(&mut Scene)) -> Scene {
    let mut scene = Scene {
        tray: TrayBox {
            length,
            width,
            height: None,
            x_walls: false,
        },
        drive: Drive {
            frequency: 20.0,
            amplitude: 0.025,
            direction: Default::default(),
            stages: Vec::new(),
        },
        particles: Particles {
            count,
            radius_min: 0.25e-3,
            radius_max: 0.5e-3,
            ..Default::default()
        },
        material: Material::default(),
        contact: ContactSpec::default(),
        toggles: Toggles::default(),
        prepare: Prepare::default(),
        run: Run {
            duration: 0.1,
            dt,
            steps_per_contact: DEFAULT_STEPS_PER_CONTACT,
            restitution_tolerance: DEFAULT_RESTITUTION_TOLERANCE,
            seed,
            threads: 0,
            snapshots_per_period: 1,
            checkpoint_interval: DEFAULT_CHECKPOINT_INTERVAL,
            sort_interval: DEFAULT_SORT_INTERVAL,
            integrator: Integrator::default(),
        },
    };
    edit(&mut scene);
    scene.validate().unwrap();
    scene
}

/// The automatic time step, `run.dt = "auto"`.
pub const AUTO: TimeStep = TimeStep::Auto(AutoDt::Auto);

/// Leaves a scene as it is.
pub fn unchanged(_: &mut Scene) {}

/// The complete dynamic state of a run with every float as its bits, so that two runs agree
/// only if they agree bit for bit (`-0.0` against `0.0` included).
pub fn state_bits(sim: &Simulation) -> Vec<u64> {
    let s = sim.export_state();
    let mut out = vec![
        s.time.to_bits(),
        s.steps,
        s.ledger.injected.to_bits(),
        s.ledger.dissipated.to_bits(),
        s.stored_energy.to_bits(),
    ];
    let vectors = [
        &s.pos,
        &s.vel,
        &s.omega,
        &s.vel_half,
        &s.omega_half,
        &s.force,
        &s.torque,
        &s.wall_histories,
    ];
    for v in vectors.into_iter().flatten().chain(s.pair_histories.iter().map(|(_, _, h)| h)) {
        out.extend(v.iter().map(|c| c.to_bits()));
    }
    out.extend(s.pair_histories.iter().flat_map(|&(i, j, _)| [i as u64, j as u64]));
    out
}

/// Mass (kg) of a grain of radius `r` (m) at the thesis' density, 2500 kg/m^3.
pub fn mass(r: f64) -> f64 {
    2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// Grains in free space under `law` for pairs and walls: no walls, no gravity, every pair
/// tested, velocity Verlet at step `dt`.
pub fn free_setup(law: ContactLaw, boundary: Boundary, dt: f64) -> Setup {
    Setup {
        pair_law: law,
        wall_law: law,
        walls: Vec::new(),
        gravity: Vec3::zeros(),
        dt,
        integrator: Integrator::VelocityVerlet,
        boundary,
        neighbors: NeighborSearch::AllPairs,
        vertical: Vertical::Free,
        container: None,
        sort: particles::scene::SortInterval::NONE,
        rolling_mu: Vec::new(),
        clump: None,
    }
}
