//! One entry point for every kind of run the analysis reads, so the DEM, the automaton and
//! LAMMPS are judged by the same code:
//!
//! - a `stripes run` directory (its `snapshots.bin`) or a `snapshots.bin` file
//!   ([`crate::snapshot`]);
//! - an automaton run: `stripes automaton` writes its lattice states in the same
//!   `snapshots.bin` format, one grain per occupied site with its centre at the cell's
//!   centre (x, y) and at the height of its pile level (z), velocities zero; it is read
//!   exactly like a DEM run, and displacements between frames are whole cells;
//! - a LAMMPS / LIGGGHTS text dump ([`crate::lammps`]), recognised by its first line
//!   `ITEM: TIMESTEP`; its time is `timestep * dt`.
//!
//! A snapshot file cut inside a frame, or a dump cut inside a frame (a killed run), is read up
//! to its last complete frame, with a warning in [`Run::warnings`]. The drive period and the
//! geometry come from the run's own metadata when there is any ([`Metadata`]):
//! `config.json` beside `snapshots.bin` (written by `stripes run`, `stripes automaton` and
//! `stripes events`) holds `scene.drive.frequency`, and `scene.model = "events"` for an
//! event-driven run of a vertical box.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::drive::{Stage, TrayDrive};
use crate::snapshot::{read_snapshots_counting, Frame, Header};

/// The kind of input found at a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum InputKind {
    /// `snapshots.bin` of a DEM or automaton run.
    Snapshots,
    /// LAMMPS text dump.
    LammpsDump,
}

/// A loaded run: where it came from, its header and its frames in time order.
#[derive(Clone, Debug)]
pub struct Run {
    pub file: PathBuf,
    pub kind: InputKind,
    pub header: Header,
    pub frames: Vec<Frame>,
    /// The drive period (s) from the run's metadata (`config.json`: `1 / scene.drive.frequency`),
    /// None without metadata.
    pub period: Option<f64>,
    /// What the frames show, from the run's metadata (a tray seen from above without it).
    pub geometry: Geometry,
    /// The tray's horizontal motion `x_tray(t)` from the run's metadata (`scene.drive`:
    /// `amplitude sin(2 pi frequency t)` along x); None without metadata, for a vertical
    /// drive, or without shaking.
    pub drive: Option<TrayDrive>,
    /// LAMMPS dumps: the velocity columns used (the others read as zero).
    pub velocity_columns: Option<Vec<String>>,
    /// Problems that did not stop the reading (a cut-off file).
    pub warnings: Vec<String>,
}

/// Why [`load`] cannot give a run; each names the file.
#[derive(Debug)]
pub enum LoadError {
    /// The file cannot be opened or read.
    Unreadable { file: PathBuf, source: std::io::Error },
    /// The file is neither a snapshot file nor a LAMMPS text dump.
    UnknownKind { file: PathBuf },
    /// The LAMMPS dump cannot be read ([`crate::lammps::DumpError`]: line, field, timestep).
    Dump(crate::lammps::DumpError),
    /// The file holds no complete frame.
    NoFrames { file: PathBuf },
    /// Frame `frame`'s time (s) does not come after the previous frame's.
    TimeOrder {
        file: PathBuf,
        frame: usize,
        time: f64,
        previous: f64,
    },
    /// The `config.json` beside a snapshot file cannot give the drive period.
    Metadata(MetadataError),
    /// The description given with the run gives no drive ([`load_described`]).
    Description { file: PathBuf, why: DescriptionError },
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Unreadable { file, source } => write!(f, "cannot read {}: {source}", file.display()),
            LoadError::UnknownKind { file } => write!(
                f,
                "{} is neither a stripes snapshot file (magic STRPSNP1) nor a LAMMPS text dump (`ITEM: TIMESTEP`)",
                file.display()
            ),
            LoadError::Dump(e) => e.fmt(f),
            LoadError::NoFrames { file } => write!(f, "{} holds no complete frame", file.display()),
            LoadError::TimeOrder {
                file,
                frame,
                time,
                previous,
            } => write!(
                f,
                "{}: frame {frame} (t = {time} s) does not come after frame {} (t = {previous} s)",
                file.display(),
                frame - 1
            ),
            LoadError::Metadata(e) => e.fmt(f),
            LoadError::Description { file, why } => match why {
                DescriptionError::Amplitude => write!(f, "{}: the run's drive amplitude is not a number >= 0", file.display()),
                DescriptionError::Stages(e) => write!(f, "{}: the run's drive stages give no drive: {e}", file.display()),
            },
        }
    }
}

impl std::error::Error for LoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            LoadError::Unreadable { source, .. } => Some(source),
            LoadError::Dump(e) => Some(e),
            LoadError::Metadata(e) => Some(e),
            _ => None,
        }
    }
}

/// Why the `config.json` beside a run could not give its drive period.
#[derive(Debug)]
pub enum MetadataError {
    /// The file is there but cannot be read.
    Unreadable { path: PathBuf, source: std::io::Error },
    /// The file is not JSON.
    NotJson { path: PathBuf, source: serde_json::Error },
    /// `scene.drive.frequency` is there but not a number.
    FrequencyNotANumber { path: PathBuf, value: serde_json::Value },
    /// The file holds no `scene` table: it cannot say whether the run is a tray or an
    /// event-driven box.
    NoScene { path: PathBuf },
    /// The file's scene does not describe the snapshots beside it (`what` says how).
    Mismatch { path: PathBuf, what: String },
    /// `scene.drive.amplitude` is there but not a number, or the drive it gives is refused.
    Amplitude { path: PathBuf, value: serde_json::Value },
    /// A stage of `scene.drive.stages` lacks a number, or the stages give no drive.
    Stage {
        path: PathBuf,
        key: String,
        value: serde_json::Value,
    },
}

impl std::fmt::Display for MetadataError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MetadataError::Unreadable { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            MetadataError::NotJson { path, source } => write!(f, "{} is not JSON: {source}", path.display()),
            MetadataError::FrequencyNotANumber { path, value } => {
                write!(f, "{}: scene.drive.frequency is {value}, not a number", path.display())
            }
            MetadataError::NoScene { path } => write!(
                f,
                "{} holds no `scene`, so it cannot say whether the run is a tray or an event-driven box, nor its drive period; \
                 restore the run's config.json, or remove it to analyse the snapshots with the assumptions said in a warning",
                path.display()
            ),
            MetadataError::Mismatch { path, what } => write!(
                f,
                "{}: {what}; it is not the description of these snapshots (restore the run's own config.json, or remove it)",
                path.display()
            ),
            MetadataError::Amplitude { path, value } => {
                write!(f, "{}: scene.drive.amplitude is {value}, not a number >= 0", path.display())
            }
            MetadataError::Stage { path, key, value } => {
                write!(f, "{}: {key} is {value}, not a drive stage's number", path.display())
            }
        }
    }
}

impl std::error::Error for MetadataError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MetadataError::Unreadable { source, .. } => Some(source),
            MetadataError::NotJson { source, .. } => Some(source),
            MetadataError::FrequencyNotANumber { .. }
            | MetadataError::NoScene { .. }
            | MetadataError::Mismatch { .. }
            | MetadataError::Amplitude { .. }
            | MetadataError::Stage { .. } => None,
        }
    }
}

/// What the frames of a run show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Geometry {
    /// A horizontal tray seen from above (the DEM, the automaton, a LAMMPS dump): frames in
    /// the (x, y) plane.
    #[default]
    Tray,
    /// An event-driven vertical box seen from the side: frames in the (x, z) plane, grains
    /// stacked in z.
    VerticalBox,
}

/// What a run's `config.json` says about it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metadata {
    /// The drive period `1 / scene.drive.frequency` (s).
    pub period: Option<f64>,
    /// `Geometry::VerticalBox` for `scene.model = "events"`.
    pub geometry: Geometry,
    /// Whether a `config.json` was there; without one, the geometry is assumed ([`load`]
    /// infers it from the snapshot header and says so in a warning).
    pub found: bool,
    /// `x_tray(t) = scene.drive.amplitude sin(2 pi scene.drive.frequency t)`, when the drive
    /// is horizontal (`scene.drive.direction` absent or `"x"`) and moves the tray; the stages of
    /// `scene.drive.stages` when the run has a drive schedule.
    pub drive: Option<TrayDrive>,
}

/// The metadata in the `config.json` beside `file`. No period when the run has none to
/// give: no `config.json`, no `scene.drive.frequency` in it, or a frequency that is not
/// positive (no shaking). A `config.json` that is there but unreadable, not JSON, holds no
/// `scene`, or holds a frequency that is not a number is an error, not missing metadata.
pub fn metadata(file: &Path) -> Result<Metadata, MetadataError> {
    let Some(dir) = file.parent() else {
        return Ok(Metadata::default());
    };
    let path = dir.join("config.json");
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Metadata::default()),
        Err(source) => return Err(MetadataError::Unreadable { path, source }),
    };
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|source| MetadataError::NotJson {
        path: path.clone(),
        source,
    })?;
    let Some(scene) = v.get("scene").filter(|s| s.is_object()) else {
        return Err(MetadataError::NoScene { path });
    };
    let geometry = if scene.get("model").and_then(|m| m.as_str()) == Some("events") {
        Geometry::VerticalBox
    } else {
        Geometry::Tray
    };
    let drive_table = scene.get("drive");
    let Some(value) = drive_table.and_then(|d| d.get("frequency")) else {
        return Ok(Metadata::of(&RunDescription { geometry, drive: None }).expect("no drive, nothing to refuse"));
    };
    let frequency = value.as_f64().ok_or_else(|| MetadataError::FrequencyNotANumber {
        path: path.clone(),
        value: value.clone(),
    })?;
    let horizontal = drive_table
        .and_then(|d| d.get("direction"))
        .and_then(|v| v.as_str())
        .is_none_or(|d| d == "x");
    let amplitude_value = drive_table.and_then(|d| d.get("amplitude"));
    let bad_amplitude = |a: &serde_json::Value| MetadataError::Amplitude {
        path: path.clone(),
        value: a.clone(),
    };
    // Only what a horizontal drive uses is read (and refused when it is not a number).
    let moving = horizontal && frequency.is_finite() && frequency > 0.0;
    let amplitude = match amplitude_value.filter(|_| moving) {
        Some(a) => Some(a.as_f64().ok_or_else(|| bad_amplitude(a))?),
        None => None,
    };
    let stages = match drive_table
        .and_then(|d| d.get("stages"))
        .and_then(|s| s.as_array())
        .filter(|_| horizontal)
    {
        Some(list) => list
            .iter()
            .enumerate()
            .map(|(k, stage)| {
                let field = |name: &str| {
                    stage.get(name).and_then(|v| v.as_f64()).ok_or_else(|| MetadataError::Stage {
                        path: path.to_path_buf(),
                        key: format!("scene.drive.stages[{k}].{name}"),
                        value: stage.get(name).cloned().unwrap_or(serde_json::Value::Null),
                    })
                };
                Ok(StageDescription {
                    frequency: field("frequency")?,
                    amplitude: field("amplitude")?,
                    duration: field("duration")?,
                })
            })
            .collect::<Result<Vec<_>, MetadataError>>()?,
        None => Vec::new(),
    };
    let description = RunDescription {
        geometry,
        drive: Some(DriveDescription {
            frequency,
            amplitude,
            horizontal,
            stages,
        }),
    };
    Metadata::of(&description).map_err(|e| match e {
        DescriptionError::Amplitude => bad_amplitude(amplitude_value.expect("only a given amplitude is refused")),
        DescriptionError::Stages(why) => MetadataError::Stage {
            path: path.to_path_buf(),
            key: "scene.drive.stages".into(),
            value: serde_json::Value::String(why),
        },
    })
}

/// What the analysis needs to know of a run besides its frames: a tray or an event-driven
/// box, and the drive. Read from the run's `config.json` ([`metadata`]), or given typed by
/// the program that has just run the model ([`load_described`]); both become [`Metadata`]
/// through [`Metadata::of`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunDescription {
    pub geometry: Geometry,
    /// None: the run has no drive (no period, every frame kept as stored).
    pub drive: Option<DriveDescription>,
}

/// A run's drive: one harmonic stage (`frequency`, `amplitude`) or a schedule of stages.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriveDescription {
    /// Hz (with stages: the last stage's); the period is its inverse when it is positive.
    pub frequency: f64,
    /// m; none where the run's description gives none (no tray motion is then known).
    pub amplitude: Option<f64>,
    /// Whether the drive moves the tray along x (a vertical drive has no tray frame).
    pub horizontal: bool,
    /// The schedule, stage after stage from t = 0; empty: the one stage above.
    pub stages: Vec<StageDescription>,
}

/// One stage of a drive schedule, as the DEM's scene writes it (`[[drive.stages]]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageDescription {
    pub frequency: f64,
    pub amplitude: f64,
    pub duration: f64,
}

/// Why a [`RunDescription`] gives no tray motion.
#[derive(Clone, Debug, PartialEq)]
pub enum DescriptionError {
    /// The amplitude is not a number >= 0.
    Amplitude,
    /// The stages give no drive (the reason).
    Stages(String),
}

impl Metadata {
    /// The metadata of a described run: the period `1 / frequency` where it is positive;
    /// for a horizontal drive the tray's motion, `x_tray = A sin(2 pi nu t)` (none at
    /// `A = 0`), or with a schedule stage `k` from the sum of the durations before it, as
    /// `A_k sin(2 pi nu_k (t - t_k))` (a zero crossing, `particles::drive`).
    pub fn of(description: &RunDescription) -> Result<Metadata, DescriptionError> {
        let mut meta = Metadata {
            geometry: description.geometry,
            found: true,
            ..Metadata::default()
        };
        let Some(d) = &description.drive else {
            return Ok(meta);
        };
        let f = d.frequency;
        meta.period = (f.is_finite() && f > 0.0).then(|| 1.0 / f);
        if !d.horizontal {
            return Ok(meta);
        }
        if let (Some(_), Some(amplitude)) = (meta.period, d.amplitude) {
            let drive = TrayDrive::harmonic(amplitude, f).map_err(|_| DescriptionError::Amplitude)?;
            meta.drive = (amplitude > 0.0).then_some(drive);
        }
        if !d.stages.is_empty() {
            let mut start = 0.0;
            let mut out = Vec::with_capacity(d.stages.len());
            for s in &d.stages {
                out.push(Stage {
                    start,
                    frequency: s.frequency,
                    amplitude: s.amplitude,
                    phase: 0.0,
                });
                start += s.duration;
            }
            meta.drive = Some(TrayDrive::from_stages(out).map_err(|e| DescriptionError::Stages(e.to_string()))?);
        }
        Ok(meta)
    }
}

/// Whether a snapshot header has the layout `stripes events` writes: a slab one largest
/// grain diameter thick (`width = 2 r_max`), where a tray is many grains wide.
pub fn looks_like_vertical_box(header: &Header) -> bool {
    let r_max = header.radii.iter().copied().fold(0.0, f64::max);
    r_max > 0.0 && (header.width - 2.0 * r_max).abs() <= 1e-12 * header.width.abs().max(1e-300)
}

/// The box the config's scene describes, checked against the snapshot header: a tray's
/// `box.length` and `box.width` are the header's length and width, an event-driven box's
/// `box.width` is the header's length (its frames are the (x, z) plane). Keys that are not
/// there are not checked.
fn check_against_header(path: &Path, meta: &Metadata, header: &Header) -> Result<(), MetadataError> {
    let Ok(text) = std::fs::read_to_string(path) else { return Ok(()) };
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Ok(());
    };
    let b = |k: &str| v["scene"]["box"][k].as_f64();
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
    let mismatch = |what: String| {
        Err(MetadataError::Mismatch {
            path: path.to_path_buf(),
            what,
        })
    };
    match meta.geometry {
        Geometry::Tray => {
            if let Some(l) = b("length").filter(|l| !near(*l, header.length)) {
                return mismatch(format!("its tray is {l} m long (box.length), the snapshots' {} m", header.length));
            }
            if v["scene"]["box"].is_object() && b("length").is_none() {
                return mismatch(
                    "its scene has a box without box.length and no model = \"events\": neither a tray nor an event-driven box".into(),
                );
            }
            if looks_like_vertical_box(header) && b("width").is_some_and(|w| !near(w, header.width)) {
                return mismatch(format!(
                    "it describes a tray {} m wide, but the snapshots are a slab one grain diameter thick, as an event-driven box writes",
                    b("width").unwrap_or_default()
                ));
            }
        }
        Geometry::VerticalBox => {
            if let Some(w) = b("width").filter(|w| !near(*w, header.length)) {
                return mismatch(format!(
                    "its event-driven box is {w} m wide (box.width), the snapshots' {} m",
                    header.length
                ));
            }
        }
    }
    Ok(())
}

/// The drive period of [`metadata`].
pub fn metadata_period(file: &Path) -> Result<Option<f64>, MetadataError> {
    Ok(metadata(file)?.period)
}

/// Loads a run directory, a `snapshots.bin` file or a LAMMPS dump; `dt` (s) converts LAMMPS
/// timesteps to time and is ignored for snapshots. Fails with a message naming the file
/// when it is of neither kind, holds no complete frame, its times do not increase, or the
/// `config.json` beside it cannot be read ([`metadata_period`]).
pub fn load(path: &Path, dt: f64) -> Result<Run, LoadError> {
    load_described(path, dt, None)
}

/// [`load`], with the run's description given typed (by the program that has just run the
/// model, from its scene) instead of read back from its `config.json`; `None` reads the
/// file as [`load`] does.
pub fn load_described(path: &Path, dt: f64, description: Option<&RunDescription>) -> Result<Run, LoadError> {
    let file = if path.is_dir() {
        path.join("snapshots.bin")
    } else {
        path.to_path_buf()
    };
    let mut head = [0u8; 16];
    let got = std::fs::File::open(&file)
        .and_then(|mut f| f.read(&mut head))
        .map_err(|source| LoadError::Unreadable {
            file: file.clone(),
            source,
        })?;
    let mut warnings = Vec::new();
    let mut velocity_columns = None;
    let (kind, header, frames) = if head[..got].starts_with(b"STRPSNP1") {
        let (h, f, rest) = read_snapshots_counting(&file).map_err(|source| LoadError::Unreadable {
            file: file.clone(),
            source,
        })?;
        if rest > 0 {
            warnings.push(format!(
                "{} is cut off: it ends {rest} bytes into a frame; analysing the {} whole frames before it",
                file.display(),
                f.len()
            ));
        }
        (InputKind::Snapshots, h, f)
    } else if String::from_utf8_lossy(&head[..got]).trim_start().starts_with("ITEM:") {
        let (h, f, notes) = crate::lammps::read_dump_noting(&file, dt).map_err(LoadError::Dump)?;
        warnings.extend(notes.warnings);
        velocity_columns = Some(notes.velocity_columns);
        (InputKind::LammpsDump, h, f)
    } else {
        return Err(LoadError::UnknownKind { file });
    };
    if frames.is_empty() {
        return Err(LoadError::NoFrames { file });
    }
    for (k, w) in frames.windows(2).enumerate() {
        if w[1].time.partial_cmp(&w[0].time) != Some(std::cmp::Ordering::Greater) {
            return Err(LoadError::TimeOrder {
                file,
                frame: k + 1,
                time: w[1].time,
                previous: w[0].time,
            });
        }
    }
    let given = match (kind, description) {
        (InputKind::Snapshots, Some(d)) => Some(Metadata::of(d).map_err(|why| LoadError::Description { file: file.clone(), why })?),
        _ => None,
    };
    let meta = match kind {
        InputKind::Snapshots if given.is_some() => given.expect("just matched"),
        InputKind::Snapshots => {
            let mut meta = metadata(&file).map_err(LoadError::Metadata)?;
            if meta.found {
                let config = file.parent().unwrap_or(Path::new(".")).join("config.json");
                check_against_header(&config, &meta, &header).map_err(LoadError::Metadata)?;
            } else {
                // No description: the geometry from the header's layout, said as assumed.
                meta.geometry = if looks_like_vertical_box(&header) {
                    Geometry::VerticalBox
                } else {
                    Geometry::Tray
                };
                warnings.push(format!(
                    "no config.json beside {}: assumed {} and took the drive period from the snapshot spacing",
                    file.display(),
                    match meta.geometry {
                        Geometry::VerticalBox =>
                            "an event-driven vertical box (its header is a slab one grain diameter thick, as `stripes events` writes)",
                        Geometry::Tray => "a tray seen from above (its header is many grains wide)",
                    }
                ));
            }
            meta
        }
        InputKind::LammpsDump => Metadata::default(),
    };
    Ok(Run {
        file,
        kind,
        header,
        frames,
        period: meta.period,
        geometry: meta.geometry,
        drive: meta.drive,
        velocity_columns,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_period_is_only_a_missing_config_or_frequency_and_a_bad_config_is_an_error() {
        let dir = std::env::temp_dir().join(format!("stripes-metadata-period-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("snapshots.bin");
        let config = dir.join("config.json");
        assert!(metadata_period(&file).unwrap().is_none(), "no config.json");
        std::fs::write(&config, r#"{"scene": {"drive": {"frequency": 20.0}}}"#).unwrap();
        assert_eq!(metadata_period(&file).unwrap(), Some(0.05));
        assert_eq!(metadata(&file).unwrap().geometry, Geometry::Tray);
        std::fs::write(&config, r#"{"scene": {"run": {}}}"#).unwrap();
        assert!(metadata_period(&file).unwrap().is_none(), "no scene.drive.frequency");
        // Issue 43, finding 7: a config.json without a scene cannot tell a tray from a box.
        std::fs::write(&config, r#"{"args": {}}"#).unwrap();
        let e = metadata_period(&file).unwrap_err();
        assert!(
            matches!(e, MetadataError::NoScene { .. }) && e.to_string().contains("tray or an event-driven box"),
            "{e}"
        );
        std::fs::write(&config, r#"{"scene": {"model": "events", "drive": {"frequency": 20.0}}}"#).unwrap();
        assert_eq!(
            metadata(&file).unwrap(),
            Metadata {
                period: Some(0.05),
                geometry: Geometry::VerticalBox,
                found: true,
                ..Metadata::default()
            }
        );
        std::fs::write(&config, r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01}}}"#).unwrap();
        let d = metadata(&file).unwrap().drive.unwrap();
        assert!((d.displacement(0.25 / 3.0) - 0.01).abs() < 1e-15);
        std::fs::write(
            &config,
            r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01, "direction": "z"}}}"#,
        )
        .unwrap();
        assert!(metadata(&file).unwrap().drive.is_none(), "a vertical drive leaves x alone");
        std::fs::write(&config, r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": "big"}}}"#).unwrap();
        let e = metadata(&file).unwrap_err();
        assert!(e.to_string().contains("scene.drive.amplitude"), "{e}");
        std::fs::write(
            &config,
            r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01, "stages": [{}, {}]}}}"#,
        )
        .unwrap();
        let e = metadata(&file).unwrap_err();
        assert!(e.to_string().contains("scene.drive.stages[0].frequency"), "{e}");
        // The experiment's protocol: 2 s at 5 Hz / 20 mm, then 3 Hz / 10 mm from a zero crossing.
        std::fs::write(
            &config,
            r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01, "stages": [
                {"frequency": 5.0, "amplitude": 0.02, "duration": 2.0},
                {"frequency": 3.0, "amplitude": 0.01, "duration": 3600.0}]}}}"#,
        )
        .unwrap();
        let d = metadata(&file).unwrap().drive.unwrap();
        assert!((d.displacement(0.05) - 0.02).abs() < 1e-15, "the first stage's turning point");
        assert!((d.displacement(2.0 + 0.25 / 3.0) - 0.01).abs() < 1e-15, "the second stage's");
        assert_eq!(d.turning_point(2.0 + 1.25 / 3.0).unwrap().stage, 1);
        std::fs::write(&config, r#"{"scene": {"drive": {"frequency": 0.0}}}"#).unwrap();
        assert!(metadata_period(&file).unwrap().is_none(), "no shaking");
        std::fs::write(&config, "{ cut off").unwrap();
        let e = metadata_period(&file).unwrap_err();
        assert!(
            matches!(e, MetadataError::NotJson { .. }) && e.to_string().contains("config.json"),
            "{e}"
        );
        std::fs::write(&config, r#"{"scene": {"drive": {"frequency": "fast"}}}"#).unwrap();
        let e = metadata_period(&file).unwrap_err();
        assert!(matches!(e, MetadataError::FrequencyNotANumber { .. }), "{e}");
        std::fs::remove_file(&config).unwrap();
        std::fs::create_dir(&config).unwrap();
        let e = metadata_period(&file).unwrap_err();
        assert!(matches!(e, MetadataError::Unreadable { .. }), "a directory in its place: {e}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Issue 42, step 2: a command that has just run a model gives the analysis its run's
    /// description typed; it is the same metadata as the run's config.json gives, through the
    /// same conversion, and no config.json is read for it.
    #[test]
    fn a_typed_description_gives_the_config_files_metadata_without_reading_it() {
        let dir = std::env::temp_dir().join(format!("stripes-described-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("snapshots.bin");
        let config = dir.join("config.json");
        let stage = |frequency, amplitude, duration| StageDescription {
            frequency,
            amplitude,
            duration,
        };
        let cases = [
            (
                r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01}}}"#,
                Some(DriveDescription {
                    frequency: 3.0,
                    amplitude: Some(0.01),
                    horizontal: true,
                    stages: vec![],
                }),
            ),
            (
                r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01, "stages": [
                    {"frequency": 5.0, "amplitude": 0.02, "duration": 2.0},
                    {"frequency": 3.0, "amplitude": 0.01, "duration": 3600.0}]}}}"#,
                Some(DriveDescription {
                    frequency: 3.0,
                    amplitude: Some(0.01),
                    horizontal: true,
                    stages: vec![stage(5.0, 0.02, 2.0), stage(3.0, 0.01, 3600.0)],
                }),
            ),
            (
                r#"{"scene": {"drive": {"frequency": 3.0, "amplitude": 0.01, "direction": "z"}}}"#,
                Some(DriveDescription {
                    frequency: 3.0,
                    amplitude: Some(0.01),
                    horizontal: false,
                    stages: vec![],
                }),
            ),
            (
                r#"{"scene": {"drive": {"frequency": 0.0, "amplitude": 0.01}}}"#,
                Some(DriveDescription {
                    frequency: 0.0,
                    amplitude: Some(0.01),
                    horizontal: true,
                    stages: vec![],
                }),
            ),
            (r#"{"scene": {"run": {}}}"#, None),
        ];
        for (json, drive) in cases {
            std::fs::write(&config, json).unwrap();
            let typed = Metadata::of(&RunDescription {
                geometry: Geometry::Tray,
                drive,
            })
            .unwrap();
            assert_eq!(typed, metadata(&file).unwrap(), "{json}");
        }
        // A run on disk: a garbled config.json is refused when read, and not read when the
        // description is given.
        let header = Header {
            length: 0.1,
            width: 0.02,
            radii: vec![1e-3; 2],
        };
        let mut w = crate::snapshot::SnapshotWriter::create(&file, header).unwrap();
        for k in 0..4 {
            let t = k as f64 / 12.0;
            w.push(t, [[0.01, 0.01, 1e-3], [0.05, 0.01, 1e-3]].into_iter(), [[0.0; 3]; 2].into_iter())
                .unwrap();
        }
        drop(w);
        std::fs::write(&config, "{ cut off").unwrap();
        assert!(matches!(load(&dir, 1e-5), Err(LoadError::Metadata(MetadataError::NotJson { .. }))));
        let given = RunDescription {
            geometry: Geometry::Tray,
            drive: Some(DriveDescription {
                frequency: 3.0,
                amplitude: Some(0.01),
                horizontal: true,
                stages: vec![],
            }),
        };
        let run = load_described(&dir, 1e-5, Some(&given)).unwrap();
        assert_eq!(run.frames.len(), 4);
        assert_eq!(run.period, Some(1.0 / 3.0));
        assert!(run.drive.is_some() && run.warnings.is_empty(), "{:?}", run.warnings);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
