//! The (nu, A) phase diagram of thesis Figs 3.30-3.31 as a sweep (`stripes phase-map`):
//! its jobs, one per model, amplitude, frequency and sample, and its report.
//!
//! Writes `phase_map.csv` (`model,frequency,amplitude,sample,phase,stripe_count,contrast,
//! mobility,onset_s,structure_peak_height,phase_robust`, the last 1 when the run's phase is
//! the same under every threshold set of the analysis' sensitivity sweep), per model the heat
//! maps of contrast, mobility and S(k) peak height with the class boundaries (nothing /
//! stripes / gas, the analysis' classifier) drawn on them, and `report.md` with both models
//! side by side and where they agree.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use analysis::plot::Heatmap;

use super::{Job, Model, Sweep};
use crate::rundir::output::CliError;
use crate::rundir::output::Written;
use crate::rundir::report::{Headline, Summary};
use crate::scene::edit::{DemEdit, Edit};

/// The jobs of a phase map, model-major, then amplitude, frequency, sample.
pub fn jobs(freqs: &[f64], amps: &[f64], models: &[Model], samples: usize, seed: u64) -> Vec<Job> {
    let mut jobs = Vec::new();
    for &model in models {
        for &a in amps {
            for &f in freqs {
                for k in 0..samples {
                    let seed = seed + k as u64;
                    let labels = super::Labels {
                        frequency: Some(f),
                        amplitude: Some(a),
                        sample: Some(k as u64),
                        ..super::Labels::default()
                    };
                    jobs.push(Job {
                        id: format!("{}-f{f}-a{a}-s{k}", model.name()),
                        model,
                        edits: [DemEdit::Frequency(f), DemEdit::Amplitude(a), DemEdit::Seed(seed)]
                            .map(Edit::Dem)
                            .to_vec(),
                        labels,
                    });
                }
            }
        }
    }
    jobs
}

const PHASES: [&str; 3] = ["nothing", "stripes", "gas"];

/// The continuous numbers drawn as heat maps under the phases, with their titles and
/// colour-bar labels:
/// `phase_<model>_<metric>.png`.
const METRICS: [(&str, &str, &str); 3] = [
    ("contrast", "contrast", "contrast (x a random layer's)"),
    ("mobility", "mobility", "mobility (mean diameters per period)"),
    ("structure_peak_height", "S(k) peak height", "S(k) peak height of the late frames"),
];

/// Whether the values are evenly spaced (to 1e-9 of their span), so a linear axis shows them.
fn evenly_spaced(v: &[f64]) -> bool {
    if v.len() < 3 {
        return true;
    }
    let step = (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64;
    v.windows(2)
        .all(|w| ((w[1] - w[0]) - step).abs() <= 1e-9 * (v[v.len() - 1] - v[0]).abs())
}

fn phase_index(p: &str) -> usize {
    PHASES.iter().position(|q| *q == p).unwrap_or(usize::MAX)
}

/// Mean of the finite values (NaN if none).
fn mean(v: &[f64]) -> f64 {
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.is_empty() {
        f64::NAN
    } else {
        f.iter().sum::<f64>() / f.len() as f64
    }
}

/// Writes the CSV, the plots and the report of whatever results exist; returns the summary.
/// What the phase map's report says: `summary.json`, field for field.
#[derive(Debug, serde::Serialize)]
pub struct PhaseMapSummary {
    pub kind: &'static str,
    pub jobs: usize,
    pub finished: usize,
    pub frequency: Vec<f64>,
    pub amplitude: Vec<f64>,
    /// Each model's phase per cell, amplitude by frequency.
    pub phases: BTreeMap<String, Vec<Vec<&'static str>>>,
    /// Where both models ran: the cells where they agree (null with one model).
    pub agreement: Option<Agreement>,
    pub runs_with_threshold_sensitive_phase: usize,
    #[serde(flatten)]
    pub written: Written,
}

/// The cells where both models have a phase, and how many of them agree.
#[derive(Debug, serde::Serialize)]
pub struct Agreement {
    pub cells: usize,
    pub agree: usize,
    pub ties: usize,
    /// NaN (null) without a cell.
    pub fraction: f64,
}

impl Summary for PhaseMapSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

pub fn report(root: &Path, sweep: &Sweep) -> Result<PhaseMapSummary, CliError> {
    let (results, mut dir) = super::open_report::<super::TrayResult>(root, sweep)?;
    let mut csv =
        String::from("model,frequency,amplitude,sample,phase,stripe_count,contrast,mobility,onset_s,structure_peak_height,phase_robust\n");
    // Runs whose phase changes with the classifier's thresholds.
    let mut fragile = Vec::new();
    // (model, amplitude index, frequency index) -> per-sample (phase, contrast, mobility).
    let mut freqs: Vec<f64> = sweep.jobs.iter().map(|j| j.labels.frequency.unwrap_or(f64::NAN)).collect();
    let mut amps: Vec<f64> = sweep.jobs.iter().map(|j| j.labels.amplitude.unwrap_or(f64::NAN)).collect();
    for v in [&mut freqs, &mut amps] {
        v.sort_by(f64::total_cmp);
        v.dedup();
    }
    // Per sample: phase, then the metrics of METRICS in order.
    type Cell = Vec<(usize, [f64; 3])>;
    let mut cells: BTreeMap<(String, usize, usize), Cell> = BTreeMap::new();
    for (job, r) in &results {
        let labels = &job.labels;
        let (f, a) = (labels.frequency.unwrap_or(f64::NAN), labels.amplitude.unwrap_or(f64::NAN));
        let sample = labels.sample.unwrap_or(0);
        let r = &r.analysis;
        let phase = r.phase_label();
        let (contrast, mobility) = (super::nan_if_none(r.contrast), super::nan_if_none(r.mobility));
        let count = super::nan_if_none(r.stripe_count_final);
        let onset = super::nan_if_none(r.stripe_onset_s);
        let height = super::nan_if_none(r.structure_peak_height);
        let robust = r.phase_robust;
        if robust == Some(false) {
            let v = r.phase_votes.unwrap_or_default();
            fragile.push(format!(
                "{} ({f} Hz, {a} m, sample {sample}): {phase}; of 27 threshold sets {} say stripes, {} gas, {} nothing",
                job.model.name(),
                v.stripes,
                v.gas,
                v.nothing
            ));
        }
        writeln!(
            csv,
            "{},{f},{a},{sample},{phase},{count},{contrast},{mobility},{onset},{height},{}",
            job.model.name(),
            robust.map_or("?", |b| if b { "1" } else { "0" })
        )?;
        let fi = freqs.iter().position(|x| *x == f).unwrap_or(0);
        let ai = amps.iter().position(|x| *x == a).unwrap_or(0);
        cells
            .entry((job.model.name().to_string(), ai, fi))
            .or_default()
            .push((phase_index(&phase), [contrast, mobility, height]));
    }
    let path = root.join("phase_map.csv");
    analysis::io::write_atomic(&path, csv.as_bytes())?;
    dir.note_files([path]);

    // Majority phase per cell; a cell whose samples split evenly between phases is a tie
    // (index 4), not given to either.
    let majority = |c: &Cell| match super::majority(c.iter().map(|t| t.0).filter(|&p| p < 3)) {
        super::Majority::None => 3,
        super::Majority::One(p) => p,
        super::Majority::Tie(_) => TIE,
    };
    let models: Vec<String> = {
        let mut m: Vec<String> = sweep.jobs.iter().map(|j| j.model.name().to_string()).collect();
        m.dedup();
        m
    };
    let mut names: Vec<&str> = PHASES.to_vec();
    names.push("-");
    names.push("tie");
    let (df, da) = (step(&freqs), step(&amps));
    let mut grids: BTreeMap<String, Vec<Vec<usize>>> = BTreeMap::new();
    for model in &models {
        let classes: Vec<Vec<usize>> = (0..amps.len())
            .map(|ai| {
                (0..freqs.len())
                    .map(|fi| cells.get(&(model.clone(), ai, fi)).map_or(3, majority))
                    .collect()
            })
            .collect();
        for (k, (metric, name, label)) in METRICS.iter().enumerate() {
            let values: Vec<Vec<f64>> = (0..amps.len())
                .map(|ai| {
                    (0..freqs.len())
                        .map(|fi| {
                            cells
                                .get(&(model.clone(), ai, fi))
                                .map_or(f64::NAN, |c| mean(&c.iter().map(|t| t.1[k]).collect::<Vec<_>>()))
                        })
                        .collect()
                })
                .collect();
            let heat = Heatmap {
                title: format!("{model}: {name} and phase"),
                x_label: "frequency (Hz)".into(),
                y_label: "amplitude (m)".into(),
                x_range: (freqs[0] - 0.5 * df, freqs[freqs.len() - 1] + 0.5 * df),
                y_range: (amps[0] - 0.5 * da, amps[amps.len() - 1] + 0.5 * da),
                values,
                colorbar_label: (*label).into(),
                scale: None,
                cell_names: None,
            };
            // Uneven axes (a list): cells in index space, named by their values.
            let heat = if evenly_spaced(&freqs) && evenly_spaced(&amps) {
                heat
            } else {
                let name = |v: &f64| format!("{v}");
                Heatmap {
                    x_range: (-0.5, freqs.len() as f64 - 0.5),
                    y_range: (-0.5, amps.len() as f64 - 0.5),
                    cell_names: Some((freqs.iter().map(name).collect(), amps.iter().map(name).collect())),
                    ..heat
                }
            };
            let files = heat
                .save_with_classes(&root.join(format!("phase_{model}_{metric}")), &classes, &names)
                .map_err(|e| format!("phase diagram: {e}"))?;
            dir.note_files(files);
        }
        grids.insert(model.clone(), classes);
    }

    // Agreement between the two models, cell by cell.
    let mut agreement = None;
    let mut md = String::new();
    writeln!(md, "# Phase map (nu, A)\n")?;
    writeln!(md, "{}\n", super::scale_line(sweep, results.len(), "cell")?)?;
    writeln!(
        md,
        "Phases by the analysis' classifier (`nothing | stripes | gas`); each cell is the majority over samples, and `tie` where the samples split evenly between phases (no phase is claimed for it).\n"
    )?;
    writeln!(
        md,
        "| {} |\n|{}",
        models
            .iter()
            .map(|m| format!("{m}: contrast / mobility"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(models.len())
    )?;
    writeln!(
        md,
        "| {} |\n| {} |\n",
        models
            .iter()
            .map(|m| format!("![](phase_{m}_contrast.png)"))
            .collect::<Vec<_>>()
            .join(" | "),
        models
            .iter()
            .map(|m| format!("![](phase_{m}_mobility.png)"))
            .collect::<Vec<_>>()
            .join(" | ")
    )?;
    writeln!(
        md,
        "S(k) peak height (the late frames' structure factor; large for regular bands): {}\n",
        models
            .iter()
            .map(|m| format!("![](phase_{m}_structure_peak_height.png)"))
            .collect::<Vec<_>>()
            .join(" ")
    )?;
    for model in &models {
        writeln!(
            md,
            "## {model}\n\n| A (m) \\ nu (Hz) | {} |\n|---|{}",
            freqs.iter().map(|f| format!("{f}")).collect::<Vec<_>>().join(" | "),
            "---|".repeat(freqs.len())
        )?;
        for (ai, a) in amps.iter().enumerate().rev() {
            let row: Vec<&str> = grids[model][ai].iter().map(|&c| names[c]).collect();
            writeln!(md, "| {a} | {} |", row.join(" | "))?;
        }
        writeln!(md)?;
    }
    writeln!(
        md,
        "## Sensitivity to the classifier's thresholds\n\nEach run's phase was taken again under 27 threshold sets (mobility and persistence halved and doubled, contrast threshold 0.8 and 1.25 times; `phase_sensitivity.csv` in each run's analysis). {} of {} runs keep their phase under all of them{}\n",
        results.len() - fragile.len(),
        results.len(),
        if fragile.is_empty() { "." } else { "; the others:" }
    )?;
    for f in &fragile {
        writeln!(md, "- {f}")?;
    }
    writeln!(md)?;
    if let (Some(d), Some(c)) = (grids.get("dem"), grids.get("automaton")) {
        let (mut same, mut both, mut differ, mut ties) = (0, 0, Vec::new(), 0);
        for ai in 0..amps.len() {
            for fi in 0..freqs.len() {
                if d[ai][fi] == TIE || c[ai][fi] == TIE {
                    ties += 1;
                }
                if d[ai][fi] < 3 && c[ai][fi] < 3 {
                    both += 1;
                    if d[ai][fi] == c[ai][fi] {
                        same += 1;
                    } else {
                        differ.push(format!(
                            "({} Hz, {} m): DEM {}, automaton {}",
                            freqs[fi], amps[ai], names[d[ai][fi]], names[c[ai][fi]]
                        ));
                    }
                }
            }
        }
        writeln!(
            md,
            "## Agreement\n\nThe models agree on {same} of {both} cells; {ties} cells where either model ties are not counted.\n"
        )?;
        for d in &differ {
            writeln!(md, "- {d}")?;
        }
        agreement = Some(Agreement {
            cells: both,
            agree: same,
            ties,
            fraction: if both > 0 { same as f64 / both as f64 } else { f64::NAN },
        });
    }
    super::write_report(root, sweep, &mut dir, md)?;
    let phases = grids
        .iter()
        .map(|(m, g)| (m.clone(), g.iter().map(|row| row.iter().map(|&c| names[c]).collect()).collect()))
        .collect();
    let summary = PhaseMapSummary {
        kind: "phase-map",
        jobs: sweep.jobs.len(),
        finished: results.len(),
        frequency: freqs,
        amplitude: amps,
        phases,
        agreement,
        runs_with_threshold_sensitive_phase: fragile.len(),
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// The class of a cell whose samples split evenly between phases.
const TIE: usize = 4;

/// Spacing of a sorted grid (1 for a single value, so its cell has a width).
fn step(v: &[f64]) -> f64 {
    if v.len() > 1 {
        (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64
    } else {
        v.first().map_or(1.0, |x| x.abs().max(1e-3) * 0.2)
    }
}

#[cfg(test)]
mod axis_tests {
    use super::evenly_spaced;

    #[test]
    fn lists_of_uneven_values_are_told_from_ranges() {
        assert!(evenly_spaced(&[5.0, 13.0, 21.0, 29.0]));
        assert!(evenly_spaced(&[0.005, 0.01, 0.015]));
        assert!(!evenly_spaced(&[3.0, 4.0, 5.0, 7.0, 10.0, 20.0]));
        assert!(evenly_spaced(&[3.0]));
    }
}
