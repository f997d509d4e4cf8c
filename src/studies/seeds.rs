//! `stripes seeds RUN...`: several analysed runs of one scene (seeds, or any set worth
//! pooling) side by side. Writes `seeds.csv` (one row per run: phase, whether the phase
//! holds under the classifier's threshold sweep, and the structure's numbers), the mean,
//! spread and standard error of each number and the pattern distances between every two
//! runs in `summary.json`, the S(k) peak spacing and the band count over time of every run
//! (`spacing_over_time.png`, `count_over_time.png`) to show coarsening or its absence, and
//! `report.md`.

use std::fmt::Write as _;
use std::path::PathBuf;

use analysis::plot::{LinePlot, Mark};
use serde::Serialize;

use crate::analyze::read;
use crate::analyze::read::SavedSummary;
use crate::rundir::output::Written;
use crate::rundir::output::{CliError, RunDir};
use crate::rundir::report::{Headline, Summary};

/// What the study is given (the command's arguments, without the command line); serialised
/// as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// Analysed runs: run directories holding analysis/, or analysis directories (at least 2).
    pub runs: Vec<PathBuf>,
    /// Output directory (default: out/seeds).
    pub out: Option<PathBuf>,
    pub force: bool,
    pub quiet: bool,
}

/// A number of an analysis summary.
type Field = fn(&SavedSummary) -> Option<f64>;

/// The summary numbers pooled over the runs: the name they are written under, their label
/// and unit for the report, and the field.
const KEYS: [(&str, &str, f64, Field); 9] = [
    ("spacing_m", "S(k) peak spacing (mm)", 1e3, |s| s.spacing_m),
    ("band_width_m", "band width (mm)", 1e3, |s| s.band_width_m),
    ("band_gap_m", "gap between bands (mm)", 1e3, |s| s.band_gap_m),
    ("in_band_fraction", "grains in bands", 1.0, |s| s.in_band_fraction),
    ("contrast", "contrast", 1.0, |s| s.contrast),
    ("structure_peak_height", "S(k) peak height", 1.0, |s| s.structure_peak_height),
    ("stripe_count_final", "bands in the last frame", 1.0, |s| s.stripe_count_final),
    ("tail_stripe_count", "bands, median of the tail", 1.0, |s| s.tail_stripe_count),
    ("stripe_onset_s", "onset (s)", 1.0, |s| s.stripe_onset_s),
];

/// Mean, sample standard deviation and standard error of the finite values; the spread and
/// the error are undefined (NaN, null in JSON) with fewer than two values, never 0.
fn spread(v: &[f64]) -> (f64, f64, f64, usize) {
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    let (mean, stderr) = analysis::stats::mean_stderr(&f);
    if f.len() < 2 {
        return (mean, f64::NAN, f64::NAN, f.len());
    }
    (mean, stderr * (f.len() as f64).sqrt(), stderr, f.len())
}

/// A number for the report: "undefined" where it is not a number.
fn shown(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3}")
    } else {
        "undefined".into()
    }
}

/// Runs `seeds` cannot pool: analyses of an event-driven vertical box, whose band widths and
/// spacings are those of grains stacked in columns, not of a tray's stripes. Refused, naming
/// each.
fn refuse_unpoolable(runs: &[PathBuf], summaries: &[SavedSummary]) -> Result<(), CliError> {
    let vertical: Vec<String> = runs
        .iter()
        .zip(summaries)
        .filter(|(_, s)| s.geometry.as_deref() == Some("vertical-box") || s.phase.as_deref() == Some("unclassified"))
        .map(|(r, _)| r.display().to_string())
        .collect();
    if vertical.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{} is an analysis of an event-driven vertical box: `seeds` pools trays' stripes (spacing, band widths, phase), which such a box \
         does not have; pool event-driven runs with `stripes events-sweep --seeds N` instead",
        vertical.join(", ")
    )
    .into())
}

/// One analysis given twice (the same directory, or a run and its `analysis/`) would count as
/// two independent runs and shrink every standard error: refused, naming both arguments.
fn refuse_repeats(runs: &[PathBuf], dirs: &[PathBuf]) -> Result<(), CliError> {
    let real: Vec<PathBuf> = dirs
        .iter()
        .map(|d| std::fs::canonicalize(d).unwrap_or_else(|_| d.clone()))
        .collect();
    for j in 1..real.len() {
        if let Some(i) = real[..j].iter().position(|r| *r == real[j]) {
            return Err(format!(
                "runs {} and {} are the same analysis ({}): each run must be given once, or its numbers count twice",
                runs[i].display(),
                runs[j].display(),
                real[j].display()
            )
            .into());
        }
    }
    Ok(())
}

/// Runs that are not of one scene: their grain count, drive period or tray packing differ.
/// Pooling them is allowed (any set worth pooling), but said, so that a spread between seeds
/// is not read from runs of different scenes.
fn unlike_runs(runs: &[PathBuf], summaries: &[SavedSummary]) -> Vec<String> {
    let mut warnings = Vec::new();
    let fields: [(&str, &str, f64, Field); 3] = [
        ("particles", "grain counts", 0.0, |s| s.particles),
        ("period_s", "drive periods", 1e-9, |s| s.period_s),
        ("mean_area_fraction", "packings", 0.05, |s| s.mean_area_fraction),
    ];
    for (key, what, rel, field) in fields {
        let v: Vec<Option<f64>> = summaries.iter().map(field).collect();
        let Some(first) = v.iter().flatten().next().copied() else {
            continue;
        };
        if v.iter().flatten().any(|x| (x - first).abs() > rel * first.abs()) {
            let each: Vec<String> = runs
                .iter()
                .zip(&v)
                .map(|(r, x)| format!("{} {}", r.display(), x.map_or("?".into(), |x| format!("{x:.4}"))))
                .collect();
            warnings.push(format!(
                "the runs differ in their {what} ({key}: {}), so they are not seeds of one scene",
                each.join(", ")
            ));
        }
    }
    warnings
}

/// What `stripes seeds` found: `summary.json`, field for field.
#[derive(Debug, Serialize)]
pub struct SeedsSummary {
    pub runs: Vec<String>,
    /// Each run's phase, `(threshold-sensitive)` where the label is not robust.
    pub phases: Vec<String>,
    /// Each quantity pooled over the runs that have it.
    pub pooled: std::collections::BTreeMap<&'static str, Pooled>,
    pub pattern_distances: Vec<Distance>,
    pub pattern_distance_mean: f64,
    pub pattern_distance_max: f64,
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub written: Written,
}

/// A quantity over the runs: mean, spread and standard error (NaN, written as null, where
/// undefined: not a spread of 0).
#[derive(Debug, Serialize)]
pub struct Pooled {
    pub mean: f64,
    pub sd: f64,
    pub stderr: f64,
    pub runs: usize,
}

/// The pattern distance between two runs.
#[derive(Debug, Serialize)]
pub struct Distance {
    pub a: String,
    pub b: String,
    pub distance: f64,
}

impl Summary for SeedsSummary {
    fn headline(&self) -> Headline {
        Headline::written(self.warnings.len(), &self.written)
    }
}

pub fn seeds(args: &Options) -> Result<SeedsSummary, CliError> {
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out/seeds"));
    let dirs = args.runs.iter().map(|r| read::resolve(r)).collect::<Result<Vec<_>, _>>()?;
    refuse_repeats(&args.runs, &dirs)?;
    let summaries = dirs.iter().map(|d| read::summary(d)).collect::<Result<Vec<_>, _>>()?;
    refuse_unpoolable(&args.runs, &summaries)?;
    let mut warnings = unlike_runs(&args.runs, &summaries);
    // A run analysed before the late structure was written has no pattern distance; it
    // still counts for everything else.
    let structures: Vec<_> = dirs
        .iter()
        .map(|d| {
            read::late_structure(d)
                .map_err(|e| warnings.push(format!("no pattern distance for {}: {e}", d.display())))
                .ok()
        })
        .collect();
    crate::rundir::output::claim(&out, args.force)?;
    let mut dir = RunDir::create(&out, &args)?;
    let names: Vec<String> = args.runs.iter().map(|r| r.display().to_string()).collect();

    // One row per run.
    let num = |s: &SavedSummary, field: Field| field(s).unwrap_or(f64::NAN);
    let mut csv = String::from("run,phase,phase_robust");
    for (k, _, _, _) in KEYS {
        csv.push(',');
        csv.push_str(k);
    }
    csv.push('\n');
    for (name, s) in names.iter().zip(&summaries) {
        let robust = s.phase_robust.map_or("?", |b| if b { "1" } else { "0" });
        let _ = write!(csv, "{name},{},{robust}", s.phase.as_deref().unwrap_or("none"));
        for (_, _, _, field) in KEYS {
            let _ = write!(csv, ",{}", num(s, field));
        }
        csv.push('\n');
    }
    dir.text("seeds.csv", &csv)?;

    // Pooled numbers.
    let mut pooled = std::collections::BTreeMap::new();
    let mut table = String::from("| quantity | mean | spread (sd) | standard error | runs | per run |\n|---|---|---|---|---|---|\n");
    for (k, label, unit, field) in KEYS {
        let v: Vec<f64> = summaries.iter().map(|s| num(s, field)).collect();
        let (mean, sd, se, n) = spread(&v);
        // NaN is written as null: an undefined spread, not a spread of 0.
        pooled.insert(
            k,
            Pooled {
                mean,
                sd,
                stderr: se,
                runs: n,
            },
        );
        if n == 1 {
            warnings.push(format!(
                "{k}: only one run has a value, so its spread and standard error are undefined (null), not 0"
            ));
        }
        let each: Vec<String> = v.iter().map(|x| shown(x * unit)).collect();
        let _ = writeln!(
            table,
            "| {label} | {} | {} | {} | {n} | {} |",
            shown(mean * unit),
            shown(sd * unit),
            shown(se * unit),
            each.join(", ")
        );
    }

    // Pattern distances between every two runs.
    let mut distances = Vec::new();
    for i in 0..structures.len() {
        for j in i + 1..structures.len() {
            let (Some(a), Some(b)) = (&structures[i], &structures[j]) else {
                continue;
            };
            if let Some(d) = analysis::structure::distance(a, b) {
                distances.push((i, j, d));
            }
        }
    }
    let values: Vec<f64> = distances.iter().map(|d| d.2).filter(|d| d.is_finite()).collect();
    let distances: Vec<Distance> = distances
        .into_iter()
        .map(|(i, j, distance)| Distance {
            a: names[i].clone(),
            b: names[j].clone(),
            distance,
        })
        .collect();
    let (d_mean, d_sd, _, d_n) = spread(&values);
    let d_max = values.iter().copied().fold(f64::NAN, f64::max);

    // Over time.
    let mut spacing_plot = LinePlot::new("S(k) peak spacing over time", "t (s)", "spacing (m)");
    let mut count_plot = LinePlot::new("Bands over time", "t (s)", "bands").integer_y();
    for (name, d) in names.iter().zip(&dirs) {
        spacing_plot = spacing_plot.series(name, read::spacings(d)?, Mark::Line);
        count_plot = count_plot.series(name, read::counts(d)?, Mark::Line);
    }
    dir.plot("spacing_over_time", &spacing_plot)?;
    dir.plot("count_over_time", &count_plot)?;

    let phases: Vec<String> = summaries
        .iter()
        .map(|s| {
            let p = s.phase.as_deref().unwrap_or("none");
            match s.phase_robust {
                Some(false) => format!("{p} (threshold-sensitive)"),
                _ => p.to_string(),
            }
        })
        .collect();
    let mut md = format!("# {} runs side by side\n\n", names.len());
    let _ = writeln!(md, "Runs: {}.\n", names.join(", "));
    let _ = writeln!(md, "Phases: {}.\n", phases.join(", "));
    md.push_str(&table);
    let _ = writeln!(
        md,
        "\nPattern distance between two runs (late S(k) and band widths): mean {d_mean:.3}, sd {d_sd:.3}, largest {d_max:.3} over {d_n} pairs. \
         This is the scale against which another model's or another scene's distance from these runs means something.\n"
    );
    for w in &warnings {
        let _ = writeln!(md, "Warning: {w}.\n");
        // The summary line counts the warnings; each is said here, where it is seen.
        eprintln!("warning: {w}");
    }
    md.push_str("![spacing over time](spacing_over_time.png)\n\n![bands over time](count_over_time.png)\n");
    dir.text("report.md", &md)?;

    let summary = SeedsSummary {
        runs: names,
        phases,
        pooled,
        pattern_distances: distances,
        pattern_distance_mean: d_mean,
        pattern_distance_max: d_max,
        warnings,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{json, Value};

    /// A summary as `summary.json` would hold it.
    fn saved(v: Value) -> SavedSummary {
        serde_json::from_value(v).unwrap()
    }

    fn runs(n: usize) -> Vec<PathBuf> {
        (1..=n).map(|i| PathBuf::from(format!("seed-{i}"))).collect()
    }

    #[test]
    fn seeds_of_one_scene_pass_and_other_scenes_are_named() {
        let a = saved(json!({"particles": 2000.0, "period_s": 1.0 / 3.0, "mean_area_fraction": 0.458}));
        let b = saved(json!({"particles": 2000.0, "period_s": 1.0 / 3.0, "mean_area_fraction": 0.461}));
        assert!(unlike_runs(&runs(2), &[a.clone(), b]).is_empty());
        let c = saved(json!({"particles": 1000.0, "period_s": 0.2, "mean_area_fraction": 0.458}));
        let w = unlike_runs(&runs(3), &[a.clone(), a, c]);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].contains("grain counts") && w[0].contains("seed-3 1000"), "{w:?}");
        assert!(w[1].contains("drive periods") && w[1].contains("seed-3 0.2000"), "{w:?}");
    }

    /// Issue 43, finding 10: one value has no spread (null, not 0), and analyses of an
    /// event-driven box are refused by name.
    #[test]
    fn one_value_has_no_spread_and_a_vertical_box_is_not_pooled() {
        let (mean, sd, se, n) = spread(&[0.03, f64::NAN]);
        assert_eq!((mean, n), (0.03, 1));
        assert!(sd.is_nan() && se.is_nan(), "one value gave sd {sd}, stderr {se}");
        assert_eq!(shown(se), "undefined");
        let (_, sd, se, n) = spread(&[1.0, 3.0]);
        assert_eq!(n, 2);
        assert!((sd - 2f64.sqrt()).abs() < 1e-12 && (se - 1.0).abs() < 1e-12);
        let tray = saved(json!({"phase": "stripes", "geometry": "tray"}));
        let vertical = saved(json!({"phase": "unclassified", "geometry": "vertical-box"}));
        assert!(refuse_unpoolable(&runs(2), &[tray.clone(), tray.clone()]).is_ok());
        let e = refuse_unpoolable(&runs(2), &[tray, vertical]).unwrap_err().to_string();
        assert!(e.starts_with("seed-2 is an analysis of an event-driven vertical box"), "{e}");
    }

    #[test]
    fn one_analysis_given_twice_is_refused() {
        let dir = std::env::temp_dir().join(format!("stripes-seeds-repeat-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("analysis")).unwrap();
        let dirs = vec![dir.join("analysis"), dir.join("analysis").join(".."), dir.join("analysis")];
        let given = vec![dir.clone(), dir.join("x"), dir.join("analysis")];
        let e = refuse_repeats(&given, &dirs).unwrap_err().to_string();
        assert!(e.contains("same analysis") && e.contains(&given[0].display().to_string()), "{e}");
        assert!(refuse_repeats(&given[..2], &dirs[..2]).is_ok());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
