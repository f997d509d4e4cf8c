//! `automaton.parameters`: the parameter file `stripes mechanism RUN` writes
//! (`RUN/mechanism/automaton.toml`), read for the automaton's `measured` rule
//! ([`automaton::measured`], [`automaton::measured_rule`]). A relative path is read from the
//! working directory, and recorded absolute in the run's `scene.toml`. The file's `[source]`
//! must match the scene (grains, mean diameter within 1 %, tray, periodic x, drive) unless
//! `automaton.parameters_force = true`; a forced run says so in its summary's warnings.
//! Every error names the key `automaton.parameters`, the file and the file's key.

use std::path::PathBuf;

use automaton::measured::{MeasuredFile, SceneSource};
use automaton::measured_rule::{BandDetection, MeasuredRule};
use particles::scene::SceneError;

use crate::cellular::{cell_shape, Cells};
use crate::scene_file::SceneFile;

/// A parameter file read for a scene.
#[derive(Clone, Debug)]
pub struct Parameters {
    pub path: PathBuf,
    pub file: MeasuredFile,
    /// Said when a file of another scene is forced on this one.
    pub warning: Option<String>,
}

fn refuse(path: &std::path::Path, message: impl std::fmt::Display) -> SceneError {
    SceneError {
        key: "automaton.parameters".into(),
        message: format!("{}: {message}", path.display()),
    }
}

/// Reads the file `file.automaton.parameters` names (if any), checks it against the scene,
/// makes its path absolute and hands its cell to the scene's lattice.
pub fn read(file: &mut SceneFile) -> Result<Option<Parameters>, SceneError> {
    let Some(given) = file.automaton.parameters.clone() else {
        return Ok(None);
    };
    let path = if given.is_relative() {
        std::env::current_dir().map(|d| d.join(&given)).unwrap_or(given)
    } else {
        given
    };
    let text = std::fs::read_to_string(&path).map_err(|e| refuse(&path, format!("cannot read: {e}")))?;
    let measured: MeasuredFile = toml::from_str(&text).map_err(|e| refuse(&path, e.to_string().trim_end()))?;
    measured.validate().map_err(|e| refuse(&path, e))?;
    let scene = &file.dem;
    let here = SceneSource {
        grains: scene.particles.count,
        mean_diameter_m: scene.particles.radius_min + scene.particles.radius_max,
        length_m: scene.tray.length,
        width_m: scene.tray.width,
        periodic: !scene.tray.x_walls,
        drive: if scene.drive.stages.is_empty() {
            vec![[scene.drive.frequency, scene.drive.amplitude]]
        } else {
            scene.drive.stages.iter().map(|s| [s.frequency, s.amplitude]).collect()
        },
    };
    let warning = match measured.source.mismatch(&here) {
        None => None,
        Some(e) if file.automaton.parameters_force => Some(format!(
            "automaton.parameters_force: {} was measured on another scene ({e}); its numbers are used anyway",
            path.display()
        )),
        Some(e) => {
            return Err(refuse(
                &path,
                format!("{e}; a file measured on another scene is refused (automaton.parameters_force = true uses it anyway)"),
            ))
        }
    };
    file.automaton.parameters_cell = Some(measured.cell_size().map_err(|e| refuse(&path, e))?);
    file.automaton.parameters = Some(path.clone());
    Ok(Some(Parameters {
        path,
        file: measured,
        warning,
    }))
}

impl Parameters {
    /// The measured rule on the scene's lattice: the file's distributions, and the DEM
    /// measure's band detection ([`analysis::stripes::StripeParams::default_for`] at the
    /// scene's mean area fraction and mean diameter) in cells.
    pub fn rule(&self, file: &SceneFile) -> Result<MeasuredRule, SceneError> {
        let (c, shape) = (Cells::of(file), cell_shape(file));
        let scene = &file.dem;
        let phi = scene.particles.count as f64 * shape.grain_area / (scene.tray.length * scene.tray.width);
        let stripes = analysis::stripes::StripeParams::default_for(phi, scene.particles.radius_min + scene.particles.radius_max);
        let band = BandDetection {
            fill: stripes.threshold / (shape.grain_area / (c.dx * c.dy)),
            min_cells: (stripes.min_width / c.dx).ceil() as usize,
        };
        MeasuredRule::new(&self.file, c.dx, c.dy, band).map_err(|e| refuse(&self.path, e))
    }
}
