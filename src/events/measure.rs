//! One event-driven run held in memory and measured, with no files: what a sweep needs of
//! each of its runs. `stripes events` runs the same loop with its snapshots and checkpoints.

use events::observe::{ledger_error, rest_height_of, Observer};
use events::Simulation;
use serde::Serialize;

use events::scene::EventScene;

/// The measured numbers of one run. A number that is NaN is written as `null` in JSON and read
/// back as NaN (a sweep's `result.json`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Measured {
    pub collisions: u64,
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub cpu_s: f64,
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub collisions_per_s: f64,
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub energy_ledger_error: f64,
    /// Mean height of the centres above the floor's mean position (m).
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub mean_height_m: f64,
    /// Mean horizontal velocity (m/s).
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub current_x_m_per_s: f64,
    /// Translational over rotational kinetic energy, over every sample (every phase).
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub k_over_r: f64,
    /// The rough-sphere paper's H: the mass-weighted centre of mass at `run.phase` minus
    /// its estimate at rest (m).
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub reduced_height_m: f64,
    /// K/R over the samples at `run.phase` only.
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub k_over_r_phase0: f64,
    /// `T_2 / T_1` over the grains in the middle third of the box's height at each sample,
    /// grain by grain ([`Observer::bulk_temperature_ratio`]; NaN with one species).
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null")]
    pub temperature_ratio_bulk: f64,
    /// Grain positions sampled above the box's open top, summed over samples
    /// ([`escaped_note`]); 0 in a result written before they were counted.
    #[serde(default)]
    pub escaped_grain_samples: u64,
    /// Per species: whole-box `T_x`, `T_z`, `T_rot` (J).
    #[serde(deserialize_with = "crate::rundir::output::nan_if_null_triples")]
    pub temperatures: Vec<[f64; 3]>,
    pub samples: u64,
}

/// Runs `scene` for its `run.duration`, sampling `run.samples_per_period` times per period
/// after `run.transient`.
pub fn measure(scene: &EventScene) -> Result<Measured, String> {
    observe(scene).map(|(m, _)| m)
}

/// Sample times of an event-driven run: every `1 / (f samples_per_period)` s, and how many
/// fit in `run.duration`.
pub fn sample_times(scene: &EventScene) -> (f64, u64) {
    let dt_sample = 1.0 / (scene.drive.frequency * scene.run.samples_per_period as f64);
    (dt_sample, (scene.run.duration / dt_sample).floor() as u64)
}

/// The sample loop of every event-driven run (`stripes events`, and in memory for sweeps and
/// studies): from sample `first` to the run's last, the simulation runs to each sample time,
/// `obs` samples it from `run.transient` on, and `after` sees it (sample index, time, and
/// whether it was sampled), e.g. to write a frame or a checkpoint. A refused event is said
/// after `prefix` (e.g. the scene's path).
pub fn sample_loop<E: From<String>>(
    sim: &mut Simulation,
    obs: &mut Observer,
    scene: &EventScene,
    (first, prefix): (u64, &str),
    mut after: impl FnMut(&Simulation, &Observer, u64, (f64, bool)) -> Result<(), E>,
) -> Result<(), E> {
    let (dt_sample, samples) = sample_times(scene);
    for k in first..=samples {
        let t = k as f64 * dt_sample;
        sim.run_until(t).map_err(|e| E::from(format!("{prefix}{e}")))?;
        let sampled = t >= scene.run.transient;
        if sampled {
            obs.sample(sim);
        }
        after(sim, obs, k, (t, sampled))?;
    }
    Ok(())
}

/// The same, with the observer that sampled the run (its profiles).
pub fn observe(scene: &EventScene) -> Result<(Measured, Observer), String> {
    let config = crate::scene::events::config(scene).map_err(|e| e.to_string())?;
    let mut sim = Simulation::new(config).map_err(|e| e.to_string())?;
    let top = sim.config.height + sim.config.lid.map_or(0.0, |m| m.amplitude);
    // The measured numbers and the comparison's profiles need only the means and the
    // profiles against height.
    let mut obs = Observer::new(sim.config.species.len(), scene.run.bin, top, sim.config.width)
        .means_and_heights()
        .with_phases(scene.run.samples_per_period as usize, false);
    let e0 = sim.energy();
    let clock = crate::host::clock::Stopwatch::start(true);
    sample_loop(&mut sim, &mut obs, scene, (1, ""), |_, _, _, _| Ok::<(), String>(()))?;
    let cpu_s = clock.seconds();
    let collisions = sim.collisions();
    let paper = PaperObservables::of(&obs, &sim, scene);
    let measured = Measured {
        collisions,
        cpu_s,
        collisions_per_s: collisions as f64 / cpu_s.max(1e-9),
        energy_ledger_error: ledger_error(&sim, e0),
        mean_height_m: obs.mean_height(),
        current_x_m_per_s: obs.mean_vx(),
        k_over_r: obs.kinetic_ratio(),
        reduced_height_m: paper.reduced_height_m,
        k_over_r_phase0: paper.k_over_r_phase,
        temperature_ratio_bulk: obs.bulk_temperature_ratio(),
        escaped_grain_samples: obs.escaped,
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

/// The escaped grains of a run, said as a warning: grains whose centres were above the box's
/// open top (`box.height`, no lid) at a sample. The profiles count them in their top bin and
/// the means at their height, so a height or profile with them is not the box's. `None` when
/// none escaped. `top` is the box's top (m), `grains` the grains per sample.
pub fn escaped_note(obs: &Observer, top: f64, grains: usize) -> Option<String> {
    (obs.escaped > 0).then(|| {
        let sampled = obs.samples.saturating_mul(grains as u64).max(1);
        format!(
            "{} of {sampled} sampled grain positions ({:.3} %) were above the box's open top ({top} m: box.height, \
             drive.lid = \"none\"), in {} of {} samples: the escaped grains are counted in the top bin of the \
             profiles and at their height in mean_height_m and reduced_height_m; a lid or a taller box keeps them in",
            obs.escaped,
            100.0 * obs.escaped as f64 / sampled as f64,
            obs.escaped_samples,
            obs.samples
        )
    })
}

/// The rough-sphere paper's observables of a run: its `H`, the mass-weighted centre of mass
/// at one phase of the drive (`run.phase`, 0 by default: the floor at its mean position
/// moving up at its peak speed) minus the centre of mass at rest estimated from the number
/// of full layers and of grains per layer, and `K/R` at that phase beside its average over
/// every phase.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PaperObservables {
    /// The phase they are taken at (fraction of a period).
    pub phase: f64,
    pub reduced_height_m: f64,
    /// The mass-weighted centre-of-mass height at the phase, above the floor's mean
    /// position (m).
    pub centre_of_mass_height_m: f64,
    /// The rest estimate and its inputs.
    pub rest_height_m: f64,
    pub rest_diameter_m: f64,
    pub rest_grains_per_layer: usize,
    pub rest_full_layers: usize,
    pub rest_grains_in_top_layer: usize,
    pub k_over_r_phase: f64,
    /// K/R over every sample, all phases together.
    pub k_over_r: f64,
    /// Samples at the phase.
    pub phase_samples: u64,
}

impl PaperObservables {
    pub fn of(obs: &Observer, sim: &Simulation, scene: &EventScene) -> Self {
        let rest = rest_height_of(&sim.config);
        let k = phase_index(scene.run.phase, obs.phases.len());
        let at = obs.phase(k);
        let com = at.com_height();
        PaperObservables {
            phase: scene.run.phase,
            reduced_height_m: com - rest.height,
            centre_of_mass_height_m: com,
            rest_height_m: rest.height,
            rest_diameter_m: rest.diameter,
            rest_grains_per_layer: rest.per_layer,
            rest_full_layers: rest.full_layers,
            rest_grains_in_top_layer: rest.top,
            k_over_r_phase: at.kinetic_ratio(),
            k_over_r: obs.kinetic_ratio(),
            phase_samples: at.samples,
        }
    }
}

/// The phase bin of `phase` (a fraction of a period) among `count` per period.
pub fn phase_index(phase: f64, count: usize) -> usize {
    ((phase * count as f64).round() as usize) % count.max(1)
}

#[cfg(test)]
mod report_checks {
    //! One short case of each event-driven report, rerun and compared with the values it
    //! gave at the commit the report names (`docs/results/<report>/check.json`): the
    //! collision count exactly, every measure within a relative 1e-9 (the engine is bit for
    //! bit reproducible on one machine; the margin allows another libm). A change that moves
    //! a trajectory fails here: rerun the report, then write the new values with
    //! `STRIPES_WRITE_REPORT_CHECKS=1 cargo test --release -p stripes report_checks`.

    use super::*;

    const TOLERANCE: f64 = 1e-9;

    fn check(report: &str, scene_file: &str, overrides: &[&str]) {
        let root = env!("CARGO_MANIFEST_DIR");
        let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let scene = crate::scene::events::load(&std::path::Path::new(root).join(scene_file), &overrides).unwrap();
        let m = measure(&scene).unwrap();
        let measures = [
            ("mean_height_m", m.mean_height_m),
            ("reduced_height_m", m.reduced_height_m),
            ("k_over_r", m.k_over_r),
            ("k_over_r_phase0", m.k_over_r_phase0),
            ("current_x_m_per_s", m.current_x_m_per_s),
            ("temperature_ratio_bulk", m.temperature_ratio_bulk),
        ];
        let path = std::path::Path::new(root).join("docs/results").join(report).join("check.json");
        if std::env::var_os("STRIPES_WRITE_REPORT_CHECKS").is_some() {
            let mut values = serde_json::Map::new();
            for (k, v) in measures {
                values.insert(k.into(), if v.is_finite() { v.into() } else { serde_json::Value::Null });
            }
            let json = serde_json::json!({
                "what": "one short case of this report, rerun by `cargo test --release -p stripes report_checks`",
                "scene": scene_file,
                "overrides": overrides,
                "tolerance": "collisions exact, measures within a relative 1e-9",
                "collisions": m.collisions,
                "measures": values,
            });
            std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap() + "\n").unwrap();
            return;
        }
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let want: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(m.collisions, want["collisions"].as_u64().unwrap(), "{report}: collisions");
        for (k, v) in measures {
            match want["measures"][k].as_f64() {
                Some(w) => assert!(
                    (v - w).abs() <= TOLERANCE * w.abs().max(1e-300),
                    "{report}: {k} = {v}, the report's check {w}"
                ),
                None => assert!(!v.is_finite(), "{report}: {k} = {v}, the report's check null"),
            }
        }
    }

    #[test]
    fn report_checks_vibrated_box() {
        check(
            "vibrated-box",
            "scenes/vibrated-box.toml",
            &["run.duration=1.0", "run.transient=0.2"],
        );
    }

    #[test]
    fn report_checks_mixture() {
        check("mixture", "scenes/mixture.toml", &["run.duration=0.4", "run.transient=0.1"]);
    }

    #[test]
    fn report_checks_ratchet() {
        check("ratchet", "scenes/ratchet.toml", &["run.duration=0.5", "run.transient=0.1"]);
    }
}

#[cfg(test)]
mod bulk_tests {
    use super::*;

    /// Issue 43, finding 8: temperature_ratio_bulk moved from 0.65 to 0.62 and 0.77 with
    /// run.bin and was null at large bins. Summed grain by grain, it is the same number for
    /// bins of one diameter, of 10 mm (which covered [20, 30] mm of the third) and of 30 mm
    /// (which left no bin centre in it), on the mixture's short run.
    #[test]
    fn the_bulk_ratio_is_the_same_for_every_run_bin() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mixture.toml");
        let ratio = |bin: &str| {
            let set = ["run.duration=0.3".to_string(), "run.transient=0.1".into(), format!("run.bin={bin}")];
            let m = measure(&crate::scene::events::load(&path, &set).unwrap()).unwrap();
            (m.temperature_ratio_bulk, m.collisions)
        };
        let one = ratio("0.0016");
        assert!(one.0 > 0.2 && one.0 < 1.0, "{one:?}");
        for bin in ["0.01", "0.03"] {
            assert_eq!(ratio(bin), one, "run.bin = {bin}");
        }
    }
}
