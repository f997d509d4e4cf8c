//! Options several commands share, each defined once with its help text and flattened
//! into the commands' arguments (`#[command(flatten)]`, and `#[serde(flatten)]` so that
//! `config.json` keeps the flat keys).

use std::path::PathBuf;

use serde::Serialize;

/// `--force` of a command that refuses an output directory holding files.
#[derive(clap::Args, Clone, Copy, Debug, Default, Serialize)]
pub struct Force {
    /// Replace the files of an output directory that already holds some (default: refuse it).
    #[arg(long)]
    pub force: bool,
}

/// `--quiet` of a command that shows its progress.
#[derive(clap::Args, Clone, Copy, Debug, Default, Serialize)]
pub struct Quiet {
    /// No progress output (warnings still go to stderr, the summary to stdout).
    #[arg(long)]
    pub quiet: bool,
}

/// `--force` and `--quiet` of a command that writes a directory and shows its progress.
#[derive(clap::Args, Clone, Copy, Debug, Default, Serialize)]
pub struct Writing {
    /// Replace the files of an output directory that already holds some (default: refuse it).
    #[arg(long)]
    pub force: bool,
    /// No progress output (warnings still go to stderr, the summary to stdout).
    #[arg(long)]
    pub quiet: bool,
}

/// `--sample-cache` of a command that starts from prepared samples.
#[derive(clap::Args, Clone, Debug, Serialize)]
pub struct SampleCache {
    /// Cache of prepared samples, shared by every run (default: $STRIPES_SAMPLE_CACHE, else
    /// out/samples).
    #[arg(long, value_name = "DIR", default_value_os_t = crate::rundir::output::default_sample_cache())]
    pub sample_cache: PathBuf,
}

/// What a command that simulates a scene file reads: the scene, its `--set` overrides, `--out`,
/// and `--force`, `--resume` and `--quiet` of a long run that can be continued from its
/// checkpoint.
#[derive(clap::Args, Clone, Debug, Serialize)]
pub struct SceneRun {
    /// Scene file (TOML), e.g. scenes/stripes.toml.
    pub scene: PathBuf,
    #[command(flatten)]
    #[serde(flatten)]
    pub set: Overrides,
    /// Output directory (default: out/<command>-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the files of an output directory that already holds some (default: refuse it).
    #[arg(long, conflicts_with = "resume")]
    pub force: bool,
    /// Continue what --out holds from its checkpoint (the scene may change only
    /// run.duration, e.g. to extend a finished run).
    #[arg(long)]
    pub resume: bool,
    /// No progress output (warnings still go to stderr, the summary to stdout).
    #[arg(long)]
    pub quiet: bool,
}

/// `--set` of a command that reads a scene file.
#[derive(clap::Args, Clone, Debug, Default, Serialize)]
pub struct Overrides {
    /// Override a scene key (repeatable), e.g. --set run.duration=5 or
    /// --set toggles.friction=false.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
}

/// Options every sweep command shares (`ablate`, `phase-map`, `events-sweep`).
#[derive(clap::Args, Debug, Serialize)]
pub struct SweepArgs {
    /// Override a scene key for every job (repeatable), e.g. --set run.duration=5.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
    /// Run only the jobs with index I mod N (e.g. 0/4); `stripes collect DIR` merges shards.
    #[arg(long, default_value = "0/1")]
    pub shard: crate::studies::sweep::Shard,
    /// Jobs run at once on this machine (default: all cores); results do not depend on it.
    #[arg(long, alias = "threads")]
    pub jobs: Option<usize>,
    #[command(flatten)]
    #[serde(flatten)]
    pub samples: SampleCache,
    #[command(flatten)]
    #[serde(flatten)]
    pub progress: Quiet,
    // Without --force, a sweep continues the same sweep in --out (its finished jobs are kept).
    #[command(flatten)]
    #[serde(skip)]
    pub replace: Force,
}

impl SweepArgs {
    /// The engine's options these arguments select.
    pub fn engine(&self) -> crate::studies::sweep::Engine {
        crate::studies::sweep::Engine {
            overrides: self.overrides.clone(),
            shard: self.shard,
            jobs: self.jobs,
            sample_cache: self.samples.sample_cache.clone(),
            quiet: self.progress.quiet,
            force: self.replace.force,
        }
    }
}
