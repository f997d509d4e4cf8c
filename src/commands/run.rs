//! `stripes run SCENE.toml`: the tray-driven DEM.
//!
//! Writes into the run directory: `scene.toml` (the resolved scene, with its `[automaton]`
//! table), `config.json`,
//! `snapshots.bin` (see `analysis::snapshot`; a frame at t = 0 and then at the chosen phase of
//! every period), `thermo.csv` and `thermo.{png,svg}` (see `crate::thermo`), `checkpoint.bin`
//! (at `run.checkpoint_interval`), with `--vtk` a ParaView series `vtk/series.pvd` (see
//! `crate::vtk_series`), and `summary.json`. `--resume` continues from `checkpoint.bin`, bit
//! for bit.
//!
//! A directory that already holds a run is refused unless `--resume` (continue it) or
//! `--force` (replace it) is given. Everything that can be checked (the scene, the time step,
//! the checkpoint of `--resume`) is checked before anything is written, and a start that
//! fails before the first step removes what it created.

use std::path::{Path, PathBuf};
use std::time::Instant;

use analysis::snapshot::Header;
use particles::advance::{advance, ObserverError};
use particles::measure;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::time_step;
use particles::timescale;
use particles::tray;
use serde::Serialize;
use serde_json::json;

use crate::output::{non_empty, progress_bar, CliError, RunDir};
use crate::run_outputs::{ContactMeans, Progress, Recorder, RecorderPlan};
use crate::samples::sample_key;
use crate::thermo::Thermo;
use crate::vtk_series::VtkSeries;

#[derive(clap::Args, Debug, Default, Serialize)]
pub struct Args {
    /// Scene file (TOML), e.g. scenes/thesis-reference.toml.
    pub scene: PathBuf,
    /// Output directory (default: out/run-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene key, e.g. --set toggles.friction=false (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
    /// Continue from the run directory's checkpoint.
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Replace the run already in the output directory (refused without it).
    #[arg(long)]
    pub force: bool,
    /// Also write every snapshot for ParaView: vtk/series.pvd (open it) with one .vtp of the
    /// grains (id, radius, velocity, angular velocity) and one of the tray per snapshot.
    #[arg(long)]
    pub vtk: bool,
    /// Simulated seconds between rows of thermo.csv (default: a tenth of the drive period).
    #[arg(long, value_name = "SECONDS")]
    pub thermo_interval: Option<f64>,
    /// Cache of prepared samples, shared by every run (default: $STRIPES_SAMPLE_CACHE, else
    /// out/samples).
    #[arg(long, value_name = "DIR", default_value_os_t = crate::output::default_sample_cache())]
    pub sample_cache: PathBuf,
    /// Also write the state the run starts from (the prepared sample, or the checkpoint with
    /// --resume) as a LAMMPS data file (atom_style sphere, units si), to run the same grains
    /// in LAMMPS (bench/lammps/in.tray).
    #[arg(long, value_name = "FILE")]
    pub lammps_data: Option<PathBuf>,
    /// Die after this many steps as `kill -9` would (a test hook for checkpoints and --resume).
    #[arg(long, hide = true)]
    pub stop_after: Option<u64>,
    /// No progress output (warnings still go to stderr, the summary to stdout).
    #[arg(long)]
    pub quiet: bool,
}

/// Files a run writes into its directory (removed by `--force` before a new run).
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

/// Refuses an output directory that holds a run unless `--resume` or `--force`, and with
/// `--force` removes the old run's files. Returns whether the directory is new (then a
/// failed start removes it).
fn claim_out_dir(out: &Path, resume: bool, force: bool) -> Result<bool, CliError> {
    if resume {
        if !out.join("checkpoint.bin").is_file() {
            return Err(format!(
                "--resume: {} holds no checkpoint.bin to continue from (nothing was written)",
                out.display()
            )
            .into());
        }
        return Ok(false);
    }
    if !non_empty(out) {
        return Ok(!out.exists());
    }
    if !force {
        return Err(format!(
            "{} already holds files (a run?); use --resume to continue it, --force to replace it, or another --out",
            out.display()
        )
        .into());
    }
    for f in RUN_FILES {
        let p = out.join(f);
        let gone = if p.is_dir() {
            std::fs::remove_dir_all(&p)
        } else {
            std::fs::remove_file(&p)
        };
        if let Err(e) = gone {
            if e.kind() != std::io::ErrorKind::NotFound {
                return Err(format!("--force: cannot remove {}: {e}", p.display()).into());
            }
        }
    }
    Ok(false)
}

/// What a checkpoint must match to be resumed: the scene and its sample, except the keys that
/// do not change the trajectory (`run.threads`, `run.checkpoint_interval`) or only say where
/// it stops (`run.duration`, so a finished run can be extended with `--resume`).
pub(crate) fn checkpoint_fingerprint(scene: &Scene) -> Result<u64, CliError> {
    let mut s = scene.clone();
    s.run.threads = 0;
    s.run.checkpoint_interval = 0.0;
    s.run.duration = 1.0;
    Ok(measure::fnv1a(toml::to_string(&s)?.as_bytes()) ^ sample_key(scene))
}

pub fn run(args: Args) -> Result<String, CliError> {
    let file = crate::scene_file::load(&args.scene, &args.overrides)?;
    file.dem.validate()?;
    let (threads, why) = crate::threads::choose(file.dem.run.threads, file.dem.particles.count);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    pool.install(|| run_in_pool(args, file, why))
}

/// `file`: the scene, with the `[automaton]` table the run directory's `scene.toml` keeps.
fn run_in_pool(args: Args, file: crate::scene_file::SceneFile, threads_why: String) -> Result<String, CliError> {
    let scene = &file.dem;
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/run-{name}")));
    // Everything that can be checked is checked before anything is written and before the
    // (possibly long) preparation.
    let setup = tray::setup(scene, tray::drive(scene), time_step::for_scene(scene)?)?;
    let gap = 1.0 / (scene.run.snapshots_per_period as f64 * scene.drive.frequency);
    if gap < 2.0 * setup.dt {
        return Err(format!(
            "scene `run.snapshots_per_period` = {}: snapshots {gap:e} s apart are closer than two steps of {:e} s; at most {} per period",
            scene.run.snapshots_per_period,
            setup.dt,
            (1.0 / (2.0 * setup.dt * scene.drive.frequency)).floor()
        )
        .into());
    }
    let warnings = time_step::warnings(scene, setup.dt)?;
    // Then the lock, held until this function returns (a second run into the same directory
    // is refused, even with --force), and only then the directory's contents.
    let existed = out.exists();
    let lock = crate::run_lock::RunLock::acquire(&out)?;
    let fresh = match claim_out_dir(&out, args.resume, args.force) {
        Ok(_) => !existed,
        Err(e) => {
            drop(lock);
            if !existed {
                let _ = std::fs::remove_dir_all(&out);
            }
            return Err(e);
        }
    };
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let checkpoint = if args.resume {
        let path = out.join("checkpoint.bin");
        Some(std::fs::read(&path).map_err(|e| format!("--resume: cannot read {}: {e}", path.display()))?)
    } else {
        None
    };
    let started = match start(&args, &file, &out, setup, checkpoint) {
        Ok(s) => s,
        Err(e) => {
            if fresh {
                let _ = std::fs::remove_dir_all(&out);
            }
            return Err(e);
        }
    };
    step(&args, scene, &out, started, warnings, threads_why)
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
fn start(
    args: &Args,
    file: &crate::scene_file::SceneFile,
    out: &Path,
    setup: particles::setup::Setup,
    checkpoint: Option<Vec<u8>>,
) -> Result<Started, CliError> {
    let scene = &file.dem;
    let dt = setup.dt;
    let total = (scene.run.duration / dt).round() as u64;
    let every = if scene.run.checkpoint_interval > 0.0 {
        ((scene.run.checkpoint_interval / dt).round() as u64).max(1)
    } else {
        u64::MAX
    };
    let interval = args.thermo_interval.unwrap_or(0.1 / scene.drive.frequency);
    let mut thermo = Thermo::new(interval, dt, out.join("thermo.csv"), every, total)?;

    // Sample: prepared once per (population, box, material, seed), shared by every run.
    let bar = progress_bar(1000, args.quiet, "prepare");
    let preparing = Instant::now();
    let (state, cached) = crate::samples::load_or_prepare(scene, &args.sample_cache, |f| bar.set_position((f * 1000.0) as u64))?;
    bar.finish_and_clear();
    let prepare_s = preparing.elapsed().as_secs_f64();
    let mut sim = Simulation::new(setup, state)?;
    let fingerprint = checkpoint_fingerprint(scene)?;
    let ckpt_path = out.join("checkpoint.bin");
    let mut frames = 0;
    if let Some(bytes) = &checkpoint {
        frames =
            crate::dem_checkpoint::restore(&mut sim, bytes, fingerprint).map_err(|e| format!("--resume: {}: {e}", ckpt_path.display()))?;
        thermo.resume(&out.join("thermo.csv"), sim.time)?;
    }
    let dir = RunDir::create(out, &json!({ "args": args, "scene": scene }))?;
    // The resolved scene with its `[automaton]` table, so that `stripes automaton --calibrate`
    // and `stripes compare --dem-run` on this directory see the automaton the scene asked for.
    analysis::io::write_atomic(&out.join("scene.toml"), file.to_toml()?.as_bytes())?;
    if let Some(path) = &args.lammps_data {
        let title = format!("stripes {} at t = {} s, {} grains", args.scene.display(), sim.time, sim.state.len());
        let mut grains = analysis::lammps_data::Grains::default();
        let s = &sim.state;
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
    // t_k = 1/(4 nu) + (k - 1) / (s nu), taken at the nearest step.
    let (nu, per) = (scene.drive.frequency, scene.run.snapshots_per_period as f64);
    let mut recorder = Recorder::open(RecorderPlan {
        header: Header {
            length: scene.tray.length,
            width: scene.tray.width,
            radii: sim.state.radius.clone(),
        },
        snapshots: out.join("snapshots.bin"),
        frames,
        snap_time: Box::new(move |k: u64| 0.25 / nu + (k - 1) as f64 / (per * nu)),
        vtk,
        checkpoint: ckpt_path,
        fingerprint,
        every,
        last: total,
    })?;
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
fn step(
    args: &Args,
    scene: &Scene,
    out: &Path,
    started: Started,
    mut warnings: Vec<String>,
    threads_why: String,
) -> Result<String, CliError> {
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
    let resolving = time_step::viscous_friction_ratio(scene, dt)?.filter(|r| *r > 1.0).map(|r| dt / r);
    if let Some(w) = thermo.balance_warning(dt, resolving) {
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
    let s = &sim.state;
    let stepped = sim.steps - start_steps;
    let energy = json!({
        "kinetic": measure::kinetic_energy(s),
        "rotational": measure::rotational_energy(s),
        "potential": measure::potential_energy(s, sim.setup.gravity),
        "stored": sim.stored_energy,
        "injected": sim.ledger.injected,
        "dissipated": sim.ledger.dissipated,
        "balance": thermo.balance().map(|b| b.0),
        "balance_relative": thermo.balance().map(|b| b.1),
    });
    let summary = json!({
        "scene": args.scene.display().to_string(),
        "particles": s.len(),
        "steps": sim.steps,
        "dt": dt,
        "simulated_s": sim.time,
        "wall_s": wall_clock.elapsed().as_secs_f64(),
        "stepping_s": stepping,
        "particle_steps_per_s": (stepped as f64 * s.len() as f64) / stepping.max(1e-12),
        "threads": rayon::current_num_threads(),
        "threads_chosen_by": threads_why,
        "steps_per_contact": timescale::shortest_contact_time(scene)? / dt,
        "snapshots": frames,
        "sample_cached": cached,
        "prepare_s": prepare_s,
        "sample_cache": args.sample_cache.display().to_string(),
        "thermo_interval_s": thermo.every as f64 * dt,
        "sample_key": format!("{:016x}", sample_key(scene)),
        "energy": energy,
        "contacts": { "pair_mean": pair_mean, "wall_mean": wall_mean },
        "neighbor_builds": sim.neighbor_builds(),
        "state_hash": format!("{:016x}", measure::state_hash(s)),
        "warnings": warnings,
    });
    dir.json("scene.json", scene)?;
    dir.finish(summary)
}
