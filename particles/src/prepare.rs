//! Sample preparation (thesis 3.5.3): radii uniform in `[r_min, r_max]`, grains on a lattice
//! in one or more layers, random horizontal velocities uniform in `[-v, v]`, a relaxation of
//! `prepare.duration` seconds on the tray at rest, then all velocities and spins zeroed.
//!
//! A sample depends only on the box, the population, the material, the preparation
//! parameters and the seed, never on the toggles or the drive: the relaxation always uses the
//! reference physics (3D, side walls, all friction on), so every ablation and every point of
//! a sweep starts from the same samples. [`sample_key`] names that dependency.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::scene::{Scene, Toggles};
use crate::sim::Simulation;
use crate::state::State;
use crate::tray::{self, GRAVITY};
use crate::wall::Motion;
use crate::{SimError, Vec3};

/// The scene with everything that does not define a sample reset: reference toggles and a
/// tray at rest.
pub fn reference(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.toggles = Toggles::default();
    // A ceiling changes nothing for grains relaxing at rest on the floor.
    s.tray.height = None;
    s.automaton = Default::default();
    s.drive.amplitude = 0.0;
    s.run.duration = s.prepare.duration;
    s.run.threads = 0;
    s.run.checkpoint_interval = 0.0;
    s.run.snapshots_per_period = 1;
    s
}

/// Revision of the preparation's results, part of every [`sample_key`]. Bump it whenever a
/// change to the DEM changes the bits of a prepared sample, so that no cache hands out samples
/// of older code under the same name (a cache filled on 2026-11-22 did, before this existed).
/// `particles/tests/sample_revision.rs` pins one small prepared sample and fails, naming this
/// constant, until it is bumped.
pub const SAMPLE_REVISION: u64 = 3;

/// A stable 64-bit name of the sample a scene starts from: FNV-1a of [`SAMPLE_REVISION`] and
/// the canonical TOML of [`reference`], which holds the seed.
pub fn sample_key(scene: &Scene) -> u64 {
    let text = toml::to_string(&reference(scene)).expect("a scene serialises");
    crate::observe::fnv1a(format!("sample revision {SAMPLE_REVISION}\n{text}").as_bytes())
}

/// The grains on their lattice, before relaxation.
pub fn initial_state(scene: &Scene) -> State {
    let mut rng = ChaCha8Rng::seed_from_u64(scene.run.seed);
    let p = &scene.particles;
    let n = p.count;
    let radii: Vec<f64> = (0..n).map(|_| rng.gen_range(p.radius_min..=p.radius_max)).collect();
    // Lattice of spacing 2.1 r_max, fully inside the side walls; as many layers as needed.
    let spacing = 2.1 * p.radius_max;
    let nx = ((scene.tray.length / spacing).floor() as usize).max(1);
    let ny = (((scene.tray.width - 2.0 * p.radius_max) / spacing).floor() as usize + 1).max(1);
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
    let (_, wall_law) = reference(scene).laws();
    let dy = if ny > 1 {
        (scene.tray.width - 2.0 * p.radius_max * 1.05) / (ny - 1) as f64
    } else {
        0.0
    };
    let mut state = State::default();
    for (i, &site) in sites.iter().enumerate() {
        let (layer, cell) = (site / per_layer, site % per_layer);
        let (ix, iy) = (cell % nx, cell / nx);
        let r = radii[i];
        let m = material.sphere_mass(r);
        let z = if layer == 0 {
            r - wall_law.normal.static_overlap(m * GRAVITY, r)
        } else {
            p.radius_max + layer as f64 * spacing
        };
        let y = if ny > 1 {
            1.05 * p.radius_max + iy as f64 * dy
        } else {
            0.5 * scene.tray.width
        };
        let x = (ix as f64 + 0.5) * scene.tray.length / nx as f64;
        let v = Vec3::new(
            rng.gen_range(-1.0..=1.0) * scene.prepare.speed,
            rng.gen_range(-1.0..=1.0) * scene.prepare.speed,
            0.0,
        );
        state.push(Vec3::new(x, y, z), v, Vec3::zeros(), r, m);
    }
    state
}

/// Prepares the sample of `scene`: lattice, random velocities, relaxation, zeroed velocities.
/// `progress` is called with the fraction done.
pub fn prepare(scene: &Scene, mut progress: impl FnMut(f64)) -> Result<State, SimError> {
    let reference = reference(scene);
    let setup = tray::setup(&reference, Motion::Fixed)?;
    let steps = (reference.prepare.duration / setup.dt).round() as u64;
    let mut sim = Simulation::new(setup, initial_state(scene))?;
    for k in 0..steps {
        sim.step()?;
        if k % 1000 == 0 {
            progress(k as f64 / steps as f64);
        }
    }
    progress(1.0);
    let mut state = sim.state;
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

/// Loads the sample of `scene` from `dir` (file `sample-<key>.bin`, see [`sample_key`]) or
/// prepares and stores it. Returns the state and whether it came from the cache.
pub fn load_or_prepare(scene: &Scene, dir: &std::path::Path, progress: impl FnMut(f64)) -> Result<(State, bool), String> {
    let key = sample_key(scene);
    let path = dir.join(format!("sample-{key:016x}.bin"));
    // Jobs of a sweep running in parallel threads often need the same sample: one prepares
    // it while the others wait for it, then load it from the cache.
    static BUSY: std::sync::Mutex<Vec<(u64, std::sync::Arc<std::sync::Mutex<()>>)>> = std::sync::Mutex::new(Vec::new());
    let lock = {
        let mut busy = BUSY.lock().unwrap_or_else(|e| e.into_inner());
        match busy.iter().find(|(k, _)| *k == key) {
            Some((_, l)) => l.clone(),
            None => {
                let l = std::sync::Arc::new(std::sync::Mutex::new(()));
                busy.push((key, l.clone()));
                l
            }
        }
    };
    let _guard = lock.lock().unwrap_or_else(|e| e.into_inner());
    if let Ok(bytes) = std::fs::read(&path) {
        let state = decode_sample(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        return Ok((state, true));
    }
    let state = prepare(scene, progress).map_err(|e| format!("sample preparation: {e}"))?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let bytes = encode_sample(&state);
    analysis::io::write_atomic(&path, &bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    // Return what a later run will load, bit for bit (the stored mass gives back the inverse
    // mass only to within an ulp), so a fresh and a cached sample run identically.
    Ok((decode_sample(&bytes).expect("a sample just encoded decodes"), false))
}

const SAMPLE_MAGIC: &[u8; 8] = b"STRPSMP1";

/// Binary sample: magic, `u64` N, then per grain position (3 `f64`), radius, mass.
fn encode_sample(s: &State) -> Vec<u8> {
    let mut w = crate::checkpoint::Writer::default();
    w.0.extend_from_slice(SAMPLE_MAGIC);
    w.u64(s.len() as u64);
    for i in 0..s.len() {
        w.vec3(&s.pos[i]);
        w.f64(s.radius[i]);
        w.f64(s.mass(i));
    }
    w.0
}

fn decode_sample(bytes: &[u8]) -> Result<State, String> {
    if bytes.len() < 16 || &bytes[..8] != SAMPLE_MAGIC {
        return Err("not a stripes sample file".into());
    }
    let mut r = crate::checkpoint::Reader::new(&bytes[8..]);
    let n = r.u64()? as usize;
    let mut s = State::default();
    for _ in 0..n {
        let (pos, radius, mass) = (r.vec3()?, r.f64()?, r.f64()?);
        s.push(pos, Vec3::zeros(), Vec3::zeros(), radius, mass);
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresh_sample_equals_cached_sample_bit_for_bit() {
        // Regression: the in-memory sample of the run that prepared it differed from the
        // cached file by an ulp in the inverse mass, so that first run did not reproduce.
        let text = r#"
            [box]
            length = 0.01
            width = 0.005
            [drive]
            frequency = 20.0
            amplitude = 0.025
            [particles]
            count = 20
            radius_min = 0.25e-3
            radius_max = 0.5e-3
            [prepare]
            duration = 0.01
            [run]
            duration = 0.1
            dt = 8e-6
            seed = 3
        "#;
        let scene = Scene::parse(text, &[], "test").unwrap();
        let dir = std::env::temp_dir().join(format!("stripes-sample-{}", std::process::id()));
        let (fresh, cached) = load_or_prepare(&scene, &dir, |_| ()).unwrap();
        assert!(!cached);
        let (again, cached) = load_or_prepare(&scene, &dir, |_| ()).unwrap();
        assert!(cached);
        assert_eq!(fresh, again);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
