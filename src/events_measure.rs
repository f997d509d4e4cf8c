//! One event-driven run held in memory and measured, with no files: what a sweep needs of
//! each of its runs. `stripes events` runs the same loop with its snapshots and checkpoints.

use events::observe::{ledger_error, Observer};
use events::Simulation;

use crate::events_scene::EventScene;

/// The measured numbers of one run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Measured {
    pub collisions: u64,
    pub cpu_s: f64,
    pub collisions_per_s: f64,
    pub energy_ledger_error: f64,
    /// Mean height of the centres above the floor's mean position (m).
    pub mean_height_m: f64,
    /// Mean horizontal velocity (m/s).
    pub current_x_m_per_s: f64,
    /// Translational over rotational kinetic energy.
    pub k_over_r: f64,
    /// `T_2 / T_1` over the middle third of the box's height (NaN with one species).
    pub temperature_ratio_bulk: f64,
    /// Per species: whole-box `T_x`, `T_z`, `T_rot` (J).
    pub temperatures: Vec<[f64; 3]>,
    pub samples: u64,
}

/// Runs `scene` for its `run.duration`, sampling `run.samples_per_period` times per period
/// after `run.transient`.
pub fn measure(scene: &EventScene) -> Result<Measured, String> {
    observe(scene).map(|(m, _)| m)
}

/// The same, with the observer that sampled the run (its profiles).
pub fn observe(scene: &EventScene) -> Result<(Measured, Observer), String> {
    let config = scene.config().map_err(|e| e.to_string())?;
    let mut sim = Simulation::new(config).map_err(|e| e.to_string())?;
    let top = sim.config.height + sim.config.lid.map_or(0.0, |m| m.amplitude);
    // The measured numbers and the comparison's profiles need only the means and the
    // profiles against height.
    let mut obs = Observer::new(sim.config.species.len(), scene.run.bin, top, sim.config.width).means_and_heights();
    let e0 = sim.energy();
    let dt_sample = 1.0 / (scene.drive.frequency * scene.run.samples_per_period as f64);
    let samples = (scene.run.duration / dt_sample).floor() as u64;
    let clock = crate::clock::Stopwatch::start(true);
    for k in 1..=samples {
        let t = k as f64 * dt_sample;
        sim.run_until(t).map_err(|e| e.to_string())?;
        if t >= scene.run.transient {
            obs.sample(&sim);
        }
    }
    let cpu_s = clock.seconds();
    let collisions = sim.collisions();
    let measured = Measured {
        collisions,
        cpu_s,
        collisions_per_s: collisions as f64 / cpu_s.max(1e-9),
        energy_ledger_error: ledger_error(&sim, e0),
        mean_height_m: obs.mean_height(),
        current_x_m_per_s: obs.mean_vx(),
        k_over_r: obs.kinetic_ratio(),
        temperature_ratio_bulk: bulk_ratio(&obs, sim.config.height),
        temperatures: (0..sim.config.species.len())
            .map(|k| {
                let (x, z, r) = obs.temperatures(k);
                [x, z, r]
            })
            .collect(),
        samples: obs.samples,
    };
    Ok((measured, obs))
}

/// `T_2 / T_1` over the middle third of a box of `height` (between the floor's and the lid's
/// mean positions): the mixture paper's "bulk", away from the walls that heat each species.
pub fn bulk_ratio(obs: &Observer, height: f64) -> f64 {
    obs.temperature_ratio(height / 3.0, 2.0 * height / 3.0)
}
