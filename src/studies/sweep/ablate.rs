//! The ablation study of thesis 3.5.4 (Figs 3.30-3.31, Table 3.6) as a sweep (`stripes
//! ablate`): its configurations (the reference and the five toggles, the automaton's own
//! ingredients, the packings), their jobs over samples, and the report: onset time, final
//! stripe count (mean +- std), MSD plateaus and phase per configuration beside the thesis'
//! values, and the density maps as a grid.

use std::fmt::Write as _;
use std::path::Path;

use super::{Job, Model, Sweep};
use crate::rundir::output::CliError;
use crate::rundir::output::Written;
use crate::rundir::report::{Headline, Summary};
use crate::scene::edit::{AutomatonEdit, AutomatonToggle, DemEdit, DemToggle, Edit};
use crate::scene::file::SceneFile;
use particles::scene::TimeStep;

/// A configuration of the ablation: its name, edits, and the thesis' outcome
/// (onset range in s, final count mean and spread) where the thesis reports one (thesis 3.5.4).
pub struct Config {
    pub name: String,
    pub edits: Vec<Edit>,
    pub thesis: Thesis,
    /// The step the configuration runs at, beside the reference's ([`pin_reference_step`]).
    pub step: StepChoice,
}

/// The step of an ablation's configuration. One change at a time: with `run.dt = "auto"` a
/// toggle changes the laws the step is chosen from, so a toggled run would also run at
/// another step than its reference. It keeps the reference's step instead, unless the
/// toggled laws need a shorter one (their own automatic step is shorter); then it runs at
/// its own and the report says so.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepChoice {
    /// The scene's own `run.dt` (the reference, or a scene with a fixed step).
    Scene,
    /// The reference's automatic step (s).
    Reference(f64),
    /// Its own automatic step (s), shorter than the reference's (s).
    Own { own: f64, reference: f64 },
}

impl StepChoice {
    /// How the report names it.
    pub fn describe(self) -> String {
        match self {
            StepChoice::Scene => "the scene's".into(),
            StepChoice::Reference(dt) => format!("the reference's, {dt:.3e} s"),
            StepChoice::Own { own, reference } => {
                format!("its own, {own:.3e} s: unstable at the reference's {reference:.3e} s")
            }
        }
    }
}

/// Sets each DEM configuration's step (see [`StepChoice`]) when the scene's step is automatic;
/// nothing changes for a scene with a fixed `run.dt`.
pub fn pin_reference_step(file: &SceneFile, configs: &mut [Config]) -> Result<(), CliError> {
    if !matches!(file.dem.run.dt, TimeStep::Auto(_)) {
        return Ok(());
    }
    let reference = particles::time_step::for_scene(&file.dem)?;
    for c in configs.iter_mut().filter(|c| c.name != "reference") {
        if !c.edits.iter().all(|e| matches!(e, Edit::Dem(_))) {
            continue;
        }
        let mut edited = file.clone();
        for e in &c.edits {
            e.apply(&mut edited);
        }
        let own = particles::time_step::for_scene(&edited.dem)?;
        c.step = if own >= reference {
            c.edits.push(Edit::Dem(DemEdit::Step(reference)));
            StepChoice::Reference(reference)
        } else {
            StepChoice::Own { own, reference }
        };
    }
    Ok(())
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
        step: StepChoice::Scene,
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
            step: StepChoice::Scene,
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
        step: StepChoice::Scene,
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
        // Ablations are of the tray's models.
        Model::Events => Vec::new(),
    }
}

pub fn jobs(configs: &[Config], model: Model, samples: usize, seed: u64) -> Vec<Job> {
    let mut jobs = Vec::new();
    for c in configs {
        for k in 0..samples {
            let labels = super::Labels {
                config: Some(c.name.clone()),
                sample: Some(k as u64),
                step: Some(c.step.describe()),
                ..super::Labels::default()
            };
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
/// What the ablation's report says: `summary.json`, field for field.
#[derive(Debug, serde::Serialize)]
pub struct AblateSummary {
    pub kind: &'static str,
    pub jobs: usize,
    pub finished: usize,
    pub rows: Vec<AblateRow>,
    #[serde(flatten)]
    pub written: Written,
}

/// One configuration of one model over its samples.
#[derive(Debug, serde::Serialize)]
pub struct AblateRow {
    pub model: &'static str,
    pub config: String,
    pub samples: usize,
    pub onset_s: f64,
    pub onset_sd: f64,
    pub stripe_count: f64,
    pub stripe_count_sd: f64,
    pub msd_plateau_before: f64,
    pub msd_plateau_after: f64,
    /// The majority phase (`tie: a / b` where samples split evenly).
    pub phase: String,
    pub step: String,
}

impl Summary for AblateSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

pub fn report(root: &Path, sweep: &Sweep) -> Result<AblateSummary, CliError> {
    let (results, mut dir) = super::open_report::<super::TrayResult>(root, sweep)?;
    let packing: Vec<usize> = sweep
        .jobs
        .iter()
        .filter_map(|j| j.labels.config.as_deref()?.strip_prefix("N=")?.parse().ok())
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
            "| configuration | samples | step | onset (s) | final stripes | MSD plateau before (m^2) | MSD plateau after (m^2) | phase | thesis | difference |\n|---|---|---|---|---|---|---|---|---|---|"
        )?;
        let mut grid = Vec::new();
        for c in &configs(model, &packing) {
            let mine: Vec<&(Job, super::TrayResult)> = results
                .iter()
                .filter(|(j, _)| j.model == model && j.labels.config.as_deref() == Some(&c.name))
                .collect();
            if mine.is_empty() {
                continue;
            }
            let get = |k: fn(&crate::analyze::read::SavedSummary) -> Option<f64>| {
                mine.iter().map(|(_, r)| super::nan_if_none(k(&r.analysis))).collect::<Vec<_>>()
            };
            let (onset, onset_sd, with_onset) = mean_std(&get(|a| a.stripe_onset_s));
            let (count, count_sd, _) = mean_std(&get(|a| a.stripe_count_final));
            let (before, _, _) = mean_std(&get(|a| a.msd_plateau_before));
            let (after, _, _) = mean_std(&get(|a| a.msd_plateau_after));
            // The majority phase; samples split evenly between phases are a tie, named as one.
            let phase = match super::majority(mine.iter().map(|(_, r)| r.analysis.phase_label())) {
                super::Majority::None => String::new(),
                super::Majority::One(p) => p,
                super::Majority::Tie(ps) => format!("tie: {}", ps.join(" / ")),
            };
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
            let step = mine[0].0.labels.step.as_deref().unwrap_or("the scene's");
            writeln!(
                md,
                "| {} | {} | {} | {} | {} +- {} | {} | {} | {} | {} | {} |",
                c.name,
                mine.len(),
                step,
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
            rows.push(AblateRow {
                model: model.name(),
                config: c.name.clone(),
                samples: mine.len(),
                onset_s: onset,
                onset_sd,
                stripe_count: count,
                stripe_count_sd: count_sd,
                msd_plateau_before: before,
                msd_plateau_after: after,
                phase,
                step: step.to_string(),
            });
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
    let summary = AblateSummary {
        kind: "ablate",
        jobs: sweep.jobs.len(),
        finished: results.len(),
        rows,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

#[cfg(test)]
mod step_tests {
    use super::*;

    /// One change at a time: on the stripe scene (`run.dt = "auto"`) every toggle runs at the
    /// reference's step unless its laws need a shorter one; a scene with a fixed step is left
    /// as it is.
    #[test]
    fn toggles_keep_the_reference_step_where_it_is_stable() {
        let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/stripes.toml"));
        let file = crate::scene::file::load(path, &[]).unwrap();
        let reference = particles::time_step::for_scene(&file.dem).unwrap();
        let mut configs = dem_configs(&[1000]);
        pin_reference_step(&file, &mut configs).unwrap();
        assert_eq!(configs[0].step, StepChoice::Scene, "the reference keeps its own");
        for c in &configs[1..] {
            match c.step {
                StepChoice::Reference(dt) => {
                    assert_eq!(dt, reference, "{}", c.name);
                    assert_eq!(c.edits.last(), Some(&Edit::Dem(DemEdit::Step(reference))), "{}", c.name);
                }
                StepChoice::Own { own, reference: r } => {
                    assert!(own < r && r == reference, "{}: {own} {r}", c.name);
                    assert!(!c.edits.iter().any(|e| matches!(e, Edit::Dem(DemEdit::Step(_)))));
                }
                StepChoice::Scene => panic!("{} left at the scene's automatic step", c.name),
            }
        }
        // The packing changes no law: it runs at the reference's step.
        assert_eq!(configs.last().unwrap().step, StepChoice::Reference(reference));
        let mut fixed = file.clone();
        fixed.dem.run.dt = TimeStep::Seconds(2e-6);
        let mut configs = dem_configs(&[]);
        pin_reference_step(&fixed, &mut configs).unwrap();
        assert!(configs.iter().all(|c| c.step == StepChoice::Scene && c.edits.len() <= 1));
    }
}
