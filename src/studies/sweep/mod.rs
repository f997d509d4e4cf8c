//! Sweeps as sets of independent jobs (ablations, phase maps, packing sweeps, and grids of an
//! event-driven scene's values): one engine for the three models.
//!
//! A sweep directory holds `sweep.json` (what the sweep is: its kind, scene, and every job) and
//! one directory per job, `jobs/<id>/`, with the model's run, its analysis, and `result.json`.
//! `result.json` is written atomically and last, so it exists only for a finished job:
//! - a re-run skips every job that has it, so a sweep killed half-way loses nothing and redoes
//!   nothing that finished;
//! - `--shard I/N` runs the jobs whose index is `I mod N` (a deterministic subset), so shards
//!   can run on different machines or as the tasks of a Slurm job array or GNU parallel;
//! - `stripes collect` ([`ablate::report`], [`phase_map::report`],
//!   [`crate::studies::events_sweep::report`]) reads whatever results exist, in job order, so
//!   two shards collected equal a single run.
//!
//! Jobs run in parallel on one machine (`--jobs`, default: all cores), each on one thread;
//! results do not depend on the thread count (see `stripes run`).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::analyze::{self, AnalysisOptions};
use crate::automaton::AutomatonOptions;
use crate::dem::RunOptions;
use crate::rundir::output::{CliError, RunDir};
use crate::scene::file::SceneFile;

pub mod ablate;
pub mod phase_map;

use crate::rundir::report::{Headline, Report, Summary};
use crate::scene::edit::{DemEdit, Edit};

/// What the engine is given besides the sweep itself: the overrides of every job, this
/// process's shard, how many jobs run at once, the cache of prepared samples, and whether to
/// show progress and to start the sweep in `--out` again (`force`; without it, the same
/// sweep continues there and another is refused). The command line's options are
/// `cli::args::SweepArgs`.
#[derive(Clone, Debug)]
pub struct Engine {
    pub overrides: Vec<String>,
    pub shard: Shard,
    pub jobs: Option<usize>,
    pub sample_cache: PathBuf,
    pub quiet: bool,
    pub force: bool,
}

impl Engine {
    /// Stores the sweep in `root` (refusing a different one), runs this shard's unfinished
    /// jobs, writes the report of every result present with `report` (also when some job
    /// failed, so nothing finished is lost from view), and returns the report's summary with
    /// the progress; fails, after the report, if any job failed.
    pub fn execute<R: Report + Serialize>(
        &self,
        root: &Path,
        sweep: &Sweep,
        report: impl Fn(&Path, &Sweep) -> Result<R, CliError>,
    ) -> Result<SweepReport<R>, CliError> {
        check_jobs(sweep)?;
        if self.force {
            forget(root)?;
        }
        // The job's identity covers the resolved scene, not only its path: results of an
        // edited scene file are never reused.
        let mut sweep = sweep.clone();
        sweep.resolved = resolved(&sweep)?;
        let sweep = &sweep;
        store(root, sweep)?;
        let parallel = self
            .jobs
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        let progress = run(root, sweep, self.shard, parallel, &self.sample_cache, self.quiet)?;
        let summary = report(root, sweep)?;
        let mut sample_preparation = None;
        if sweep.kind != SweepKind::EventsSweep {
            let preparation = preparation(root, sweep)?;
            append_preparation(&root.join("report.md"), &preparation)?;
            sample_preparation = Some(preparation);
        }
        if !progress.failed.is_empty() {
            return Err(format!(
                "{} job(s) failed (the report {} lists them): {}",
                progress.failed.len(),
                root.join("report.md").display(),
                progress.failed.join("; ")
            )
            .into());
        }
        Ok(SweepReport {
            summary,
            sample_preparation,
            progress,
        })
    }
}

/// What a sweep's command prints: the report's summary (its `summary.json`), with how the
/// samples were prepared (tray sweeps) and what this run of the sweep did.
#[derive(Debug, Serialize)]
pub struct SweepReport<R> {
    #[serde(flatten)]
    pub summary: R,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample_preparation: Option<Preparation>,
    pub progress: Progress,
}

impl<R: Report + Serialize> Summary for SweepReport<R> {
    fn headline(&self) -> Headline {
        self.summary.headline()
    }
}

/// Which model a job runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    Dem,
    Automaton,
    /// The event-driven model, on an event-driven scene.
    Events,
}

impl Model {
    pub fn name(self) -> &'static str {
        match self {
            Model::Dem => "dem",
            Model::Automaton => "automaton",
            Model::Events => "events",
        }
    }
}

/// Models of a phase map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum Which {
    // The values are described in the options' help (`--model`), so that `--help` prints
    // the same short form as every other command's.
    // The DEM (`stripes run`).
    Dem,
    // The cellular automaton (`stripes automaton`).
    Automaton,
    // Both, on the same samples.
    Both,
}

impl Which {
    pub fn models(self) -> Vec<Model> {
        match self {
            Which::Dem => vec![Model::Dem],
            Which::Automaton => vec![Model::Automaton],
            Which::Both => vec![Model::Dem, Model::Automaton],
        }
    }
}

/// One independent job: a model run on the sweep's scene with some edits, then analysed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Job {
    /// Unique within the sweep; the job's directory name.
    pub id: String,
    pub model: Model,
    /// Typed changes to the sweep's scene (after the sweep's own `--set` overrides).
    pub edits: Vec<Edit>,
    /// What the job stands for (configuration, frequency, amplitude, sample, ...), copied into
    /// its result.
    pub labels: Labels,
}

/// What a job stands for, each sweep kind setting its own: the ablation's configuration,
/// step and sample; the phase map's frequency, amplitude and sample; the event-driven
/// sweep's grid point. Written as a JSON object of the fields set (in `sweep.json` and each
/// job's `result.json`); the fields are in alphabetical order, so the object is the one the
/// sweeps wrote when the labels were a map.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Labels {
    /// Drive amplitude (m) of a phase-map cell.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// The ablation's configuration (e.g. `reference`, `N=2000`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub config: Option<String>,
    /// Drive frequency (Hz) of a phase-map cell.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency: Option<f64>,
    /// The event-driven sweep's grid point (index into its axes' grid).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<u64>,
    /// Sample index (the sample's seed offset).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample: Option<u64>,
    /// The ablation's time step, in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<String>,
}

/// What a sweep is, and so what `collect` draws from its results. Stored in `sweep.json` by
/// its command's name (`"ablate"`, `"phase-map"`); any other name is refused when the sweep
/// is loaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SweepKind {
    /// `stripes ablate`: the reference and its toggles over samples.
    Ablate,
    /// `stripes phase-map`: a grid of drive frequencies and amplitudes.
    PhaseMap,
    /// `stripes events-sweep`: a grid of an event-driven scene's values, over seeds.
    EventsSweep,
}

impl SweepKind {
    /// The command's name, as stored.
    pub fn name(self) -> &'static str {
        match self {
            SweepKind::Ablate => "ablate",
            SweepKind::PhaseMap => "phase-map",
            SweepKind::EventsSweep => "events-sweep",
        }
    }
}

impl std::fmt::Display for SweepKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The definition of a sweep, stored as `sweep.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    /// What `collect` draws.
    pub kind: SweepKind,
    pub scene: PathBuf,
    /// Overrides applied to every job.
    pub overrides: Vec<String>,
    pub jobs: Vec<Job>,
    /// The resolved scene (TOML, overrides applied) the jobs run: part of the sweep's
    /// identity, so that a scene file edited after some jobs finished is not mixed with them.
    /// Filled by [`SweepArgs::execute`]; empty in a `sweep.json` written before it existed.
    #[serde(default)]
    pub resolved: String,
}

/// `I/N`: this process runs the jobs whose index is `I mod N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (i, n) = s.split_once('/').ok_or_else(|| format!("--shard wants I/N, e.g. 0/4, got `{s}`"))?;
        let index: usize = i.trim().parse().map_err(|_| format!("--shard: `{i}` is not a whole number"))?;
        let count: usize = n.trim().parse().map_err(|_| format!("--shard: `{n}` is not a whole number"))?;
        if count == 0 || index >= count {
            return Err(format!("--shard {s}: need 0 <= I < N"));
        }
        Ok(Self { index, count })
    }
}

/// Parses `LO:HI:N` into N evenly spaced values (N = 1 gives LO), or a comma-separated list
/// of increasing values. Errors name the option `--what` and say what is wrong: the shape, a
/// number, LO above HI, N = 0, or a list out of order.
pub fn parse_range(s: &str, what: &str) -> Result<Vec<f64>, String> {
    let number = |p: &str, name: &str| -> Result<f64, String> {
        match p.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!("--{what} {s}: {name} `{p}` is not a finite number")),
        }
    };
    if s.contains(',') {
        // An explicit list, e.g. 2,3,5,8,13,20 (uneven axes, such as a geometric series).
        let values = s
            .split(',')
            .enumerate()
            .map(|(k, p)| number(p, &format!("value {}", k + 1)))
            .collect::<Result<Vec<f64>, String>>()?;
        if values.windows(2).any(|w| w[1] <= w[0]) {
            return Err(format!("--{what} {s}: list the values in increasing order, each once"));
        }
        return Ok(values);
    }
    if !s.contains(':') {
        // One value is an axis of one point.
        return Ok(vec![number(s, "the value")?]);
    }
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 3 {
        return Err(format!(
            "--{what} wants LO:HI:N (e.g. 5:29:7), a list (e.g. 2,3,5,8) or one value, got `{s}`"
        ));
    }
    let (lo, hi) = (number(parts[0], "LO")?, number(parts[1], "HI")?);
    let n: usize = parts[2]
        .trim()
        .parse()
        .map_err(|_| format!("--{what} {s}: N `{}` is not a whole number of points", parts[2]))?;
    if n == 0 {
        return Err(format!("--{what} {s}: N = 0 asks for no points; N must be at least 1"));
    }
    if hi < lo {
        return Err(format!(
            "--{what} {s}: LO = {lo} is above HI = {hi}; write the range from low to high"
        ));
    }
    Ok((0..n)
        .map(|k| if n == 1 { lo } else { lo + (hi - lo) * k as f64 / (n - 1) as f64 })
        .collect())
}

fn job_dir(root: &Path, job: &Job) -> PathBuf {
    root.join("jobs").join(&job.id)
}

/// Writes `sweep.json`, refusing to mix two different sweeps in one directory.
/// `--force`: removes the sweep in `root` (its `sweep.json`, its `jobs/` and the summary's
/// files), so that the sweep starts again; files of the user's are left alone.
fn forget(root: &Path) -> Result<(), CliError> {
    crate::rundir::output::claim(root, true)?;
    for p in [root.join("sweep.json"), root.join("report.md")] {
        if let Err(e) = std::fs::remove_file(&p) {
            if e.kind() != std::io::ErrorKind::NotFound {
                return Err(format!("--force: cannot remove {}: {e}", p.display()).into());
            }
        }
    }
    match std::fs::remove_dir_all(root.join("jobs")) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(format!("--force: cannot remove {}: {e}", root.join("jobs").display()).into())
        }
        _ => Ok(()),
    }
}

/// The resolved scene of a sweep (TOML, the sweep's overrides applied): a tray scene file, or
/// the event-driven scene of an `events-sweep`.
fn resolved(sweep: &Sweep) -> Result<String, CliError> {
    Ok(match sweep.kind {
        SweepKind::EventsSweep => toml::to_string(&crate::scene::events::load(&sweep.scene, &sweep.overrides)?)?,
        _ => crate::scene::file::load(&sweep.scene, &sweep.overrides)?.to_toml()?,
    })
}

pub fn store(root: &Path, sweep: &Sweep) -> Result<(), CliError> {
    std::fs::create_dir_all(root).map_err(|e| format!("cannot create {}: {e}", root.display()))?;
    let path = root.join("sweep.json");
    if let Ok(text) = std::fs::read_to_string(&path) {
        let old: Sweep = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        if old.resolved != sweep.resolved {
            return Err(format!(
                "{} holds a sweep of another resolved scene ({}); its results would be mixed with this one's: use another --out",
                root.display(),
                scene_change(&old.resolved, &sweep.resolved)
            )
            .into());
        }
        if old != *sweep {
            return Err(format!(
                "{} holds a different sweep (other scene, ranges, samples or overrides); use another --out",
                root.display()
            )
            .into());
        }
        return Ok(());
    }
    analysis::io::write_json_atomic(&path, sweep)?;
    Ok(())
}

/// What differs between two resolved scenes, in words: the changed keys (`key: a -> b`).
fn scene_change(old: &str, new: &str) -> String {
    if old.is_empty() {
        return "the stored sweep predates the record of its resolved scene".into();
    }
    let parse = |t: &str| crate::scene::file::parse(t, &[], "sweep.json");
    match (parse(old), parse(new)) {
        (Ok(a), Ok(b)) => {
            let mut keys = crate::scene::file::differences(&a.dem, &b.dem);
            if a.automaton != b.automaton {
                keys.push("the [automaton] table".into());
            }
            if keys.is_empty() {
                "the scene text differs".into()
            } else {
                format!("changed: {}", keys.join(", "))
            }
        }
        _ => "the scene text differs".into(),
    }
}

/// Reads `sweep.json`.
pub fn load(root: &Path) -> Result<Sweep, CliError> {
    let path = root.join("sweep.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e} (is this a sweep directory?)", path.display()))?;
    Ok(serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?)
}

/// What running a sweep did.
#[derive(Debug, Default, Serialize)]
pub struct Progress {
    pub ran: usize,
    pub skipped: usize,
    pub failed: Vec<String>,
    pub other_shards: usize,
}

/// Runs the jobs of this shard that have no result yet, `parallel` at a time.
pub fn run(root: &Path, sweep: &Sweep, shard: Shard, parallel: usize, samples: &Path, quiet: bool) -> Result<Progress, CliError> {
    let mine: Vec<&Job> = sweep
        .jobs
        .iter()
        .enumerate()
        .filter(|(k, _)| k % shard.count == shard.index)
        .map(|(_, j)| j)
        .collect();
    let todo: Vec<&Job> = mine
        .iter()
        .copied()
        .filter(|j| !job_dir(root, j).join("result.json").exists())
        .collect();
    let mut progress = Progress {
        skipped: mine.len() - todo.len(),
        other_shards: sweep.jobs.len() - mine.len(),
        ..Progress::default()
    };
    let bar = crate::rundir::output::progress_bar(todo.len() as u64, quiet, sweep.kind.name());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(parallel.max(1)).build()?;
    let next = AtomicUsize::new(0);
    let outcomes: Vec<(String, Result<(), String>)> = pool.install(|| {
        use rayon::prelude::*;
        (0..parallel.max(1))
            .into_par_iter()
            .flat_map_iter(|_| {
                let mut done = Vec::new();
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some(job) = todo.get(k) else { break };
                    let r = run_job(root, sweep, job, samples).map_err(|e| e.to_string());
                    bar.inc(1);
                    done.push((job.id.clone(), r));
                }
                done
            })
            .collect()
    });
    bar.finish_and_clear();
    for (id, r) in outcomes {
        let error_file = root.join("jobs").join(&id).join(ERROR_FILE);
        match r {
            Ok(()) => {
                progress.ran += 1;
                let _ = std::fs::remove_file(&error_file);
            }
            Err(e) => {
                // Kept beside the job's partial run, so that the report can say why it stopped;
                // a re-run retries the job (it has no result) and removes the file on success.
                std::fs::create_dir_all(error_file.parent().expect("a job directory"))?;
                analysis::io::write_atomic(&error_file, format!("{e}\n").as_bytes())?;
                progress.failed.push(format!("{id}: {e}"));
            }
        }
    }
    Ok(progress)
}

/// Opens a sweep's report: the results present (in job order) and the sweep directory as
/// an output directory (its `config.json` names the sweep).
pub fn open_report<T: serde::de::DeserializeOwned>(root: &Path, sweep: &Sweep) -> Result<(Vec<(Job, T)>, RunDir), CliError> {
    let results = results(root, sweep)?;
    let dir = RunDir::create(
        root,
        &json!({ "sweep": sweep.kind, "scene": sweep.scene, "overrides": sweep.overrides }),
    )?;
    Ok((results, dir))
}

/// Writes `report.md` (the body `md`, then [`unfinished_section`]) atomically into the
/// sweep's directory.
pub fn write_report(root: &Path, sweep: &Sweep, dir: &mut RunDir, mut md: String) -> Result<(), CliError> {
    md.push_str(&unfinished_section(root, sweep));
    let path = root.join("report.md");
    analysis::io::write_atomic(&path, md.as_bytes())?;
    dir.note_files([path]);
    Ok(())
}

/// File in a job's directory holding the error that stopped its last attempt.
const ERROR_FILE: &str = "error.txt";

/// The report section on jobs without a result: each stopped job with its error, then the
/// count of jobs not run yet (other shards, or an interrupted sweep). Empty when every job
/// has finished.
pub fn unfinished_section(root: &Path, sweep: &Sweep) -> String {
    let mut failed = Vec::new();
    let mut pending = 0;
    for job in &sweep.jobs {
        let dir = job_dir(root, job);
        if dir.join("result.json").exists() {
            continue;
        }
        match std::fs::read_to_string(dir.join(ERROR_FILE)) {
            Ok(e) => failed.push(format!("- `{}` stopped: {}", job.id, e.trim())),
            Err(_) => pending += 1,
        }
    }
    let mut md = String::new();
    if !failed.is_empty() {
        md.push_str("## Jobs that stopped with an error\n\nTheir partial runs are kept in `jobs/<id>/run`; a re-run retries them.\n\n");
        md.push_str(&failed.join("\n"));
        md.push_str("\n\n");
    }
    if pending > 0 {
        md.push_str(&format!(
            "{pending} job(s) have not run yet (other shards, or an interrupted sweep).\n\n"
        ));
    }
    md
}

/// The scene of a job: the sweep's scene with the sweep's overrides, the job's edits, and
/// one thread (jobs are the parallel unit, and results do not depend on threads).
fn job_scene(sweep: &Sweep, job: &Job) -> Result<SceneFile, CliError> {
    let mut file = crate::scene::file::load(&sweep.scene, &sweep.overrides)?;
    for edit in job.edits.iter().chain([&Edit::Dem(DemEdit::Threads(1))]) {
        edit.apply(&mut file);
    }
    Ok(file)
}

/// The scene of an event-driven job: the sweep's scene with the sweep's overrides, then the
/// job's values and seed, read by the event-driven scene's loader as `--set` would be.
pub fn events_job_scene(sweep: &Sweep, job: &Job) -> Result<events::scene::EventScene, CliError> {
    let mut set = sweep.overrides.clone();
    for e in &job.edits {
        match e {
            Edit::Events(e) => set.push(e.to_set()),
            other => return Err(format!("job `{}`: {other:?} is not an edit of an event-driven scene", job.id).into()),
        }
    }
    Ok(crate::scene::events::load(&sweep.scene, &set)?)
}

/// What an event-driven job stores as `result.json`: its labels beside what it measured, or
/// why the run stopped (a collapse without a guard, say: an outcome of the physics, kept as
/// the job's result, not retried).
#[derive(Debug, Serialize, Deserialize)]
pub struct EventsResult {
    pub id: String,
    pub labels: Labels,
    pub measured: Option<crate::events::measure::Measured>,
    pub failure: Option<String>,
    pub wall_s: f64,
}

/// Runs one event-driven job in memory and writes its `result.json`, atomically and last.
fn run_events_job(root: &Path, sweep: &Sweep, job: &Job) -> Result<(), CliError> {
    let scene = events_job_scene(sweep, job)?;
    let wall = std::time::Instant::now();
    let (measured, failure) = match crate::events::measure::measure(&scene) {
        Ok(m) => (Some(m), None),
        Err(e) => (None, Some(e)),
    };
    let result = EventsResult {
        id: job.id.clone(),
        labels: job.labels.clone(),
        measured,
        failure,
        wall_s: wall.elapsed().as_secs_f64(),
    };
    let dir = job_dir(root, job);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    analysis::io::write_json_atomic(&dir.join("result.json"), &result)?;
    Ok(())
}

/// Checks the scene of every job (the sweep's scene with the job's edits) before any job
/// starts, so a bad value fails the sweep at once, naming the job and the key, instead of
/// failing its jobs one by one after others have run.
pub fn check_jobs(sweep: &Sweep) -> Result<(), CliError> {
    for job in &sweep.jobs {
        let blame = |e: &dyn std::fmt::Display| format!("job `{}` ({} of the sweep): {e}", job.id, sweep.kind);
        // One kind of scene per sweep: event-driven jobs in an events sweep, tray jobs elsewhere.
        if (job.model == Model::Events) != (sweep.kind == SweepKind::EventsSweep) {
            return Err(blame(&format!("a {} job in a sweep of kind {}", job.model.name(), sweep.kind)).into());
        }
        if job.model == Model::Events {
            events_job_scene(sweep, job)
                .and_then(|s| Ok(crate::scene::events::config(&s)?))
                .map_err(|e| blame(&e))?;
            continue;
        }
        let file = job_scene(sweep, job).map_err(|e| blame(&e))?;
        file.validate().map_err(|e| blame(&e))?;
        if let particles::scene::TimeStep::Seconds(_) = file.dem.run.dt {
            particles::time_step::for_scene(&file.dem).map_err(|e| blame(&e))?;
        }
    }
    Ok(())
}

/// What a job's model run reports to its result.
#[derive(Debug, Serialize)]
struct Speed {
    wall_s: f64,
    particle_steps_per_s: Option<f64>,
}

/// The DEM's sample of a job: prepared by it, or loaded (or waited for) from the cache.
#[derive(Debug, Serialize, Deserialize)]
struct SamplePreparation {
    prepare_s: Option<f64>,
    cached: Option<bool>,
}

/// What a finished job stores as `result.json`: its labels beside the analysis.
#[derive(Debug, Serialize)]
struct JobResult<'a> {
    id: &'a str,
    model: &'static str,
    #[serde(flatten)]
    labels: &'a Labels,
    analysis: analyze::AnalysisSummary,
    speed: Speed,
    sample_preparation: SamplePreparation,
}

/// Runs one job: the model into `jobs/<id>/run`, the shared analysis into `jobs/<id>/analysis`,
/// then `result.json` (labels + the analysis summary), atomically and last.
fn run_job(root: &Path, sweep: &Sweep, job: &Job, samples: &Path) -> Result<(), CliError> {
    if job.model == Model::Events {
        return run_events_job(root, sweep, job);
    }
    let dir = job_dir(root, job);
    let run_dir = dir.join("run");
    let file = job_scene(sweep, job)?;
    // The run's analysis is told its drive by the scene, not by the run's config.json.
    let description = analyze::run::describe_tray(&file.dem);
    let (speed, sample_preparation) = match job.model {
        Model::Dem => {
            let s = crate::dem::run_dem(
                &crate::dem::resolve(&sweep.scene, file)?,
                &RunOptions {
                    out: run_dir.clone(),
                    sample_cache: samples.to_path_buf(),
                    quiet: true,
                    // A job re-run after a failure replaces what the failed attempt left.
                    force: true,
                    ..RunOptions::default()
                },
            )?;
            (
                Speed {
                    wall_s: s.wall_s,
                    particle_steps_per_s: Some(s.particle_steps_per_s),
                },
                SamplePreparation {
                    prepare_s: Some(s.prepare_s),
                    cached: Some(s.sample_cached),
                },
            )
        }
        Model::Events => unreachable!("event-driven jobs run in run_events_job"),
        Model::Automaton => {
            let s = crate::automaton::run_automaton(
                &crate::automaton::resolve_lattice(&sweep.scene, file)?,
                &AutomatonOptions {
                    out: run_dir.clone(),
                    sample_cache: samples.to_path_buf(),
                    quiet: true,
                    ..AutomatonOptions::default()
                },
            )?;
            (
                Speed {
                    wall_s: s.wall_s,
                    particle_steps_per_s: None,
                },
                SamplePreparation {
                    prepare_s: None,
                    cached: None,
                },
            )
        }
    };
    let analysis = analyze::analyze(&run_dir, &AnalysisOptions::into_dir(dir.join("analysis")).described(description))?;
    let result = JobResult {
        id: &job.id,
        model: job.model.name(),
        labels: &job.labels,
        analysis,
        speed,
        sample_preparation,
    };
    analysis::io::write_json_atomic(&dir.join("result.json"), &serde_json::to_value(&result)?)?;
    Ok(())
}

/// What preparing the DEM's samples cost a sweep (from the jobs' `result.json`).
#[derive(Debug, Default, Serialize)]
pub struct Preparation {
    /// DEM jobs that prepared their sample, and those that loaded it from the cache.
    pub prepared: usize,
    pub loaded: usize,
    /// Wall seconds spent preparing, and spent loading or waiting for another job's sample.
    pub prepare_s: f64,
    pub load_s: f64,
}

/// Sums the sample preparation of the sweep's finished jobs.
pub fn preparation(root: &Path, sweep: &Sweep) -> Result<Preparation, CliError> {
    /// The part of a tray job's `result.json` read here.
    #[derive(Deserialize)]
    struct Prepared {
        sample_preparation: SamplePreparation,
    }
    let mut p = Preparation::default();
    for (_, prepared) in results::<Prepared>(root, sweep)? {
        let (Some(s), Some(c)) = (prepared.sample_preparation.prepare_s, prepared.sample_preparation.cached) else {
            continue;
        };
        if c {
            p.loaded += 1;
            p.load_s += s;
        } else {
            p.prepared += 1;
            p.prepare_s += s;
        }
    }
    Ok(p)
}

/// Adds a line on the sample preparation to a sweep's report.
fn append_preparation(report: &Path, p: &Preparation) -> Result<(), CliError> {
    let Ok(mut text) = std::fs::read_to_string(report) else {
        return Ok(());
    };
    text.push_str(&format!(
        "\n**Sample preparation.** {} DEM job(s) prepared their sample ({:.1} s of wall time in all); {} loaded it from the cache or waited for the job preparing it ({:.1} s). Each distinct sample is prepared once: jobs in one process share a lock, processes (shards) a lock file beside the sample.\n",
        p.prepared, p.prepare_s, p.loaded, p.load_s
    ));
    analysis::io::write_atomic(report, text.as_bytes())?;
    Ok(())
}

/// The results present, in job order, with the job each belongs to, read as `T` (the part
/// of `result.json` the reader needs); a result that is not one names its file and job.
pub fn results<T: serde::de::DeserializeOwned>(root: &Path, sweep: &Sweep) -> Result<Vec<(Job, T)>, CliError> {
    let mut out = Vec::new();
    for job in &sweep.jobs {
        let path = job_dir(root, job).join("result.json");
        if let Ok(text) = std::fs::read_to_string(&path) {
            let v: T = serde_json::from_str(&text).map_err(|e| format!("{}: result of job `{}`: {e}", path.display(), job.id))?;
            out.push((job.clone(), v));
        }
    }
    Ok(out)
}

/// What the reports of a tray sweep read from a finished job's `result.json`: its
/// analysis' phase and numbers (a number `summary.json` wrote as null reads as none).
#[derive(Clone, Debug, Default, Deserialize)]
pub struct TrayResult {
    pub analysis: crate::analyze::read::SavedSummary,
}

/// A number of a job's analysis, `NaN` when it has none (as the reports' means take it).
pub fn nan_if_none(x: Option<f64>) -> f64 {
    x.unwrap_or(f64::NAN)
}

/// The "Scale: ..." line of a sweep's report: scene, N, box, packing, duration, samples per
/// `unit` (cell, configuration) and how many jobs have finished.
pub fn scale_line(sweep: &Sweep, finished: usize, unit: &str) -> Result<String, CliError> {
    let scene = crate::scene::file::load(&sweep.scene, &sweep.overrides)?.dem;
    let samples = sweep.jobs.iter().filter_map(|j| j.labels.sample).max().map_or(1, |k| k + 1);
    Ok(format!(
        "Scale: scene `{}`, N = {}, box {} m x {} m (packing {:.3}), {} s per run, {samples} sample(s) per {unit}, {finished} of {} jobs finished.",
        sweep.scene.display(),
        scene.particles.count,
        scene.tray.length,
        scene.tray.width,
        scene.packing(),
        scene.run.duration,
        sweep.jobs.len()
    ))
}

/// The phase most samples of a cell or configuration share: one phase, a tie between the
/// phases that share the largest count (never given to either), or none without samples.
#[derive(Clone, Debug, PartialEq)]
pub enum Majority<T> {
    None,
    One(T),
    Tie(Vec<T>),
}

/// The majority of `items` (see [`Majority`]); tied items come in their order.
pub fn majority<T: Ord + Clone>(items: impl IntoIterator<Item = T>) -> Majority<T> {
    let mut counts: std::collections::BTreeMap<T, usize> = std::collections::BTreeMap::new();
    for item in items {
        *counts.entry(item).or_default() += 1;
    }
    let top = counts.values().copied().max().unwrap_or(0);
    let mut leaders: Vec<T> = counts.into_iter().filter(|(_, n)| *n == top).map(|(t, _)| t).collect();
    match leaders.len() {
        0 => Majority::None,
        1 => Majority::One(leaders.remove(0)),
        _ => Majority::Tie(leaders),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweep_kind_is_stored_by_its_command_name_and_an_unknown_one_is_refused_on_load() {
        for kind in [SweepKind::Ablate, SweepKind::PhaseMap] {
            let stored = serde_json::to_string(&kind).unwrap();
            assert_eq!(stored, format!("\"{}\"", kind.name()));
            assert_eq!(serde_json::from_str::<SweepKind>(&stored).unwrap(), kind);
        }
        let dir = std::env::temp_dir().join(format!("stripes-sweep-kind-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let json = |kind: &str| format!(r#"{{"kind": "{kind}", "scene": "s.toml", "overrides": [], "jobs": []}}"#);
        std::fs::write(dir.join("sweep.json"), json("phase-map")).unwrap();
        assert_eq!(load(&dir).unwrap().kind, SweepKind::PhaseMap);
        std::fs::write(dir.join("sweep.json"), json("phase_map")).unwrap();
        let e = load(&dir).unwrap_err().to_string();
        assert!(e.contains("sweep.json") && e.contains("unknown variant `phase_map`"), "{e}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn ranges_and_shards_parse_and_reject_nonsense() {
        assert_eq!(parse_range("5:29:4", "frequency").unwrap(), vec![5.0, 13.0, 21.0, 29.0]);
        assert_eq!(parse_range("0.01:0.01:1", "amplitude").unwrap(), vec![0.01]);
        assert!(parse_range("5:29", "frequency").is_err());
        let e = parse_range("29:5:3", "frequency").unwrap_err();
        assert!(e.contains("--frequency") && e.contains("LO = 29 is above HI = 5"), "{e}");
        let e = parse_range("5:29:0", "amplitude").unwrap_err();
        assert!(e.contains("--amplitude") && e.contains("N = 0"), "{e}");
        assert_eq!(parse_range("2,3,5,8", "frequency").unwrap(), vec![2.0, 3.0, 5.0, 8.0]);
        let e = parse_range("2,5,3", "frequency").unwrap_err();
        assert!(e.contains("increasing"), "{e}");
        let e = parse_range("2,x", "frequency").unwrap_err();
        assert!(e.contains("value 2"), "{e}");
        let e = parse_range("5:x:3", "frequency").unwrap_err();
        assert!(e.contains("HI `x`"), "{e}");
        // One value is an axis of one point (`phase-map --frequency 5`).
        assert_eq!(parse_range("5", "frequency").unwrap(), vec![5.0]);
        assert!(parse_range("x", "frequency").unwrap_err().contains("`x`"));
        assert_eq!("1/4".parse::<Shard>().unwrap(), Shard { index: 1, count: 4 });
        assert!("4/4".parse::<Shard>().is_err());
        assert!("x/2".parse::<Shard>().is_err());
    }
}

#[cfg(test)]
mod majority_tests {
    use super::{majority, Majority};

    /// A tie is named as one and never given to the first phase; one leader wins; nothing
    /// gives nothing.
    #[test]
    fn an_even_split_is_a_tie() {
        assert_eq!(majority(["stripes", "gas"]), Majority::Tie(vec!["gas", "stripes"]));
        assert_eq!(majority(["stripes", "gas", "stripes"]), Majority::One("stripes"));
        assert_eq!(majority([1usize, 0, 0, 1, 2]), Majority::Tie(vec![0, 1]));
        assert_eq!(majority(Vec::<usize>::new()), Majority::None);
    }
}
