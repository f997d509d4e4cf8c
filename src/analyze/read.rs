//! Reading back what `stripes analyze` wrote into an analysis directory: the late structure,
//! the count and the S(k) peak over time, the summary. For commands that put several
//! analysed runs side by side (`compare`, `seeds`).

use std::path::{Path, PathBuf};

use analysis::io::read_csv;

use crate::rundir::output::CliError;

/// The analysis directory of `path`: `path` itself when it holds `summary.json` and
/// `structure.csv`, else its `analysis/` (a run directory analysed in place).
pub fn resolve(path: &Path) -> Result<PathBuf, CliError> {
    for dir in [path.to_path_buf(), path.join("analysis")] {
        if dir.join("summary.json").is_file() && dir.join("structure.csv").is_file() {
            return Ok(dir);
        }
    }
    Err(format!(
        "{} is neither an analysis directory nor a run directory with one (no summary.json and structure.csv): run `stripes analyze` on it first",
        path.display()
    )
    .into())
}

fn table(analysis: &Path, name: &str) -> Result<Vec<Vec<f64>>, CliError> {
    let p = analysis.join(name);
    let (_, rows) = read_csv(&p).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
    Ok(rows)
}

/// The late-time structure (`structure_factor_late.csv`, `bands_late.csv`).
pub fn late_structure(analysis: &Path) -> Result<analysis::structure::Structure, CliError> {
    let s = table(analysis, "structure_factor_late.csv")?
        .iter()
        .filter(|r| r.len() >= 3)
        .map(|r| (r[0], r[2]))
        .collect();
    let band_widths = table(analysis, "bands_late.csv")?
        .iter()
        .filter_map(|r| r.first().copied())
        .filter(|w| w.is_finite())
        .collect();
    Ok(analysis::structure::Structure { s, band_widths })
}

/// `(t, count)`: the first two columns of the coarsening curve (`coarsening.csv`).
pub fn counts(analysis: &Path) -> Result<Vec<(f64, f64)>, CliError> {
    Ok(table(analysis, "coarsening.csv")?
        .iter()
        .filter(|r| r.len() >= 2)
        .map(|r| (r[0], r[1]))
        .collect())
}

/// `(t, spacing)`: the S(k) peak's wavelength per frame (`structure.csv`), frames without
/// a peak left out.
pub fn spacings(analysis: &Path) -> Result<Vec<(f64, f64)>, CliError> {
    Ok(table(analysis, "structure.csv")?
        .iter()
        .filter(|r| r.len() >= 3 && r[2].is_finite())
        .map(|r| (r[0], r[2]))
        .collect())
}

/// `summary.json`, read as [`SavedSummary`].
pub fn summary(analysis: &Path) -> Result<SavedSummary, CliError> {
    let p = analysis.join("summary.json");
    let text = std::fs::read_to_string(&p).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
    Ok(serde_json::from_str(&text).map_err(|e| format!("{} is not an analysis summary: {e}", p.display()))?)
}

/// An analysis' `summary.json` as the studies read it back (`stripes seeds`, the sweeps'
/// reports): the phase and the numbers they pool. A number written as null (undefined)
/// reads as none; keys that an older analysis did not write read as none.
#[derive(Clone, Debug, Default, serde::Deserialize)]
pub struct SavedSummary {
    /// `tray` or `vertical-box`.
    pub geometry: Option<String>,
    /// `stripes`, `gas`, `nothing`, `unclassified` (a vertical box) or none.
    pub phase: Option<String>,
    pub phase_robust: Option<bool>,
    pub phase_votes: Option<analysis::report::PhaseVotes>,
    pub particles: Option<f64>,
    pub period_s: Option<f64>,
    pub mean_area_fraction: Option<f64>,
    pub contrast: Option<f64>,
    pub mobility: Option<f64>,
    pub stripe_count_final: Option<f64>,
    pub tail_stripe_count: Option<f64>,
    pub stripe_onset_s: Option<f64>,
    pub structure_peak_height: Option<f64>,
    pub spacing_m: Option<f64>,
    pub band_width_m: Option<f64>,
    pub band_gap_m: Option<f64>,
    pub in_band_fraction: Option<f64>,
    pub msd_plateau_before: Option<f64>,
    pub msd_plateau_after: Option<f64>,
}

impl SavedSummary {
    /// The phase's name, `?` without one.
    pub fn phase_label(&self) -> String {
        self.phase.clone().unwrap_or_else(|| "?".into())
    }
}
