//! `stripes analyze RUN_DIR|SNAPSHOTS|DUMP`: the shared analysis of a DEM run, an automaton
//! run or a LAMMPS dump (see `analysis::input`), written as CSV tables, PNG + SVG plots and
//! `summary.json`. All numbers come from `analysis::report::analyze`; this module only
//! writes and draws them.

use std::path::PathBuf;

use analysis::density::CountProfile;
use analysis::input::load;
use analysis::plot::{Heatmap, LinePlot, Mark};
use analysis::report::{analyze, Options, Report};
use serde::Serialize;

use crate::output::{CliError, RunDir};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// A run directory (holding snapshots.bin), a snapshots.bin file (DEM or automaton) or a
    /// LAMMPS text dump (`ITEM: ATOMS id radius x y z [vx vy vz]`).
    pub input: PathBuf,
    /// Output directory (default: <RUN_DIR>/analysis, or <DUMP>.analysis beside a dump).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the files of an output directory that already holds some (default: refuse it).
    #[arg(long)]
    pub force: bool,
    /// Cell width of the density map (m); the area fraction is averaged exactly per cell.
    #[arg(long, default_value_t = 1e-3, value_parser = crate::cli_values::positive, allow_negative_numbers = true)]
    pub cell: f64,
    /// Stripe threshold on the area fraction (default: 1.5 x the layer's mean, at most halfway from the mean to the jammed 0.82)
    #[arg(long, value_parser = crate::cli_values::positive)]
    pub threshold: Option<f64>,
    /// Minimum stripe width (m; default: five mean grain diameters).
    #[arg(long)]
    pub min_width: Option<f64>,
    /// Time step of a LAMMPS dump (s): time = timestep x dt. Ignored for snapshots.
    #[arg(long, default_value = "8e-6")]
    pub dt: f64,
    /// Drive period for the MSD per period (s; default: 1 / drive.frequency from the run's
    /// config.json, else the median snapshot spacing).
    #[arg(long)]
    pub period: Option<f64>,
    /// Index of the tracer grain (0-based; LAMMPS: in order of atom id).
    #[arg(long, default_value_t = 0)]
    pub tracer: usize,
    /// Fraction of the frames, at the end, taken as the final state for the phase.
    #[arg(long, default_value_t = 0.1)]
    pub tail: f64,
    /// The layer is periodic in y too (walls off): y displacements use the minimum image.
    #[arg(long)]
    pub periodic_y: bool,
    /// Window FROM,TO (s) of the MSD plateau a1 before stripes (default: the first three
    /// quarters of the time before the onset; without onset, the first half of the run).
    #[arg(long)]
    pub plateau_before: Option<String>,
    /// Window FROM,TO (s) of the MSD plateau a2 after stripes (default: from the onset plus a
    /// quarter of the remaining time; without onset, the second half of the run).
    #[arg(long)]
    pub plateau_after: Option<String>,
    /// Classifier: below this mobility (mean diameters per period) the phase is `nothing`.
    #[arg(long, default_value_t = 0.1)]
    pub mobility_min: f64,
    /// Classifier: at or above this contrast (x random layer), with stripes, the phase is `stripes`.
    #[arg(long, default_value_t = 2.0)]
    pub contrast_min: f64,
    /// Classifier: drive periods over which a band must hold its place (in the time-averaged
    /// profile) to count as a stationary stripe, whatever the contrast.
    #[arg(long, default_value_t = 10.0)]
    pub persistence_periods: f64,
}

impl Default for Args {
    /// The command-line defaults, with an empty input path: other commands build their
    /// arguments as `Args { input, out, force: true, ..Args::default() }` (a command that
    /// analyses its own run owns that folder and replaces an earlier analysis).
    fn default() -> Self {
        Self {
            input: PathBuf::new(),
            out: None,
            force: false,
            cell: 1e-3,
            threshold: None,
            min_width: None,
            dt: analysis::lammps::DEFAULT_DT,
            period: None,
            tracer: 0,
            tail: 0.1,
            periodic_y: false,
            plateau_before: None,
            plateau_after: None,
            mobility_min: analysis::classify::ClassifyParams::default().mobility_min,
            contrast_min: analysis::classify::ClassifyParams::default().contrast_min,
            persistence_periods: analysis::classify::ClassifyParams::default().persistence_periods,
        }
    }
}

fn window(s: &Option<String>, name: &str) -> Result<Option<(f64, f64)>, CliError> {
    let Some(s) = s else { return Ok(None) };
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--{name}: expected FROM,TO in seconds, got `{s}`"))?;
    match v[..] {
        [a, b] if a <= b => Ok(Some((a, b))),
        _ => Err(format!("--{name}: expected FROM,TO with FROM <= TO, got `{s}`").into()),
    }
}

impl Args {
    /// The library options these arguments select.
    pub fn options(&self) -> Result<Options, CliError> {
        let mut o = Options {
            cell: self.cell,
            threshold: self.threshold,
            min_width: self.min_width,
            period: self.period,
            periodic_y: self.periodic_y,
            tracer: self.tracer,
            tail_fraction: self.tail,
            plateau_before: window(&self.plateau_before, "plateau-before")?,
            plateau_after: window(&self.plateau_after, "plateau-after")?,
            ..Options::default()
        };
        // Written so that NaN fails each test.
        for (option, x) in [("--mobility-min", self.mobility_min), ("--contrast-min", self.contrast_min)] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("{option} must be a number >= 0, got {x}").into());
            }
        }
        o.classify.mobility_min = self.mobility_min;
        o.classify.contrast_min = self.contrast_min;
        if !(self.persistence_periods.is_finite() && self.persistence_periods > 0.0) {
            return Err(format!("--persistence-periods must be a positive number, got {}", self.persistence_periods).into());
        }
        o.classify.persistence_periods = self.persistence_periods;
        Ok(o)
    }
}

pub fn run(args: Args) -> Result<String, CliError> {
    let mut opts = args.options()?;
    let run = load(&args.input, args.dt)?;
    for w in &run.warnings {
        eprintln!("warning: {w}");
    }
    // The drive period: given, else the run's own metadata, never the snapshot spacing when
    // the metadata is there (a cut-off file has too few frames to infer it).
    let period_source = if args.period.is_some() {
        "--period"
    } else if let Some(p) = run.period {
        opts.period = Some(p);
        "run metadata (config.json: 1 / scene.drive.frequency)"
    } else {
        "median snapshot spacing"
    };
    let report = analyze(&run.header, &run.frames, &opts).map_err(|e| format!("{}: {e}", run.file.display()))?;
    let out = args.out.clone().unwrap_or_else(|| {
        if args.input.is_dir() {
            args.input.join("analysis")
        } else if run.kind == analysis::input::InputKind::LammpsDump {
            let mut name = run.file.file_name().unwrap_or_default().to_os_string();
            name.push(".analysis");
            run.file.with_file_name(name)
        } else {
            run.file.parent().unwrap_or(std::path::Path::new(".")).join("analysis")
        }
    });
    // The analysis must not write over the run it reads (its config.json and summary.json
    // carry the run's period and outcome).
    let same = |a: &std::path::Path, b: &std::path::Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y);
    let run_dir = if args.input.is_dir() {
        args.input.clone()
    } else {
        run.file.parent().unwrap_or(std::path::Path::new(".")).to_path_buf()
    };
    if same(&out, &run_dir) {
        return Err(format!(
            "--out {} is the run directory itself: the analysis would replace the run's config.json and summary.json; choose another --out (default: {}/analysis)",
            out.display(),
            run_dir.display()
        )
        .into());
    }
    crate::output::claim(&out, args.force)?;
    let mut dir = RunDir::create(&out, &args)?;
    write_tables(&mut dir, &report, &run)?;
    draw(&mut dir, &report)?;
    let mut summary = serde_json::to_value(report.summary())?;
    if let serde_json::Value::Object(m) = &mut summary {
        m.insert("input".into(), run.file.display().to_string().into());
        m.insert("input_kind".into(), serde_json::to_value(run.kind)?);
        m.insert("period_source".into(), period_source.into());
        if let Some(cols) = &run.velocity_columns {
            m.insert("velocity_columns".into(), serde_json::to_value(cols)?);
        }
        let mut warnings = run.warnings.clone();
        if let Err(e) = report.phase() {
            eprintln!("warning: {e}");
            warnings.push(e.to_string());
        }
        if event_driven(&run.file) {
            // A vertical box seen from the side: grains stack in z, so the "area fraction"
            // counts columns of grains and the tray's stripe classes mean nothing here.
            let note = "an event-driven run of a vertical box: its frames are the (x, z) plane, so the area fraction is grains per column (not a packing) and the tray's phases do not apply; phase left unclassified. The density map, structure factor and bands still describe the horizontal profile over time";
            eprintln!("warning: {note}");
            warnings.push(note.into());
            m.insert("phase".into(), "unclassified".into());
            m.insert("phase_note".into(), note.into());
        }
        m.insert("warnings".into(), serde_json::to_value(warnings)?);
    }
    dir.finish(summary)
}

fn write_tables(dir: &mut RunDir, r: &Report, run: &analysis::input::Run) -> Result<(), CliError> {
    let mut names = vec!["t".to_string()];
    names.extend((0..r.cells).map(|c| format!("x{:.6}", (c as f64 + 0.5) * r.cell)));
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let rows: Vec<Vec<f64>> = r
        .times
        .iter()
        .zip(&r.density_map)
        .map(|(t, phi)| std::iter::once(*t).chain(phi.iter().copied()).collect())
        .collect();
    dir.csv("density_map.csv", &names, &rows)?;
    let rows: Vec<Vec<f64>> = r
        .coarsening
        .iter()
        .zip(&r.contrast_series)
        .map(|(c, k)| vec![c.time, c.count as f64, c.mean_width, c.mean_mass, c.mass_fraction, *k])
        .collect();
    dir.csv(
        "coarsening.csv",
        &["t", "count", "mean_width", "mean_mass", "mass_fraction", "contrast"],
        &rows,
    )?;
    let rows: Vec<Vec<f64>> = r
        .times
        .iter()
        .zip(&r.stripes)
        .flat_map(|(t, s)| s.iter().map(move |s| vec![*t, s.start, s.center, s.width, s.mass]))
        .collect();
    dir.csv("stripes.csv", &["t", "start", "center", "width", "mass"], &rows)?;
    // Structure: the S(k) peak and the fraction in bands per frame, the late S(k), the late
    // band widths and gaps.
    let nan = f64::NAN;
    let rows: Vec<Vec<f64>> = r
        .structure
        .iter()
        .map(|p| {
            let (k, spacing, height, width) = p.peak.map_or((nan, nan, nan, nan), |q| (q.k, q.spacing, q.height, q.width));
            vec![p.time, k, spacing, height, width, p.in_band_fraction]
        })
        .collect();
    dir.csv(
        "structure.csv",
        &[
            "t",
            "peak_k_per_m",
            "spacing_m",
            "peak_height",
            "peak_fwhm_per_m",
            "in_band_fraction",
        ],
        &rows,
    )?;
    let rows: Vec<Vec<f64>> = r.late.s.iter().map(|&(k, s)| vec![k, 2.0 * std::f64::consts::PI / k, s]).collect();
    dir.csv("structure_factor_late.csv", &["k_per_m", "wavelength_m", "S"], &rows)?;
    let n = r.late.band_widths.len().max(r.late_gaps.len());
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|j| {
            vec![
                r.late.band_widths.get(j).copied().unwrap_or(nan),
                r.late_gaps.get(j).copied().unwrap_or(nan),
            ]
        })
        .collect();
    dir.csv("bands_late.csv", &["band_width_m", "gap_m"], &rows)?;
    let sk = LinePlot::new("Structure factor of the late frames", "wavelength 2 pi / k (m)", "S(k)")
        .series(
            "S(k)",
            r.late.s.iter().map(|&(k, s)| (2.0 * std::f64::consts::PI / k, s)).collect(),
            Mark::LinePoints,
        )
        .series(
            "independent grains",
            r.late.s.iter().map(|&(k, _)| (2.0 * std::f64::consts::PI / k, 1.0)).collect(),
            Mark::Dashed,
        )
        .log_x()
        .legend(analysis::plot::LegendCorner::UpperLeft)
        .include_y(0.0)
        .include_y(1.25 * r.late.s.iter().map(|p| p.1).fold(1.0, f64::max));
    dir.plot("structure_factor", &sk)?;
    let rows: Vec<Vec<f64>> = r.msd.iter().map(|p| vec![p.time, p.d]).collect();
    dir.csv("msd.csv", &["t", "D"], &rows)?;
    let rows: Vec<Vec<f64>> = r
        .autocorrelation
        .iter()
        .map(|a| vec![a.lag as f64, a.lag_s, a.raw, a.normalised])
        .collect();
    dir.csv("autocorrelation.csv", &["lag", "lag_s", "C_raw", "C_normalised"], &rows)?;
    let rows: Vec<Vec<f64>> = r
        .tracer
        .points
        .iter()
        .map(|p| vec![p.time, p.x, p.y, p.z, p.x_unwrapped, p.vx])
        .collect();
    dir.csv("tracer.csv", &["t", "x", "y", "z", "x_unwrapped", "vx"], &rows)?;
    let d = &r.radii;
    let rows: Vec<Vec<f64>> = (0..d.whole.len())
        .map(|k| vec![d.edges[k], d.edges[k + 1], d.whole[k], d.stripes[k]])
        .collect();
    dir.csv("radii.csv", &["r_from", "r_to", "pdf_whole", "pdf_stripes"], &rows)?;
    // The exact binning-free count density (Appendix A) of the last frame.
    let last = run.frames.last().expect("analyze refuses empty runs");
    let x: Vec<f64> = last.pos.iter().map(|p| p[0]).collect();
    let p = CountProfile::new(&x, &run.header.radii, run.header.length);
    let rows: Vec<Vec<f64>> = (0..p.breaks.len())
        .map(|k| vec![p.breaks[k], p.breaks.get(k + 1).copied().unwrap_or(p.length), p.values[k] as f64])
        .collect();
    dir.csv("count_density_final.csv", &["x_from", "x_to", "grains"], &rows)
}

fn draw(dir: &mut RunDir, r: &Report) -> Result<(), CliError> {
    let t0 = r.times[0];
    let t1 = r.times.last().copied().unwrap_or(t0).max(t0 + 1e-9);
    let heat = Heatmap {
        title: "Projected area fraction phi(x, t)".into(),
        x_label: "x (m)".into(),
        y_label: "t (s)".into(),
        x_range: (0.0, r.length),
        y_range: (t0, t1),
        values: r.density_map.clone(),
        colorbar_label: "area fraction".into(),
        scale: None,
        cell_names: None,
    };
    let files = heat
        .save(&dir.path.join("density_map"))
        .map_err(|e| format!("cannot draw density_map: {e}"))?;
    dir.note_files(files);

    let mut count = LinePlot::new("Stripes over time", "t (s)", "stripe count").integer_y().series(
        "stripes",
        r.coarsening.iter().map(|c| (c.time, c.count as f64)).collect(),
        Mark::Line,
    );
    if let Some(on) = r.onset {
        let max = r.coarsening.iter().map(|c| c.count).max().unwrap_or(0) as f64;
        count = count.series(&format!("onset {on:.3} s"), vec![(on, 0.0), (on, max.max(1.0))], Mark::Dashed);
    }
    dir.plot("stripe_count", &count)?;

    let mut msd = LinePlot::new("Mean square displacement per period (eq 3.30)", "t (s)", "D (m^2)").series(
        "D",
        r.msd.iter().map(|p| (p.time, p.d)).collect(),
        Mark::Line,
    );
    // A log axis only when D spans more than a decade and a half (with less, plotters
    // draws no tick labels on it).
    let positive = r.msd.iter().map(|p| p.d).filter(|d| *d > 0.0);
    let (lo, hi) = positive.fold((f64::INFINITY, 0.0f64), |(a, b), d| (a.min(d), b.max(d)));
    if hi > 30.0 * lo {
        msd = msd.log_y();
    }
    for (name, p) in [("a1", r.plateau_before), ("a2", r.plateau_after)] {
        if let Some(p) = p {
            let label = format!("{name} = {:.3e} m^2 on [{:.2}, {:.2}] s", p.value, p.from, p.to);
            msd = msd.series(&label, vec![(p.from, p.value), (p.to, p.value)], Mark::Dashed);
        }
    }
    dir.plot("msd", &msd)?;

    let tr = &r.tracer;
    let path: Vec<(f64, f64)> = tr.points.iter().map(|p| (p.x_unwrapped, p.y)).collect();
    let mut traj = LinePlot::new(
        &format!("Tracer {} (R = {:.3} mm): trajectory", tr.index, tr.radius * 1e3),
        "x, followed across the periodic seam (m)",
        "y (m)",
    )
    .series("path", path.clone(), Mark::Line);
    if let (Some(a), Some(b)) = (path.first(), path.last()) {
        traj = traj.series("start", vec![*a], Mark::Points).series("end", vec![*b], Mark::Points);
    }
    dir.plot("tracer_trajectory", &traj)?;
    // Without velocities (an automaton run, a dump without `vx`) the phase space would be a
    // line at v_x = 0: not drawn.
    if tr.points.iter().any(|p| p.vx != 0.0) {
        let phase = LinePlot::new(
            &format!("Tracer {}: phase space", tr.index),
            "x, followed across the periodic seam (m)",
            "v_x (m/s)",
        )
        .series("snapshots", tr.points.iter().map(|p| (p.x_unwrapped, p.vx)).collect(), Mark::Points);
        dir.plot("tracer_phase_space", &phase)?;
    }

    let d = &r.radii;
    let steps = |v: &[f64]| -> Vec<(f64, f64)> {
        (0..v.len())
            .flat_map(|k| [(d.edges[k] * 1e3, v[k] * 1e-3), (d.edges[k + 1] * 1e3, v[k] * 1e-3)])
            .collect()
    };
    let mut radii = LinePlot::new("Radii: stripes against the whole layer", "R (mm)", "probability density (1/mm)").series(
        &format!("whole layer, mean {:.4} mm", d.mean_whole * 1e3),
        steps(&d.whole),
        Mark::Line,
    );
    if d.in_stripes > 0 {
        radii = radii.series(
            &format!(
                "in stripes ({} over the last {} frames), mean {:.4} mm",
                d.in_stripes,
                d.frames,
                d.mean_stripes * 1e3
            ),
            steps(&d.stripes),
            Mark::Dashed,
        );
    } else {
        // An empty series: the legend says why there is no second curve.
        radii = radii.series(
            &format!("in stripes: no grain in a stripe over the last {} frames", d.frames),
            Vec::new(),
            Mark::Dashed,
        );
    }
    dir.plot("radii", &radii)?;

    let ac = LinePlot::new("Autocorrelation of D (eq 3.32)", "lag (s)", "normalised C").series(
        "C",
        r.autocorrelation.iter().map(|a| (a.lag_s, a.normalised)).collect(),
        Mark::Line,
    );
    dir.plot("autocorrelation", &ac)
}

/// Whether the run beside `file` is an event-driven one (`config.json`'s `scene.model`).
fn event_driven(file: &std::path::Path) -> bool {
    let config = file.parent().map(|d| d.join("config.json"));
    let text = config.and_then(|c| std::fs::read_to_string(c).ok());
    let value: Option<serde_json::Value> = text.and_then(|t| serde_json::from_str(&t).ok());
    value.is_some_and(|v| v["scene"]["model"] == "events")
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: Args,
    }

    #[test]
    fn default_matches_the_command_line_defaults() {
        let parsed = Cli::parse_from(["analyze", "run"]).args;
        let default = Args {
            input: "run".into(),
            ..Args::default()
        };
        assert_eq!(serde_json::to_value(&parsed).unwrap(), serde_json::to_value(&default).unwrap());
        assert_eq!(parsed.options().unwrap(), Options::default());
    }
}
