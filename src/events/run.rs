//! The event-driven run of a vibrated box: a new run, or one continued from its
//! checkpoint, written as a run directory (`stripes events` documents its files).
//! [`run_events`] returns the typed [`EventsSummary`]; the same summary is `summary.json`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use analysis::plot::{LinePlot, Mark};
use analysis::snapshot::{Header, SnapshotWriter};
use events::observe::{ledger_error, Observer};
use events::Simulation;
use serde::Serialize;
use serde_json::json;

use crate::events::checkpoint;
use crate::rundir::output::CliError as Error;
use crate::rundir::output::{progress_bar, RunDir, Written};
use crate::rundir::report::{Headline, Summary};
use events::scene::EventScene;

/// How to run an event-driven scene and where to write it.
#[derive(Clone, Debug, Default, Serialize)]
pub struct EventsOptions {
    /// The run directory.
    pub out: PathBuf,
    /// Replace the files of a directory that already holds some.
    pub force: bool,
    /// Continue the run in `out` from its `checkpoint.bin`.
    pub resume: bool,
    /// No progress output.
    pub quiet: bool,
}

/// The temperatures of one species (J).
#[derive(Clone, Debug, Serialize)]
pub struct Temperatures {
    pub t_x_j: f64,
    pub t_z_j: f64,
    pub t_rot_j: f64,
}

/// What an event-driven run did: `summary.json` of its directory, field for field.
#[derive(Clone, Debug, Serialize)]
pub struct EventsSummary {
    pub scene: String,
    pub particles: usize,
    pub simulated_s: f64,
    pub samples: u64,
    pub collisions: u64,
    pub pair_collisions: u64,
    pub wall_collisions: u64,
    pub cell_crossings: u64,
    pub collisions_per_s: f64,
    pub resumed: bool,
    pub cpu_s: f64,
    pub energy_ledger_error: f64,
    pub wall_work_j: f64,
    pub dissipated_j: f64,
    /// The unweighted mean height of the centres over every sample (m).
    pub mean_height_m: f64,
    /// The rough-sphere paper's H and K/R (`reduced_height_m`, `k_over_r_phase`, ...).
    #[serde(flatten)]
    pub paper: crate::events::measure::PaperObservables,
    pub current_x_m_per_s: f64,
    /// `T_2 / T_1` over the grains in the middle third of the box's height, grain by grain
    /// (no height bins: the same for every `run.bin`); NaN (null) with one species.
    pub temperature_ratio_bulk: f64,
    /// Grain positions sampled above the box's open top (no lid), summed over samples, their
    /// fraction of every sampled position, and the samples with at least one (a warning says
    /// so when there are any).
    pub escaped_grain_samples: u64,
    pub escaped_fraction: f64,
    pub escaped_samples: u64,
    pub temperatures: Vec<Temperatures>,
    /// The side-wall cluster's record (null in a periodic box).
    pub side_cluster: Option<crate::events::side::SideSummary>,
    /// In a mixture, each species' share of its own kind among its near neighbours against
    /// random labels (`null` for one species).
    pub segregation: Option<crate::events::segregation::SegregationSummary>,
    pub wall_s: f64,
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub written: Written,
}

impl Summary for EventsSummary {
    fn headline(&self) -> Headline {
        Headline {
            simulated_s: Some(self.simulated_s),
            wall_s: Some(self.wall_s),
            ..Headline::written(self.warnings.len(), &self.written)
        }
    }
}

/// Runs the event-driven scene read from `path` into `opts.out`, new or continued from its
/// checkpoint. Particles that do not fit, or a checkpoint of another scene, leave nothing
/// behind.
pub fn run_events(path: &Path, scene: &EventScene, opts: &EventsOptions) -> Result<EventsSummary, Error> {
    let config = crate::scene::events::config(scene)?;
    let out = opts.out.clone();
    let fingerprint = fingerprint(scene)?;
    // A directory without a checkpoint is named with what it holds (issue 43: "nothing was
    // written" was said of a run stopped before its first checkpoint, with 48 MB written).
    let fresh = crate::rundir::output::claim_run(&out, opts.resume, opts.force, &[])?;
    let resumed = if opts.resume {
        let path = out.join("checkpoint.bin");
        let bytes = std::fs::read(&path).map_err(|e| format!("--resume: cannot read {}: {e}", path.display()))?;
        let c = checkpoint::decode(&bytes).map_err(|e| format!("--resume: {}: {e}", path.display()))?;
        crate::events::resume::check(&out, scene, c.fingerprint == fingerprint)?;
        Some(c)
    } else {
        None
    };
    // Placed before anything is written: particles that do not fit leave nothing behind.
    let start = match resumed {
        Some(c) => {
            let sim = Simulation::import_state(config, c.state.clone())
                .map_err(|e| format!("--resume: {}: {e}", out.join("checkpoint.bin").display()))?;
            Start { sim, resumed: Some(c) }
        }
        None => Start {
            sim: Simulation::new(config)?,
            resumed: None,
        },
    };
    let lock = crate::rundir::lock::RunLock::acquire(&out)?;
    let result = simulate(path, opts, scene, start, fingerprint, &out);
    drop(lock);
    if result.is_err() && fresh {
        let _ = std::fs::remove_dir_all(&out);
    }
    result
}

/// The simulation to run, new or continued from a checkpoint.
struct Start {
    sim: Simulation,
    resumed: Option<checkpoint::Checkpoint>,
}

/// What a checkpoint must match to be resumed: the scene, except `run.duration`, and the
/// content of its restitution tables (none: the scene's alone, as before tables were hashed).
fn fingerprint(scene: &EventScene) -> Result<u64, Error> {
    let mut s = scene.clone();
    s.run.duration = 0.0;
    Ok(crate::rundir::bytes::fnv1a(toml::to_string(&s)?.as_bytes()) ^ crate::events::resume::tables_hash(scene)?)
}

/// Wall time before the first checkpoint of an invocation, and between the later ones: a
/// run stopped within its first seconds can already be resumed (issue 43: before, the first
/// came after 30 s, and a run stopped sooner had written snapshots but no checkpoint).
const FIRST_CHECKPOINT: Duration = Duration::from_secs(3);
const CHECKPOINT_EVERY: Duration = Duration::from_secs(30);

/// Whether a checkpoint is due `since` the last one (or the start), when this invocation has
/// already written `written` of them.
fn checkpoint_due(since: Duration, written: u64) -> bool {
    since >= if written == 0 { FIRST_CHECKPOINT } else { CHECKPOINT_EVERY }
}

fn simulate(
    path: &Path,
    opts: &EventsOptions,
    scene: &EventScene,
    start: Start,
    fingerprint: u64,
    out: &Path,
) -> Result<EventsSummary, Error> {
    let Start { mut sim, resumed } = start;
    let mut dir = RunDir::create(out, &json!({ "args": opts, "scene_file": path, "scene": scene }))?;
    analysis::io::write_atomic(&out.join("scene.toml"), toml::to_string(scene)?.as_bytes())?;
    let species = sim.config.species.len();
    let rmax = sim.config.radius_max();
    let header = Header {
        length: sim.config.width,
        width: 2.0 * rmax,
        radii: sim.radius.clone(),
    };
    let snapshots_path = out.join("snapshots.bin");
    let (dt_sample, samples) = crate::events::measure::sample_times(scene);
    let top = sim.config.height + sim.config.lid.map_or(0.0, |m| m.amplitude);
    let (mut obs, e0, first, mut frames, mut snapshots) = match resumed {
        Some(c) => {
            let snapshots = SnapshotWriter::open_append(&snapshots_path, header, c.frames)
                .map_err(|e| format!("--resume: {}: {e}", snapshots_path.display()))?;
            (c.observer, c.e0, c.sample + 1, c.frames, snapshots)
        }
        None => {
            let mut obs = Observer::new(species, scene.run.bin, top, sim.config.width)
                .with_phases(scene.run.samples_per_period as usize, scene.run.phase_resolved);
            if let Some(base) = &sim.config.base {
                obs = obs.with_phase_field(base, sim.config.width, sim.config.height);
            }
            let e0 = sim.energy();
            (obs, e0, 1, 0, SnapshotWriter::create(&snapshots_path, header)?)
        }
    };
    let mut warnings = Vec::new();
    let still = |m: Option<events::Motion>| m.is_none_or(|m| m.amplitude == 0.0);
    if still(sim.config.floor) && still(sim.config.lid) {
        let w = "nothing moves the grains (drive amplitude 0): inelastic grains settle on the floor, which \
                 an event-driven model approaches through ever more frequent collisions, so the run slows down \
                 as they settle";
        eprintln!("warning: {w}");
        warnings.push(w.to_string());
    }
    for w in crate::scene::events::warnings(scene) {
        eprintln!("warning: {w}");
        warnings.push(w);
    }
    let said = warnings.len();
    let collisions_before = sim.collisions();
    let bar = progress_bar(samples, opts.quiet, "events");
    bar.set_position(first - 1);
    let wall = Instant::now();
    let mut last_checkpoint = Instant::now();
    let mut checkpoints = 0u64;
    let checkpoint_path = out.join("checkpoint.bin");
    let checkpoint = |sim: &Simulation, obs: &Observer, sample: u64, frames: u64, snapshots: &mut SnapshotWriter| {
        // The frames the checkpoint counts are on disk before it is.
        snapshots.sync()?;
        let c = checkpoint::Checkpoint {
            fingerprint,
            sample,
            frames,
            e0,
            state: sim.export_state(),
            observer: obs.clone(),
        };
        analysis::io::write_atomic(&checkpoint_path, &checkpoint::encode(&c))
            .map_err(|e| Error::from(format!("cannot write {}: {e}", checkpoint_path.display())))
    };
    // On-CPU time of the loop (events, samples and frames): the speed on an idle core.
    let clock = crate::host::clock::Stopwatch::start(true);
    let prefix = format!("{}: ", path.display());
    crate::events::measure::sample_loop(&mut sim, &mut obs, scene, (first, &prefix), |sim, obs, k, (t, sampled)| {
        if sampled {
            let states: Vec<_> = (0..sim.len()).map(|i| sim.state(i)).collect();
            snapshots.push(
                t,
                states.iter().map(|(r, _)| [r.x, rmax, r.y]),
                states.iter().map(|(_, v)| [v.x, 0.0, v.y]),
            )?;
            frames += 1;
        }
        if checkpoint_due(last_checkpoint.elapsed(), checkpoints) {
            checkpoint(sim, obs, k, frames, &mut snapshots)?;
            last_checkpoint = Instant::now();
            checkpoints += 1;
        }
        bar.set_message(format!("t = {t:.3} s of {} s, {} collisions", scene.run.duration, sim.collisions()));
        bar.set_position(k);
        Ok::<(), Error>(())
    })?;
    let stepping = clock.seconds();
    bar.finish_and_clear();
    // The end is a checkpoint too: `--resume` with a longer run.duration extends the run.
    checkpoint(&sim, &obs, samples.max(first - 1), frames, &mut snapshots)?;
    dir.note_files([checkpoint_path.clone()]);
    let wall_s = wall.elapsed().as_secs_f64();
    let ledger = ledger_error(&sim, e0);
    if ledger > 1e-9 {
        warnings.push(format!(
            "the energy ledger misses by {ledger:e} of the energy moved (expected round-off, below 1e-9)"
        ));
    }
    warnings.extend(crate::events::measure::escaped_note(
        &obs,
        events::observe::box_top(&sim.config),
        sim.len(),
    ));
    if sim.ledger.dissipated < 0.0 {
        warnings.push(format!(
            "the collisions added {:e} J instead of dissipating it (dissipated_j < 0): a collapse guard \
             (guard.min_rebound_speed = {} m/s) sent grains apart faster than they met",
            -sim.ledger.dissipated,
            scene.guard.min_rebound_speed.map_or("none".to_string(), |v| v.to_string())
        ));
    }
    if obs.samples == 0 {
        warnings.push("no samples after run.transient: the profiles are empty".into());
    }
    // Profiles: per species, density and temperatures against height and across the box.
    let up: Vec<Vec<[f64; 5]>> = (0..species).map(|k| obs.profile(k)).collect();
    profile_files(&mut dir, &up, &HEIGHT, obs.bin, obs.samples)?;
    if species == 2 {
        temperature_ratio_plot(&mut dir, &up, obs.bin, obs.samples, sim.config.height)?;
    }
    let width = sim.config.width;
    let across: Vec<Vec<[f64; 5]>> = (0..species).map(|k| obs.profile_across(k, width)).collect();
    profile_files(&mut dir, &across, &ACROSS, width / obs.across_bins as f64, obs.samples)?;
    crate::events::distributions::write(&mut dir, &obs, &sim)?;
    phase_files(&mut dir, &obs, &sim, width)?;
    let side_cluster = crate::events::side::write(&mut dir, &obs, dt_sample, sim.len())?;
    if let (Some(field), Some(base)) = (&obs.field, &sim.config.base) {
        crate::events::fields::write(&mut dir, field, base)?;
    }
    dir.note_files([out.join("scene.toml"), out.join("snapshots.bin")]);
    let temperatures = (0..species)
        .map(|k| {
            let (t_x_j, t_z_j, t_rot_j) = obs.temperatures(k);
            Temperatures { t_x_j, t_z_j, t_rot_j }
        })
        .collect();
    for w in &warnings[said..] {
        eprintln!("warning: {w}");
    }
    let collisions = sim.collisions();
    let summary = EventsSummary {
        scene: path.display().to_string(),
        particles: sim.len(),
        simulated_s: scene.run.duration,
        samples: obs.samples,
        collisions,
        pair_collisions: sim.counts.pair,
        wall_collisions: sim.counts.wall,
        cell_crossings: sim.counts.cell,
        collisions_per_s: (collisions - collisions_before) as f64 / stepping.max(1e-9),
        resumed: first > 1,
        cpu_s: stepping,
        energy_ledger_error: ledger,
        wall_work_j: sim.ledger.wall_work,
        dissipated_j: sim.ledger.dissipated,
        mean_height_m: obs.mean_height(),
        paper: crate::events::measure::PaperObservables::of(&obs, &sim, scene),
        current_x_m_per_s: obs.mean_vx(),
        temperature_ratio_bulk: obs.bulk_temperature_ratio(),
        escaped_grain_samples: obs.escaped,
        escaped_fraction: obs.escaped as f64 / obs.samples.saturating_mul(sim.len() as u64).max(1) as f64,
        escaped_samples: obs.escaped_samples,
        temperatures,
        side_cluster,
        segregation: crate::events::segregation::summary(&obs),
        wall_s,
        warnings,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// `phases.csv`: per phase of the drive (a fraction of a period, phase 0 the floor at its
/// mean position moving up), the samples, the mass-weighted centre of mass, the reduced
/// height (minus the rest estimate) and K/R; with `run.phase_resolved`, every profile per
/// phase too (`profiles_phase.csv`, `profiles_across_phase.csv`: a `phase` column, then the
/// columns of `profiles.csv` and `profiles_across.csv`).
fn phase_files(dir: &mut RunDir, obs: &Observer, sim: &Simulation, width: f64) -> Result<(), Error> {
    let n = obs.phases.len();
    let rest = events::observe::rest_height_of(&sim.config).height;
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let p = obs.phase(k);
            vec![
                k as f64 / n as f64,
                p.samples as f64,
                p.com_height(),
                p.com_height() - rest,
                p.kinetic_ratio(),
            ]
        })
        .collect();
    dir.csv(
        "phases.csv",
        &["phase", "samples", "centre_of_mass_m", "reduced_height_m", "k_over_r"],
        &rows,
    )?;
    if obs.phase_heights.is_empty() {
        return Ok(());
    }
    let species = sim.config.species.len();
    for (name, column, across) in [("profiles_phase.csv", "z_m", false), ("profiles_across_phase.csv", "x_m", true)] {
        let mut header = vec!["phase".to_string(), column.to_string()];
        for s in 1..=species {
            for c in ["n_per_m", "tx_j", "tz_j", "trot_j"] {
                header.push(format!("{c}_{s}"));
            }
        }
        let mut rows = Vec::new();
        for k in 0..n {
            let profiles: Vec<Vec<[f64; 5]>> = (0..species)
                .map(|s| {
                    if across {
                        obs.phase_profile_across(k, s, width)
                    } else {
                        obs.phase_profile(k, s)
                    }
                    .unwrap_or_default()
                })
                .collect();
            for b in 0..profiles[0].len() {
                let mut row = vec![k as f64 / n as f64, profiles[0][b][0]];
                for p in &profiles {
                    row.extend_from_slice(&p[b][1..]);
                }
                rows.push(row);
            }
        }
        let refs: Vec<&str> = header.iter().map(String::as_str).collect();
        dir.csv(name, &refs, &rows)?;
    }
    Ok(())
}

/// The files of one axis' profiles.
struct Axis {
    column: &'static str,
    csv: &'static str,
    density: &'static str,
    temperature: &'static str,
    along: &'static str,
    label: &'static str,
}

const HEIGHT: Axis = Axis {
    column: "z_m",
    csv: "profiles.csv",
    density: "density_profile",
    temperature: "temperature_profile",
    along: "against height",
    label: "z (m)",
};

const ACROSS: Axis = Axis {
    column: "x_m",
    csv: "profiles_across.csv",
    density: "density_across",
    temperature: "temperature_across",
    along: "across the box",
    label: "x (m)",
};

/// Writes per-species profiles (rows `(position, n, T_x, T_z, T_rot)` on bins of `bin`
/// metres) as a table and two plots; temperatures are drawn only where a bin saw at least 50
/// grains over the run (else noise).
fn profile_files(dir: &mut RunDir, profiles: &[Vec<[f64; 5]>], axis: &Axis, bin: f64, samples: u64) -> Result<(), Error> {
    let mut header = vec![axis.column.to_string()];
    for k in 1..=profiles.len() {
        for c in ["n_per_m", "tx_j", "tz_j", "trot_j"] {
            header.push(format!("{c}_{k}"));
        }
    }
    let rows: Vec<Vec<f64>> = (0..profiles[0].len())
        .map(|b| {
            let mut row = vec![profiles[0][b][0]];
            for p in profiles {
                row.extend_from_slice(&p[b][1..]);
            }
            row
        })
        .collect();
    let header_refs: Vec<&str> = header.iter().map(String::as_str).collect();
    dir.csv(axis.csv, &header_refs, &rows)?;
    let mut density = LinePlot::new(&format!("Number density {}", axis.along), axis.label, "n (1/m per sample)");
    let mut temperature = LinePlot::new(&format!("Granular temperature {}", axis.along), axis.label, "T (J)");
    let enough = |r: &[f64; 5]| r[1] * samples as f64 * bin >= 50.0;
    let mut t_max: f64 = 0.0;
    for (k, p) in profiles.iter().enumerate() {
        density = density.series(
            &format!("species {}", k + 1),
            p.iter().map(|r| (r[0], r[1])).collect(),
            Mark::LinePoints,
        );
        let kept: Vec<&[f64; 5]> = p.iter().filter(|r| enough(r)).collect();
        t_max = kept.iter().map(|r| r[2].max(r[3])).fold(t_max, f64::max);
        temperature = temperature
            .series(
                &format!("T_x, species {}", k + 1),
                kept.iter().map(|r| (r[0], r[2])).collect(),
                Mark::Line,
            )
            .series(
                &format!("T_z, species {}", k + 1),
                kept.iter().map(|r| (r[0], r[3])).collect(),
                Mark::Dashed,
            );
    }
    // On a log axis: near a vibrated wall the temperature is tens of times the bulk's, and
    // a tall box's rise above its minimum (the mixture paper's Fig. 11) would vanish on a
    // linear one. Room above the data for the legend.
    let temperature = temperature.log_y().include_y(5.0 * t_max);
    dir.plot(axis.density, &density)?;
    dir.plot(axis.temperature, &temperature)
}

/// The mixture paper's Fig. 2: the ratio `T_2 / T_1` of the translational temperatures
/// (`(T_x + T_z) / 2`) against height, where both species saw at least 50 grains in a bin,
/// beside its value over the middle third (the bulk).
fn temperature_ratio_plot(dir: &mut RunDir, profiles: &[Vec<[f64; 5]>], bin: f64, samples: u64, height: f64) -> Result<(), Error> {
    let enough = |r: &[f64; 5]| r[1] * samples as f64 * bin >= 50.0;
    let ratio: Vec<(f64, f64)> = profiles[0]
        .iter()
        .zip(&profiles[1])
        .filter(|(a, b)| enough(a) && enough(b))
        .map(|(a, b)| (a[0], (b[2] + b[3]) / (a[2] + a[3])))
        .collect();
    let mut plot = LinePlot::new("Temperature ratio T2/T1 against height", "z (m)", "T2/T1")
        .series("T2/T1", ratio, Mark::LinePoints)
        .include_y(0.0)
        .include_y(1.0);
    for z in [height / 3.0, 2.0 * height / 3.0] {
        plot = plot.series(
            if z < height / 2.0 {
                "bulk (middle third): from"
            } else {
                "bulk: to"
            },
            vec![(z, 0.0), (z, 1.0)],
            Mark::Dashed,
        );
    }
    dir.plot("temperature_ratio", &plot)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 43: a run stopped before its first checkpoint (then after 30 s of wall time)
    /// left snapshots but nothing to resume from. The first comes after 3 s, the later ones
    /// every 30 s.
    #[test]
    fn the_first_checkpoint_comes_within_seconds() {
        let s = Duration::from_secs_f64;
        assert!(!checkpoint_due(s(2.9), 0));
        assert!(checkpoint_due(s(3.0), 0));
        assert!(!checkpoint_due(s(3.0), 1) && !checkpoint_due(s(29.9), 4));
        assert!(checkpoint_due(s(30.0), 1));
    }
}
