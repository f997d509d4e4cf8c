//! The automaton's run of a scene: its lattice from the DEM's prepared sample, its
//! parameters from the tray ([`crate::automaton::lattice`]), its states written as `snapshots.bin`
//! and analysed like a DEM run. [`run_automaton`] returns the typed [`AutomatonSummary`];
//! the same summary is `summary.json`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use automaton::mapping::SlideMeasure;
use automaton::{Params, RuleSet};
use serde::Serialize;
use serde_json::{json, Value};

use crate::analyze::{analyze, AnalysisOptions, AnalysisSummary};
use crate::automaton::lattice::{self, evolve, setup, Cells};
use crate::rundir::output::CliError as Error;
use crate::rundir::output::{progress_bar, RunDir, Written};
use crate::rundir::report::{Headline, Summary};
use crate::scene::file::SceneFile;

/// A scene checked for the automaton: both tables valid and a lattice the automaton can
/// hold ([`lattice::validate_lattice`]). Built by [`resolve_lattice`].
#[derive(Clone, Debug)]
pub struct LatticeScene {
    /// Where the scene was read (named in the summary).
    pub path: PathBuf,
    pub file: SceneFile,
    /// The file `automaton.parameters` names, read and checked.
    pub parameters: Option<crate::automaton::parameters::Parameters>,
}

/// Checks `file` (read from `path`) for the automaton, before anything is written.
pub fn resolve_lattice(path: &Path, mut file: SceneFile) -> Result<LatticeScene, Error> {
    file.validate()?;
    let parameters = crate::automaton::parameters::read(&mut file)?;
    lattice::validate_lattice(&file)?;
    Ok(LatticeScene {
        path: path.to_path_buf(),
        file,
        parameters,
    })
}

/// How to run the automaton and where to write it.
#[derive(Clone, Debug, Default, Serialize)]
pub struct AutomatonOptions {
    /// The run directory.
    pub out: PathBuf,
    /// Replace the files of a directory that already holds some.
    pub force: bool,
    /// Rule set (default: the scene's `automaton.rule`).
    pub rule: Option<RuleSet>,
    /// Cache of prepared samples.
    pub sample_cache: PathBuf,
    /// No progress output.
    pub quiet: bool,
}

/// How the tray maps onto the automaton.
#[derive(Clone, Debug, Serialize)]
pub struct Mapping {
    pub tray_acceleration: f64,
    pub friction_acceleration: f64,
    pub slide_dem: SlideMeasure,
    pub slide_coulomb_block: SlideMeasure,
    pub flight_cap_cells: f64,
}

/// What an automaton run did, with the keys of its analysis that every model's summary
/// repeats: `summary.json` of its directory, field for field.
#[derive(Clone, Debug, Serialize)]
pub struct AutomatonSummary {
    /// The analysis' phase, stripes, structure and plateaus
    /// ([`AnalysisSummary::shared_keys`], its warnings merged into `warnings`).
    #[serde(flatten)]
    pub analysis: serde_json::Map<String, Value>,
    pub scene: String,
    pub rule: RuleSet,
    pub params: Params,
    pub cells: Cells,
    pub grains: u64,
    pub mass_initial: u64,
    pub mass_final: u64,
    pub displaced_to_free_cell: usize,
    pub stacked: usize,
    pub mapping: Mapping,
    pub periods: u64,
    pub half_steps: u64,
    pub stepping_s: f64,
    pub wall_s: f64,
    pub cell_updates_per_s: f64,
    /// The `measured` rule's grains followed one by one: their moves per half period and per
    /// period, their mobility, and the columns' fill ([`lattice::MeasuredTrace`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured_trace: Option<lattice::MeasuredTrace>,
    /// The run's warnings, then its analysis'.
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub written: Written,
    /// The whole analysis of the run (`<out>/analysis/summary.json`).
    #[serde(skip)]
    pub analysed: AnalysisSummary,
}

impl Summary for AutomatonSummary {
    fn headline(&self) -> Headline {
        Headline {
            wall_s: Some(self.wall_s),
            phase: Some(self.analysed.phase_line()),
            ..Headline::written(self.warnings.len(), &self.written)
        }
    }
}

/// Runs the automaton on a checked scene into `opts.out` and analyses it into
/// `<out>/analysis`.
pub fn run_automaton(scene: &LatticeScene, opts: &AutomatonOptions) -> Result<AutomatonSummary, Error> {
    let (file, out) = (&scene.file, opts.out.as_path());
    // The rule first: a refused one writes nothing.
    let rule = file.automaton.rule_with(opts.rule).map_err(|e| e.to_string())?;
    crate::rundir::output::claim(out, opts.force)?;
    let mut dir = RunDir::create(out, &json!({ "args": opts, "scene_file": scene.path, "scene": file }))?;
    analysis::io::write_atomic(&out.join("scene.toml"), file.to_toml()?.as_bytes())?;
    let s = setup(file, &opts.sample_cache, opts.quiet)?;
    let mut params = lattice::params(file, rule, &s.slide_dem, &file.automaton.free_params());
    if rule.is_measured() {
        params.measured = scene
            .parameters
            .as_ref()
            .map(|p| p.rule(file, rule == RuleSet::Swing))
            .transpose()?;
    }
    let wall = Instant::now();
    let b = progress_bar(1, opts.quiet, "automaton");
    let outcome = evolve(file, s.lattice, params, Some(&out.join("snapshots.bin")), s.radius, &b, |_, _| ())?;
    b.finish_and_clear();
    let wall_s = wall.elapsed().as_secs_f64();
    let analysed = analyze(
        out,
        &AnalysisOptions::into_dir(out.join("analysis")).described(crate::analyze::run::describe_tray(&file.dem)),
    )?;
    let mut keys = analysed.shared_keys()?;
    keys.remove("warnings");
    for w in &outcome.warnings {
        eprintln!("warning: {w}");
    }
    let mut warnings: Vec<String> = scene.parameters.iter().flat_map(|p| p.warnings.clone()).collect();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    warnings.extend(outcome.warnings.iter().cloned());
    warnings.extend(analysed.warnings.iter().cloned());
    let c = outcome.cells;
    let cell_updates = (c.nx * c.ny) as f64 * outcome.half_steps as f64;
    let drive = lattice::tray_drive(&file.dem);
    dir.note_files([out.join("snapshots.bin"), out.join("scene.toml")]);
    let summary = AutomatonSummary {
        analysis: keys,
        scene: scene.path.display().to_string(),
        rule,
        params,
        cells: c,
        grains: outcome.mass.0,
        mass_initial: outcome.mass.0,
        mass_final: outcome.mass.1,
        displaced_to_free_cell: s.displaced,
        stacked: s.stacked,
        mapping: Mapping {
            tray_acceleration: drive.tray_acceleration(),
            friction_acceleration: drive.friction_acceleration(),
            slide_dem: s.slide_dem,
            slide_coulomb_block: s.slide_coulomb,
            flight_cap_cells: (s.slide_dem.displacement / c.dx).round(),
        },
        periods: outcome.periods,
        half_steps: outcome.half_steps,
        stepping_s: outcome.stepping_s,
        wall_s,
        cell_updates_per_s: cell_updates / outcome.stepping_s.max(1e-12),
        measured_trace: outcome.trace.clone(),
        warnings,
        written: dir.written(),
        analysed,
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}
