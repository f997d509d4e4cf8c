//! A DEM run's measures for the coarse model ([`analysis::coarse`]), written as the
//! automaton's parameter file `automaton.toml` and as `coarse.json` (issue 40, step 1).
//!
//! Read from the run's own frames (`snapshots.bin` and the drive in `config.json`); nothing
//! is fitted to spacing, width, counts or onset. The excursions are taken before the camera's
//! stripe onset (every half period when no stripes form). The lattice cell is the side of a
//! square holding one mean grain at the band cores' packing, so that a cell holds about one
//! grain where grains are densest.

use std::path::Path;

use analysis::coarse::{measure, Bands, ClassMoves, Coarse, Windows};
use analysis::density::mean_area_fraction;
use analysis::stripes::StripeParams;
use serde::Serialize;

use crate::rundir::output::{CliError, RunDir};

/// Where the parameters come from: the automaton's own reader's type (what a scene that names
/// the file must share with it).
pub use automaton::measured::Source;

/// The lattice cell.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    /// `sqrt(pi r^2 / core_packing)` with `r` the mean radius (m); None without bands.
    pub size_m: Option<f64>,
    /// What the size rests on, in words.
    pub rule: &'static str,
}

/// The excursion tables, in metres.
#[derive(Clone, Debug, Serialize)]
pub struct Excursions {
    /// The window's end (s): the stripe onset, or None for the whole run.
    pub before_s: Option<f64>,
    pub half_periods: usize,
    /// How the local state is taken, in words.
    pub local_state: String,
    /// Fraction of the periods whose drift (`drift_signed`) is positive.
    pub drift_positive_fraction: f64,
    pub all: ClassMoves,
    /// Over two consecutive half periods: the back-and-forth and the net move per period.
    pub swing: analysis::coarse::Spread,
    pub drift_per_period: analysis::coarse::Spread,
    /// The drift over the period signed along the tray's x (`+` towards +x).
    pub drift_signed: analysis::coarse::Spread,
    pub by_packing: Vec<ClassMoves>,
    pub by_contacts: Vec<ClassMoves>,
}

/// The swing against the packing of a window around each grain, over every half period of
/// the run (the automaton's `swing` rule), in metres ([`analysis::coarse::SwingField`]).
#[derive(Clone, Debug, Serialize)]
pub struct SwingFieldOut {
    /// What the table is, in words.
    pub window: &'static str,
    /// The window's half-length along x, in mean diameters, and its half-height across (m).
    pub local_radius_diameters: f64,
    pub across_m: f64,
    /// The half periods measured start before this time (s; absent: the whole run,
    /// `stripes mechanism --swing-until`): the field measured over a run's formation and
    /// over its steady state differ (docs/results/coarse-model/report.md).
    pub until_s: Option<f64>,
    pub half_periods: usize,
    /// `[|dy| (m, the bin's lower edge), correlation]` of two grains' moves within the
    /// window's length along x.
    pub correlation_across: Vec<[f64; 2]>,
    pub classes: Vec<analysis::coarse::SwingClass>,
}

/// The lift-off and melting thresholds, from a DEM phase map ([`analysis::thresholds`]).
#[derive(Clone, Debug, Serialize)]
pub struct ThresholdsOut {
    /// The phase map's `phase_map.csv` (its `dem` rows).
    pub phase_map: String,
    pub rule: &'static str,
    pub by_frequency: Vec<analysis::thresholds::FrequencyThresholds>,
}

/// The `dem` cells of a phase map's `phase_map.csv` (`model,frequency,amplitude,sample,phase,...`);
/// a cell whose run gave no phase is left out. Errors name the file and the line.
pub fn read_phase_map(path: &Path) -> Result<Vec<analysis::thresholds::MapCell>, CliError> {
    use analysis::classify::Phase;
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: cannot read ({e})", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').map(str::trim).collect();
    let col = |name: &str| {
        header.iter().position(|h| *h == name).ok_or_else(|| {
            format!(
                "{}: no `{name}` column in its first line (a `stripes phase-map` phase_map.csv)",
                path.display()
            )
        })
    };
    let (model, freq, amp, phase) = (col("model")?, col("frequency")?, col("amplitude")?, col("phase")?);
    let mut cells = Vec::new();
    for (n, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let field = |k: usize| {
            f.get(k).copied().ok_or_else(|| {
                format!(
                    "{}: line {} has {} fields, the header {}",
                    path.display(),
                    n + 2,
                    f.len(),
                    header.len()
                )
            })
        };
        if field(model)? != "dem" {
            continue;
        }
        let number = |k: usize, name: &str| -> Result<f64, CliError> {
            field(k)?
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| format!("{}: line {}: `{name}` must be a positive number", path.display(), n + 2).into())
        };
        let p = match field(phase)? {
            "nothing" => Phase::Nothing,
            "stripes" => Phase::Stripes,
            "gas" => Phase::Gas,
            _ => continue,
        };
        cells.push(analysis::thresholds::MapCell {
            frequency: number(freq, "frequency")?,
            amplitude: number(amp, "amplitude")?,
            phase: p,
        });
    }
    if cells.is_empty() {
        return Err(format!("{}: no `dem` row with a phase: the thresholds need a DEM phase map", path.display()).into());
    }
    Ok(cells)
}

/// Quantities the file cannot give from one run, with the reason.
#[derive(Clone, Debug, Serialize)]
pub struct NotMeasured {
    pub quantity: &'static str,
    pub why: &'static str,
}

/// `automaton.toml`.
#[derive(Clone, Debug, Serialize)]
pub struct Parameters {
    pub note: &'static str,
    pub source: Source,
    pub cell: Cell,
    pub excursion: Excursions,
    pub swing_field: SwingFieldOut,
    pub bands: Bands,
    /// From a DEM phase map (`stripes mechanism --phase-map`), else listed in `not_measured`.
    pub thresholds: Option<ThresholdsOut>,
    pub not_measured: Vec<NotMeasured>,
}

/// The measures of the run at `run` (a `stripes run` directory), written into `dir` as
/// `automaton.toml` and `coarse.json`; `periodic` is the scene's x boundary; the swing field
/// over the half periods that start before `swing_until` (s; None: the whole run); the
/// thresholds from the DEM phase map `phase_map` (its `phase_map.csv`), if given.
pub fn write(
    run: &Path,
    periodic: bool,
    swing_until: Option<f64>,
    phase_map: Option<&Path>,
    dir: &mut RunDir,
) -> Result<Parameters, CliError> {
    let thresholds = phase_map
        .map(|p| {
            read_phase_map(p).map(|cells| ThresholdsOut {
                phase_map: p.display().to_string(),
                rule: "per frequency, each amplitude's majority phase over its samples; lift-off: the first amplitude not \
                       `nothing`, melting: after the first `stripes`, the first `gas`, each with the amplitude below it",
                by_frequency: analysis::thresholds::thresholds(&cells, particles::constants::GRAVITY),
            })
        })
        .transpose()?;
    let input = analysis::input::load(run, 0.0).map_err(|e| CliError::from(e.to_string()))?;
    for w in &input.warnings {
        eprintln!("warning: {w}");
    }
    let drive = input.drive.as_ref().ok_or_else(|| {
        CliError::from(format!(
            "{}: its config.json gives no horizontal drive that moves the tray: no half periods to measure",
            run.display()
        ))
    })?;
    let h = &input.header;
    let n = h.radii.len();
    let mean_r = h.radii.iter().sum::<f64>() / n.max(1) as f64;
    let params = StripeParams::default_for(mean_area_fraction(&h.radii, h.length, h.width), 2.0 * mean_r);
    let cells = (h.length / 1e-3).round().max(1.0) as usize;
    let camera = analysis::camera::measure(h, &input.frames, Some(drive), &params, cells);
    let windows = Windows {
        before: camera.stripe_onset,
        swing_until,
    };
    let coarse: Coarse = measure(h, &input.frames, drive, periodic, windows, &params, cells)
        .map_err(|e| CliError::from(format!("{}: {e}", run.display())))?;
    let params = Parameters {
        note: "measured by `stripes mechanism` on the DEM run named in [source], from its frames at the tray's turning points; \
               nothing here is fitted to spacing, width, counts or onset",
        source: Source {
            run: run.display().to_string(),
            grains: n,
            mean_diameter_m: coarse.mean_diameter_m,
            length_m: h.length,
            width_m: h.width,
            periodic,
            drive: drive.stages().iter().map(|s| [s.start, s.frequency, s.amplitude]).collect(),
        },
        cell: Cell {
            size_m: coarse.bands.core_packing.map(|phi| (std::f64::consts::PI * mean_r * mean_r / phi).sqrt()),
            rule: "the side of a square holding one mean grain at the band cores' packing",
        },
        excursion: Excursions {
            before_s: coarse.before_s,
            half_periods: coarse.half_periods,
            local_state: format!(
                "packing: projected area of the grains centred within {} mean diameters, over that disk; contacts: centres nearer than (r_i + r_j)(1 + {})",
                analysis::coarse::LOCAL_RADIUS_DIAMETERS,
                analysis::coarse::CONTACT_GAP
            ),
            all: coarse.all.clone(),
            swing: coarse.swing,
            drift_per_period: coarse.drift,
            drift_signed: coarse.drift_signed,
            drift_positive_fraction: coarse.drift_positive_fraction,
            by_packing: coarse.by_packing.clone(),
            by_contacts: coarse.by_contacts.clone(),
        },
        swing_field: SwingFieldOut {
            window: "every half period of the run (dense packings exist only once bands have formed); packing: projected area \
                     of the grains centred within local_radius_diameters mean diameters along x and across_m across (as far as \
                     moves stay correlated above 1/e across the tray, or its width), over the window's area inside the tray; \
                     relative: a grain's signed move less the mean move of its neighbours within the local disk",
            local_radius_diameters: analysis::coarse::LOCAL_RADIUS_DIAMETERS,
            across_m: coarse.swing_field.across_m,
            until_s: coarse.swing_field.until_s,
            half_periods: coarse.swing_field.half_periods,
            correlation_across: coarse
                .swing_field
                .correlation_across
                .iter()
                .enumerate()
                .filter_map(|(b, c)| c.map(|c| [b as f64 * coarse.mean_diameter_m, c]))
                .collect(),
            classes: coarse.swing_field.classes.clone(),
        },
        bands: coarse.bands.clone(),
        not_measured: if thresholds.is_some() {
            vec![]
        } else {
            vec![
                NotMeasured {
                    quantity: "lift-off threshold (the drive from which grains move on the tray)",
                    why: "one run has one drive: give a DEM phase map (stripes mechanism --phase-map)",
                },
                NotMeasured {
                    quantity: "melting threshold (the drive above which bands dissolve)",
                    why: "one run has one drive: give a DEM phase map (stripes mechanism --phase-map)",
                },
            ]
        },
        thresholds,
    };
    let text = toml::to_string(&params).map_err(|e| CliError::from(format!("automaton.toml: {e}")))?;
    dir.text("automaton.toml", &text)?;
    dir.json("coarse.json", &coarse)?;
    Ok(params)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_phase_map_is_read_by_its_columns_and_refused_by_line() {
        let d = std::env::temp_dir().join(format!("stripes-phase-map-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("phase_map.csv");
        let write = |text: &str| std::fs::write(&p, text).unwrap();
        write("model,frequency,amplitude,sample,phase\ndem,3,0.002,0,nothing\nautomaton,3,0.002,0,gas\ndem,3,0.008,0,stripes\ndem,3,0.010,0,none\n");
        let cells = read_phase_map(&p).unwrap();
        assert_eq!(cells.len(), 2, "the automaton's row and the run without a phase are left out");
        assert_eq!((cells[1].frequency, cells[1].amplitude), (3.0, 0.008));
        write("model,frequency,amplitude,sample,phase\ndem,3,-1,0,gas\n");
        let e = read_phase_map(&p).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("amplitude"), "{e}");
        write("model,frequency,amplitude,sample,phase\ndem,3\n");
        let e = read_phase_map(&p).unwrap_err().to_string();
        assert!(e.contains("line 2 has 2 fields"), "{e}");
        write("model,frequency,amplitude,sample,phase\nautomaton,3,0.002,0,gas\n");
        let e = read_phase_map(&p).unwrap_err().to_string();
        assert!(e.contains("no `dem` row"), "{e}");
        write("model,freq\n");
        let e = read_phase_map(&p).unwrap_err().to_string();
        assert!(e.contains("`frequency`"), "{e}");
        std::fs::remove_dir_all(&d).ok();
    }
}
