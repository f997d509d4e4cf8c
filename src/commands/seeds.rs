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
use serde_json::{json, Value};

use crate::analysis_dir;
use crate::output::{CliError, RunDir};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Analysed runs: run directories holding analysis/, or analysis directories (at least 2).
    #[arg(required = true, num_args = 2..)]
    pub runs: Vec<PathBuf>,
    /// Output directory (default: out/seeds).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub replace: crate::cli_args::Force,
}

/// The summary numbers pooled over the runs, with their units for the report.
const KEYS: [(&str, &str, f64); 9] = [
    ("spacing_m", "S(k) peak spacing (mm)", 1e3),
    ("band_width_m", "band width (mm)", 1e3),
    ("band_gap_m", "gap between bands (mm)", 1e3),
    ("in_band_fraction", "grains in bands", 1.0),
    ("contrast", "contrast", 1.0),
    ("structure_peak_height", "S(k) peak height", 1.0),
    ("stripe_count_final", "bands in the last frame", 1.0),
    ("tail_stripe_count", "bands, median of the tail", 1.0),
    ("stripe_onset_s", "onset (s)", 1.0),
];

/// Mean, sample standard deviation and standard error of the finite values.
fn spread(v: &[f64]) -> (f64, f64, f64, usize) {
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    let (mean, stderr) = analysis::stats::mean_stderr(&f);
    (mean, stderr * (f.len() as f64).sqrt(), stderr, f.len())
}

pub fn run(args: Args) -> Result<String, CliError> {
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out/seeds"));
    let dirs = args.runs.iter().map(|r| analysis_dir::resolve(r)).collect::<Result<Vec<_>, _>>()?;
    let summaries = dirs.iter().map(|d| analysis_dir::summary(d)).collect::<Result<Vec<_>, _>>()?;
    // A run analysed before the late structure was written has no pattern distance; it
    // still counts for everything else.
    let mut warnings = Vec::new();
    let structures: Vec<_> = dirs
        .iter()
        .map(|d| {
            analysis_dir::late_structure(d)
                .map_err(|e| warnings.push(format!("no pattern distance for {}: {e}", d.display())))
                .ok()
        })
        .collect();
    crate::output::claim(&out, args.replace.force)?;
    let mut dir = RunDir::create(&out, &args)?;
    let names: Vec<String> = args.runs.iter().map(|r| r.display().to_string()).collect();

    // One row per run.
    let num = |s: &Value, k: &str| s[k].as_f64().unwrap_or(f64::NAN);
    let mut csv = String::from("run,phase,phase_robust");
    for (k, _, _) in KEYS {
        csv.push(',');
        csv.push_str(k);
    }
    csv.push('\n');
    for (name, s) in names.iter().zip(&summaries) {
        let robust = s["phase_robust"].as_bool().map_or("?", |b| if b { "1" } else { "0" });
        let _ = write!(csv, "{name},{},{robust}", s["phase"].as_str().unwrap_or("none"));
        for (k, _, _) in KEYS {
            let _ = write!(csv, ",{}", num(s, k));
        }
        csv.push('\n');
    }
    dir.text("seeds.csv", &csv)?;

    // Pooled numbers.
    let mut pooled = serde_json::Map::new();
    let mut table = String::from("| quantity | mean | spread (sd) | standard error | runs | per run |\n|---|---|---|---|---|---|\n");
    for (k, label, unit) in KEYS {
        let v: Vec<f64> = summaries.iter().map(|s| num(s, k)).collect();
        let (mean, sd, se, n) = spread(&v);
        pooled.insert(k.into(), json!({ "mean": mean, "sd": sd, "stderr": se, "runs": n }));
        let each: Vec<String> = v.iter().map(|x| format!("{:.3}", x * unit)).collect();
        let _ = writeln!(
            table,
            "| {label} | {:.3} | {:.3} | {:.3} | {n} | {} |",
            mean * unit,
            sd * unit,
            se * unit,
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
                distances.push(json!({ "a": names[i], "b": names[j], "distance": d }));
            }
        }
    }
    let values: Vec<f64> = distances.iter().filter_map(|d| d["distance"].as_f64()).collect();
    let (d_mean, d_sd, _, d_n) = spread(&values);
    let d_max = values.iter().copied().fold(f64::NAN, f64::max);

    // Over time.
    let mut spacing_plot = LinePlot::new("S(k) peak spacing over time", "t (s)", "spacing (m)");
    let mut count_plot = LinePlot::new("Bands over time", "t (s)", "bands").integer_y();
    for (name, d) in names.iter().zip(&dirs) {
        spacing_plot = spacing_plot.series(name, analysis_dir::spacings(d)?, Mark::Line);
        count_plot = count_plot.series(name, analysis_dir::counts(d)?, Mark::Line);
    }
    dir.plot("spacing_over_time", &spacing_plot)?;
    dir.plot("count_over_time", &count_plot)?;

    let phases: Vec<String> = summaries
        .iter()
        .map(|s| {
            let p = s["phase"].as_str().unwrap_or("none");
            match s["phase_robust"].as_bool() {
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
    }
    md.push_str("![spacing over time](spacing_over_time.png)\n\n![bands over time](count_over_time.png)\n");
    dir.text("report.md", &md)?;

    dir.finish(json!({
        "runs": names,
        "phases": phases,
        "pooled": pooled,
        "pattern_distances": distances,
        "pattern_distance_mean": d_mean,
        "pattern_distance_max": d_max,
        "out": out.display().to_string(),
        "warnings": warnings,
    }))
}
