//! Sample preparation (thesis 3.5.3): radii uniform in `[r_min, r_max]`, grains on a lattice
//! in one or more layers, random horizontal velocities uniform in `[-v, v]`, a relaxation of
//! `prepare.duration` seconds on the tray at rest, then all velocities and spins zeroed.
//!
//! A sample depends only on the box, the population, the material, the preparation
//! parameters and the seed, never on the toggles or the drive: the relaxation always uses the
//! reference physics (3D, side walls, all friction on), so every ablation and every point of
//! a sweep starts from the same samples. [`reference()`] is that dependency: the root crate's
//! sample cache names a sample by it and [`SAMPLE_REVISION`].

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::constants::GRAVITY;
use crate::scene::{Scene, Toggles};
use crate::sim::Simulation;
use crate::state::State;
use crate::time_step;
use crate::tray;
use crate::wall::Motion;
use crate::{SimError, Vec3};

/// The scene with everything that does not define a sample reset: reference toggles and a
/// tray at rest.
pub fn reference(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.toggles = Toggles::default();
    // A ceiling changes nothing for grains relaxing at rest on the floor.
    s.tray.height = None;
    s.drive.amplitude = 0.0;
    // The tray rests during preparation, so its frequency changes nothing either: every
    // frequency of a sweep shares one sample per seed.
    s.drive.frequency = 1.0;
    // Nor the schedule of its stages: the experiment's protocol starts from the sample of
    // its tray.
    s.drive.stages.clear();
    // Nor its direction: a vibrated box and a shaken tray of the same grains share samples.
    s.drive.direction = Default::default();
    s.run.duration = s.prepare.duration;
    s.run.threads = 0;
    s.run.checkpoint_interval = 0.0;
    s.run.snapshots_per_period = 1;
    // The preparation keeps the grains in their order, so that a sample does not depend on
    // the sort of the runs that start from it.
    s.run.sort_interval = crate::scene::SortInterval::NONE;
    s
}

/// Revision of the preparation's results, part of every sample's name in the root crate's
/// cache (`src/samples.rs`, with the scene's [`reference()`]). Bump it whenever a
/// change to the DEM changes the bits of a prepared sample, so that no cache hands out samples
/// of older code under the same name (a cache filled on 2026-11-22 did, before this existed).
/// `particles/tests/sample_revision.rs` pins one small prepared sample and fails, naming this
/// constant, until it is bumped.
pub const SAMPLE_REVISION: u64 = 8;

/// The grains on their lattice, before relaxation. A clump (`particles.shape = "clump"`)
/// takes a site of the lattice whose spacing is 2.1 times its reach (the circle about its
/// centre that holds it lying flat, [`crate::clump::ClumpShape::reach`]), so clumps of any
/// orientation never overlap; it lies flat with a random orientation in the plane (uniform,
/// drawn after the grain's velocity), its spheres one after another in the state, each
/// carrying `1/n` of the union's mass.
pub fn initial_state(scene: &Scene) -> Result<State, SimError> {
    let mut rng = ChaCha8Rng::seed_from_u64(scene.run.seed);
    let p = &scene.particles;
    let n = p.count;
    let clump = scene.clump_shape()?;
    let radii: Vec<f64> = (0..n).map(|_| rng.gen_range(p.radius_min..=p.radius_max)).collect();
    // A grain's reach in the plane (m): its radius, or its clump's circle.
    let reach = p.radius_max * clump.map_or(1.0, |c| c.reach());
    // Lattice of spacing 2.1 times the reach, fully inside the side walls; as many layers as
    // needed.
    let spacing = 2.1 * reach;
    let nx = ((scene.tray.length / spacing).floor() as usize).max(1);
    let ny = (((scene.tray.width - 2.0 * reach) / spacing).floor() as usize + 1).max(1);
    let per_layer = nx * ny;
    let layers = n.div_ceil(per_layer);
    // Fill the lower layers completely and a random subset of the top one.
    let full = (layers - 1) * per_layer;
    let mut top: Vec<usize> = (0..per_layer).collect();
    for k in (1..top.len()).rev() {
        top.swap(k, rng.gen_range(0..=k));
    }
    let mut sites: Vec<usize> = (0..full).collect();
    sites.extend(top.iter().take(n - full).map(|&k| full + k));
    sites.sort_unstable();
    let material = scene.material();
    let (_, wall_law) = reference(scene).laws()?;
    let dy = if ny > 1 {
        (scene.tray.width - 2.0 * reach * 1.05) / (ny - 1) as f64
    } else {
        0.0
    };
    let mut state = State::default();
    for (i, &site) in sites.iter().enumerate() {
        let (layer, cell) = (site / per_layer, site % per_layer);
        let (ix, iy) = (cell % nx, cell / nx);
        let r = radii[i];
        // Mass of the grain, and of each of its spheres.
        let (m, spheres) = match clump {
            None => (material.sphere_mass(r), 1),
            Some(c) => (material.density * c.mass_and_inertia().0 * r.powi(3), c.spheres),
        };
        let m_sphere = m / spheres as f64;
        let z = if layer == 0 {
            r - wall_law.normal.static_overlap(m_sphere * GRAVITY, r)
        } else {
            p.radius_max + layer as f64 * spacing
        };
        let y = if ny > 1 {
            1.05 * reach + iy as f64 * dy
        } else {
            0.5 * scene.tray.width
        };
        let x = (ix as f64 + 0.5) * scene.tray.length / nx as f64;
        let v = Vec3::new(
            rng.gen_range(-1.0..=1.0) * scene.prepare.speed,
            rng.gen_range(-1.0..=1.0) * scene.prepare.speed,
            0.0,
        );
        match clump {
            None => state.push(Vec3::new(x, y, z), v, Vec3::zeros(), r, m),
            Some(c) => {
                let angle: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
                let (sin, cos) = angle.sin_cos();
                for b in c.offsets() {
                    let arm = Vec3::new(cos * b.x - sin * b.y, sin * b.x + cos * b.y, 0.0) * r;
                    state.push(Vec3::new(x, y, z) + arm, v, Vec3::zeros(), r, m_sphere);
                }
            }
        }
    }
    Ok(state)
}

/// Prepares the sample of `scene`: lattice, random velocities, relaxation, zeroed velocities.
/// `progress` is called with the fraction done.
pub fn prepare(scene: &Scene, mut progress: impl FnMut(f64)) -> Result<State, SimError> {
    let reference = reference(scene);
    let setup = tray::setup(&reference, Motion::Fixed, time_step::for_scene(&reference)?)?;
    let steps = (reference.prepare.duration / setup.dt).round() as u64;
    let mut sim = Simulation::new(setup, initial_state(scene)?)?;
    for k in 0..steps {
        sim.step()?;
        if k % 1000 == 0 {
            progress(k as f64 / steps as f64);
        }
    }
    progress(1.0);
    let mut state = sim.into_state();
    for i in 0..state.len() {
        state.vel[i] = Vec3::zeros();
        state.omega[i] = Vec3::zeros();
        state.vel_half[i] = Vec3::zeros();
        state.omega_half[i] = Vec3::zeros();
        state.force[i] = Vec3::zeros();
        state.torque[i] = Vec3::zeros();
    }
    Ok(state)
}
