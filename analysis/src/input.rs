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
        return Ok(Metadata {
            geometry,
            found: true,
            ..Metadata::default()
        });
    };
    let f = value.as_f64().ok_or_else(|| MetadataError::FrequencyNotANumber {
        path: path.clone(),
        value: value.clone(),
    })?;
    let period = (f.is_finite() && f > 0.0).then(|| 1.0 / f);
    let horizontal = drive_table
        .and_then(|d| d.get("direction"))
        .and_then(|v| v.as_str())
        .is_none_or(|d| d == "x");
    let mut drive = None;
    if let (Some(_), true) = (period, horizontal) {
        if let Some(a) = drive_table.and_then(|d| d.get("amplitude")) {
            let bad = || MetadataError::Amplitude {
                path: path.clone(),
                value: a.clone(),
            };
            let amplitude = a.as_f64().ok_or_else(bad)?;
            let d = TrayDrive::harmonic(amplitude, f).map_err(|_| bad())?;
            drive = (amplitude > 0.0).then_some(d);
        }
    }
    if let (Some(stages), true) = (drive_table.and_then(|d| d.get("stages")), horizontal) {
        drive = schedule(stages, &path)?;
    }
    Ok(Metadata {
        period,
        geometry,
        found: true,
        drive,
    })
}

/// The tray's motion of a drive schedule, `scene.drive.stages` as the DEM writes it: a list of
/// `{frequency, amplitude, duration}`, stage `k` starting at the sum of the durations before it
/// with `x_tray = A_k sin(2 pi nu_k (t - t_k))` (a zero crossing, `particles::drive`). An
/// empty list is the single drive above; a stage whose field is not a number is an error
/// naming it.
fn schedule(stages: &serde_json::Value, path: &Path) -> Result<Option<TrayDrive>, MetadataError> {
    let Some(list) = stages.as_array().filter(|l| !l.is_empty()) else {
        return Ok(None);
    };
    let mut start = 0.0;
    let mut out = Vec::with_capacity(list.len());
    for (k, stage) in list.iter().enumerate() {
        let field = |name: &str| {
            stage.get(name).and_then(|v| v.as_f64()).ok_or_else(|| MetadataError::Stage {
                path: path.to_path_buf(),
                key: format!("scene.drive.stages[{k}].{name}"),
                value: stage.get(name).cloned().unwrap_or(serde_json::Value::Null),
            })
        };
        let (frequency, amplitude, duration) = (field("frequency")?, field("amplitude")?, field("duration")?);
        out.push(Stage {
            start,
            frequency,
            amplitude,
            phase: 0.0,
        });
        start += duration;
    }
    TrayDrive::from_stages(out).map(Some).map_err(|e| MetadataError::Stage {
        path: path.to_path_buf(),
        key: "scene.drive.stages".into(),
        value: serde_json::Value::String(e.to_string()),
    })
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
    let meta = match kind {
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
}
