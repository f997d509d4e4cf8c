//! `stripes single`: one sphere on the shaken plate (thesis 3.3) with the tray's own laws,
//! its amplitudes against frequency next to the closed forms of rolling and sliding, and the
//! rolling-friction stopping test (thesis 3.5.2, Fig 3.19).
//!
//! Writes `amplitudes.csv` (`frequency,rolling_friction,x_peak_to_peak,vx_amplitude`, one
//! row per frequency and rolling friction, `rolling_friction` = mu_r in s, 0 for none),
//! `x_peak_to_peak.png`/`.svg` and `vx_amplitude.png`/`.svg` (both against nu, with the
//! predictions of [`particles::experiment::single::Amplitudes`]), `scene.toml` (the
//! resolved scene), the stopping test (`rolling_stop.csv`, `rolling_stop.png`) and, for a
//! single frequency, the trajectories and their phase-space, position and velocity plots.

use std::path::PathBuf;

use analysis::plot::{LegendCorner, LinePlot, Mark};
use particles::constants::GRAVITY;
use particles::contact::RollingLaw;
use particles::experiment::single::{self as sphere, Amplitudes, Sample, SphereOnFloor};
use particles::scene::{Scene, TimeStep};
use particles::time_step;
use serde::Serialize;
use serde_json::json;

use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Summary};

/// The thesis' reference scene, the default of `--scene`.
const THESIS_REFERENCE: &str = include_str!("../../scenes/thesis-reference.toml");

/// What the study is given (the command's arguments, without the command line); serialised
/// as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// Scene whose particle-wall law (after its toggles), grain density, drive, time step and
    /// integrator the sphere uses.
    /// (default: the thesis' reference scene, `scenes/thesis-reference.toml`, built into the
    /// program so that `stripes single` works from any directory).
    pub scene: Option<PathBuf>,
    pub overrides: Vec<String>,
    /// Shaking frequency (Hz), or a sweep `LO:HI:N` (N frequencies evenly spaced from LO to
    /// HI). Default: the scene's drive.frequency.
    pub frequency: Option<String>,
    /// Shaking amplitude (m). Default: the scene's drive.amplitude.
    pub amplitude: Option<f64>,
    /// Sphere radius (m). Default: the scene's particles.radius_max (thesis 3.3: 0.5 mm).
    pub radius: Option<f64>,
    /// Duration of each shaking run (s); the amplitudes are measured over its last half.
    pub duration: f64,
    /// Rolling friction mu_r of the runs "with rolling friction" (s). Default: the scene's
    /// contact.rolling_friction; with 0 only the runs without rolling friction are made.
    pub mu_r: Option<f64>,
    /// Rolling friction coefficients of the stopping test (s), comma separated.
    pub stop_mu_r: Vec<f64>,
    /// Launch speed of the stopping test (m/s).
    pub stop_speed: f64,
    /// Duration of the stopping test (s); 0 skips it.
    pub stop_duration: f64,
    /// Time step (s). Default: the scene's run.dt (for "auto", the step the scene's tray
    /// would take at each frequency).
    pub dt: Option<f64>,
    /// Output directory.
    pub out: PathBuf,
    pub force: bool,
    pub quiet: bool,
}

/// The frequencies of `--frequency`: one value, or `LO:HI:N`.
pub fn parse_frequencies(text: &str) -> Result<Vec<f64>, String> {
    let bad = || format!("--frequency takes a frequency (Hz) or a sweep LO:HI:N, got `{text}`");
    let parts: Vec<&str> = text.split(':').collect();
    let number = |s: &str| s.trim().parse::<f64>().map_err(|_| bad());
    let out = match parts.as_slice() {
        [f] => vec![number(f)?],
        [lo, hi, n] => {
            let (lo, hi) = (number(lo)?, number(hi)?);
            let n: usize = n.trim().parse().map_err(|_| bad())?;
            match n {
                0 => return Err(bad()),
                1 => vec![lo],
                _ => (0..n).map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64).collect(),
            }
        }
        _ => return Err(bad()),
    };
    if out.iter().all(|f| f.is_finite() && *f > 0.0) {
        Ok(out)
    } else {
        Err(format!("--frequency must be positive, got `{text}`"))
    }
}

fn table(samples: &[Sample]) -> Vec<Vec<f64>> {
    samples
        .iter()
        .map(|s| vec![s.t, s.x, s.z, s.vx, s.vz, s.omega_y, s.floor_x, s.floor_vx])
        .collect()
}

/// Mean of x over the samples in [t0, t1).
fn mean_x(samples: &[Sample], t0: f64, t1: f64) -> f64 {
    let sel: Vec<f64> = samples.iter().filter(|s| s.t >= t0 && s.t < t1).map(|s| s.x).collect();
    sel.iter().sum::<f64>() / sel.len().max(1) as f64
}

/// Regime of a Coulomb floor at `Gamma` (thesis floor law with coefficient `mu`).
fn regime(gamma: f64, mu: f64) -> &'static str {
    if mu.is_infinite() {
        "uncapped (rolls)"
    } else if gamma <= sphere::rolling_gamma(mu) {
        "rolling"
    } else if gamma < sphere::continuous_sliding_gamma(mu) {
        "stick-slip"
    } else {
        "sliding"
    }
}

/// One shaking run: a frequency, a rolling friction, and what came out.
struct Shaken {
    frequency: f64,
    mu_r: f64,
    dt: f64,
    samples: Vec<Sample>,
    amplitudes: Amplitudes,
}

/// What `stripes single` found: `summary.json`, field for field.
#[derive(Debug, Serialize)]
pub struct SingleSummary {
    pub amplitude: f64,
    pub radius: f64,
    /// The wall's Coulomb coefficient, `"inf"` when uncapped.
    #[serde(serialize_with = "finite_or_inf")]
    pub wall_friction: f64,
    pub amplitudes: Vec<AmplitudeRow>,
    /// With one frequency: each run's drift over the run, `drift_<run>_m`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drift: Option<std::collections::BTreeMap<String, f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rolling_stop: Option<Vec<Stop>>,
    #[serde(flatten)]
    pub written: Written,
}

/// One shaking run's amplitudes beside the rolling and sliding predictions.
#[derive(Debug, Serialize)]
pub struct AmplitudeRow {
    pub frequency: f64,
    pub gamma: f64,
    pub rolling_friction: f64,
    pub dt: f64,
    pub x_peak_to_peak: f64,
    pub vx_amplitude: f64,
    pub rolling_prediction: Amplitudes,
    pub sliding_prediction: Option<Amplitudes>,
    pub coulomb_regime: &'static str,
}

/// Where a launched sphere stopped, for one rolling friction.
#[derive(Debug, Serialize)]
pub struct Stop {
    pub mu_r: f64,
    pub distance_m: f64,
    pub final_speed: f64,
}

fn finite_or_inf<S: serde::Serializer>(mu: &f64, s: S) -> Result<S::Ok, S::Error> {
    if mu.is_finite() {
        s.serialize_f64(*mu)
    } else {
        s.serialize_str("inf")
    }
}

impl Summary for SingleSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

pub fn single_sphere(args: &Options) -> Result<SingleSummary, CliError> {
    let mut scene = match &args.scene {
        Some(path) => crate::scene::file::load(path, &args.overrides)?,
        None => crate::scene::file::parse(THESIS_REFERENCE, &args.overrides, "scenes/thesis-reference.toml (built in)")?,
    }
    .dem;
    if let Some(a) = args.amplitude {
        scene.drive.amplitude = a;
    }
    let frequencies = match &args.frequency {
        Some(text) => parse_frequencies(text)?,
        None => vec![scene.drive.frequency],
    };
    scene.drive.frequency = frequencies[0];
    scene.validate()?;
    let amplitude = scene.drive.amplitude;
    let radius = args.radius.unwrap_or(scene.particles.radius_max);
    let mu_r = args.mu_r.unwrap_or(scene.contact.rolling_friction);
    let longest = 1.0 / frequencies.iter().cloned().fold(f64::INFINITY, f64::min);
    if !(amplitude >= 0.0 && radius > 0.0 && mu_r >= 0.0 && args.duration.is_finite()) {
        return Err("--amplitude must be >= 0, --radius positive, --mu-r >= 0".into());
    }
    if args.duration < 4.0 * longest {
        return Err(format!(
            "--duration must cover at least four periods of the lowest frequency ({} s)",
            4.0 * longest
        )
        .into());
    }
    if args.dt.is_some_and(|dt| !(dt.is_finite() && dt > 0.0)) {
        return Err("--dt must be positive".into());
    }
    crate::rundir::output::claim(&args.out, args.force)?;
    let mut dir = RunDir::create(&args.out, &json!({ "args": &args, "scene": &scene }))?;
    analysis::io::write_atomic(&args.out.join("scene.toml"), toml::to_string(&scene)?.as_bytes())?;
    dir.note_files([args.out.join("scene.toml")]);
    let mu = scene.contact.wall_friction;
    let rolling_frictions: Vec<f64> = if mu_r > 0.0 { vec![0.0, mu_r] } else { vec![0.0] };

    // The shaking runs.
    let mut runs = Vec::new();
    for &f in &frequencies {
        let mut at = scene.clone();
        at.drive.frequency = f;
        let dt = match (args.dt, at.run.dt) {
            (Some(dt), _) => dt,
            (None, TimeStep::Seconds(dt)) => dt,
            (None, TimeStep::Auto(_)) => time_step::for_scene(&at)?,
        };
        let every = ((1.0 / f) / dt / 200.0).max(1.0) as u64; // about 200 samples per period
        for &m in &rolling_frictions {
            let mut grain = SphereOnFloor::on_scene(&at, radius, dt)?;
            grain.law.rolling = if m > 0.0 {
                RollingLaw::BrilliantovPoschel { mu_r: m }
            } else {
                RollingLaw::None
            };
            let samples = grain.shake(amplitude, f, args.duration, every)?;
            let amplitudes = sphere::amplitudes(&samples, f).ok_or("the run is too short to measure amplitudes")?;
            eprintln!(
                "{f:.3} Hz, mu_r {m:e} s: x peak-to-peak {:.4e} m, vx amplitude {:.4e} m/s",
                amplitudes.x_peak_to_peak, amplitudes.vx_amplitude
            );
            runs.push(Shaken {
                frequency: f,
                mu_r: m,
                dt,
                samples,
                amplitudes,
            });
        }
    }
    let rows: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| vec![r.frequency, r.mu_r, r.amplitudes.x_peak_to_peak, r.amplitudes.vx_amplitude])
        .collect();
    dir.csv(
        "amplitudes.csv",
        &["frequency", "rolling_friction", "x_peak_to_peak", "vx_amplitude"],
        &rows,
    )?;
    amplitude_plots(&mut dir, &runs, amplitude, mu, radius)?;
    let amplitudes = runs
        .iter()
        .map(|r| {
            let g = sphere::gamma(amplitude, r.frequency, GRAVITY);
            AmplitudeRow {
                frequency: r.frequency,
                gamma: g,
                rolling_friction: r.mu_r,
                dt: r.dt,
                x_peak_to_peak: r.amplitudes.x_peak_to_peak,
                vx_amplitude: r.amplitudes.vx_amplitude,
                rolling_prediction: Amplitudes::rolling(amplitude, r.frequency),
                sliding_prediction: mu.is_finite().then(|| Amplitudes::sliding(mu, GRAVITY, r.frequency)),
                coulomb_regime: regime(g, mu),
            }
        })
        .collect();
    let drift = if frequencies.len() == 1 {
        Some(trajectories(&mut dir, &runs, amplitude)?)
    } else {
        None
    };
    let rolling_stop = if args.stop_duration > 0.0 {
        Some(stopping_test(&mut dir, args, &scene, radius)?)
    } else {
        None
    };
    let summary = SingleSummary {
        amplitude,
        radius,
        wall_friction: mu,
        amplitudes,
        drift,
        rolling_stop,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// `x_peak_to_peak` and `vx_amplitude` against nu, each next to the rolling and (for a
/// finite `mu`) sliding predictions.
fn amplitude_plots(dir: &mut RunDir, runs: &[Shaken], amplitude: f64, mu: f64, radius: f64) -> Result<(), CliError> {
    let (lo, hi) = runs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
        (l.min(r.frequency), h.max(r.frequency))
    });
    let grid: Vec<f64> = (0..=200).map(|k| lo + (hi - lo) * k as f64 / 200.0).collect();
    let floor = if mu.is_finite() {
        format!("wall friction {mu}")
    } else {
        "wall friction inf".to_string()
    };
    for (stem, label, pick) in [
        (
            "x_peak_to_peak",
            "x peak-to-peak (m)",
            (|a: &Amplitudes| a.x_peak_to_peak) as fn(&Amplitudes) -> f64,
        ),
        ("vx_amplitude", "v_x amplitude (m/s)", |a: &Amplitudes| a.vx_amplitude),
    ] {
        let mut plot = LinePlot::new(
            &format!("One sphere (R = {radius} m) on the shaken floor, A = {amplitude} m, {floor}"),
            "frequency nu (Hz)",
            label,
        );
        let mut mus: Vec<f64> = runs.iter().map(|r| r.mu_r).collect();
        mus.sort_by(f64::total_cmp);
        mus.dedup();
        for m in mus {
            let name = if m > 0.0 {
                format!("DEM, rolling friction {m:e} s")
            } else {
                "DEM, no rolling friction".to_string()
            };
            let points = runs
                .iter()
                .filter(|r| r.mu_r == m)
                .map(|r| (r.frequency, pick(&r.amplitudes)))
                .collect();
            plot = plot.series(&name, points, Mark::Points);
        }
        plot = plot.series(
            "rolling without slip",
            grid.iter().map(|&f| (f, pick(&Amplitudes::rolling(amplitude, f)))).collect(),
            Mark::Dashed,
        );
        // Sliding only where a Coulomb floor cannot hold rolling (Gamma > 7 mu / 2).
        let sliding: Vec<(f64, f64)> = grid
            .iter()
            .filter(|&&f| sphere::gamma(amplitude, f, GRAVITY) > sphere::rolling_gamma(mu))
            .map(|&f| (f, pick(&Amplitudes::sliding(mu, GRAVITY, f))))
            .collect();
        if mu.is_finite() && !sliding.is_empty() {
            plot = plot.series(&format!("Coulomb sliding, mu = {mu} (Gamma > 7 mu / 2)"), sliding, Mark::Dashed);
        }
        // The legend where the points are not: sliding amplitudes fall with nu, rolling
        // velocities rise.
        let corner = match (mu.is_finite(), stem) {
            (true, "x_peak_to_peak") => LegendCorner::UpperRight,
            (true, _) => LegendCorner::UpperLeft,
            (false, "x_peak_to_peak") => LegendCorner::LowerRight,
            (false, _) => LegendCorner::UpperLeft,
        };
        // A Coulomb floor spans decades (log axis); an uncapped one holds x at 2 (2/7) A,
        // drawn from 0 so that its small scatter does not look like a trend.
        let plot = plot.legend(corner);
        let plot = if mu.is_finite() {
            // Whole decades, so that the log axis has labelled ticks.
            let ys: Vec<f64> = plot
                .series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.1))
                .filter(|y| *y > 0.0)
                .collect();
            let (lo, hi) = ys.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &y| (l.min(y), h.max(y)));
            plot.log_y()
                .include_y(10f64.powf(lo.log10().floor()))
                .include_y(10f64.powf(hi.log10().ceil()))
        } else {
            plot.include_y(0.0)
        };
        dir.plot(stem, &plot)?;
    }
    Ok(())
}

/// Trajectories of a single-frequency run and their plots; returns the drifts.
fn trajectories(dir: &mut RunDir, runs: &[Shaken], amplitude: f64) -> Result<std::collections::BTreeMap<String, f64>, CliError> {
    let header = ["t", "x", "z", "vx", "vz", "omega_y", "floor_x", "floor_vx"];
    let f = runs[0].frequency;
    let period = 1.0 / f;
    let mut phase = LinePlot::new(&format!("Phase space of one sphere at {f} Hz, {amplitude} m"), "x (m)", "v_x (m/s)");
    let mut position = LinePlot::new("Position of one sphere on the shaken plate", "t (s)", "x (m)");
    let window = 3.0 * period;
    let mut velocity = LinePlot::new("Sphere velocity and floor velocity", "t (s)", "v_x (m/s)");
    let mut drifts = std::collections::BTreeMap::new();
    for r in runs {
        let name = if r.mu_r > 0.0 {
            "with_rolling_friction"
        } else {
            "without_rolling_friction"
        };
        let s = &r.samples;
        dir.csv(&format!("trajectory_{name}.csv"), &header, &table(s))?;
        let label = name.replace('_', " ");
        phase = phase.series(&label, s.iter().map(|s| (s.x, s.vx)).collect(), Mark::Line);
        position = position.series(&label, s.iter().map(|s| (s.t, s.x)).collect(), Mark::Line);
        // Velocity against the floor's over the first three periods (Fig 3.7b, 3.10b).
        velocity = velocity.series(
            &label,
            s.iter().filter(|s| s.t <= window).map(|s| (s.t, s.vx)).collect(),
            Mark::Line,
        );
        let end = (s.last().map_or(0.0, |l| l.t) / period).floor() * period;
        drifts.insert(format!("drift_{name}_m"), mean_x(s, end - period, end) - mean_x(s, 0.0, period));
    }
    velocity = velocity.series(
        "floor",
        runs[0]
            .samples
            .iter()
            .filter(|s| s.t <= window)
            .map(|s| (s.t, s.floor_vx))
            .collect(),
        Mark::Dashed,
    );
    dir.plot("phase_space", &phase)?;
    dir.plot("position", &position)?;
    dir.plot("velocity_vs_floor", &velocity)?;
    Ok(drifts)
}

/// The rolling-friction stopping test on a fixed floor with the scene's law (its rolling
/// friction replaced by each of `--stop-mu-r`).
fn stopping_test(dir: &mut RunDir, args: &Options, scene: &Scene, radius: f64) -> Result<Vec<Stop>, CliError> {
    let dt = match (args.dt, scene.run.dt) {
        (Some(dt), _) => dt,
        (None, TimeStep::Seconds(dt)) => dt,
        (None, TimeStep::Auto(_)) => time_step::for_scene(scene)?,
    };
    let mut stop_plot = LinePlot::new(
        &format!("Distance of a {radius} m sphere launched at {} m/s", args.stop_speed),
        "t (s)",
        "distance (m)",
    );
    let mut stops = Vec::new();
    let mut stop_rows: Vec<Vec<f64>> = Vec::new();
    let stop_every = (0.01 / dt).max(1.0) as u64;
    for &mu_r in &args.stop_mu_r {
        let mut grain = SphereOnFloor::on_scene(scene, radius, dt)?;
        grain.law.rolling = if mu_r > 0.0 {
            RollingLaw::BrilliantovPoschel { mu_r }
        } else {
            RollingLaw::None
        };
        let samples = grain.launch(args.stop_speed, args.stop_duration, stop_every)?;
        if stop_rows.is_empty() {
            stop_rows = samples.iter().map(|s| vec![s.t]).collect();
        }
        for (row, s) in stop_rows.iter_mut().zip(&samples) {
            row.push(s.x - samples[0].x);
        }
        stop_plot = stop_plot.series(
            &format!("mu_r = {mu_r:e} s"),
            samples.iter().map(|s| (s.t, s.x - samples[0].x)).collect(),
            Mark::Line,
        );
        let last = samples.last().expect("at least one sample");
        stops.push(Stop {
            mu_r,
            distance_m: last.x - samples[0].x,
            final_speed: last.vx,
        });
    }
    let mut stop_header = vec!["t".to_string()];
    stop_header.extend(args.stop_mu_r.iter().map(|m| format!("distance_mu_r_{m:e}")));
    let stop_header: Vec<&str> = stop_header.iter().map(String::as_str).collect();
    dir.csv("rolling_stop.csv", &stop_header, &stop_rows)?;
    dir.plot("rolling_stop", &stop_plot)?;
    Ok(stops)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 42: an uncapped wall friction is written as `"inf"` (JSON has no infinity), a
    /// finite one as its number, and the drift and the stopping test only where they ran.
    #[test]
    fn the_summary_writes_an_uncapped_friction_as_inf() {
        let summary = |mu: f64| SingleSummary {
            amplitude: 0.025,
            radius: 5e-4,
            wall_friction: mu,
            amplitudes: Vec::new(),
            drift: None,
            rolling_stop: None,
            written: Written::default(),
        };
        let inf = serde_json::to_value(summary(f64::INFINITY)).unwrap();
        assert_eq!(inf["wall_friction"], "inf");
        assert!(inf.get("drift").is_none() && inf.get("rolling_stop").is_none());
        assert_eq!(serde_json::to_value(summary(0.3)).unwrap()["wall_friction"], 0.3);
    }

    #[test]
    fn frequencies_are_one_value_or_a_sweep() {
        assert_eq!(parse_frequencies("20").unwrap(), vec![20.0]);
        assert_eq!(parse_frequencies("5:29:4").unwrap(), vec![5.0, 13.0, 21.0, 29.0]);
        assert_eq!(parse_frequencies("3:9:1").unwrap(), vec![3.0]);
        for bad in ["", "x", "5:29", "5:29:0", "5:29:x", "-1", "0:3:2", "1:2:3:4"] {
            assert!(parse_frequencies(bad).is_err(), "{bad}");
        }
    }
}
