//! `stripes run SCENE.toml`: the tray-driven DEM.
//!
//! Writes into the run directory: `scene.toml` (the resolved scene), `config.json`,
//! `snapshots.bin` (see `analysis::snapshot`; a frame at t = 0 and then at the chosen phase of
//! every period), `checkpoint.bin` (at `run.checkpoint_interval`), optional `vtk/` frames,
//! and `summary.json`. `--resume` continues from `checkpoint.bin`, bit for bit.

use std::path::PathBuf;
use std::time::Instant;

use analysis::snapshot::Header;
use particles::observe;
use particles::observer::{advance, ObserverError};
use particles::prepare;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::tray;
use serde::Serialize;
use serde_json::json;

use crate::observers::{ContactMeans, Progress, Recorder, RecorderPlan};
use crate::output::{progress_bar, CliError, RunDir};

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
    #[arg(long)]
    pub resume: bool,
    /// Also write every snapshot as a legacy VTK file (vtk/frame_NNNNN.vtk) for ParaView.
    #[arg(long)]
    pub vtk: bool,
    /// Directory of prepared samples, shared by all runs.
    #[arg(long, default_value = "out/samples")]
    pub samples: PathBuf,
    /// Also write the state the run starts from (the prepared sample, or the checkpoint with
    /// --resume) as a LAMMPS data file (atom_style sphere, units si), to run the same grains
    /// in LAMMPS (bench/lammps/in.tray).
    #[arg(long, value_name = "FILE")]
    pub lammps_data: Option<PathBuf>,
    /// Die after this many steps as `kill -9` would (a test hook for checkpoints and --resume).
    #[arg(long, hide = true)]
    pub stop_after: Option<u64>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// What a checkpoint must match to be resumed: the scene and its sample, except the keys that
/// do not change the trajectory (`run.threads`, `run.checkpoint_interval`) or only say where
/// it stops (`run.duration`, so a finished run can be extended with `--resume`).
pub(crate) fn checkpoint_fingerprint(scene: &Scene) -> Result<u64, CliError> {
    let mut s = scene.clone();
    s.run.threads = 0;
    s.run.checkpoint_interval = 0.0;
    s.run.duration = 1.0;
    Ok(observe::fnv1a(toml::to_string(&s)?.as_bytes()) ^ prepare::sample_key(scene))
}

pub fn run(args: Args) -> Result<String, CliError> {
    let scene = crate::scene_file::load(&args.scene, &args.overrides)?.dem;
    scene.validate()?;
    let threads = scene.run.threads;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    pool.install(|| run_in_pool(args, scene))
}

fn run_in_pool(args: Args, scene: Scene) -> Result<String, CliError> {
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/run-{name}")));
    let scene_toml = toml::to_string(&scene)?;
    let mut dir = RunDir::create(&out, &json!({ "args": &args, "scene": &scene }))?;
    analysis::io::write_atomic(&out.join("scene.toml"), scene_toml.as_bytes())?;

    // Everything that can be checked is checked before the (possibly long) preparation.
    let setup = tray::setup(&scene, tray::drive(&scene))?;
    let dt = setup.dt;
    let warnings = tray::warnings(&scene, dt)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }

    // Sample: prepared once per (population, box, material, seed), shared by every run.
    let bar = progress_bar(1000, args.quiet, "prepare");
    let (state, cached) = crate::samples::load_or_prepare(&scene, &args.samples, |f| bar.set_position((f * 1000.0) as u64))?;
    bar.finish_and_clear();
    let mut sim = Simulation::new(setup, state)?;
    let fingerprint = checkpoint_fingerprint(&scene)?;
    let header = Header {
        length: scene.tray.length,
        width: scene.tray.width,
        radii: sim.state.radius.clone(),
    };
    let snap_path = out.join("snapshots.bin");
    let ckpt_path = out.join("checkpoint.bin");
    let frames = if args.resume {
        let bytes = std::fs::read(&ckpt_path).map_err(|e| format!("--resume: cannot read {}: {e}", ckpt_path.display()))?;
        sim.restore(&bytes, fingerprint)
            .map_err(|e| format!("--resume: {}: {e}", ckpt_path.display()))?
    } else {
        0
    };
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

    // Snapshot k >= 1 at the turning point x_tray = +A of each period (sin = 1):
    // t_k = 1/(4 nu) + (k - 1) / (s nu), taken at the nearest step.
    let (nu, per) = (scene.drive.frequency, scene.run.snapshots_per_period as f64);
    let total = (scene.run.duration / dt).round() as u64;
    let mut recorder = Recorder::open(RecorderPlan {
        header,
        snapshots: snap_path.clone(),
        frames,
        snap_time: Box::new(move |k: u64| 0.25 / nu + (k - 1) as f64 / (per * nu)),
        vtk: args.vtk.then(|| out.join("vtk")),
        checkpoint: ckpt_path.clone(),
        fingerprint,
        every: if scene.run.checkpoint_interval > 0.0 {
            ((scene.run.checkpoint_interval / dt).round() as u64).max(1)
        } else {
            u64::MAX
        },
        last: total,
    })?;
    if recorder.frames == 0 {
        recorder.snapshot(&sim)?;
    }
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
    let stepping = match advance(
        &mut sim,
        total,
        &mut [&mut contacts, &mut recorder, &mut Progress(&bar), &mut killer],
    ) {
        Ok(seconds) => seconds,
        Err(e) => {
            // Keep everything written so far: the snapshots up to now and the last checkpoint.
            recorder.writer.sync()?;
            bar.abandon();
            let kept = if ckpt_path.exists() {
                format!("the last checkpoint is {}", ckpt_path.display())
            } else {
                "no checkpoint was due yet".to_string()
            };
            return Err(format!(
                "{e}; the {} snapshots so far are in {} and {kept}",
                recorder.frames,
                snap_path.display()
            )
            .into());
        }
    };
    recorder.writer.sync()?;
    bar.finish_and_clear();
    let frames = recorder.frames;
    let (pair_mean, wall_mean) = contacts.means();
    let s = &sim.state;
    let stepped = sim.steps - start_steps;
    let energy = json!({
        "kinetic": observe::kinetic_energy(s),
        "rotational": observe::rotational_energy(s),
        "potential": observe::potential_energy(s, sim.setup.gravity),
        "stored": sim.stored_energy,
        "injected": sim.ledger.injected,
        "dissipated": sim.ledger.dissipated,
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
        "steps_per_contact": tray::shortest_contact_time(&scene)? / dt,
        "snapshots": frames,
        "sample_cached": cached,
        "sample_key": format!("{:016x}", prepare::sample_key(&scene)),
        "energy": energy,
        "contacts": { "pair_mean": pair_mean, "wall_mean": wall_mean },
        "neighbor_builds": sim.neighbor_builds(),
        "state_hash": format!("{:016x}", observe::state_hash(s)),
        "warnings": warnings,
    });
    dir.json("scene.json", &scene)?;
    dir.finish(summary)
}
