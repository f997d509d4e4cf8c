//! The shared analysis of a run directory, a `snapshots.bin` file or a LAMMPS dump: one
//! [`analysis::report::Report`], written as CSV tables, plots and `summary.json`, and
//! returned as the typed [`AnalysisSummary`].

use std::path::{Path, PathBuf};

use analysis::input::{load_described, DriveDescription, Geometry, InputKind, RunDescription, StageDescription};
use analysis::report::{Options, Summary};
use serde::ser::Error as _;
use serde::{Serialize, Serializer};
use serde_json::Value;

use analysis::camera::{Camera, CameraSummary};
use analysis::classify::{Classification, Phase};

use super::files::{draw, draw_camera, top_view, write_camera, write_tables};
use crate::rundir::output::CliError as Error;
use crate::rundir::output::{RunDir, Written};
use crate::rundir::report::{self, Headline, PhaseLine};

/// How to analyse a run and where to write the analysis.
#[derive(Clone, Debug, Serialize)]
pub struct AnalysisOptions {
    /// The analysis directory (default: `<RUN_DIR>/analysis`, or `<DUMP>.analysis` beside a
    /// dump).
    pub out: Option<PathBuf>,
    /// Replace an earlier analysis in it.
    pub force: bool,
    /// Time step of a LAMMPS dump (s); ignored for snapshots.
    pub dt: f64,
    /// The analysis' settings; without a period, the run's metadata gives it.
    pub options: Options,
    /// Times (s) of the top views of a tray (`top_view.png`); empty: the first, middle and
    /// last stroboscopic frames.
    pub top_view: Vec<f64>,
    /// The frame of `density_map.png`: the camera's (tray frame, one frame per period at the
    /// turning point) or every frame as stored (lab frame).
    pub map_frame: MapFrame,
    /// The run's description (tray or box, drive), given typed by a command that has just
    /// run the model from its scene ([`describe_tray`]); none: read from the run's
    /// `config.json`.
    #[serde(skip)]
    pub description: Option<RunDescription>,
}

/// The description of a run of a tray scene, for its analysis: a tray, its drive's
/// frequency, amplitude, direction and stages, as the scene gives them (what the run's
/// `config.json` says of it, without reading it back).
pub fn describe_tray(scene: &particles::scene::Scene) -> RunDescription {
    let d = &scene.drive;
    RunDescription {
        geometry: Geometry::Tray,
        drive: Some(DriveDescription {
            frequency: d.frequency,
            amplitude: Some(d.amplitude),
            horizontal: d.direction == particles::scene::DriveDirection::X,
            stages: d
                .stages
                .iter()
                .map(|s| StageDescription {
                    frequency: s.frequency,
                    amplitude: s.amplitude,
                    duration: s.duration,
                })
                .collect(),
        }),
    }
}

/// Which frames and positions `density_map.png` draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MapFrame {
    /// The stroboscopic frames at the drive's turning points, positions relative to the tray.
    #[default]
    Tray,
    /// Every frame, positions as stored (the DEM's: the lab frame).
    Lab,
}

impl std::str::FromStr for MapFrame {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "tray" => Ok(MapFrame::Tray),
            "lab" => Ok(MapFrame::Lab),
            _ => Err(format!("expected `tray` or `lab`, got `{s}`")),
        }
    }
}

impl AnalysisOptions {
    /// The defaults of `stripes analyze`, into `out`, replacing an earlier analysis there
    /// (a command that analyses its own run owns that directory).
    pub fn into_dir(out: PathBuf) -> Self {
        Self {
            out: Some(out),
            force: true,
            dt: analysis::lammps::DEFAULT_DT,
            options: Options::default(),
            top_view: Vec::new(),
            map_frame: MapFrame::Tray,
            description: None,
        }
    }

    /// These options, with the run's description given ([`AnalysisOptions::description`]).
    pub fn described(self, description: RunDescription) -> Self {
        Self {
            description: Some(description),
            ..self
        }
    }
}

/// Where the drive period of an analysis came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PeriodSource {
    /// Given in the options (`--period`).
    Given,
    /// The run's `config.json`.
    Metadata,
    /// The run's scene, given by the command that has just run it
    /// ([`AnalysisOptions::description`]).
    Described,
    /// The median spacing of the snapshots.
    Spacing,
}

impl PeriodSource {
    pub fn describe(self) -> &'static str {
        match self {
            PeriodSource::Given => "--period",
            PeriodSource::Metadata => "run metadata (config.json: 1 / scene.drive.frequency)",
            PeriodSource::Described => "run metadata (the run's scene, given by the command that ran it: 1 / drive.frequency)",
            PeriodSource::Spacing => "median snapshot spacing",
        }
    }
}

/// Cells of the density map, per frame and in all (8 bytes each), beyond which `--cell` is
/// refused before anything is allocated.
pub const MAX_MAP_CELLS_PER_FRAME: f64 = 1e6;
pub const MAX_MAP_CELLS: f64 = 2e8;

/// Why an event-driven run of a vertical box gets no phase.
pub const VERTICAL_BOX_NOTE: &str = "an event-driven run of a vertical box: its frames are the (x, z) plane, so the area fraction is grains per column (not a packing) and the tray's phases do not apply; phase left unclassified. The density map, structure factor and bands still describe the horizontal profile over time";

/// What an analysis found: the report's scalars and where they came from. Serialises as
/// the analysis directory's `summary.json`: the report's keys, then `input`, `input_kind`,
/// `period_source`, `velocity_columns` (dumps), `warnings`, `out` and `files`; the phase
/// of a vertical box is `"unclassified"`.
#[derive(Clone, Debug)]
pub struct AnalysisSummary {
    pub report: Summary,
    pub input: PathBuf,
    pub input_kind: InputKind,
    pub geometry: Geometry,
    pub period_source: PeriodSource,
    pub velocity_columns: Option<Vec<String>>,
    /// The reader's, the classifier's and the geometry's warnings.
    pub warnings: Vec<String>,
    pub written: Written,
    /// The camera's measures (a tray only), with `label_note` when the phase and the last
    /// stroboscopic frame's count disagree.
    pub camera: Option<CameraSummary>,
    pub camera_label_note: Option<String>,
}

/// The keys of an analysis summary that a model's own summary repeats (`stripes
/// automaton`, `stripes compare`).
const SHARED_KEYS: [&str; 21] = [
    "camera",
    "stripe_count_final",
    "stripe_onset_s",
    "phase",
    "phase_note",
    "phase_robust",
    "phase_votes",
    "mobility",
    "contrast",
    "stationary_stripe_count",
    "stripe_mean_width_final_m",
    "stripe_spacing_m",
    "msd_plateau_before",
    "msd_plateau_after",
    "spacing_m",
    "structure_peak_height",
    "structure_peak_width_per_m",
    "band_width_m",
    "band_gap_m",
    "in_band_fraction",
    "warnings",
];

impl AnalysisSummary {
    /// The summary as JSON (`summary.json`).
    pub fn to_json(&self) -> Result<serde_json::Map<String, Value>, serde_json::Error> {
        let Value::Object(mut m) = serde_json::to_value(&self.report)? else {
            return Err(serde_json::Error::custom("the report's summary is not a JSON object"));
        };
        m.insert("input".into(), self.input.display().to_string().into());
        m.insert("input_kind".into(), serde_json::to_value(self.input_kind)?);
        m.insert("period_source".into(), self.period_source.describe().into());
        m.insert("geometry".into(), serde_json::to_value(self.geometry)?);
        if let Some(cols) = &self.velocity_columns {
            m.insert("velocity_columns".into(), serde_json::to_value(cols)?);
        }
        if self.geometry == Geometry::VerticalBox {
            m.insert("phase".into(), "unclassified".into());
            m.insert("phase_note".into(), VERTICAL_BOX_NOTE.into());
        }
        if let Some(c) = &self.camera {
            let mut v = serde_json::to_value(c)?;
            if let Value::Object(o) = &mut v {
                o.insert("label_note".into(), serde_json::to_value(&self.camera_label_note)?);
            }
            m.insert("camera".into(), v);
        }
        m.insert("warnings".into(), serde_json::to_value(&self.warnings)?);
        m.insert("out".into(), self.written.out.clone().into());
        m.insert("files".into(), serde_json::to_value(&self.written.files)?);
        Ok(m)
    }

    /// The keys a model's summary repeats (phase, stripes, structure, plateaus, warnings).
    pub fn shared_keys(&self) -> Result<serde_json::Map<String, Value>, serde_json::Error> {
        let mut all = self.to_json()?;
        Ok(SHARED_KEYS.iter().filter_map(|k| all.remove_entry(*k)).collect())
    }

    /// What this analysis says, typed, as the reports that set models side by side read it
    /// (`stripes compare`); [`Self::shared_keys`] is the same for `summary.json`.
    pub fn outcome(&self) -> Outcome {
        let r = &self.report;
        let vertical = self.geometry == Geometry::VerticalBox;
        Outcome {
            phase: if vertical { None } else { r.phase },
            phase_note: if vertical {
                Some(VERTICAL_BOX_NOTE.into())
            } else {
                r.phase_note.clone()
            },
            phase_votes: (!r.phase_robust).then_some(r.phase_votes),
            stripe_count_final: r.stripe_count_final,
            stationary_stripe_count: r.stationary_stripe_count,
            stripe_onset_s: r.stripe_onset_s,
            stripe_mean_width_final_m: r.stripe_mean_width_final_m,
            mobility: finite(r.mobility),
            contrast: finite(r.contrast),
            msd_plateau_before: r.msd_plateau_before,
            msd_plateau_after: r.msd_plateau_after,
            spacing_m: r.spacing_m,
            structure_peak_height: r.structure_peak_height,
            band_width_m: r.band_width_m,
            band_gap_m: r.band_gap_m,
            in_band_fraction: finite(r.in_band_fraction),
            warnings: self.warnings.clone(),
        }
    }
}

/// A value that `summary.json` would write as `null` (NaN, infinite) is none.
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// What a model's analysis found, typed: the phase (none where it has none: too few frames,
/// a vertical box), the threshold sets' votes where the label is not robust, the stripes,
/// the structure, the MSD plateaus and the analysis' warnings. Read by the reports that set
/// two models side by side; `summary.json` writes the same values by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outcome {
    pub phase: Option<Phase>,
    pub phase_note: Option<String>,
    /// The votes of the 27 threshold sets around the default, when they do not all agree
    /// with the label (`phase_robust = false`).
    pub phase_votes: Option<analysis::report::PhaseVotes>,
    pub stripe_count_final: usize,
    pub stationary_stripe_count: usize,
    pub stripe_onset_s: Option<f64>,
    pub stripe_mean_width_final_m: Option<f64>,
    /// Mean diameters per drive period.
    pub mobility: Option<f64>,
    /// Density contrast, times a random layer's.
    pub contrast: Option<f64>,
    pub msd_plateau_before: Option<f64>,
    pub msd_plateau_after: Option<f64>,
    /// The late frames' S(k) peak spacing (m).
    pub spacing_m: Option<f64>,
    pub structure_peak_height: Option<f64>,
    pub band_width_m: Option<f64>,
    pub band_gap_m: Option<f64>,
    pub in_band_fraction: Option<f64>,
    pub warnings: Vec<String>,
}

impl Outcome {
    /// The phase's name, `unknown` without one.
    pub fn phase_name(&self) -> &'static str {
        self.phase.map_or("unknown", Phase::name)
    }

    /// The stripe spacing (m) of a run with stripes: the late frames' S(k) peak, the one
    /// measure used for every model; none for a run without stripes (a gas's S(k) peak is
    /// not a stripe spacing).
    pub fn stripe_spacing(&self) -> Option<f64> {
        let striped = self.phase == Some(Phase::Stripes) || self.stripe_count_final > 0;
        striped.then_some(self.spacing_m).flatten()
    }
}

impl AnalysisSummary {
    /// The classification's part of a line for people: the phase, the final stripe count
    /// and whether the label is robust.
    pub fn phase_line(&self) -> PhaseLine {
        let r = &self.report;
        let phase = if self.geometry == Geometry::VerticalBox {
            Some("unclassified".to_string())
        } else {
            r.phase.map(|p| p.name().to_string())
        };
        PhaseLine {
            phase,
            stripe_count_final: Some(r.stripe_count_final),
            robust: Some(if r.phase_robust { Ok(()) } else { Err(r.phase_votes) }),
        }
    }
}

impl report::Summary for AnalysisSummary {
    fn headline(&self) -> Headline {
        Headline {
            phase: Some(self.phase_line()),
            ..Headline::written(self.warnings.len(), &self.written)
        }
    }
}

impl Serialize for AnalysisSummary {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.to_json().map_err(S::Error::custom)?.serialize(s)
    }
}

/// Analyses the run at `input` (a run directory, `snapshots.bin` or a LAMMPS dump) and
/// writes the analysis directory. The drive period is the options', else the run's
/// metadata, never the snapshot spacing when the metadata is there (a cut-off file has too
/// few frames to infer it).
pub fn analyze(input: &Path, opts: &AnalysisOptions) -> Result<AnalysisSummary, Error> {
    let mut options = opts.options.clone();
    let run = load_described(input, opts.dt, opts.description.as_ref())?;
    for w in &run.warnings {
        eprintln!("warning: {w}");
    }
    let period_source = if options.period.is_some() {
        PeriodSource::Given
    } else if let Some(p) = run.period {
        options.period = Some(p);
        if opts.description.is_some() {
            PeriodSource::Described
        } else {
            PeriodSource::Metadata
        }
    } else {
        PeriodSource::Spacing
    };
    // The density map's size before it is allocated: cells per frame, times frames.
    let cells = run.header.length / options.cell;
    let total = cells * run.frames.len() as f64;
    if !(cells <= MAX_MAP_CELLS_PER_FRAME && total <= MAX_MAP_CELLS) {
        return Err(format!(
            "--cell {} m gives {cells:.3e} cells across the {} m box, {total:.3e} over {} frames ({:.1} GB of density map); \
             at most {MAX_MAP_CELLS_PER_FRAME:e} per frame and {MAX_MAP_CELLS:e} in all: use a wider cell",
            options.cell,
            run.header.length,
            run.frames.len(),
            total * 8.0 / 1e9
        )
        .into());
    }
    let report = analysis::report::analyze(&run.header, &run.frames, &options).map_err(|e| format!("{}: {e}", run.file.display()))?;
    let out = opts.out.clone().unwrap_or_else(|| {
        if input.is_dir() {
            input.join("analysis")
        } else if run.kind == InputKind::LammpsDump {
            let mut name = run.file.file_name().unwrap_or_default().to_os_string();
            name.push(".analysis");
            run.file.with_file_name(name)
        } else {
            run.file.parent().unwrap_or(Path::new(".")).join("analysis")
        }
    });
    // The analysis must not write over the run it reads (its config.json and summary.json
    // carry the run's period and outcome).
    let same = |a: &Path, b: &Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y);
    let run_dir = if input.is_dir() {
        input.to_path_buf()
    } else {
        run.file.parent().unwrap_or(Path::new(".")).to_path_buf()
    };
    if same(&out, &run_dir) {
        return Err(format!(
            "--out {} is the run directory itself: the analysis would replace the run's config.json and summary.json; choose another --out (default: {}/analysis)",
            out.display(),
            run_dir.display()
        )
        .into());
    }
    crate::rundir::output::claim(&out, opts.force)?;
    let mut dir = RunDir::create(&out, &serde_json::json!({ "input": input, "options": opts }))?;
    write_tables(&mut dir, &report, &run)?;
    let camera = (run.geometry == Geometry::Tray)
        .then(|| analysis::camera::measure(&run.header, &run.frames, run.drive.as_ref(), &report.stripe_params, report.cells));
    draw(
        &mut dir,
        &report,
        run.geometry,
        camera.as_ref().filter(|_| opts.map_frame == MapFrame::Tray),
    )?;
    if let Some(c) = &camera {
        write_camera(&mut dir, c, &report)?;
        draw_camera(&mut dir, c, &report)?;
        top_view(&mut dir, &run, c, &opts.top_view)?;
    }
    let mut warnings = run.warnings.clone();
    let camera_label_note = camera
        .as_ref()
        .and_then(|c| label_note(c, report.phase().ok(), &report.classification));
    if let Some(n) = &camera_label_note {
        eprintln!("warning: {n}");
        warnings.push(n.clone());
    }
    if let Err(e) = report.phase() {
        eprintln!("warning: {e}");
        warnings.push(e.to_string());
    }
    if run.geometry == Geometry::VerticalBox {
        // A vertical box seen from the side: grains stack in z, so the "area fraction"
        // counts columns of grains and the tray's stripe classes mean nothing here.
        eprintln!("warning: {VERTICAL_BOX_NOTE}");
        warnings.push(VERTICAL_BOX_NOTE.into());
    }
    let summary = AnalysisSummary {
        report: report.summary(),
        input: run.file.clone(),
        input_kind: run.kind,
        geometry: run.geometry,
        period_source,
        velocity_columns: run.velocity_columns.clone(),
        warnings,
        written: dir.written(),
        camera: camera.as_ref().map(Camera::summary),
        camera_label_note,
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// Why the phase and the camera's count of the last stroboscopic frame disagree, if they do:
/// a run labelled `stripes` whose last frame holds none, or a run with stripes in its last
/// frame that is not labelled `stripes`.
pub fn label_note(camera: &Camera, phase: Option<Phase>, evidence: &Classification) -> Option<String> {
    let last = camera.stripes.last().map_or(0, Vec::len);
    let at = camera.frames.last().map_or(f64::NAN, |f| f.time);
    match phase {
        Some(Phase::Stripes) if last == 0 => Some(format!(
            "labelled `stripes` ({} stationary stripe(s) in the profile averaged over the last {} periods, {} in the median tail frame), but the camera's last frame (t = {at:.3} s) holds no stripe",
            evidence.stationary_stripe_count, evidence.params.persistence_periods, evidence.tail_stripe_count
        )),
        Some(p) if p != Phase::Stripes && last > 0 => Some(format!(
            "the camera's last frame (t = {at:.3} s) holds {last} stripe(s), but the run is labelled `{}` (mobility {:.3}, contrast {:.2}, {} stationary stripe(s))",
            p.name(),
            evidence.mobility,
            evidence.contrast,
            evidence.stationary_stripe_count
        )),
        _ => None,
    }
}
