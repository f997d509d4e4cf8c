//! `stripes windows WINDOW...`: one long run's camera, analysed in windows (`stripes analyze`
//! on stretches of its frames, as `scripts/experiment/window.py` cuts them), joined over
//! time. A run of an hour is analysed in pieces, and a piece's frames may be gone by the time
//! the next is analysed (a continuation on another machine holds only its own frames); each
//! window's `camera_count.csv` and `summary.json` are kept, and this joins them:
//!
//! - `counts.csv`: every window's stroboscopic counts in time order, with the time since the
//!   schedule's last stage began (`t3`, the experiment's switch to 3 Hz / 10 mm) and the
//!   window each came from; windows that overlap, or that belong to different drives, are
//!   refused; the stretches between windows are named as gaps (no frames there);
//! - the coarsening law on the joined count, both ways ([`analysis::coarsening_law`]), on
//!   the time since `t3`, from the count's peak after the onset of stripes
//!   ([`analysis::camera::coarsening_start`]: the rule `stripes analyze` uses in one window);
//! - `count_log.png`: the count on log axes, its mean over log-spaced bins, both fits, and
//!   reference counts given with `--reference T:S` (e.g. the experiment's) as points;
//! - each window's lifetimes of counted stripes (tracks do not cross a gap, so they are not
//!   joined), and `report.md`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use analysis::coarsening_law::{compare, LawComparison};
use analysis::plot::{LegendCorner, LinePlot, Mark};
use serde::Serialize;
use serde_json::Value;

use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Summary};

/// What the study is given; serialised as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// Analysed windows of one run: directories holding `camera_count.csv` and
    /// `summary.json`, or run directories with them under `analysis/`.
    pub windows: Vec<PathBuf>,
    /// Output directory (default: out/windows).
    pub out: Option<PathBuf>,
    /// Reference counts `(time since t3 in s, count)`, drawn beside the run's.
    pub reference: Vec<(f64, f64)>,
    pub force: bool,
    pub quiet: bool,
}

/// Bins per decade of time for the count's mean on the plot.
const BINS_PER_DECADE: f64 = 10.0;

/// One window's frames and what its own analysis said.
struct Window {
    name: String,
    t: Vec<f64>,
    count: Vec<usize>,
    contrast: Vec<f64>,
    /// Start of the drive schedule's last stage (s).
    t3: f64,
    lifetimes: Value,
}

fn read_window(path: &Path) -> Result<Window, CliError> {
    let dir = [path.to_path_buf(), path.join("analysis")]
        .into_iter()
        .find(|d| d.join("camera_count.csv").is_file() && d.join("summary.json").is_file())
        .ok_or_else(|| {
            format!(
                "{}: no camera_count.csv and summary.json (in it or in its analysis/): run `stripes analyze` on the window first",
                path.display()
            )
        })?;
    let file = dir.join("camera_count.csv");
    let (header, rows) = analysis::io::read_csv(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("{}: no column `{name}`", file.display()))
    };
    let (ct, cc, cx) = (col("t")?, col("count")?, col("contrast")?);
    let mut w = Window {
        name: path.display().to_string(),
        t: Vec::with_capacity(rows.len()),
        count: Vec::with_capacity(rows.len()),
        contrast: Vec::with_capacity(rows.len()),
        t3: 0.0,
        lifetimes: Value::Null,
    };
    for (k, r) in rows.iter().enumerate() {
        let (t, c) = (r[ct], r[cc]);
        if !t.is_finite() || !c.is_finite() || c < 0.0 || c.fract() != 0.0 {
            return Err(format!("{}: row {} has time {t} and count {c}", file.display(), k + 2).into());
        }
        if w.t.last().is_some_and(|&last| t <= last) {
            return Err(format!("{}: row {}: time {t} does not follow {}", file.display(), k + 2, w.t[k - 1]).into());
        }
        w.t.push(t);
        w.count.push(c as usize);
        w.contrast.push(r[cx]);
    }
    if w.t.is_empty() {
        return Err(format!("{}: no frames", file.display()).into());
    }
    let file = dir.join("summary.json");
    let text = std::fs::read_to_string(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    let summary: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    let camera = &summary["camera"];
    w.t3 = camera["drive"]["stages"]
        .as_array()
        .and_then(|s| s.last())
        .and_then(|s| s["start"].as_f64())
        .unwrap_or(0.0);
    w.lifetimes = camera["lifetimes"].clone();
    Ok(w)
}

/// The windows in time order; overlapping windows, or windows of different drives, refused.
fn order(mut windows: Vec<Window>) -> Result<Vec<Window>, CliError> {
    windows.sort_by(|a, b| a.t[0].total_cmp(&b.t[0]));
    for p in windows.windows(2) {
        let (a, b) = (&p[0], &p[1]);
        if b.t[0] <= *a.t.last().unwrap() {
            return Err(format!(
                "windows {} ({:.3}-{:.3} s) and {} ({:.3}-{:.3} s) overlap: give each frame once",
                a.name,
                a.t[0],
                a.t.last().unwrap(),
                b.name,
                b.t[0],
                b.t.last().unwrap()
            )
            .into());
        }
        if (a.t3 - b.t3).abs() > 1e-9 {
            return Err(format!(
                "windows {} and {} are of different drives (last stage from {} s and {} s): not one run",
                a.name, b.name, a.t3, b.t3
            )
            .into());
        }
    }
    Ok(windows)
}

/// Stretches without frames between consecutive windows: `(from, to)` in s, where the step
/// between the windows exceeds twice the median step between frames.
fn gaps(windows: &[Window]) -> Vec<(f64, f64)> {
    let mut steps: Vec<f64> = windows.iter().flat_map(|w| w.t.windows(2).map(|p| p[1] - p[0])).collect();
    steps.sort_by(f64::total_cmp);
    let median = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
    windows
        .windows(2)
        .map(|p| (*p[0].t.last().unwrap(), p[1].t[0]))
        .filter(|(a, b)| b - a > 2.0 * median)
        .collect()
}

/// The mean of `(x, y)` over log-spaced bins of x (`BINS_PER_DECADE`), at each bin's
/// geometric centre; x must be positive.
fn log_binned(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut bins: std::collections::BTreeMap<i64, (f64, usize)> = std::collections::BTreeMap::new();
    for &(x, y) in points.iter().filter(|p| p.0 > 0.0) {
        let e = bins.entry((x.log10() * BINS_PER_DECADE).floor() as i64).or_insert((0.0, 0));
        e.0 += y;
        e.1 += 1;
    }
    bins.into_iter()
        .map(|(k, (sum, n))| (10f64.powf((k as f64 + 0.5) / BINS_PER_DECADE), sum / n as f64))
        .collect()
}

/// [`log_binned`] on each stretch of `points` (time since t3, count) between the gaps (run
/// time), the stretches separated by a point with a NaN count, so that the plot's line does
/// not bridge a gap.
fn binned_between_gaps(points: &[(f64, f64)], gaps: &[(f64, f64)], t3: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut rest = points;
    for &(from, _) in gaps {
        let cut = rest.partition_point(|p| p.0 + t3 <= from);
        out.extend(log_binned(&rest[..cut]));
        out.push((from - t3, f64::NAN));
        rest = &rest[cut..];
    }
    out.extend(log_binned(rest));
    out
}

#[derive(Debug, Serialize)]
pub struct WindowsSummary {
    pub windows: Vec<WindowSummary>,
    /// Start of the drive's last stage (s); times below are since it.
    pub t3_s: f64,
    pub frames: usize,
    /// Stretches without frames, `(from, to)` in s of run time.
    pub gaps_s: Vec<(f64, f64)>,
    pub stripe_count_max: usize,
    /// Onset of stripes on the joined count (time since t3, s): from it on every frame holds one.
    pub stripe_onset_s: Option<f64>,
    /// Where the coarsening fits start (time since t3, s).
    pub coarsening_from_s: Option<f64>,
    pub coarsening_law: LawComparison,
    /// A fitted rate is negative: the count grows over the fitted stretch (no coarsening).
    pub count_grows: bool,
    pub reference: Vec<ReferencePoint>,
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub written: Written,
}

#[derive(Debug, Serialize)]
pub struct WindowSummary {
    pub name: String,
    pub from_s: f64,
    pub to_s: f64,
    pub frames: usize,
    pub count_mean: f64,
    pub contrast_mean: f64,
    /// The window's own lifetimes of counted stripes (its summary's `camera.lifetimes`).
    pub lifetimes: Value,
}

/// A reference count beside the run's mean count within one second of its time.
#[derive(Debug, Serialize)]
pub struct ReferencePoint {
    /// Time since t3 (s).
    pub t_s: f64,
    pub count: f64,
    /// The run's counts at the frames within 1 s of it (empty: no frames there).
    pub run_counts: Vec<usize>,
}

impl Summary for WindowsSummary {
    fn headline(&self) -> Headline {
        Headline::written(self.warnings.len(), &self.written)
    }
}

pub fn windows(args: &Options) -> Result<WindowsSummary, CliError> {
    if args.windows.is_empty() {
        return Err("windows: give at least one analysed window".into());
    }
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out/windows"));
    let windows = order(args.windows.iter().map(|p| read_window(p)).collect::<Result<Vec<_>, _>>()?)?;
    let t3 = windows[0].t3;
    crate::rundir::output::claim(&out, args.force)?;
    let mut dir = RunDir::create(&out, &args)?;
    let mut warnings = Vec::new();

    // The joined series, in time since t3 (frames before t3 are kept in the table, not fitted).
    let mut rows = Vec::new();
    let (mut t, mut count) = (Vec::new(), Vec::new());
    for (k, w) in windows.iter().enumerate() {
        for i in 0..w.t.len() {
            rows.push(vec![w.t[i], w.t[i] - t3, w.count[i] as f64, w.contrast[i], k as f64]);
            if w.t[i] > t3 {
                t.push(w.t[i] - t3);
                count.push(w.count[i]);
            }
        }
    }
    dir.csv("counts.csv", &["t", "t_since_last_stage", "count", "contrast", "window"], &rows)?;
    let gaps = gaps(&windows);
    let (onset, from) = analysis::camera::coarsening_start(&t, &count);
    let law = compare(&t[from..], &count[from..].iter().map(|&c| c as f64).collect::<Vec<_>>());
    let reference: Vec<ReferencePoint> = args
        .reference
        .iter()
        .map(|&(at, c)| ReferencePoint {
            t_s: at,
            count: c,
            run_counts: t
                .iter()
                .zip(&count)
                .filter(|(x, _)| (**x - at).abs() <= 1.0)
                .map(|(_, c)| *c)
                .collect(),
        })
        .collect();
    if t.is_empty() {
        warnings.push(format!("no frame after the last stage's start ({t3} s): nothing to fit or draw"));
    }
    let grows = [law.power, law.logarithmic].iter().flatten().any(|f| f.rate < 0.0);
    if grows {
        warnings.push(format!(
            "a fitted rate is negative: from its peak, {:.1} s after the last stage began, the count grows rather than decays, so neither law describes a coarsening here",
            t.get(from).copied().unwrap_or(f64::NAN)
        ));
    }

    let pts: Vec<(f64, f64)> = t.iter().zip(&count).map(|(x, c)| (*x, *c as f64)).collect();
    let mut plot = LinePlot::new(
        "Stripes counted at the turning points, windows of one run joined",
        "time since the last stage began (s)",
        "stripe count S",
    )
    .integer_y()
    .include_y(0.0)
    .log_x()
    .legend(LegendCorner::UpperRight)
    .series("S, every frame", pts.clone(), Mark::Points)
    .series(
        &format!("S, mean over 1/{BINS_PER_DECADE} decade"),
        binned_between_gaps(&pts, &gaps, t3),
        Mark::LinePoints,
    );
    let fit_t = &t[from..];
    for (name, fit, power) in [("S = a t^-alpha", law.power, true), ("S = a - b ln t", law.logarithmic, false)] {
        if let Some(f) = fit {
            let label = format!(
                "{name}: {} = {:.3} [{:.3}, {:.3}]",
                if power { "alpha" } else { "b" },
                f.rate,
                f.rate_ci95.0,
                f.rate_ci95.1
            );
            plot = plot.series(&label, fit_t.iter().map(|&x| (x, f.eval(x, power))).collect(), Mark::Dashed);
        }
    }
    if !args.reference.is_empty() {
        plot = plot.series("reference", args.reference.clone(), Mark::Points);
    }
    if !pts.is_empty() {
        dir.plot("count_log", &plot)?;
    }

    let summaries: Vec<WindowSummary> = windows
        .iter()
        .map(|w| WindowSummary {
            name: w.name.clone(),
            from_s: w.t[0],
            to_s: *w.t.last().unwrap(),
            frames: w.t.len(),
            count_mean: w.count.iter().sum::<usize>() as f64 / w.t.len() as f64,
            contrast_mean: w.contrast.iter().sum::<f64>() / w.t.len() as f64,
            lifetimes: w.lifetimes.clone(),
        })
        .collect();
    let mut md = format!("# {} windows of one run, joined\n\n", windows.len());
    let _ = writeln!(
        md,
        "Times are since the drive's last stage began (t3 = {t3} s). Counts are each window's own camera counts (`stripes analyze`).\n"
    );
    md.push_str(
        "| window | from (s) | to (s) | frames | mean count | mean contrast | stripe lifetime (s) |\n|---|---|---|---|---|---|---|\n",
    );
    for w in &summaries {
        let life = match (w.lifetimes["mean_s"].as_f64(), w.lifetimes["stderr_s"].as_f64()) {
            (Some(m), Some(e)) => format!(
                "{m:.2} +- {e:.2} (longest {:.1})",
                w.lifetimes["longest_seen_s"].as_f64().unwrap_or(f64::NAN)
            ),
            _ => "none".into(),
        };
        let _ = writeln!(
            md,
            "| {} | {:.2} | {:.2} | {} | {:.2} | {:.2} | {life} |",
            w.name, w.from_s, w.to_s, w.frames, w.count_mean, w.contrast_mean
        );
    }
    if gaps.is_empty() {
        md.push_str("\nNo gaps between the windows.\n");
    } else {
        let g: Vec<String> = gaps.iter().map(|(a, b)| format!("{a:.1}-{b:.1} s")).collect();
        let _ = writeln!(md, "\nNo frames in {} (run time): the joined count has gaps there.", g.join(", "));
    }
    let shown = |x: Option<f64>| x.map_or("none".to_string(), |v| format!("{v:.2} s"));
    let _ = writeln!(
        md,
        "\nOnset of stripes on the joined count: {}; coarsening fitted from {} on ({} frames): {}.\n",
        shown(onset),
        shown(t.get(from).copied()),
        t.len() - from,
        law.note
    );
    for (name, fit) in [
        ("power law S = a t^-alpha", law.power),
        ("logarithm S = a - b ln t", law.logarithmic),
    ] {
        if let Some(f) = fit {
            let _ = writeln!(
                md,
                "- {name}: a = {:.4} [{:.4}, {:.4}], rate = {:.4} [{:.4}, {:.4}] (95 %), AIC {:.1}",
                f.a, f.a_ci95.0, f.a_ci95.1, f.rate, f.rate_ci95.0, f.rate_ci95.1, f.aic
            );
        }
    }
    if !reference.is_empty() {
        md.push_str("\n| time since t3 (s) | reference count | the run's counts within 1 s |\n|---|---|---|\n");
        for r in &reference {
            let c: Vec<String> = r.run_counts.iter().map(|c| c.to_string()).collect();
            let _ = writeln!(
                md,
                "| {} | {} | {} |",
                r.t_s,
                r.count,
                if c.is_empty() { "no frames".into() } else { c.join(" ") }
            );
        }
    }
    for w in &warnings {
        let _ = writeln!(md, "\nWarning: {w}.");
        eprintln!("warning: {w}");
    }
    if !pts.is_empty() {
        md.push_str("\n![count on log axes](count_log.png)\n");
    }
    dir.text("report.md", &md)?;
    let summary = WindowsSummary {
        windows: summaries,
        t3_s: t3,
        frames: rows.len(),
        gaps_s: gaps,
        stripe_count_max: count.iter().copied().max().unwrap_or(0),
        stripe_onset_s: onset,
        coarsening_from_s: t.get(from).copied(),
        coarsening_law: law,
        count_grows: grows,
        reference,
        warnings,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(name: &str, t: &[f64], count: &[usize]) -> Window {
        Window {
            name: name.into(),
            t: t.to_vec(),
            count: count.to_vec(),
            contrast: vec![1.0; t.len()],
            t3: 2.0,
            lifetimes: Value::Null,
        }
    }

    #[test]
    fn windows_are_put_in_order_their_gaps_named_and_overlaps_refused() {
        let a = window("a", &[3.0, 4.0, 5.0], &[1, 2, 3]);
        let b = window("b", &[10.0, 11.0], &[2, 2]);
        let c = window("c", &[6.0, 7.0], &[3, 2]);
        let w = order(vec![b, a, c]).unwrap();
        let names: Vec<&str> = w.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["a", "c", "b"]);
        assert_eq!(
            gaps(&w),
            vec![(7.0, 10.0)],
            "a step of 3 against frames 1 s apart is a gap; one of 1 is not"
        );
        let e = order(vec![window("a", &[3.0, 4.0, 5.0], &[1, 1, 1]), window("d", &[5.0, 6.0], &[1, 1])])
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("overlap") && e.contains("a (") && e.contains("d ("), "{e}");
        let mut other = window("e", &[9.0], &[1]);
        other.t3 = 0.0;
        let e = order(vec![window("a", &[3.0], &[1]), other]).err().unwrap().to_string();
        assert!(e.contains("different drives"), "{e}");
    }

    #[test]
    fn the_binned_mean_is_broken_at_each_gap() {
        // t3 = 2: run times 12 and 13 before the gap (13, 90), 92 after it.
        let m = binned_between_gaps(&[(10.0, 1.0), (11.0, 3.0), (90.0, 5.0)], &[(13.0, 92.0)], 2.0);
        assert_eq!(m.len(), 3, "{m:?}");
        assert!(m[0].1 == 2.0 && m[1].1.is_nan() && m[2].1 == 5.0, "{m:?}");
    }

    #[test]
    fn the_log_binned_mean_averages_within_a_tenth_of_a_decade() {
        // 100 and 110 share the bin [10^2, 10^2.1); 200 is in [10^2.3, 10^2.4).
        let m = log_binned(&[(100.0, 1.0), (110.0, 3.0), (200.0, 5.0), (0.0, 9.0)]);
        assert_eq!(m.len(), 2, "{m:?}");
        assert!((m[0].0 - 10f64.powf(2.05)).abs() < 1e-9 && m[0].1 == 2.0, "{m:?}");
        assert!((m[1].0 - 10f64.powf(2.35)).abs() < 1e-9 && m[1].1 == 5.0, "{m:?}");
    }
}
