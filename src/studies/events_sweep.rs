//! `stripes events-sweep SCENE --vary KEY=V1,V2,... [--vary ...] [--seeds N]`: the
//! event-driven model over a grid of scene values and seeds, as a sweep of the one engine
//! ([`crate::studies::sweep`]): jobs in parallel, one `result.json` each, `--shard I/N`, a
//! re-run that continues the same sweep (a different one is refused), and `stripes collect`.
//! The report writes `runs.csv` (one row per finished run; a run that stopped, e.g. a collapse,
//! is a row of NaN and a warning), `means.csv` (per grid point: the runs that finished, and
//! the mean and the standard error over them of every measure), a plot of the current, the
//! height and K/R against the first varied key (one line per value of the others),
//! `report.md` and `summary.json`, printed last. The reports of the vibrated-layer papers are
//! made with it.

use std::path::{Path, PathBuf};

use analysis::plot::{LinePlot, Mark};
use serde::Serialize;

use crate::events::measure::Measured;
use crate::rundir::output::CliError;
use crate::rundir::output::Written;
use crate::rundir::report::{Headline, Summary};
use crate::scene::edit::{Edit, EventsEdit};
use crate::studies::sweep::{self, Engine, EventsResult, Job, Model, Sweep, SweepKind, SweepReport};

/// What the study is given besides the engine's options (`--set`, `--shard`, `--jobs`,
/// `--force`, `--quiet`).
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// Event-driven scene file (model = "events").
    pub scene: PathBuf,
    /// The varied keys and their numbers (`KEY=V1,V2,...`).
    pub vary: Vec<String>,
    /// Seeds per grid point: run.seed = 1..=N.
    pub seeds: u64,
    /// Sweep directory (default: out/events-sweep-<scene name>).
    pub out: Option<PathBuf>,
    /// Logarithmic axes in the plots.
    pub log: bool,
}

/// One varied key and its values.
#[derive(Clone, Debug, PartialEq)]
struct Axis {
    key: String,
    values: Vec<f64>,
}

fn axes(vary: &[String]) -> Result<Vec<Axis>, CliError> {
    let mut axes: Vec<Axis> = Vec::new();
    for v in vary {
        let (key, list) = v
            .split_once('=')
            .ok_or_else(|| format!("--vary {v}: must look like KEY=V1,V2,..."))?;
        let values = list
            .split(',')
            .map(|x| x.trim().parse::<f64>().map_err(|_| format!("--vary {v}: `{x}` is not a number")))
            .collect::<Result<Vec<_>, _>>()?;
        let key = key.trim().to_string();
        // Two axes of one key would set it twice per run, the last one winning, while the
        // rows were labelled with both: each axis is named once.
        if let Some(a) = axes.iter().find(|a| a.key == key) {
            return Err(format!(
                "--vary {key} is given twice ({} and {list}): each sweep axis is named once; list all its values in one --vary {key}=V1,V2,...",
                a.values.iter().map(f64::to_string).collect::<Vec<_>>().join(",")
            )
            .into());
        }
        axes.push(Axis { key, values });
    }
    Ok(axes)
}

/// The key of a `KEY=VALUE` override.
fn set_key(set: &str) -> &str {
    set.split_once('=').map_or(set, |(k, _)| k).trim()
}

/// Refuses keys set twice: an axis also given by `--set` (the axis would win, and the
/// summary would show both), and the seed set by `--seeds N > 1` and by `--vary run.seed` or
/// `--set run.seed` (identical runs under different labels). Returns whether the scene's
/// own seed is kept (`run.seed` varied or set): then `--seeds` is 1 and no seed is imposed.
fn check_keys(axes: &[Axis], overrides: &[String], seeds: u64) -> Result<bool, CliError> {
    for a in axes {
        if let Some(s) = overrides.iter().find(|s| set_key(s) == a.key) {
            return Err(format!("--vary {} and --set {s}: the key is set twice; give it with --vary only", a.key).into());
        }
    }
    let seed_given = axes.iter().any(|a| a.key == "run.seed") || overrides.iter().any(|s| set_key(s) == "run.seed");
    if seed_given && seeds > 1 {
        return Err(format!(
            "--seeds {seeds} and run.seed (--vary or --set) both set the seed of every run, so runs would repeat under other labels; \
             give --seeds N (run.seed = 1..=N) or run.seed, not both"
        )
        .into());
    }
    Ok(seed_given)
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

/// The sweep's jobs: every grid point (first axis slowest), each with `seeds` seeds (or the
/// scene's own seed where the seed is varied or set), labelled with the point's index.
fn jobs(axes: &[Axis], seeds: u64, own_seed: bool) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (k, p) in grid(axes).iter().enumerate() {
        for seed in 1..=if own_seed { 1 } else { seeds } {
            let mut edits: Vec<Edit> = axes
                .iter()
                .zip(p)
                .map(|(a, &value)| Edit::Events(EventsEdit::Set { key: a.key.clone(), value }))
                .collect();
            if !own_seed {
                edits.push(Edit::Events(EventsEdit::Seed(seed)));
            }
            let labels = crate::studies::sweep::Labels {
                point: Some(k as u64),
                ..Default::default()
            };
            jobs.push(Job {
                id: if own_seed { format!("p{k:03}") } else { format!("p{k:03}-s{seed}") },
                model: Model::Events,
                edits,
                labels,
            });
        }
    }
    jobs
}

/// The axes of a stored sweep, from its jobs' edits: each varied key in order, with its
/// values in the order the grid first takes them.
fn stored_axes(sweep: &Sweep) -> Vec<Axis> {
    let mut axes: Vec<Axis> = Vec::new();
    for job in &sweep.jobs {
        for e in &job.edits {
            if let Edit::Events(EventsEdit::Set { key, value }) = e {
                match axes.iter_mut().find(|a| &a.key == key) {
                    Some(a) if !a.values.contains(value) => a.values.push(*value),
                    Some(_) => {}
                    None => axes.push(Axis {
                        key: key.clone(),
                        values: vec![*value],
                    }),
                }
            }
        }
    }
    axes
}

pub fn events_sweep(args: &Options, engine: &Engine) -> Result<SweepReport<EventsSweepSummary>, CliError> {
    let axes = axes(&args.vary)?;
    let own_seed = check_keys(&axes, &engine.overrides, args.seeds)?;
    if args.log {
        // A log axis cannot show a value at or below 0: refused before anything runs.
        if let Some(v) = axes[0].values.iter().find(|v| **v <= 0.0) {
            return Err(format!(
                "--log: the x axis is {} and takes {v}, which a logarithmic axis cannot show; leave out --log or the value",
                axes[0].key
            )
            .into());
        }
    }
    let name = args
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/events-sweep-{name}")));
    let sweep = Sweep {
        kind: SweepKind::EventsSweep,
        scene: args.scene.clone(),
        overrides: engine.overrides.clone(),
        jobs: jobs(&axes, args.seeds, own_seed),
        resolved: String::new(),
    };
    // Every job's scene is read and checked before anything runs or is written.
    sweep::check_jobs(&sweep)?;
    if !out.join("sweep.json").exists() {
        // A directory of something else is not taken over without --force.
        crate::rundir::output::claim(&out, engine.force)?;
    }
    let log = args.log;
    engine.execute(&out, &sweep, move |root, sweep| report_with(root, sweep, log))
}

/// The report of an events sweep's results present (`stripes collect`): linear axes.
pub fn report(root: &Path, sweep: &Sweep) -> Result<EventsSweepSummary, CliError> {
    let log = std::fs::read_to_string(root.join("plots.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<PlotScale>(&t).ok())
        .is_some_and(|p| p.log);
    report_with(root, sweep, log)
}

/// How the plots were drawn, kept so that `collect` draws them alike.
#[derive(Serialize, serde::Deserialize)]
struct PlotScale {
    log: bool,
}

fn report_with(root: &Path, sweep: &Sweep, log: bool) -> Result<EventsSweepSummary, CliError> {
    let axes = stored_axes(sweep);
    let points = grid(&axes);
    let per = sweep.jobs.len() / points.len().max(1);
    let (found, mut dir) = sweep::open_report::<EventsResult>(root, sweep)?;
    dir.json("plots.json", &serde_json::to_value(PlotScale { log })?)?;
    let mut results: Vec<Option<(Job, EventsResult)>> = Vec::new();
    results.resize_with(sweep.jobs.len(), || None);
    for (job, v) in found {
        let k = sweep
            .jobs
            .iter()
            .position(|j| j.id == job.id)
            .expect("a result of the sweep's own job");
        results[k] = Some((job, v));
    }
    let mut failures = Vec::new();
    let mut warnings = Vec::new();
    // Each finished job's seed, from its scene (read once: the escaped grains' note needs it too).
    let mut seeds = vec![f64::NAN; results.len()];
    for (k, (job, r)) in results.iter().enumerate().filter_map(|(k, r)| r.as_ref().map(|r| (k, r))) {
        if let Some(f) = &r.failure {
            let line = format!("{}: {f}", job.id);
            eprintln!("warning: run {line}");
            failures.push(line);
        }
        let scene = sweep::events_job_scene(sweep, job)?;
        seeds[k] = scene.run.seed as f64;
        // Grains above the box's open top are counted in the top bin and the means: said
        // per run.
        if let Some(m) = r.measured.as_ref().filter(|m| m.escaped_grain_samples > 0) {
            let grains: usize = scene.particles.species.iter().map(|s| s.count).sum();
            let sampled = m.samples.saturating_mul(grains as u64).max(1);
            let w = format!(
                "run {}: {} of {sampled} sampled grain positions ({:.3} %) were above the box's open top \
                 (box.height = {} m, drive.lid = \"none\"), counted in the top profile bin and in its heights",
                job.id,
                m.escaped_grain_samples,
                100.0 * m.escaped_grain_samples as f64 / sampled as f64,
                scene.tray.height
            );
            eprintln!("warning: {w}");
            warnings.push(w);
        }
    }
    let finished = results.iter().flatten().count();
    let measured: Vec<Option<&Measured>> = results.iter().map(|r| r.as_ref().and_then(|(_, r)| r.measured.as_ref())).collect();
    let Some(example) = measured.iter().flatten().next().copied() else {
        if let Some(first) = failures.first() {
            return Err(format!("every run that finished stopped; the first: {first}").into());
        }
        let md = format!("# events-sweep of `{}`\n\nNo run has finished yet.\n\n", sweep.scene.display());
        sweep::write_report(root, sweep, &mut dir, md)?;
        let summary = EventsSweepSummary {
            kind: "events-sweep",
            jobs: sweep.jobs.len(),
            runs: 0,
            grid: None,
            written: dir.written(),
        };
        dir.finish_typed(&summary)?;
        return Ok(summary);
    };
    let columns: Vec<&str> = measures(example).iter().map(|(n, _)| *n).collect();
    let mut header: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
    header.push("seed");
    header.extend(&columns);
    let mut rows = Vec::new();
    for (k, r) in results.iter().enumerate() {
        let Some((_, r)) = r else { continue };
        let mut row = points[k / per.max(1)].clone();
        row.push(seeds[k]);
        match &r.measured {
            Some(m) => row.extend(measures(m).iter().map(|(_, v)| *v)),
            None => row.extend(std::iter::repeat_n(f64::NAN, columns.len())),
        }
        rows.push(row);
    }
    dir.csv("runs.csv", &header, &rows)?;
    // Means and standard errors over seeds, per grid point.
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
            let group: Vec<&Measured> = measured[k * per..(k + 1) * per].iter().flatten().copied().collect();
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
        if log {
            plot = plot.log_x();
            if c > 0 {
                plot = plot.log_y();
                // The points a log axis cannot show are said, not dropped silently.
                let hidden = means.iter().filter(|row| row[axes.len() + 1 + 2 * c] <= 0.0).count();
                if hidden > 0 {
                    let w = format!(
                        "--log: {} leaves out {hidden} grid point(s) whose mean {} is 0 or negative (they are in means.csv)",
                        columns[c], columns[c]
                    );
                    eprintln!("warning: {w}");
                    warnings.push(w);
                }
            }
        }
        dir.plot(&columns[c].replace("_m_per_s", "").replace("_m", ""), &plot)?;
    }
    let cpu: f64 = measured.iter().flatten().map(|m| m.cpu_s).sum();
    let collisions: u64 = measured.iter().flatten().map(|m| m.collisions).sum();
    let wall_s: f64 = results.iter().flatten().map(|(_, r)| r.wall_s).sum();
    let mut md = format!(
        "# events-sweep of `{}`\n\n{} grid point(s) of {}, {per} run(s) each; {finished} of {} runs finished, {} stopped.\n\n\
         Tables: `runs.csv` (one row per run), `means.csv` (mean and standard error over seeds per point); plots against `{}`.\n\n",
        sweep.scene.display(),
        points.len(),
        axes.iter().map(|a| format!("`{}`", a.key)).collect::<Vec<_>>().join(" x "),
        sweep.jobs.len(),
        failures.len(),
        axes[0].key,
    );
    for w in &warnings {
        md.push_str(&format!("Warning: {w}\n\n"));
    }
    sweep::write_report(root, sweep, &mut dir, std::mem::take(&mut md))?;
    let summary = EventsSweepSummary {
        kind: "events-sweep",
        jobs: sweep.jobs.len(),
        runs: finished,
        grid: Some(GridSummary {
            scene: sweep.scene.display().to_string(),
            grid_points: points.len(),
            seeds: per,
            wall_s,
            cpu_s: cpu,
            collisions,
            collisions_per_cpu_s: collisions as f64 / cpu.max(1e-9),
            worst_energy_ledger_error: measured.iter().flatten().map(|m| m.energy_ledger_error).fold(0.0, f64::max),
            failed: failures,
            warnings,
        }),
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// `summary.json` of an event-driven sweep (and its stdout line).
#[derive(Debug, Serialize)]
pub struct EventsSweepSummary {
    kind: &'static str,
    jobs: usize,
    /// Runs finished so far.
    runs: usize,
    /// What the finished runs measured; none before the first run finishes.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    grid: Option<GridSummary>,
    #[serde(flatten)]
    written: Written,
}

/// The sweep's totals once a run has finished.
#[derive(Debug, Serialize)]
struct GridSummary {
    scene: String,
    grid_points: usize,
    seeds: usize,
    wall_s: f64,
    cpu_s: f64,
    collisions: u64,
    collisions_per_cpu_s: f64,
    worst_energy_ledger_error: f64,
    failed: Vec<String>,
    warnings: Vec<String>,
}

impl Summary for EventsSweepSummary {
    fn headline(&self) -> Headline {
        let (warnings, wall_s, failed) = match &self.grid {
            Some(g) => (g.warnings.len(), Some(g.wall_s), Some(g.failed.len())),
            None => (0, None, None),
        };
        Headline {
            wall_s,
            failed,
            ..Headline::written(warnings, &self.written)
        }
    }
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
        // Issue 43, finding 5: an axis named twice ran both rows at the last value under
        // two labels; it is refused, naming the key.
        let e = axes(&["base.asymmetry=0,0.5".into(), "base.asymmetry=0.1".into()]).unwrap_err();
        assert!(
            e.to_string().contains("--vary base.asymmetry is given twice (0,0.5 and 0.1)"),
            "{e}"
        );
        let (m, s) = analysis::stats::mean_stderr(&[1.0, 2.0, 3.0]);
        assert!((m - 2.0).abs() < 1e-15 && (s - (1.0f64 / 3.0).sqrt()).abs() < 1e-15);
    }

    /// Issue 43, finding 5: `--vary run.seed` with `--seeds N` gave identical runs under two
    /// labels (the seed loop overwrote the varied seed); both are refused together, and a seed
    /// given by `--vary` or `--set` is the one each run uses. A key both varied and set is
    /// refused too.
    #[test]
    fn a_seed_is_set_once_and_every_key_once() {
        let seeds = axes(&["run.seed=1,2".into()]).unwrap();
        let e = check_keys(&seeds, &[], 2).unwrap_err();
        assert!(e.to_string().contains("--seeds 2 and run.seed"), "{e}");
        assert!(check_keys(&seeds, &[], 1).unwrap(), "the varied seed is kept");
        assert!(check_keys(&[], &["run.seed=7".into()], 1).unwrap(), "a --set seed is kept");
        assert!(check_keys(&[], &["run.seed=7".into()], 3).is_err());
        assert!(!check_keys(&axes(&["run.bin=1e-3".into()]).unwrap(), &[], 3).unwrap());
        let e = check_keys(&axes(&["run.bin=1e-3".into()]).unwrap(), &["run.bin = 2e-3".into()], 1).unwrap_err();
        assert!(e.to_string().contains("--vary run.bin and --set run.bin = 2e-3"), "{e}");
    }

    /// Issue 43, finding 10: `--log` dropped the points at or below 0 without a word; an x
    /// value a log axis cannot show is refused before anything runs (and a y value left out
    /// is said in a warning).
    #[test]
    fn a_log_axis_refuses_values_it_cannot_show() {
        let out = std::env::temp_dir().join(format!("stripes-sweep-log-{}", std::process::id()));
        let args = Options {
            scene: concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml").into(),
            vary: vec!["base.asymmetry=0,0.5".into()],
            seeds: 1,
            out: Some(out.clone()),
            log: true,
        };
        let engine = Engine {
            overrides: Vec::new(),
            shard: sweep::Shard { index: 0, count: 1 },
            jobs: Some(1),
            sample_cache: out.join("samples"),
            quiet: true,
            force: false,
        };
        let e = events_sweep(&args, &engine).unwrap_err().to_string();
        assert!(e.contains("--log: the x axis is base.asymmetry and takes 0"), "{e}");
        assert!(!out.exists(), "a refused sweep wrote {}", out.display());
    }
}
