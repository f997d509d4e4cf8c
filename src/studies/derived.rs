//! The automaton derived from a DEM run (issue 40): the run's measures written as the
//! automaton's parameter file (`stripes mechanism RUN --coarse-only`, [`crate::studies::coarse`]),
//! then the automaton's `swing` rule from that file on the same scene and sample. `stripes
//! compare` shows it beside the DEM and the scene's own automaton.
//!
//! Layout under the comparison's `--out DIR`: `derived/parameters/` (`automaton.toml`,
//! `coarse.json`) and `derived/automaton/` (the run and its `analysis/`).

use std::path::{Path, PathBuf};

use ::automaton::RuleSet;
use serde_json::json;

use crate::analyze::run::Outcome;
use crate::automaton::run::AutomatonSummary;
use crate::automaton::{resolve_lattice, run_automaton, AutomatonOptions};
use crate::rundir::output::{CliError, RunDir};
use crate::scene::file::SceneFile;

/// The derived automaton's run.
pub struct Derived {
    /// The parameter file it ran from.
    pub parameters: PathBuf,
    pub run: AutomatonSummary,
    pub keys: Outcome,
    /// Its analysis directory.
    pub analysis: PathBuf,
}

/// Measures the DEM run at `dem` (of the scene `file`, read from `scene_path`) into
/// `out/derived/parameters/automaton.toml` and runs the `swing` rule from it into
/// `out/derived/automaton`, on the sample cache `samples`. An error says why there is no
/// derived automaton (a DEM run without bands has no cell; one with one frame per period has
/// no half periods); the comparison reports it and goes on.
pub fn derive(scene_path: &Path, file: &SceneFile, dem: &Path, out: &Path, samples: &Path, quiet: bool) -> Result<Derived, CliError> {
    let pdir = out.join("derived").join("parameters");
    let mut dir = RunDir::create(&pdir, &json!({ "run": dem, "scene": &file.dem }))?;
    crate::studies::coarse::write(dem, !file.dem.tray.x_walls, None, None, &mut dir)?;
    let written = dir.written();
    dir.finish_typed(&json!({ "run": dem, "file": "automaton.toml", "written": written }))?;
    let parameters = pdir.join("automaton.toml");
    let mut derived = file.clone();
    derived.automaton.parameters = Some(parameters.clone());
    derived.automaton.parameters_force = false;
    // The file gives the cell: a scene's own `automaton.cell` is for its own rule.
    derived.automaton.cell = None;
    let run_dir = out.join("derived").join("automaton");
    let run = run_automaton(
        &resolve_lattice(scene_path, derived)?,
        &AutomatonOptions {
            out: run_dir.clone(),
            force: true, // inside the comparison's own directory, claimed by it
            rule: Some(RuleSet::Swing),
            sample_cache: samples.to_path_buf(),
            quiet,
        },
    )?;
    let keys = run.analysed.outcome();
    Ok(Derived {
        parameters,
        run,
        keys,
        analysis: run_dir.join("analysis"),
    })
}
