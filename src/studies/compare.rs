//! The comparison behind `stripes compare SCENE.toml`: both models on the same scene and the same sample, analysed
//! by the same code (`stripes analyze`), side by side in `report.md`: the two density maps,
//! stripe count over time of both in one plot and one table, onset times, each model's speed.
//!
//! Layout of `--out DIR`: `dem/` (the DEM run, unless `--dem-run` names an existing one),
//! `automaton/`, their `analysis/` subdirectories, `derived/` (the automaton derived from the
//! DEM run's own measures, [`crate::studies::derived`]), and at the top `report.md`,
//! `stripe_count.{png,svg}`, `stripe_count.csv`, the two density maps, `summary.json`.

use std::path::{Path, PathBuf};

use analysis::io::read_csv;
use analysis::plot::{Heatmap, LinePlot, Mark};
use serde::Serialize;
use serde_json::json;

use analysis::classify::Phase;

use crate::analyze::read;
use crate::analyze::run::Outcome;
use crate::analyze::{analyze, AnalysisOptions};
use crate::automaton::lattice::load_scene;
use crate::automaton::{resolve_lattice, run_automaton, AutomatonOptions};
use crate::dem::samples::sample_key;
use crate::dem::{resolve, run_dem, RunOptions};
use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Summary};
use crate::studies::vibrated_box::BoxSummary;

/// What a comparison is given: the scene file and its overrides, where it writes, and the
/// runs it may reuse. Serialised as the command's arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    pub scene: PathBuf,
    pub overrides: Vec<String>,
    pub out: Option<PathBuf>,
    pub force: bool,
    pub resume: bool,
    pub quiet: bool,
    /// Reuse this DEM run directory instead of running the DEM.
    pub dem_run: Option<PathBuf>,
    /// A second DEM run of the same scene with another seed: the scale of the pattern distance.
    pub seed_scale_run: Option<PathBuf>,
    pub sample_cache: PathBuf,
    /// Vibrated box only: runs per model.
    pub seeds: u64,
    /// Vibrated box only: simulated time discarded before sampling (s).
    pub transient: f64,
}

fn stage(quiet: bool, k: usize, what: &str) {
    if !quiet {
        eprintln!("compare [{k}/4] {what}");
    }
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?)
}

/// The pattern distance between the models in words: scaled by the seed-to-seed distance
/// where there is one, and never called agreement without it.
fn structure_line(distance: Option<f64>, scale: Option<f64>) -> String {
    match (distance, scale) {
        (None, _) => "Pattern distance: not defined (a run has no structure factor).".into(),
        (Some(d), Some(s)) if s > 0.0 => {
            let r = d / s;
            if r <= 1.0 {
                format!("Pattern distance {d:.3}, {r:.2} times the distance between two DEM seeds ({s:.3}): the structures agree as closely as two seeds do.")
            } else {
                format!("Pattern distance {d:.3}, {r:.2} times the distance between two DEM seeds ({s:.3}): the structures differ, whatever their labels.")
            }
        }
        (Some(d), _) => format!(
            "Pattern distance {d:.3} (late S(k) and band widths; 0 for one pattern). Without a second DEM seed (`--seed-scale-run`) it has no scale, \
             so no agreement in structure is claimed."
        ),
    }
}

/// A number for the report: to the millisecond (times), or "none".
fn fmt_opt(v: Option<f64>) -> String {
    v.filter(|f| f.is_finite()).map_or("none".into(), |f| format!("{f:.3}"))
}

/// What the thesis reports for its reference tray (thesis 3.5.4, Table 3.5).
const THESIS: &str = "stripes after 3-5 s and 4 +- 0.875 stripes after 20 s (N = 4000 on 0.4 m x 0.02 m, 20 Hz, 25 mm); \
MSD per period plateaus at a1 ~ 1.6e-4 m^2 before and a2 ~ 8.9e-4 m^2 after the onset (frictionless ~ 4e-5 m^2)";

/// What the thesis' experiment shows at its gentle drive (thesis 2.2.6: 3 Hz, 10 mm, Gamma 0.36,
/// the rolling regime of `scenes/stripes.toml`).
const EXPERIMENT: &str = "irregular clusters after about 1 s, merging into distinct stripes within 3-5 s \
(clear at 10 s), static relative to the plate while the grains between them move like a gas (mustard seeds, 3 Hz, 10 mm)";

/// Where the two models agree and where they differ, in words, with the likely reason.
/// `rolling`: a free sphere rolls without slip on the drive (the automaton's frustration and
/// trains act, [`::automaton::mapping::rolls_without_slip`]).
fn agreement(dem: &Outcome, auto: &Outcome, rolling: bool) -> Vec<String> {
    let mut out = Vec::new();
    let (pd, pa) = (dem.phase_name(), auto.phase_name());
    out.push(if pd == pa {
        format!("Both models give phase `{pd}`.")
    } else {
        format!("The phases differ: DEM `{pd}`, automaton `{pa}`.")
    });
    {
        let (cd, ca) = (dem.stripe_count_final, auto.stripe_count_final);
        let d = cd.abs_diff(ca);
        out.push(if d <= 1 {
            format!("Stripe counts agree within one stripe (DEM {cd}, automaton {ca}).")
        } else {
            format!("Stripe counts differ by {d} (DEM {cd}, automaton {ca}).")
        });
    }
    if let (Some(sd), Some(sa)) = (dem.stripe_spacing(), auto.stripe_spacing()) {
        let r = sa / sd;
        let within = (0.85..=1.15).contains(&r);
        out.push(format!(
            "Spacing: DEM {:.1} mm, automaton {:.1} mm (ratio {r:.2}){}.",
            sd * 1e3,
            sa * 1e3,
            if within { ", within 15 %" } else { "" }
        ));
        if rolling && !within {
            out.last_mut().expect("just pushed").push_str(
                " The automaton's spacing depends on its cell length, a coarse-graining fitted for the onset \
                 (docs/results/automaton-rolling/report.md); what sets the DEM's is open (docs/results/spacing/report.md).",
            );
        }
    }
    match (dem.stripe_onset_s, auto.stripe_onset_s) {
        (Some(od), Some(oa)) => {
            let r = oa / od;
            let mut line = format!("Onset: DEM {od:.2} s, automaton {oa:.2} s (ratio {r:.2}).");
            if r > 1.5 && rolling {
                line.push_str(
                    " The automaton's bands grow more slowly: a crowded grain is held at random, with probability \
                     1 - (1 - h)^n per half period, while in the DEM every grain's rolling amplitude falls with the local packing at once, \
                     so dense patches follow the floor from the first periods (docs/results/mechanism/report.md, section 3).",
                );
            } else if r < 1.0 / 1.5 {
                line.push_str(" The automaton's bands form sooner than the DEM's.");
            }
            out.push(line);
        }
        (od, oa) => out.push(format!(
            "Onset: DEM {}, automaton {}.",
            od.map_or("none".into(), |v| format!("{v:.2} s")),
            oa.map_or("none".into(), |v| format!("{v:.2} s"))
        )),
    }
    out
}

/// One sentence on what a model's layer did, from its analysis summary keys.
fn interpret(model: &str, keys: &Outcome) -> String {
    let mobility = keys
        .mobility
        .map_or("unknown".into(), |m| format!("{m:.3} mean diameters per period"));
    let contrast = keys.contrast.map_or("unknown".into(), |c| format!("{c:.2} x a random layer"));
    let plateaus = match (keys.msd_plateau_before, keys.msd_plateau_after) {
        (None, None) => "no flat MSD plateau".to_string(),
        (a, b) => format!(
            "MSD plateaus a1 = {}, a2 = {}",
            a.map_or("none".into(), |v| format!("{v:.2e} m^2")),
            b.map_or("none".into(), |v| format!("{v:.2e} m^2"))
        ),
    };
    let sentence = match keys.phase {
        Some(Phase::Nothing) => format!(
            "The {model} layer stayed in lockstep with the tray (mobility {mobility}, below the `nothing` threshold): no stripes, contrast {contrast}; {plateaus}."
        ),
        Some(Phase::Stripes) => {
            let onset = keys
                .stripe_onset_s
                .map_or("no onset found (no lasting stripe count)".to_string(), |t| format!("onset {t:.3} s"));
            if keys.stripe_count_final > 0 {
                format!(
                    "The {model} formed stripes: {} at the end ({} stationary), {onset}, contrast {contrast}, mobility {mobility}; {plateaus}.",
                    keys.stripe_count_final, keys.stationary_stripe_count,
                )
            } else {
                // The label comes from bands that held their place over the last periods (or the
                // contrast); the last frame's count is what the threshold sees in one frame.
                format!(
                    "The {model} is labelled `stripes` ({} band(s) held their place over the last periods), but its last frame \
                     holds no stripe above the threshold; {onset}, contrast {contrast}, mobility {mobility}; {plateaus}.",
                    keys.stationary_stripe_count,
                )
            }
        }
        Some(Phase::Gas) => format!(
            "The {model} layer stayed mobile without lasting stripes (a gas): mobility {mobility}, contrast {contrast}, {} stripes at the end; {plateaus}.",
            keys.stripe_count_final,
        ),
        None => format!(
            "The {model} run gives no phase: {}.",
            keys.phase_note.as_deref().unwrap_or("unknown reason")
        ),
    };
    match keys.phase_votes {
        Some(v) => format!(
            "{sentence} The label rests on the classifier's thresholds: of 27 threshold sets around the default, {} say stripes, {} gas and {} nothing.",
            v.stripes, v.gas, v.nothing
        ),
        None => sentence,
    }
}

/// Every warning of the runs and analyses, named by where it came from.
fn run_warnings(sources: &[(&str, &[String])]) -> Vec<String> {
    sources
        .iter()
        .flat_map(|(name, ws)| ws.iter().map(move |w| format!("{name}: {w}")))
        .collect()
}

/// What a DEM run's `summary.json` tells the report: its speed and its warnings. A run
/// reused with `--dem-run` may have stopped before its end, without a summary: all unknown.
#[derive(Clone, Debug, Default, serde::Deserialize)]
struct DemRunNumbers {
    particle_steps_per_s: Option<f64>,
    wall_s: Option<f64>,
    #[serde(default)]
    warnings: Vec<String>,
}

/// One colour scale for several maps: from the lowest to the highest value of any.
fn common_scale(maps: &[Heatmap]) -> (f64, f64) {
    maps.iter()
        .map(Heatmap::own_range)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (l, h)| (a.min(l), b.max(h)))
}

/// The density map of an analysis directory, titled with the model: the camera's
/// (`camera_profiles.csv`: one frame per drive period at the turning point, positions relative
/// to the tray) where the analysis has one, else every frame as stored (`density_map.csv`).
/// Issue 43: the DEM's map was drawn from its lab-frame frames, four per period, so that its
/// bands zig-zagged by the drive's amplitude beside the automaton's.
fn density_map(model: &str, analysis: &Path, length: f64) -> Result<Heatmap, CliError> {
    let camera = analysis.join("camera_profiles.csv");
    // The camera's table has the tray's displacement after the time.
    let (p, skip, frames) = if camera.is_file() {
        (camera, 2, ", tray frame at the turning points")
    } else {
        (analysis.join("density_map.csv"), 1, ", every frame as stored")
    };
    let (_, rows) = read_csv(&p).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
    let t0 = rows.first().map_or(0.0, |r| r[0]);
    let t1 = rows.last().map_or(1.0, |r| r[0]).max(t0 + 1e-9);
    Ok(Heatmap {
        title: format!("{model}: area fraction phi(x, t){frames}"),
        x_label: "x (m)".into(),
        y_label: "t (s)".into(),
        x_range: (0.0, length),
        y_range: (t0, t1),
        values: rows.into_iter().map(|r| r[skip.min(r.len())..].to_vec()).collect(),
        colorbar_label: "area fraction".into(),
        scale: None,
        cell_names: None,
    })
}

/// The two models' stripe counts on one time axis: a row at every time either model has a
/// frame, each model's count that of its latest frame at or before it (NaN before its first
/// frame and after its last). Frames are paired by time, never by index: the models take
/// their frames at different rates.
fn one_time_axis(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<Vec<f64>> {
    let mut times: Vec<f64> = a.iter().chain(b).map(|p| p.0).filter(|t| t.is_finite()).collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    let at = |series: &[(f64, f64)], t: f64| {
        let last = series.last().map_or(f64::NEG_INFINITY, |p| p.0);
        if t > last {
            return f64::NAN;
        }
        series.iter().take_while(|p| p.0 <= t).last().map_or(f64::NAN, |p| p.1)
    };
    times.into_iter().map(|t| vec![t, at(a, t), at(b, t)]).collect()
}

/// Both models on the scene and its sample, analysed alike, written to `report.md`; a scene
/// with `drive.direction = "z"` goes to the vibrated box's three-way check.
/// What `stripes compare` found: the tray's DEM against the automaton, or the vibrated
/// box's three models; `summary.json`, field for field.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum CompareSummary {
    Tray(Box<TraySummary>),
    VibratedBox(Box<BoxSummary>),
}

impl Summary for CompareSummary {
    fn headline(&self) -> Headline {
        match self {
            CompareSummary::Tray(t) => Headline::written(t.warnings.len(), &t.written),
            CompareSummary::VibratedBox(b) => b.headline(),
        }
    }
}

/// The DEM and the automaton on one scene and sample.
#[derive(Clone, Debug, Serialize)]
pub struct TraySummary {
    pub scene: String,
    pub sample_key: String,
    pub dem_run: String,
    pub warnings: Vec<String>,
    pub dem: ModelRun,
    pub automaton: ModelRun,
    /// The automaton derived from this DEM run (the `swing` rule from its measures), or why
    /// there is none (`derived_note`).
    pub derived: Option<ModelRun>,
    pub derived_note: Option<String>,
    pub pattern_distance: Option<f64>,
    pub pattern_distance_seed_scale: Option<f64>,
    pub pattern_distance_scaled: Option<f64>,
    #[serde(flatten)]
    pub written: Written,
}

/// One model's run: its analysis' shared keys, its speed and its bands.
#[derive(Clone, Debug, Serialize)]
pub struct ModelRun {
    /// The keys of the analysis that every model's summary repeats
    /// ([`crate::analyze::AnalysisSummary::shared_keys`]).
    pub analysis: serde_json::Map<String, serde_json::Value>,
    #[serde(flatten)]
    pub speed: Speed,
    pub wall_s: Option<f64>,
    pub spacing_m: Option<f64>,
    pub band_width_m: Option<f64>,
    pub in_band_fraction: Option<f64>,
}

/// A model's speed in its own unit.
#[derive(Clone, Copy, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Speed {
    ParticleStepsPerS(Option<f64>),
    CellUpdatesPerS(Option<f64>),
}

pub fn compare_scene(args: &Options) -> Result<CompareSummary, CliError> {
    let file = load_scene(&args.scene, &args.overrides)?;
    let scene = &file.dem;
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("out/compare-{name}")));
    // A vertically vibrated box is compared with the event-driven model, not the automaton.
    if crate::studies::vibrated_box::is_vibrated_box(scene) {
        let summary = crate::studies::vibrated_box::compare(
            &file,
            &crate::studies::vibrated_box::Options {
                scene: args.scene.clone(),
                out,
                seeds: args.seeds,
                transient: args.transient,
                sample_cache: args.sample_cache.clone(),
                force: args.force,
                quiet: args.quiet,
            },
        )?;
        return Ok(CompareSummary::VibratedBox(Box::new(summary)));
    }
    // Everything that can be checked is checked before anything is written or removed: the
    // lattice, a given DEM run, then the one claim of a resumable run (its checkpoint in
    // `dem/`; a resume on a given `--dem-run` has none of its own to find), then a resume
    // continues only the comparison it finds, both models on the scene given now.
    crate::automaton::lattice::validate_lattice(&file)?;
    if let Some(d) = &args.dem_run {
        check_dem_run(d, scene)?;
    }
    let fresh = if args.resume && args.dem_run.is_some() {
        !out.exists()
    } else {
        crate::rundir::output::claim_resumable(&out, &out.join("dem"), "an earlier comparison", args.resume, args.force, &[])?
    };
    if args.resume && args.dem_run.is_none() {
        crate::rundir::resume::check(&out.join("dem"), &file, &format!("--resume {}", out.display()))?;
    }
    let result = compare(args, &file, &out);
    if result.is_err() && fresh && !out.join("dem").join("checkpoint.bin").is_file() {
        // A failed start leaves nothing behind; a DEM run that got going is kept for --resume.
        let _ = std::fs::remove_dir_all(&out);
    }
    result
}

/// `--dem-run`: its resolved scene must be this scene (every key but the thread count and
/// the checkpoint interval), and so its sample.
fn check_dem_run(d: &Path, scene: &particles::scene::Scene) -> Result<(), CliError> {
    let dem_scene = load_scene(&d.join("scene.toml"), &[])?.dem;
    // The whole resolved scene must agree, not only the sample: a 20 Hz DEM run compared
    // with a 10 Hz automaton run is not "the same scene".
    let differ = crate::scene::file::differences(&dem_scene, scene);
    if !differ.is_empty() {
        return Err(format!(
            "--dem-run {}: its scene.toml differs from this scene in {} key(s) (its value -> this scene's): {}",
            d.display(),
            differ.len(),
            differ.join("; ")
        )
        .into());
    }
    if sample_key(&dem_scene) != sample_key(scene) {
        return Err(format!(
            "--dem-run {}: its sample ({:016x}) is not the scene's ({:016x}); both models must start from the same sample",
            d.display(),
            sample_key(&dem_scene),
            sample_key(scene)
        )
        .into());
    }
    Ok(())
}

fn compare(args: &Options, file: &crate::scene::file::SceneFile, out: &Path) -> Result<CompareSummary, CliError> {
    let scene = &file.dem;
    let args_json = json!({ "args": args, "scene": file });
    // A resume rewrites config.json only once both runs are done: one killed on the way
    // leaves the directory's description as it was.
    let mut dir = if args.resume {
        RunDir::open(out)?
    } else {
        RunDir::create(out, &args_json)?
    };

    // 1. DEM.
    let mut fresh = None;
    let dem_dir = match &args.dem_run {
        Some(d) => {
            stage(args.quiet, 1, &format!("DEM: reusing {}", d.display()));
            d.clone()
        }
        None => {
            let d = out.join("dem");
            // Finished at the duration asked for; a longer one extends the run.
            let finished = args.resume
                && d.join("summary.json").is_file()
                && load_scene(&d.join("scene.toml"), &[]).is_ok_and(|f| f.dem.run.duration == scene.run.duration);
            stage(
                args.quiet,
                1,
                if finished {
                    "DEM run (finished before: kept)"
                } else if args.resume {
                    "DEM run (resumed from its checkpoint)"
                } else {
                    "DEM run"
                },
            );
            if !finished {
                let resolved = resolve(&args.scene, file.clone())?;
                let summary = run_dem(
                    &resolved,
                    &RunOptions {
                        out: d.clone(),
                        resume: args.resume,
                        force: args.force,
                        sample_cache: args.sample_cache.clone(),
                        quiet: args.quiet,
                        ..RunOptions::default()
                    },
                )?;
                fresh = Some(summary);
            }
            d
        }
    };
    // A run reused with --dem-run may have stopped before its end, without summary.json: its
    // speed is then unknown. A summary that is there but unreadable is an error.
    let summary = dem_dir.join("summary.json");
    let dem_run = match (fresh, &args.dem_run) {
        (Some(s), _) => DemRunNumbers {
            particle_steps_per_s: Some(s.particle_steps_per_s),
            wall_s: Some(s.wall_s),
            warnings: s.warnings,
        },
        (None, Some(_)) if !summary.exists() => DemRunNumbers::default(),
        (None, _) => read_json(&summary)?,
    };

    // 2. Automaton, same scene and sample.
    stage(args.quiet, 2, "automaton run");
    let auto_dir = out.join("automaton");
    let automaton = run_automaton(
        &resolve_lattice(&args.scene, file.clone())?,
        &AutomatonOptions {
            out: auto_dir.clone(),
            force: true, // inside the comparison's own directory, claimed above
            rule: None,
            sample_cache: args.sample_cache.clone(),
            quiet: args.quiet,
        },
    )?;

    // The automaton derived from this DEM run (issue 40): its measures, then the swing rule.
    let derived =
        crate::studies::derived::derive(&args.scene, file, &dem_dir, out, &args.sample_cache, args.quiet).map_err(|e| e.to_string());

    if args.resume {
        dir.json("config.json", &args_json)?;
    }

    // 3. The same analysis of both (the automaton's was made by its run).
    stage(args.quiet, 3, "analysis");
    let dem_analysis_dir = out.join("dem-analysis");
    // The DEM run (fresh, or reused and checked to be this scene's) is described by the scene.
    let dem_analysed = analyze(
        &dem_dir,
        &AnalysisOptions::into_dir(dem_analysis_dir.clone()).described(crate::analyze::run::describe_tray(scene)),
    )?;
    let (dem_keys, auto_keys) = (dem_analysed.outcome(), automaton.analysed.outcome());

    // The structures, and their distance; a second DEM seed gives its scale.
    let dem_structure = read::late_structure(&dem_analysis_dir)?;
    let auto_structure = read::late_structure(&auto_dir.join("analysis"))?;
    let pattern_distance = analysis::structure::distance(&dem_structure, &auto_structure);
    let seed_scale = match &args.seed_scale_run {
        Some(d) => {
            // Another seed: only run.seed (and so the sample) may differ from this scene.
            let other = load_scene(&d.join("scene.toml"), &[])?.dem;
            let differ = crate::scene::file::differences(&other, scene);
            if differ.len() != 1 || !differ[0].starts_with("run.seed:") {
                return Err(format!(
                    "--seed-scale-run {} must be this scene with another run.seed; it differs in: {}",
                    d.display(),
                    if differ.is_empty() {
                        "nothing (the same seed)".to_string()
                    } else {
                        differ.join("; ")
                    }
                )
                .into());
            }
            let dir2 = out.join("seed-scale-analysis");
            analyze(d, &AnalysisOptions::into_dir(dir2.clone()))?;
            analysis::structure::distance(&dem_structure, &read::late_structure(&dir2)?)
        }
        None => None,
    };

    // 4. Report.
    stage(args.quiet, 4, "report");
    let dem_counts = read::counts(&dem_analysis_dir)?;
    let auto_counts = read::counts(&auto_dir.join("analysis"))?;
    let mut plot = LinePlot::new("Stripe count over time, same scene and sample", "t (s)", "stripes")
        .integer_y()
        .series("DEM", dem_counts.clone(), Mark::LinePoints)
        .series("automaton", auto_counts.clone(), Mark::LinePoints);
    if let Ok(d) = &derived {
        plot = plot.series(
            "automaton derived from the DEM (swing)",
            read::counts(&d.analysis)?,
            Mark::LinePoints,
        );
    }
    dir.plot("stripe_count", &plot)?;
    let rows = one_time_axis(&dem_counts, &auto_counts);
    dir.csv("stripe_count.csv", &["t", "count_dem", "count_automaton"], &rows)?;
    // The two density maps on one colour scale, each titled with its model.
    let maps = [
        density_map("DEM", &dem_analysis_dir, scene.tray.length)?,
        density_map("automaton", &auto_dir.join("analysis"), scene.tray.length)?,
    ];
    let scale = common_scale(&maps);
    for (map, stem) in maps.into_iter().zip(["density_map_dem", "density_map_automaton"]) {
        let map = Heatmap { scale: Some(scale), ..map };
        let files = map.save(&out.join(stem)).map_err(|e| format!("cannot draw {stem}: {e}"))?;
        dir.note_files(files);
    }

    let (dem_speed, dem_wall) = (dem_run.particle_steps_per_s, dem_run.wall_s);
    let (auto_speed, auto_wall) = (Some(automaton.cell_updates_per_s), Some(automaton.wall_s));
    let simulated = scene.run.duration;
    let speed = |wall: Option<f64>| wall.map_or("unknown".to_string(), |w| format!("{:.3}", simulated / w.max(1e-12)));
    let mut md = String::new();
    md.push_str(&format!("# DEM and automaton on `{}`\n\n", args.scene.display()));
    md.push_str(&format!(
        "Same scene and same prepared sample (key `{:016x}`), same analysis (`stripes analyze`: exact area fraction in 1 mm cells, \
         stripes above 1.5 x the mean area fraction, capped halfway from the mean to a jammed layer's 0.82, and at least five mean \
         diameters wide; the phase is `stripes` when a band holds its place over the last 10 drive periods, or when the contrast \
         is at least 2 with a stripe in the final frames; the analysis defaults). {} grains on a {} m x {} m tray, \
         {} Hz, {} m, {} s.\n\n",
        sample_key(scene),
        scene.particles.count,
        scene.tray.length,
        scene.tray.width,
        scene.drive.frequency,
        scene.drive.amplitude,
        scene.run.duration
    ));
    md.push_str("## What happened\n\n");
    md.push_str(&format!("- {}\n", interpret("DEM", &dem_keys)));
    md.push_str(&format!("- {}\n", interpret("automaton", &auto_keys)));
    match &derived {
        Ok(d) => md.push_str(&format!(
            "- {} (the `swing` rule from `{}`, which `stripes mechanism` measured on this DEM run; issue 40's validation \
             ladder has not held, docs/results/coarse-model/report.md)\n",
            interpret("derived automaton", &d.keys),
            d.parameters.strip_prefix(out).unwrap_or(&d.parameters).display()
        )),
        Err(why) => md.push_str(&format!("- No automaton derived from this DEM run: {why}\n")),
    }
    md.push_str(&format!("- The thesis' simulation (reference tray, sec 3.5.4): {THESIS}\n"));
    md.push_str(&format!("- The thesis' experiment (sec 2.2.6): {EXPERIMENT}\n\n"));
    let rolling = file.automaton.rolling && ::automaton::mapping::rolls_without_slip(&crate::automaton::lattice::tray_drive(scene));
    md.push_str("## Where they agree and where they differ\n\n");
    for line in agreement(&dem_keys, &auto_keys, rolling) {
        md.push_str(&format!("- {line}\n"));
    }
    md.push_str(&format!("- {}\n", structure_line(pattern_distance, seed_scale)));
    md.push('\n');
    let mm = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{:.1}", x * 1e3));
    md.push_str("## Structure\n\n| model | S(k) peak spacing (mm) | peak height | band width (mm) | gap (mm) | grains in bands |\n|---|---|---|---|---|---|\n");
    let derived_keys = derived.as_ref().ok().map(|d| &d.keys);
    let structure_rows = [
        ("DEM", Some(&dem_keys)),
        ("automaton", Some(&auto_keys)),
        ("derived automaton (swing)", derived_keys),
    ];
    for (name, k) in structure_rows.into_iter().filter_map(|(n, k)| k.map(|k| (n, k))) {
        md.push_str(&format!(
            "| {name} | {} | {} | {} | {} | {} |\n",
            mm(k.spacing_m),
            fmt_opt(k.structure_peak_height),
            mm(k.band_width_m),
            mm(k.band_gap_m),
            fmt_opt(k.in_band_fraction),
        ));
    }
    md.push_str(
        "\nSpacing is the peak of the late frames' structure factor S(k) of the grain positions along x (for both models the same \
         measure); band widths and gaps are those of the bands of the late frames. S(k) of each model: `dem-analysis/structure_factor.png`, \
         `automaton/analysis/structure_factor.png`.\n\n\
         Top views (x-y) at the first, middle and last frames, to see whether the bands span the tray's width:\n\n\
         ![DEM, top view](dem-analysis/top_view.png)\n\n![automaton, top view](automaton/analysis/top_view.png)\n\n",
    );
    let no_warnings = Vec::new();
    let (derived_run, derived_analysis) = match &derived {
        Ok(d) => (&d.run.warnings, &d.keys.warnings),
        Err(_) => (&no_warnings, &no_warnings),
    };
    let warnings = run_warnings(&[
        ("DEM run", &dem_run.warnings),
        ("DEM analysis", &dem_keys.warnings),
        ("automaton run", &automaton.warnings),
        ("automaton analysis", &auto_keys.warnings),
        ("derived automaton run", derived_run),
        ("derived automaton analysis", derived_analysis),
    ]);
    if !warnings.is_empty() {
        md.push_str("## Warnings of the runs\n\n");
        for w in &warnings {
            md.push_str(&format!("- {w}\n"));
        }
        md.push('\n');
    }
    md.push_str("| model | stripes at the end | spacing (mm) | mean width (mm) | onset (s) | phase | wall time (s) | simulated s per wall s | speed |\n|---|---|---|---|---|---|---|---|---|\n");
    // One row of the models' table: counts, structure and phase from the analysis, then wall
    // time, simulated seconds per wall second and speed.
    let model_row = |name: &str, k: &Outcome, wall: Option<f64>, decimals: usize, rate: String| {
        format!(
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {rate} |\n",
            k.stripe_count_final,
            mm(k.stripe_spacing()),
            mm(k.stripe_mean_width_final_m),
            fmt_opt(k.stripe_onset_s),
            k.phase.map_or("none", Phase::name),
            wall.map_or("unknown".into(), |w| format!("{w:.decimals$}")),
            speed(wall),
        )
    };
    let rate = |v: Option<f64>, unit: &str| v.map_or("unknown".into(), |s| format!("{s:.3e} {unit}"));
    md.push_str(&model_row("DEM", &dem_keys, dem_wall, 1, rate(dem_speed, "particle-steps/s")));
    md.push_str(&model_row(
        "automaton",
        &auto_keys,
        auto_wall,
        2,
        rate(auto_speed, "cell updates/s"),
    ));
    if let Ok(d) = &derived {
        md.push_str(&model_row(
            "derived automaton (swing)",
            &d.keys,
            Some(d.run.wall_s),
            2,
            rate(Some(d.run.cell_updates_per_s), "cell updates/s"),
        ));
    }
    md.push_str("| thesis' simulation (N = 4000, 0.4 m, 20 Hz, 25 mm, 20 s) | 4 +- 0.875 | 100 | | 3 to 5 | stripes | | | |\n");
    md.push_str("| thesis' experiment (3 Hz, 10 mm) | | | | 1 (clusters) to 3-5 (stripes) | stripes | | | |\n\n");
    md.push_str(
        "Wall times cover each model's time loop with its snapshot output; the shared sample preparation and the automaton's \
         single-sphere mapping run are not included. The DEM speed is particle-steps per second of its stepping; the automaton's \
         is lattice cells times half steps per second.\n\n",
    );
    md.push_str("## Stripe count over time\n\n![stripe count](stripe_count.png)\n\n| t (s) | DEM | automaton |\n|---|---|---|\n");
    let every = (rows.len() / 25).max(1);
    for (k, r) in rows.iter().enumerate() {
        if k % every == 0 || k + 1 == rows.len() {
            md.push_str(&format!("| {:.3} | {} | {} |\n", r[0], r[1], r[2]));
        }
    }
    md.push_str("\n## Density maps (area fraction over x and t)\n\n| DEM | automaton |\n|---|---|\n");
    md.push_str("| ![DEM](density_map_dem.png) | ![automaton](density_map_automaton.png) |\n\n");
    md.push_str(
        "Bands narrower than the minimum stripe width (five mean grain diameters, `stripes analyze --min-width`) \
         show in the maps but are not counted as stripes; the automaton's map often has such thin bands, one or \
         two cells wide.\n\n",
    );
    {
        let m = &automaton.mapping;
        md.push_str(&format!(
            "## Automaton mapping\n\nFlight cap {} cells (single-sphere DEM slide {} m per half period, Coulomb block {} m); \
             tray acceleration {} m/s^2 against mu g = {} m/s^2. Parameters: `{}`.\n",
            fmt_opt(Some(m.flight_cap_cells)),
            fmt_opt(Some(m.slide_dem.displacement)),
            fmt_opt(Some(m.slide_coulomb_block.displacement)),
            fmt_opt(Some(m.tray_acceleration)),
            fmt_opt(Some(m.friction_acceleration)),
            serde_json::to_value(automaton.params)?,
        ));
    }
    let report = out.join("report.md");
    analysis::io::write_atomic(&report, md.as_bytes())?;
    dir.note_files([report]);
    // The two runs and their analyses are part of what this command wrote.
    for sub in ["dem", "automaton"] {
        dir.note_tree(Path::new(sub));
    }
    if out.join("derived").is_dir() {
        dir.note_tree(Path::new("derived"));
    }
    let summary = TraySummary {
        scene: args.scene.display().to_string(),
        sample_key: format!("{:016x}", sample_key(scene)),
        dem_run: dem_dir.display().to_string(),
        warnings,
        dem: ModelRun {
            analysis: dem_analysed.shared_keys()?,
            speed: Speed::ParticleStepsPerS(dem_speed),
            wall_s: dem_wall,
            spacing_m: dem_keys.spacing_m,
            band_width_m: dem_keys.band_width_m,
            in_band_fraction: dem_keys.in_band_fraction,
        },
        automaton: ModelRun {
            analysis: automaton.analysed.shared_keys()?,
            speed: Speed::CellUpdatesPerS(auto_speed),
            wall_s: auto_wall,
            spacing_m: auto_keys.spacing_m,
            band_width_m: auto_keys.band_width_m,
            in_band_fraction: auto_keys.in_band_fraction,
        },
        derived: match &derived {
            Ok(d) => Some(ModelRun {
                analysis: d.run.analysis.clone(),
                speed: Speed::CellUpdatesPerS(Some(d.run.cell_updates_per_s)),
                wall_s: Some(d.run.wall_s),
                spacing_m: d.keys.spacing_m,
                band_width_m: d.keys.band_width_m,
                in_band_fraction: d.keys.in_band_fraction,
            }),
            Err(_) => None,
        },
        derived_note: derived.as_ref().err().cloned(),
        pattern_distance,
        pattern_distance_seed_scale: seed_scale,
        pattern_distance_scaled: pattern_distance.and_then(|d| analysis::structure::scaled(d, seed_scale)),
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(CompareSummary::Tray(Box::new(summary)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 42: each model's speed is written under its own key, as the JSON object that
    /// `compare` built before its summary was a struct.
    #[test]
    fn a_models_speed_is_written_under_its_own_key() {
        let run = |speed| ModelRun {
            analysis: serde_json::Map::new(),
            speed,
            wall_s: Some(2.0),
            spacing_m: None,
            band_width_m: Some(1e-3),
            in_band_fraction: None,
        };
        let dem = serde_json::to_value(run(Speed::ParticleStepsPerS(Some(5e6)))).unwrap();
        let automaton = serde_json::to_value(run(Speed::CellUpdatesPerS(None))).unwrap();
        assert_eq!(
            dem.to_string(),
            r#"{"analysis":{},"band_width_m":0.001,"in_band_fraction":null,"particle_steps_per_s":5000000.0,"spacing_m":null,"wall_s":2.0}"#
        );
        assert_eq!(automaton["cell_updates_per_s"], serde_json::Value::Null);
        assert!(automaton.get("particle_steps_per_s").is_none());
    }

    fn outcome(phase: Option<Phase>, count: usize, onset: Option<f64>) -> Outcome {
        Outcome {
            phase,
            stripe_count_final: count,
            stripe_onset_s: onset,
            ..Outcome::default()
        }
    }

    /// Issue 19, point 14: the report says in words what each model did, and repeats every
    /// warning with where it came from.
    #[test]
    fn the_report_interprets_and_repeats_warnings() {
        let dem = Outcome {
            mobility: Some(0.018),
            contrast: Some(0.53),
            ..outcome(Some(Phase::Nothing), 0, None)
        };
        let s = interpret("DEM", &dem);
        assert!(s.contains("stayed in lockstep") && s.contains("mobility 0.018"), "{s}");
        let auto = Outcome {
            stationary_stripe_count: 2,
            contrast: Some(2.5),
            mobility: Some(6.0),
            ..outcome(Some(Phase::Stripes), 3, Some(0.7125))
        };
        let s = interpret("automaton", &auto);
        assert!(s.contains("formed stripes: 3 at the end (2 stationary), onset 0.713 s"), "{s}");
        assert!(!s.contains("thresholds"), "no sweep, no claim about it: {s}");
        let fragile = Outcome {
            phase_votes: Some(analysis::report::PhaseVotes {
                nothing: 0,
                stripes: 21,
                gas: 6,
            }),
            ..auto.clone()
        };
        let s = interpret("DEM", &fragile);
        assert!(
            s.ends_with("of 27 threshold sets around the default, 21 say stripes, 6 gas and 0 nothing."),
            "{s}"
        );
        // Issue 43: a run labelled stripes whose last frame holds none says so, and an onset
        // that was not found is not "none s".
        let held = Outcome {
            stationary_stripe_count: 1,
            ..outcome(Some(Phase::Stripes), 0, None)
        };
        let s = interpret("automaton", &held);
        assert!(!s.contains("formed stripes") && s.contains("last frame holds no stripe"), "{s}");
        assert!(
            s.contains("1 band(s) held") && s.contains("no onset found") && !s.contains("none s"),
            "{s}"
        );
        let none = Outcome {
            phase_note: Some("too few frames for a phase".into()),
            ..Outcome::default()
        };
        assert!(interpret("DEM", &none).contains("no phase: too few frames"));
        assert!(THESIS.contains("4 +- 0.875"));
        let w = run_warnings(&[("DEM run", &["dt coarse".to_string()]), ("automaton run", &[])]);
        assert_eq!(w, vec!["DEM run: dt coarse".to_string()]);
    }

    /// Issue 17, point 4: the report says where the models agree and differ, with spacing.
    #[test]
    fn agreement_names_phase_count_spacing_and_onset() {
        let dem = Outcome {
            spacing_m: Some(0.0333333),
            ..outcome(Some(Phase::Stripes), 3, Some(1.5))
        };
        let auto = Outcome {
            spacing_m: Some(0.05),
            ..outcome(Some(Phase::Stripes), 2, Some(4.5))
        };
        let lines = agreement(&dem, &auto, true);
        assert_eq!(lines[0], "Both models give phase `stripes`.");
        assert!(lines[1].contains("agree within one stripe"), "{lines:?}");
        assert!(
            lines[2].contains("Spacing: DEM 33.3 mm, automaton 50.0 mm (ratio 1.50)"),
            "{lines:?}"
        );
        assert!(lines[3].contains("ratio 3.00") && lines[3].contains("more slowly"), "{lines:?}");
        let gas = outcome(Some(Phase::Gas), 0, None);
        let lines = agreement(&dem, &gas, false);
        assert!(lines[0].contains("differ") && lines[1].contains("differ by 3"), "{lines:?}");
        assert_eq!(lines.len(), 3, "no spacing without stripes: {lines:?}");
        assert!(lines[2].contains("automaton none"), "{lines:?}");
        assert_eq!(gas.stripe_spacing(), None);
        let gas_with_peak = Outcome {
            spacing_m: Some(0.02),
            ..gas.clone()
        };
        assert_eq!(gas_with_peak.stripe_spacing(), None, "a gas's S(k) peak is not a stripe spacing");
        let sk = Outcome {
            spacing_m: Some(0.04),
            ..outcome(Some(Phase::Stripes), 3, None)
        };
        assert_eq!(
            sk.stripe_spacing(),
            Some(0.04),
            "the S(k) peak (the profile's mode is not in an outcome)"
        );
    }

    /// Issue 19, point 14: the two density maps carry the model's name and share one scale.
    #[test]
    fn density_maps_are_named_and_share_a_scale() {
        let d = std::env::temp_dir().join(format!("stripes-compare-maps-{}", std::process::id()));
        let (a, b) = (d.join("a"), d.join("b"));
        for (dir, hi) in [(&a, 0.5), (&b, 0.8)] {
            std::fs::create_dir_all(dir).unwrap();
            analysis::io::write_csv_atomic(
                &dir.join("density_map.csv"),
                &["t", "x0", "x1"],
                &[vec![0.0, 0.1, hi], vec![0.05, 0.2, 0.3]],
            )
            .unwrap();
        }
        let maps = [density_map("DEM", &a, 0.1).unwrap(), density_map("automaton", &b, 0.1).unwrap()];
        assert!(maps[0].title.starts_with("DEM") && maps[1].title.starts_with("automaton"));
        assert_eq!(common_scale(&maps), (0.1, 0.8));
        // Issue 43, plots: with the camera's stroboscopic tray-frame profiles beside it, the
        // map is drawn from them (one frame per period, the tray's displacement left out), not
        // from the lab-frame frames of density_map.csv.
        analysis::io::write_csv_atomic(
            &a.join("camera_profiles.csv"),
            &["t", "tray_x", "x0", "x1"],
            &[vec![0.0, 0.01, 0.6, 0.7], vec![1.0, -0.01, 0.65, 0.75]],
        )
        .unwrap();
        let map = density_map("DEM", &a, 0.1).unwrap();
        assert_eq!(map.values, vec![vec![0.6, 0.7], vec![0.65, 0.75]]);
        assert_eq!(map.y_range, (0.0, 1.0));
        assert!(map.title.contains("tray frame at the turning points"), "{}", map.title);
        std::fs::remove_dir_all(d).unwrap();
    }

    /// Issue 43, finding 4: the count table pairs the models' frames by time, not by index
    /// (an automaton's frame at 8 s beside the DEM's at 8 s, not beside its 32nd frame).
    #[test]
    fn the_count_table_pairs_frames_by_time() {
        let dem: Vec<(f64, f64)> = (0..=40).map(|k| (0.25 * k as f64, (k / 10) as f64)).collect();
        let auto: Vec<(f64, f64)> = (0..=10).map(|k| (k as f64, 10.0 + k as f64)).collect();
        let rows = one_time_axis(&dem, &auto);
        assert_eq!(rows.len(), 41, "the automaton's times are among the DEM's");
        for r in &rows {
            let k = (r[0] / 0.25).round() as usize;
            assert_eq!(r[1], (k / 10) as f64, "DEM at t = {}", r[0]);
            assert_eq!(
                r[2],
                10.0 + r[0].floor(),
                "automaton at t = {} holds its frame at {}",
                r[0],
                r[0].floor()
            );
        }
        let last = rows.last().unwrap();
        assert_eq!((last[0], last[1], last[2]), (10.0, 4.0, 20.0));
        let short = one_time_axis(&dem[..5], &auto);
        assert!(short.iter().filter(|r| r[0] > 1.0).all(|r| r[1].is_nan() && r[2].is_finite()));
    }

    /// The report never calls two structures in agreement without the seed-to-seed scale,
    /// and calls them different above it.
    #[test]
    fn the_pattern_distance_claims_agreement_only_within_the_seed_scale() {
        assert!(structure_line(Some(0.4), None).contains("no agreement in structure is claimed"));
        assert!(structure_line(Some(0.4), Some(0.1)).contains("the structures differ"));
        assert!(structure_line(Some(0.05), Some(0.1)).contains("agree as closely as two seeds do"));
        assert!(structure_line(None, Some(0.1)).contains("not defined"));
    }
}
