//! `stripes events-sweep SCENE --vary KEY=V1,V2,... [--vary ...] [--seeds N]`: the
//! event-driven model over a grid of scene values and seeds, run in parallel in memory.
//! It writes `runs.csv` (one row per run; a failed run, e.g. a collapse, is a row of NaN and
//! a warning), `means.csv` (per grid point: the runs that finished, and the mean and the
//! standard error over them of every measure), a plot of the current, the height and K/R
//! against the first varied key (one line per value of the others), and `summary.json`,
//! printed last. The reports of the vibrated-layer papers are made with it.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

use analysis::plot::{LinePlot, Mark};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

use crate::events_measure::{measure, Measured};
use crate::output::{progress_bar, CliError, RunDir};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Event-driven scene file (model = "events"), e.g. scenes/ratchet.toml.
    pub scene: PathBuf,
    /// A key and the numbers it takes, e.g. --vary base.asymmetry=0,0.25,0.5 (repeatable:
    /// every combination runs). An array of tables takes an index: particles.species.0.count.
    #[arg(long = "vary", value_name = "KEY=V1,V2,...", required = true)]
    pub vary: Vec<String>,
    /// Override a scene key for every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
    /// Seeds per grid point: run.seed = 1..=N.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub seeds: u64,
    /// Worker threads (default: every core). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory (default: out/events-sweep-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the files of an output directory that already holds some (default: refuse it).
    #[arg(long)]
    pub force: bool,
    /// Draw the plots on a logarithmic x axis, and H and K/R on a logarithmic y axis too
    /// (a power law shows as a line).
    #[arg(long)]
    pub log: bool,
    #[command(flatten)]
    #[serde(flatten)]
    pub progress: crate::cli_args::Quiet,
}

/// One varied key and its values.
#[derive(Clone, Debug, PartialEq)]
struct Axis {
    key: String,
    values: Vec<f64>,
}

fn axes(vary: &[String]) -> Result<Vec<Axis>, CliError> {
    vary.iter()
        .map(|v| {
            let (key, list) = v
                .split_once('=')
                .ok_or_else(|| format!("--vary {v}: must look like KEY=V1,V2,..."))?;
            let values = list
                .split(',')
                .map(|x| x.trim().parse::<f64>().map_err(|_| format!("--vary {v}: `{x}` is not a number")))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(Axis {
                key: key.trim().to_string(),
                values,
            })
        })
        .collect()
}

/// Every combination of the axes' values, the first axis varying slowest.
fn grid(axes: &[Axis]) -> Vec<Vec<f64>> {
    axes.iter().fold(vec![Vec::new()], |acc, a| {
        acc.iter()
            .flat_map(|p| {
                a.values.iter().map(move |&v| {
                    let mut q = p.clone();
                    q.push(v);
                    q
                })
            })
            .collect()
    })
}

/// The measures written per run, in column order.
fn measures(m: &Measured) -> Vec<(&'static str, f64)> {
    let mut out = vec![
        ("current_x_m_per_s", m.current_x_m_per_s),
        ("mean_height_m", m.mean_height_m),
        ("reduced_height_m", m.reduced_height_m),
        ("k_over_r", m.k_over_r),
        ("k_over_r_phase0", m.k_over_r_phase0),
        ("collisions", m.collisions as f64),
        ("collisions_per_s", m.collisions_per_s),
        ("energy_ledger_error", m.energy_ledger_error),
    ];
    if m.temperatures.len() == 2 {
        out.push(("temperature_ratio_bulk", m.temperature_ratio_bulk));
    }
    let names = [["t_x_j_1", "t_z_j_1", "t_rot_j_1"], ["t_x_j_2", "t_z_j_2", "t_rot_j_2"]];
    for (k, t) in m.temperatures.iter().enumerate() {
        for c in 0..3 {
            out.push((names[k][c], t[c]));
        }
    }
    out
}

pub fn run(args: Args) -> Result<String, CliError> {
    let axes = axes(&args.vary)?;
    let points = grid(&axes);
    let name = args
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/events-sweep-{name}")));
    // Every scene of the grid is read and checked before anything runs or is written.
    // The varied keys are the user's `--vary KEY=...` text, applied as `--set` is; the seed
    // is set on the scene itself.
    let mut jobs = Vec::new();
    for p in &points {
        let mut set = args.overrides.clone();
        set.extend(axes.iter().zip(p).map(|(a, v)| format!("{}={v}", a.key)));
        let point = crate::events_scene::load(&args.scene, &set)?;
        for seed in 1..=args.seeds {
            let mut scene = point.clone();
            scene.run.seed = seed;
            scene.config()?;
            jobs.push((p.clone(), seed, scene));
        }
    }
    crate::output::claim(&out, args.force)?;
    let lock = crate::run_lock::RunLock::acquire(&out)?;
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads.max(1)).build()?;
    let bar = progress_bar(jobs.len() as u64, args.progress.quiet, "events-sweep");
    let done = AtomicU64::new(0);
    let wall = std::time::Instant::now();
    let results: Vec<Result<Measured, String>> = pool.install(|| {
        jobs.par_iter()
            .map(|(_, _, scene)| {
                let r = measure(scene);
                bar.set_position(done.fetch_add(1, Ordering::Relaxed) + 1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    let wall_s = wall.elapsed().as_secs_f64();
    // A run that fails (a collapse without a guard, say) is reported and left out of the
    // means, not allowed to sink the others.
    let mut measured = Vec::new();
    let mut failures = Vec::new();
    for ((p, seed, _), r) in jobs.iter().zip(results) {
        match r {
            Ok(m) => measured.push(Some(m)),
            Err(e) => {
                let set: Vec<String> = axes.iter().zip(p).map(|(a, v)| format!("{}={v}", a.key)).collect();
                let line = format!("{} seed {seed}: {e}", set.join(" "));
                eprintln!("warning: run {line}");
                failures.push(line);
                measured.push(None);
            }
        }
    }
    let Some(example) = measured.iter().flatten().next().cloned() else {
        return Err(format!("every run failed; the first: {}", failures[0]).into());
    };
    let mut dir = RunDir::create(&out, &json!({ "args": args }))?;
    let columns: Vec<&str> = measures(&example).iter().map(|(n, _)| *n).collect();
    let mut header: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
    header.push("seed");
    header.extend(&columns);
    let rows: Vec<Vec<f64>> = jobs
        .iter()
        .zip(&measured)
        .map(|((p, seed, _), m)| {
            let mut row = p.clone();
            row.push(*seed as f64);
            match m {
                Some(m) => row.extend(measures(m).iter().map(|(_, v)| *v)),
                None => row.extend(std::iter::repeat_n(f64::NAN, columns.len())),
            }
            row
        })
        .collect();
    dir.csv("runs.csv", &header, &rows)?;
    // Means and standard errors over seeds, per grid point.
    let per = args.seeds as usize;
    let mut mean_header: Vec<String> = axes.iter().map(|a| a.key.clone()).collect();
    mean_header.push("runs".into());
    for c in &columns {
        mean_header.push(format!("{c}_mean"));
        mean_header.push(format!("{c}_stderr"));
    }
    let means: Vec<Vec<f64>> = points
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let group: Vec<&Measured> = measured[k * per..(k + 1) * per].iter().flatten().collect();
            let mut row = p.clone();
            row.push(group.len() as f64);
            for c in 0..columns.len() {
                let xs: Vec<f64> = group.iter().map(|m| measures(m)[c].1).collect();
                let (mean, err) = analysis::stats::mean_stderr(&xs);
                row.push(mean);
                row.push(err);
            }
            row
        })
        .collect();
    let mean_refs: Vec<&str> = mean_header.iter().map(String::as_str).collect();
    dir.csv("means.csv", &mean_refs, &means)?;
    // Plots against the first axis, one line per value of the others.
    let first = &axes[0];
    let labels = [
        ("current_x_m_per_s", "current <v_x> (m/s)"),
        ("mean_height_m", "mean height of the centres (m)"),
        ("reduced_height_m", "H: centre of mass at phase 0 minus rest (m)"),
        ("k_over_r", "K/R, all phases"),
        ("k_over_r_phase0", "K/R at phase 0"),
        ("temperature_ratio_bulk", "T2/T1 in the bulk"),
    ];
    let plots: Vec<(usize, &str)> = labels
        .iter()
        .filter_map(|(name, label)| columns.iter().position(|n| n == name).map(|c| (c, *label)))
        .collect();
    for (c, label) in plots {
        let mut plot = LinePlot::new(&format!("{} against {}", columns[c], first.key), &first.key, label);
        let rest = points.len() / first.values.len();
        for r in 0..rest {
            // Mean and standard error over seeds at each value of the first axis.
            let (line, errors): (Vec<(f64, f64)>, Vec<f64>) = (0..first.values.len())
                .map(|i| {
                    let row = &means[i * rest + r];
                    ((row[0], row[axes.len() + 1 + 2 * c]), row[axes.len() + 2 + 2 * c])
                })
                .filter(|((_, y), _)| y.is_finite())
                .unzip();
            let name: Vec<String> = axes[1..]
                .iter()
                .enumerate()
                .map(|(j, a)| format!("{}={}", a.key, means[r][j + 1]))
                .collect();
            let name = if name.is_empty() {
                "mean over seeds".to_string()
            } else {
                name.join(", ")
            };
            plot = plot.series_with_errors(&name, line, errors, Mark::LinePoints);
        }
        if c == 0 {
            plot = plot.include_y(0.0);
        }
        if args.log {
            plot = plot.log_x();
            if c > 0 {
                plot = plot.log_y();
            }
        }
        dir.plot(&columns[c].replace("_m_per_s", "").replace("_m", ""), &plot)?;
    }
    let cpu: f64 = measured.iter().flatten().map(|m| m.cpu_s).sum();
    let collisions: u64 = measured.iter().flatten().map(|m| m.collisions).sum();
    let summary = dir.finish(json!({
        "scene": args.scene.display().to_string(),
        "runs": measured.len(),
        "grid_points": points.len(),
        "seeds": args.seeds,
        "threads": threads,
        "wall_s": wall_s,
        "cpu_s": cpu,
        "collisions": collisions,
        "collisions_per_cpu_s": collisions as f64 / cpu.max(1e-9),
        "worst_energy_ledger_error": measured.iter().flatten().map(|m| m.energy_ledger_error).fold(0.0, f64::max),
        "failed": failures,
    }));
    drop(lock);
    summary
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_is_every_combination_first_axis_slowest_and_bad_values_are_named() {
        let a = axes(&["a=1,2".into(), "b=10,20,30".into()]).unwrap();
        let g = grid(&a);
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], vec![1.0, 10.0]);
        assert_eq!(g[2], vec![1.0, 30.0]);
        assert_eq!(g[3], vec![2.0, 10.0]);
        let e = axes(&["a=1,x".into()]).unwrap_err();
        assert!(e.to_string().contains("`x` is not a number"), "{e}");
        assert!(axes(&["a".into()]).is_err());
        let (m, s) = analysis::stats::mean_stderr(&[1.0, 2.0, 3.0]);
        assert!((m - 2.0).abs() < 1e-15 && (s - (1.0f64 / 3.0).sqrt()).abs() < 1e-15);
    }
}
