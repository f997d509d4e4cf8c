//! The DEM run of a resolved scene: prepares (or loads) its sample, steps it with the
//! run's observers, and writes the run directory (`stripes run` documents its files).
//! [`run_dem`] returns the typed [`DemSummary`]; the same summary is `summary.json`.

use std::path::PathBuf;
use std::time::Instant;

use analysis::snapshot::Header;
use particles::advance::{advance, ObserverError};
use particles::measure;
use particles::sim::Simulation;
use particles::timescale;
use serde::Serialize;
use serde_json::json;

use super::resolve::Resolved;
use crate::dem::observers::{ContactMeans, Progress, Recorder, RecorderPlan};
use crate::dem::thermo::Thermo;
use crate::dem::vtk::VtkSeries;
use crate::rundir::output::CliError as Error;
use crate::rundir::output::{progress_bar, RunDir, Written};
use crate::rundir::report::{Headline, Summary};

/// How to run a resolved scene and where to write it (the scene itself is in [`Resolved`]).
#[derive(Clone, Debug, Default, Serialize)]
pub struct RunOptions {
    /// The run directory.
    pub out: PathBuf,
    /// Continue from the directory's `checkpoint.bin`.
    pub resume: bool,
    /// Replace the run already in the directory.
    pub force: bool,
    /// Also write every snapshot for ParaView (`vtk/series.pvd`).
    pub vtk: bool,
    /// Simulated seconds between rows of `thermo.csv` (default: a tenth of the drive period).
    pub thermo_interval: Option<f64>,
    /// Cache of prepared samples.
    pub sample_cache: PathBuf,
    /// Also write the starting state as a LAMMPS data file.
    pub lammps_data: Option<PathBuf>,
    /// Die after this many steps as `kill -9` would (a test hook for `--resume`).
    pub stop_after: Option<u64>,
    /// Wall seconds by which the first checkpoint is written whatever
    /// `run.checkpoint_interval` says (default [`crate::dem::observers::FIRST_CHECKPOINT_WALL`]).
    pub first_checkpoint_after: Option<f64>,
    /// No progress output.
    pub quiet: bool,
}

/// The energies at the end of a run (J) and the ledger's balance.
#[derive(Clone, Debug, Serialize)]
pub struct Energy {
    pub kinetic: f64,
    pub rotational: f64,
    pub potential: f64,
    pub stored: f64,
    pub injected: f64,
    pub dissipated: f64,
    pub balance: Option<f64>,
    pub balance_relative: Option<f64>,
}

/// Mean contacts per grain over the run.
#[derive(Clone, Debug, Serialize)]
pub struct Contacts {
    pub pair_mean: f64,
    pub wall_mean: f64,
}

/// One stage of the drive as the summary lists it.
#[derive(Clone, Debug, Serialize)]
pub struct StageStart {
    /// s.
    pub start_s: f64,
    /// Hz.
    pub frequency: f64,
    /// m.
    pub amplitude: f64,
}

/// What a DEM run did: `summary.json` of its directory, field for field.
#[derive(Clone, Debug, Serialize)]
pub struct DemSummary {
    pub scene: String,
    pub particles: usize,
    pub steps: u64,
    pub dt: f64,
    pub simulated_s: f64,
    pub wall_s: f64,
    pub stepping_s: f64,
    pub particle_steps_per_s: f64,
    pub threads: usize,
    pub threads_chosen_by: String,
    /// The team size the steps ran on at the end: `threads`, or fewer where fewer stepped
    /// faster on this machine's load (`particles::pace`).
    pub team_at_end: usize,
    pub steps_per_contact: f64,
    pub snapshots: u64,
    /// Whether the sample came from the cache (false for a resume, which needs no sample), and
    /// the wall seconds spent preparing or loading it (waiting for another process that
    /// prepares it included).
    pub sample_cached: bool,
    pub prepare_s: f64,
    pub sample_cache: String,
    pub thermo_interval_s: f64,
    pub sample_key: String,
    pub energy: Energy,
    pub contacts: Contacts,
    pub neighbor_builds: u64,
    /// The drive's stages in order, each with its start (s): one for a single drive.
    pub drive_stages: Vec<StageStart>,
    pub state_hash: String,
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub written: Written,
}

impl Summary for DemSummary {
    fn headline(&self) -> Headline {
        Headline {
            simulated_s: Some(self.simulated_s),
            wall_s: Some(self.wall_s),
            snapshots: Some(self.snapshots),
            ..Headline::written(self.warnings.len(), &self.written)
        }
    }
}

/// Files a run writes into its directory (removed by `--force` before a new run,
/// [`crate::rundir::output::claim_run`]).
const RUN_FILES: [&str; 10] = [
    "config.json",
    "scene.toml",
    "scene.json",
    "summary.json",
    "snapshots.bin",
    "checkpoint.bin",
    "thermo.csv",
    "thermo.png",
    "thermo.svg",
    "vtk",
];

/// Runs a resolved scene into `opts.out` on its own pool of threads (`run.threads`, or
/// chosen by [`crate::host::threads::choose`]). Everything that can be checked is checked before
/// anything is written, and a start that fails before the first step removes what it
/// created.
pub fn run_dem(resolved: &Resolved, opts: &RunOptions) -> Result<DemSummary, Error> {
    let scene = resolved.scene();
    let (threads, why) = crate::host::threads::choose(scene.run.threads, scene.particles.count);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    pool.install(|| run_in_pool(resolved, opts, why))
}

fn run_in_pool(resolved: &Resolved, opts: &RunOptions, threads_why: String) -> Result<DemSummary, Error> {
    let out = &opts.out;
    // The lock, held until this function returns (a second run into the same directory is
    // refused, even with --force), and only then the directory's contents.
    let existed = out.exists();
    let lock = crate::rundir::lock::RunLock::acquire(out)?;
    let fresh = match crate::rundir::output::claim_run(out, opts.resume, opts.force, &RUN_FILES) {
        Ok(_) => !existed,
        Err(e) => {
            drop(lock);
            if !existed {
                let _ = std::fs::remove_dir_all(out);
            }
            return Err(e);
        }
    };
    if opts.resume {
        // A resume continues only the run it finds (crate::rundir::resume).
        crate::rundir::resume::check(out, &resolved.file, &format!("--resume {}", out.display()))?;
    }
    for w in &resolved.warnings {
        eprintln!("warning: {w}");
    }
    let checkpoint = if opts.resume {
        let path = out.join("checkpoint.bin");
        Some(std::fs::read(&path).map_err(|e| format!("--resume: cannot read {}: {e}", path.display()))?)
    } else {
        None
    };
    let started = match start(resolved, opts, checkpoint) {
        Ok(s) => s,
        Err(e) => {
            if fresh {
                let _ = std::fs::remove_dir_all(out);
            }
            return Err(e);
        }
    };
    step(resolved, opts, started, threads_why)
}

/// A run ready for its time loop.
struct Started {
    dir: RunDir,
    sim: Simulation,
    recorder: Recorder,
    thermo: Thermo,
    /// Whether the sample came from the cache, and the wall seconds spent preparing or
    /// loading it (waiting for another process that prepares it included).
    cached: bool,
    prepare_s: f64,
}

/// Prepares (or loads) the sample, restores the checkpoint of `--resume`, and writes the
/// run's configuration, the first snapshot and the first thermo row.
fn start(resolved: &Resolved, opts: &RunOptions, checkpoint: Option<Vec<u8>>) -> Result<Started, Error> {
    let (file, out, args) = (&resolved.file, opts.out.as_path(), opts);
    let scene = &file.dem;
    let dt = resolved.dt();
    let total = (scene.run.duration / dt).round() as u64;
    let every = if scene.run.checkpoint_interval > 0.0 {
        ((scene.run.checkpoint_interval / dt).round() as u64).max(1)
    } else {
        u64::MAX
    };
    let interval = args.thermo_interval.unwrap_or(0.1 / scene.drive.frequency);
    let mut thermo = Thermo::new(interval, dt, out.join("thermo.csv"), every, total)?;

    // Sample: prepared once per (population, box, material, seed), shared by every run. A
    // resume takes its grains' radii and masses from the lattice instead: everything that
    // moves comes from the checkpoint, so nothing is prepared only to be overwritten.
    let bar = progress_bar(1000, args.quiet || checkpoint.is_some(), "prepare");
    let preparing = Instant::now();
    let (state, cached) = match checkpoint {
        Some(_) => (crate::dem::samples::for_resume(scene)?, false),
        None => crate::dem::samples::load_or_prepare(scene, &args.sample_cache, |f| bar.set_position((f * 1000.0) as u64))?,
    };
    bar.finish_and_clear();
    let prepare_s = preparing.elapsed().as_secs_f64();
    let mut sim = Simulation::new(resolved.setup.clone(), state)?;
    let fingerprint = resolved.fingerprint;
    let ckpt_path = out.join("checkpoint.bin");
    let mut frames = 0;
    if let Some(bytes) = &checkpoint {
        frames = crate::dem::checkpoint::restore(&mut sim, bytes, fingerprint).map_err(|e| {
            let why = crate::dem::checkpoint::fingerprint_of(bytes)
                .filter(|&found| found != fingerprint)
                .and_then(|found| crate::dem::resolve::refusal_reason(scene, found))
                .map(|r| format!(": {r}"))
                .unwrap_or_default();
            format!(
                "--resume: {}: {e}{why} (nothing was changed; --force starts the run again)",
                ckpt_path.display()
            )
        })?;
        thermo.resume(&out.join("thermo.csv"), sim.time)?;
    }
    let dir = RunDir::create(out, &json!({ "args": args, "scene_file": resolved.path, "scene": scene }))?;
    // The resolved scene with its `[automaton]` table, so that `stripes automaton --calibrate`
    // and `stripes compare --dem-run` on this directory see the automaton the scene asked for.
    analysis::io::write_atomic(&out.join("scene.toml"), file.to_toml()?.as_bytes())?;
    if let Some(path) = &args.lammps_data {
        let title = format!("stripes {} at t = {} s, {} grains", resolved.path.display(), sim.time, sim.len());
        let mut grains = analysis::lammps_data::Grains::default();
        let state = sim.state();
        let s = &*state;
        for i in 0..s.len() {
            let v = |x: &particles::Vec3| [x.x, x.y, x.z];
            grains.push(v(&s.pos[i]), v(&s.vel[i]), v(&s.omega[i]), s.radius[i]);
        }
        let text = analysis::lammps_data::data_file(&grains, scene.material.density, scene.tray.length, scene.tray.width, &title);
        analysis::io::write_atomic(path, text.as_bytes())?;
    }
    let vtk = if args.vtk {
        // Side walls drawn up to the ceiling, or ten of the largest grains without one.
        let height = scene.tray.height.unwrap_or(20.0 * scene.particles.radius_max);
        Some(VtkSeries::open(
            &out.join("vtk"),
            sim.time,
            scene.tray.length,
            scene.tray.width,
            height,
        )?)
    } else {
        None
    };

    // Snapshot k >= 1 at the turning point x_tray = +A of each period (sin = 1):
    // t_k = 1/(4 nu) + (k - 1) / (s nu), taken at the nearest step; with a schedule, at each
    // stage's own turning points (`particles::drive::Schedule::snapshot_time`).
    let (nu, per) = (scene.drive.frequency, scene.run.snapshots_per_period as f64);
    let schedule = scene.drive.schedule();
    let per_u32 = scene.run.snapshots_per_period;
    let mut recorder = Recorder::open(RecorderPlan {
        header: Header {
            length: scene.tray.length,
            width: scene.tray.width,
            radii: sim.state().radius.clone(),
        },
        snapshots: out.join("snapshots.bin"),
        frames,
        snap_time: match schedule {
            None => Box::new(move |k: u64| 0.25 / nu + (k - 1) as f64 / (per * nu)),
            Some(schedule) => Box::new(move |k: u64| schedule.snapshot_time(k, per_u32)),
        },
        vtk,
        checkpoint: ckpt_path,
        fingerprint,
        every,
        last: total,
        first_by: args
            .first_checkpoint_after
            .map_or(crate::dem::observers::FIRST_CHECKPOINT_WALL, |s| {
                std::time::Duration::from_secs_f64(s.clamp(0.0, 1e9))
            }),
    })?;
    thermo.follow(recorder.checkpoints.clone());
    if recorder.frames == 0 {
        recorder.snapshot(&sim)?;
    }
    if thermo.is_empty() {
        thermo.push(&sim, false);
    }
    Ok(Started {
        dir,
        sim,
        recorder,
        thermo,
        cached,
        prepare_s,
    })
}

/// The time loop of a started run, then its summary.
fn step(resolved: &Resolved, opts: &RunOptions, started: Started, threads_why: String) -> Result<DemSummary, Error> {
    let (scene, out, args) = (resolved.scene(), opts.out.as_path(), opts);
    let mut warnings = Vec::new();
    let Started {
        mut dir,
        mut sim,
        mut recorder,
        mut thermo,
        cached,
        prepare_s,
    } = started;
    let dt = sim.setup.dt;
    let total = (scene.run.duration / dt).round() as u64;
    let bar = progress_bar(total, args.quiet, "run");
    bar.set_position(sim.steps);
    let mut contacts = ContactMeans::default();
    let stop_after = args.stop_after;
    let mut killer = |sim: &Simulation| -> Result<(), ObserverError> {
        if stop_after.is_some_and(|n| sim.steps >= n) {
            // As `kill -9` would: no final checkpoint, and buffered snapshot bytes are lost
            // (`exit` runs no destructors), so a resume starts from the last due checkpoint.
            bar.abandon();
            eprintln!("killed after {} steps as asked (--stop-after); continue with --resume", sim.steps);
            std::process::exit(137);
        }
        Ok(())
    };
    let start_steps = sim.steps;
    let wall_clock = Instant::now();
    let mut progress = Progress {
        bar: &bar,
        duration: scene.run.duration,
    };
    let stepping = match advance(
        &mut sim,
        total,
        &mut [&mut contacts, &mut recorder, &mut thermo, &mut progress, &mut killer],
    ) {
        Ok(seconds) => seconds,
        Err(e) => {
            // Keep everything written so far: the snapshots up to now, the thermo table up
            // to the failing step, and the last checkpoint.
            recorder.writer.sync()?;
            thermo.push(&sim, false);
            thermo.write()?;
            bar.abandon();
            let kept = if recorder.checkpoint.exists() {
                format!("the last checkpoint is {}", recorder.checkpoint.display())
            } else {
                "no checkpoint was due yet".to_string()
            };
            return Err(format!(
                "{e}; the {} snapshots so far are in {}, the thermo table in {} and {kept}",
                recorder.frames,
                out.join("snapshots.bin").display(),
                thermo.path.display()
            )
            .into());
        }
    };
    recorder.writer.sync()?;
    bar.finish_and_clear();
    thermo.write()?;
    if let Some(w) = thermo.balance_warning(dt) {
        eprintln!("warning: {w}");
        warnings.push(w);
    }
    dir.note_files([thermo.path.clone(), out.join("snapshots.bin"), recorder.checkpoint.clone()]);
    dir.plot("thermo", &thermo.plot())?;
    if let Some(vtk) = &recorder.vtk {
        dir.note_files([vtk.pvd_path()]);
    }
    let frames = recorder.frames;
    let (pair_mean, wall_mean) = contacts.means();
    let state = sim.state();
    let s = &*state;
    let stepped = sim.steps - start_steps;
    let (balance, balance_relative) = thermo.balance().map_or((None, None), |b| (Some(b.0), Some(b.1)));
    let (kinetic, rotational, potential) = sim.energies();
    let energy = Energy {
        kinetic,
        rotational,
        potential,
        stored: sim.stored_energy,
        injected: sim.ledger.injected,
        dissipated: sim.ledger.dissipated,
        balance,
        balance_relative,
    };
    dir.json("scene.json", scene)?;
    if let Some(w) = particles::waits() {
        // `STRIPES_WAITS` set: where the threads waited (docs/performance.md, issue 41).
        eprintln!(
            "waits (all threads, s): team for its next job {:.3}, at barriers {:.3}, caller for the team {:.3}; {} waits ended asleep; {} blocks taken over; stepping {stepping:.3} s",
            w.for_job_s, w.at_barrier_s, w.for_team_s, w.sleeps, w.taken_over
        );
    }
    let summary = DemSummary {
        scene: resolved.path.display().to_string(),
        particles: s.len(),
        steps: sim.steps,
        dt,
        simulated_s: sim.time,
        wall_s: wall_clock.elapsed().as_secs_f64(),
        stepping_s: stepping,
        particle_steps_per_s: (stepped as f64 * s.len() as f64) / stepping.max(1e-12),
        threads: rayon::current_num_threads(),
        threads_chosen_by: threads_why,
        team_at_end: sim.team_size(),
        steps_per_contact: timescale::shortest_contact_time(scene)? / dt,
        snapshots: frames,
        sample_cached: cached,
        prepare_s,
        sample_cache: args.sample_cache.display().to_string(),
        thermo_interval_s: thermo.every as f64 * dt,
        sample_key: format!("{:016x}", resolved.sample_key),
        energy,
        contacts: Contacts { pair_mean, wall_mean },
        neighbor_builds: sim.neighbor_builds(),
        drive_stages: scene
            .drive
            .stage_starts()
            .into_iter()
            .map(|(start_s, frequency, amplitude)| StageStart {
                start_s,
                frequency,
                amplitude,
            })
            .collect(),
        state_hash: format!("{:016x}", measure::state_hash(s)),
        warnings,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}
