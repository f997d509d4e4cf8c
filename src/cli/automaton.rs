//! `stripes automaton SCENE.toml`: the Strassburger cellular automaton (thesis 3.1) on the
//! same scene file and the same prepared sample as `stripes run`, written as snapshots that
//! `stripes analyze` reads, and analysed by it. `--bench` measures its speed, `--calibrate`
//! fits its free parameters to DEM runs (see [`crate::automaton::calibrate`]). The run itself is the
//! pipeline's ([`crate::automaton::run_automaton`]).
//!
//! Time: one drive period is two half steps (a flight towards +x, then towards -x, the
//! grains' slide relative to the tray between the turning points). Frame 0 is the sample at
//! t = 0; frame k >= 1 follows k periods and carries the DEM's snapshot time
//! `t_k = 1/(4 nu) + (k - 1)/nu`, so both models' curves share one time axis. The lattice is
//! the tray frame: positions are written shifted by the tray's displacement at that phase.

use std::path::{Path, PathBuf};

use automaton::RuleSet;
use serde::Serialize;
use serde_json::json;

use crate::automaton::{resolve_lattice, run_automaton, AutomatonOptions};
use crate::rundir::report::{report, Reported};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Scene file (TOML), the same as for `stripes run` (optional table [automaton]); not
    /// with --calibrate, which uses each DEM run's own scene.toml.
    #[arg(required_unless_present = "calibrate", conflicts_with = "calibrate")]
    pub scene: Option<PathBuf>,
    /// Output directory (default: out/automaton-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub replace: crate::cli::args::Force,
    #[command(flatten)]
    #[serde(flatten)]
    pub set: crate::cli::args::Overrides,
    /// Rule set: strict (thesis 3.1 exactly), physical (plus what a shaken tray supplies,
    /// the scene's [automaton] table), measured (every number from a DEM run's parameter
    /// file, automaton.parameters) or swing (every grain swings each half period by the
    /// swing the same file measured at its packing). Default: the scene's automaton.rule,
    /// itself physical.
    #[arg(long, value_parser = rule_parser())]
    pub rule: Option<RuleSet>,
    #[command(flatten)]
    #[serde(flatten)]
    pub samples: crate::cli::args::SampleCache,
    /// Measure the speed (cell updates per second, one core) on the scene's tray with a
    /// random layer of its grain count instead of running it.
    #[arg(long)]
    pub bench: bool,
    /// Wall-clock seconds per benchmark case.
    #[arg(long, default_value_t = 3.0)]
    pub bench_seconds: f64,
    /// Fit the free parameters to these DEM run directories (each holding scene.toml and
    /// snapshots.bin) and report the fit.
    #[arg(long, num_args = 1.., value_name = "RUN_DIR")]
    pub calibrate: Vec<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub progress: crate::cli::args::Quiet,
}

pub fn run(args: Args) -> Reported {
    if !args.calibrate.is_empty() {
        return report(crate::automaton::calibrate::run(&crate::automaton::calibrate::Calibration {
            runs: args.calibrate.clone(),
            out: args.out.clone(),
            overrides: args.set.overrides.clone(),
            samples: args.samples.sample_cache.clone(),
            quiet: args.progress.quiet,
        })?);
    }
    let path = args.scene.clone().ok_or("a scene file is needed")?;
    let scene = resolve_lattice(&path, crate::scene::file::load(&path, &args.set.overrides)?)?;
    if args.bench {
        let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out/automaton-bench"));
        let config = json!({ "args": &args, "scene": &scene.file.dem });
        return report(crate::automaton::bench::bench(
            &path,
            &scene.file,
            &out,
            args.replace.force,
            args.bench_seconds,
            &config,
        )?);
    }
    report(run_automaton(&scene, &args.options(&path))?)
}

/// `--rule`: the automaton's own rule-set type, by its scene-file names.
fn rule_parser() -> impl clap::builder::TypedValueParser<Value = RuleSet> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(RuleSet::NAMES).map(|s| s.parse::<RuleSet>().expect("one of the names"))
}

impl Args {
    /// The pipeline's options these arguments select for the scene at `path`.
    fn options(&self, path: &Path) -> AutomatonOptions {
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        AutomatonOptions {
            out: self.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/automaton-{name}"))),
            force: self.replace.force,
            rule: self.rule,
            sample_cache: self.samples.sample_cache.clone(),
            quiet: self.progress.quiet,
        }
    }
}
