//! `stripes events SCENE`: the event-driven model of a vibrated box (crate `events`) on an
//! event-driven scene (`model = "events"`, see `docs/scenes.md`). It writes the run
//! directory as `stripes run` does: `config.json`, `scene.toml`, `snapshots.bin` (the
//! format `stripes analyze` reads, the vertical plane stored as x and z with y = R_max),
//! `profiles.csv` with plots of the density and temperature profiles, `checkpoint.bin`
//! (every 30 s of wall time and at the end), and `summary.json`, printed last. `--resume`
//! continues a run from its checkpoint bit for bit, also past its old `run.duration`. The
//! run itself is the pipeline's ([`crate::events::run_events`]).

use std::path::PathBuf;

use crate::events::{run_events, EventsOptions};
use crate::rundir::report::{report, Reported};

/// The command's arguments: a scene run's, with nothing of its own.
pub type Args = crate::cli::args::SceneRun;

pub fn run(args: Args) -> Reported {
    let scene = crate::scene::events::load(&args.scene, &args.set.overrides)?;
    let name = args
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let opts = EventsOptions {
        out: args.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/events-{name}"))),
        force: args.force,
        resume: args.resume,
        quiet: args.quiet,
    };
    report(run_events(&args.scene, &scene, &opts)?)
}
