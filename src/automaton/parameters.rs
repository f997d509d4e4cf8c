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

use crate::automaton::lattice::{cell_shape, Cells};
use crate::scene::file::SceneFile;

/// A parameter file read for a scene.
#[derive(Clone, Debug)]
pub struct Parameters {
    pub path: PathBuf,
    pub file: MeasuredFile,
    /// Said in the run's summary: a file of another scene forced on this one, a scene's
    /// `automaton.cell` replaced by the file's.
    pub warnings: Vec<String>,
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
    let mut warnings: Vec<String> = match measured.source.mismatch(&here) {
        None => vec![],
        Some(e) if file.automaton.parameters_force => vec![format!(
            "automaton.parameters_force: {} was measured on another scene ({e}); its numbers are used anyway",
            path.display()
        )],
        Some(e) => {
            return Err(refuse(
                &path,
                format!("{e}; a file measured on another scene is refused (automaton.parameters_force = true uses it anyway)"),
            ))
        }
    };
    let cell = measured.cell_size().map_err(|e| refuse(&path, e))?;
    if let Some(c) = file.automaton.cell {
        warnings.push(format!(
            "automaton.cell = {c} m is not used: the measured rule's cell is the parameter file's cell.size_m = {cell} m"
        ));
    }
    file.automaton.parameters_cell = Some(cell);
    file.automaton.parameters = Some(path.clone());
    Ok(Some(Parameters {
        path,
        file: measured,
        warnings,
    }))
}

impl Parameters {
    /// The measured rule on the scene's lattice: the file's distributions (and its swing
    /// field, which the `swing` rule needs: `swing` refuses a file without one), and the DEM
    /// measure's band detection ([`analysis::stripes::StripeParams::default_for`] at the
    /// scene's mean area fraction and mean diameter) in cells.
    pub fn rule(&self, file: &SceneFile, swing: bool) -> Result<MeasuredRule, SceneError> {
        if swing {
            self.file.swing_field().map_err(|e| refuse(&self.path, e))?;
        }
        let (c, shape) = (Cells::of(file), cell_shape(file));
        let scene = &file.dem;
        let phi = scene.particles.count as f64 * shape.grain_area / (scene.tray.length * scene.tray.width);
        let stripes = analysis::stripes::StripeParams::default_for(phi, scene.particles.radius_min + scene.particles.radius_max);
        let band = BandDetection {
            fill: stripes.threshold / (shape.grain_area / (c.dx * c.dy)),
            min_cells: (stripes.min_width / c.dx).ceil() as usize,
        };
        MeasuredRule::new(&self.file, c.dx, c.dy, band, shape.grain_area / (c.dx * c.dy)).map_err(|e| refuse(&self.path, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stripe scene's tray, grains and drive, and a trimmed copy of the parameter file
    /// `stripes mechanism` wrote from its 10 s DEM run (seed 1).
    const SCENE: &str = r#"
[box]
length = 0.1
width = 0.02
[drive]
frequency = 3.0
amplitude = 0.01
[particles]
count = 2000
radius_min = 0.25e-3
radius_max = 0.5e-3
[run]
duration = 2.0
dt = 8e-6
seed = 1
"#;
    const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/automaton-stripes-seed1.toml");

    fn scene(set: &[&str]) -> SceneFile {
        let mut all = vec![format!("automaton.parameters={FILE}")];
        all.extend(set.iter().map(|s| s.to_string()));
        crate::scene::file::parse(SCENE, &all, "test").unwrap()
    }

    #[test]
    fn the_mechanism_file_reads_and_gives_the_rule_its_numbers() {
        let mut f = scene(&[]);
        let p = read(&mut f).unwrap().unwrap();
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
        assert_eq!(p.file.source.grains, 2000);
        assert_eq!(p.file.excursion.by_contacts.len(), 7);
        assert_eq!(f.automaton.parameters_cell, Some(0.0007584766454585922));
        let c = Cells::of(&f);
        assert_eq!((c.nx, c.ny), (132, 26), "cells of the file's 0.758 mm");
        let rule = p.rule(&f, false).unwrap();
        assert_eq!(rule.edge_escape, 0.41420118343195267);
        // Grains with 2 contacts draw from the class of 2; the lattice's 4 from the class of 4.
        assert_eq!(rule.excursion[2].at(0.5), 0.014013540446437753);
        assert_eq!(rule.excursion[4].at(0.25), 0.009518606102848132);
        assert!((rule.excursion[0].mean() - 0.013507414001141657).abs() < 1e-12);
        // The band columns: the DEM measure's area-fraction threshold over a grain's share
        // of a cell, which is the band cores' packing (the cell's definition) up to the
        // sample's radii against the scene's range.
        assert!(rule.band.fill > 0.7 && rule.band.fill < 0.95, "{:?}", rule.band);
        assert_eq!(rule.band.min_cells, 5, "5 mean diameters");
        assert!(f.to_toml().unwrap().contains("automaton-stripes-seed1.toml"));
    }

    #[test]
    fn a_file_of_another_scene_is_refused_by_key_unless_forced() {
        for (set, key) in [
            ("particles.count=1999", "source.grains"),
            ("particles.radius_max=0.52e-3", "source.mean_diameter_m"),
            ("box.width=0.03", "source.width_m"),
            ("box.x_walls=true", "source.periodic"),
            ("drive.amplitude=0.012", "source.drive"),
        ] {
            let e = read(&mut scene(&[set])).unwrap_err();
            assert_eq!(e.key, "automaton.parameters");
            assert!(e.message.contains(FILE) && e.message.contains(key), "{set}: {e}");
            let mut forced = scene(&[set, "automaton.parameters_force=true"]);
            let p = read(&mut forced).unwrap().unwrap();
            assert!(p.warnings.len() == 1 && p.warnings[0].contains(key), "{:?}", p.warnings);
        }
        // Within 1 % of the mean diameter the file is the scene's.
        assert!(read(&mut scene(&["particles.radius_max=0.503e-3"])).is_ok());
    }

    #[test]
    fn bad_files_name_the_file_and_key() {
        let dir = std::env::temp_dir().join(format!("stripes-parameters-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = std::fs::read_to_string(FILE).unwrap();
        for (from, to, key) in [
            ("size_m = 0.0007584766454585922\n", "", "cell.size_m"),
            (
                "edge_escape_per_period = 0.41420118343195267",
                "edge_escape_per_period = 1.4",
                "bands.edge_escape_per_period",
            ),
            ("q25 = 0.01283641483061668", "q25 = 0.02", "excursion.all.excursion"),
            ("[bands]", "[bandz]", "bands"),
        ] {
            let bad = dir.join("bad.toml");
            std::fs::write(&bad, text.replacen(from, to, 1)).unwrap();
            let mut f = crate::scene::file::parse(SCENE, &[format!("automaton.parameters={}", bad.display())], "t").unwrap();
            let e = read(&mut f).unwrap_err();
            assert!(e.message.contains("bad.toml") && e.message.contains(key), "{key}: {e}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
