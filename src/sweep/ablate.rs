//! The ablation study of thesis 3.5.4 (Figs 3.30-3.31, Table 3.6) as a sweep (`stripes
//! ablate`): its configurations (the reference and the five toggles, the automaton's own
//! ingredients, the packings), their jobs over samples, and the report: onset time, final
//! stripe count (mean +- std), MSD plateaus and phase per configuration beside the thesis'
//! values, and the density maps as a grid.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use serde_json::{json, Value};

use super::{Job, Model, Sweep};
use crate::output::CliError;
use crate::scene_edit::{AutomatonEdit, AutomatonToggle, DemEdit, DemToggle, Edit};

/// A configuration of the ablation: its name, edits, and the thesis' outcome
/// (onset range in s, final count mean and spread) where the thesis reports one (thesis 3.5.4).
pub struct Config {
    pub name: String,
    pub edits: Vec<Edit>,
    pub thesis: Thesis,
}

/// What the thesis reports for a configuration.
#[derive(Clone, Copy)]
pub enum Thesis {
    Stripes { onset: (f64, f64), count: f64, spread: f64 },
    NoStripes,
    Text(&'static str),
    NotRun,
}

/// The DEM configurations: reference, the thesis' four toggles, rolling off, and the packings.
pub fn dem_configs(packing: &[usize]) -> Vec<Config> {
    let c = |name: &str, e: &[Edit], thesis| Config {
        name: name.into(),
        edits: e.to_vec(),
        thesis,
    };
    let mut v = vec![
        c(
            "reference",
            &[],
            Thesis::Stripes {
                onset: (3.0, 5.0),
                count: 4.0,
                spread: 0.875,
            },
        ),
        c("friction-off", &[Edit::Dem(DemEdit::Off(DemToggle::Friction))], Thesis::NoStripes),
        c(
            "jumping-off",
            &[Edit::Dem(DemEdit::Off(DemToggle::Jumping))],
            Thesis::Stripes {
                onset: (6.0, 9.0),
                count: 4.0,
                spread: 1.0,
            },
        ),
        c(
            "dissipation-off",
            &[Edit::Dem(DemEdit::Off(DemToggle::Dissipation))],
            Thesis::Stripes {
                onset: (2.0, 4.0),
                count: 4.0,
                spread: 1.0,
            },
        ),
        c(
            "walls-off",
            &[Edit::Dem(DemEdit::Off(DemToggle::Walls))],
            Thesis::Stripes {
                onset: (4.0, 6.0),
                count: 5.0,
                spread: 1.0,
            },
        ),
        c("rolling-off", &[Edit::Dem(DemEdit::Off(DemToggle::Rolling))], Thesis::NotRun),
    ];
    for &n in packing {
        let text = match n {
            1000 => "no stripes",
            2000 => "weak stripes",
            4000 => "stripes",
            8000 => "massive merging structures",
            _ => "",
        };
        v.push(Config {
            name: format!("N={n}"),
            edits: vec![Edit::Dem(DemEdit::Count(n))],
            thesis: if text.is_empty() { Thesis::NotRun } else { Thesis::Text(text) },
        });
    }
    v
}

/// The automaton's own ablations: the reference and each ingredient of the `physical` rule
/// switched off, plus the same packings as the DEM.
pub fn automaton_configs(packing: &[usize]) -> Vec<Config> {
    let c = |name: &str, e: &[Edit]| Config {
        name: name.into(),
        edits: e.to_vec(),
        thesis: Thesis::NotRun,
    };
    let mut v = vec![
        c("reference", &[]),
        c("threshold-off", &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Threshold))]),
        c("flight-cap-off", &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::FlightCap))]),
        c(
            "stochastic-off",
            &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Stochastic))],
        ),
        c("knock-off", &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Knock))]),
        c("lateral-none", &[Edit::Automaton(AutomatonEdit::LateralNone)]),
        c("sideways-off", &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Sideways))]),
        c("rolling-off", &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Rolling))]),
        c(
            "frustration-off",
            &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Frustration))],
        ),
        c("trains-off", &[Edit::Automaton(AutomatonEdit::Off(AutomatonToggle::Trains))]),
        c("strict", &[Edit::Automaton(AutomatonEdit::StrictRule)]),
    ];
    v.extend(dem_configs(packing).into_iter().filter(|c| c.name.starts_with("N=")));
    v
}

/// The configurations of a model.
fn configs(model: Model, packing: &[usize]) -> Vec<Config> {
    match model {
        Model::Dem => dem_configs(packing),
        Model::Automaton => automaton_configs(packing),
    }
}

pub fn jobs(configs: &[Config], model: Model, samples: usize, seed: u64) -> Vec<Job> {
    let mut jobs = Vec::new();
    for c in configs {
        for k in 0..samples {
            let mut labels = serde_json::Map::new();
            labels.insert("config".into(), c.name.clone().into());
            labels.insert("sample".into(), k.into());
            let mut edits = c.edits.clone();
            edits.push(Edit::Dem(DemEdit::Seed(seed + k as u64)));
            jobs.push(Job {
                id: format!("{}-{}-s{k}", model.name(), c.name.replace('=', "")),
                model,
                edits,
                labels,
            });
        }
    }
    jobs
}

/// Mean and sample standard deviation of the finite values (`NaN`s when none).
fn mean_std(v: &[f64]) -> (f64, f64, usize) {
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    let n = f.len();
    if n == 0 {
        return (f64::NAN, f64::NAN, 0);
    }
    let m = f.iter().sum::<f64>() / n as f64;
    let s = if n > 1 {
        (f.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
    } else {
        0.0
    };
    (m, s, n)
}

/// `x` in scientific notation with three significant digits, `-` when not finite.
fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "-".into()
    }
}

fn fmt(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "-".into()
    }
}

/// Writes the report of whatever results exist; returns the summary.
pub fn report(root: &Path, sweep: &Sweep) -> Result<Value, CliError> {
    let (results, mut dir) = super::open_report(root, sweep)?;
    let packing: Vec<usize> = sweep
        .jobs
        .iter()
        .filter_map(|j| j.labels.get("config")?.as_str()?.strip_prefix("N=")?.parse().ok())
        .collect();
    let mut md = String::new();
    writeln!(md, "# Ablation study (thesis 3.5.4)\n")?;
    writeln!(
        md,
        "{} The thesis ran N = 4000 in 0.4 m x 0.02 m for 20 s, 9 samples.\n",
        super::scale_line(sweep, results.len(), "configuration")?
    )?;
    let mut rows = Vec::new();
    let models: Vec<Model> = {
        let mut m: Vec<Model> = sweep.jobs.iter().map(|j| j.model).collect();
        m.dedup();
        m
    };
    for model in models {
        writeln!(md, "## {}\n", model.name())?;
        writeln!(
            md,
            "| configuration | samples | onset (s) | final stripes | MSD plateau before (m^2) | MSD plateau after (m^2) | phase | thesis | difference |\n|---|---|---|---|---|---|---|---|---|"
        )?;
        let mut grid = Vec::new();
        for c in &configs(model, &packing) {
            let mine: Vec<&(Job, Value)> = results
                .iter()
                .filter(|(j, _)| j.model == model && j.labels.get("config").and_then(Value::as_str) == Some(&c.name))
                .collect();
            if mine.is_empty() {
                continue;
            }
            let get = |k: &str| mine.iter().map(|(_, r)| super::metric(r, k)).collect::<Vec<_>>();
            let (onset, onset_sd, with_onset) = mean_std(&get("stripe_onset_s"));
            let (count, count_sd, _) = mean_std(&get("stripe_count_final"));
            let (before, _, _) = mean_std(&get("msd_plateau_before"));
            let (after, _, _) = mean_std(&get("msd_plateau_after"));
            let mut phases: BTreeMap<String, usize> = BTreeMap::new();
            for (_, r) in &mine {
                *phases.entry(super::label(r, "phase")).or_default() += 1;
            }
            let phase = phases.iter().max_by_key(|(_, n)| **n).map(|(p, _)| p.clone()).unwrap_or_default();
            let (thesis, diff) = match c.thesis {
                Thesis::Stripes {
                    onset: (lo, hi),
                    count: tc,
                    spread,
                } => (
                    format!("onset {lo}-{hi} s, {tc} +- {spread}"),
                    format!(
                        "{}, count {}",
                        if onset.is_finite() {
                            format!("onset {:+.1} s", onset - 0.5 * (lo + hi))
                        } else {
                            "no onset".into()
                        },
                        fmt(count - tc, 2)
                    ),
                ),
                Thesis::NoStripes => ("no stripes".into(), format!("count {}", fmt(count, 2))),
                Thesis::Text(t) => (t.into(), "-".into()),
                Thesis::NotRun => ("not run".into(), "-".into()),
            };
            writeln!(
                md,
                "| {} | {} | {} | {} +- {} | {} | {} | {} | {} | {} |",
                c.name,
                mine.len(),
                if with_onset > 0 {
                    format!("{} +- {} ({with_onset} with onset)", fmt(onset, 1), fmt(onset_sd, 1))
                } else {
                    "none".into()
                },
                fmt(count, 2),
                fmt(count_sd, 2),
                sci(before),
                sci(after),
                phase,
                thesis,
                diff
            )?;
            rows.push(json!({
                "model": model.name(), "config": c.name, "samples": mine.len(), "onset_s": onset, "onset_sd": onset_sd,
                "stripe_count": count, "stripe_count_sd": count_sd, "msd_plateau_before": before,
                "msd_plateau_after": after, "phase": phase,
            }));
            let (j, _) = mine[0];
            grid.push(format!("{}<br>![](jobs/{}/analysis/density_map.png)", c.name, j.id));
        }
        writeln!(md, "\nDensity maps (first sample of each configuration):\n")?;
        for chunk in grid.chunks(3) {
            writeln!(md, "| {} |", chunk.join(" | "))?;
            if chunk.as_ptr() == grid.as_ptr() {
                writeln!(md, "|{}", "---|".repeat(chunk.len()))?;
            }
        }
        writeln!(md)?;
    }
    super::write_report(root, sweep, &mut dir, md)?;
    let line = dir.finish(json!({ "kind": "ablate", "jobs": sweep.jobs.len(), "finished": results.len(), "rows": rows }))?;
    Ok(serde_json::from_str(&line)?)
}
