//! `stripes single`: one sphere on the shaken plate (thesis 3.3) and the rolling-friction
//! stopping test (thesis 3.5.2, Fig 3.19).

use std::path::PathBuf;

use analysis::plot::{LinePlot, Mark};
use particles::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::experiment::single::{Sample, SphereOnFloor};
use serde::Serialize;
use serde_json::json;

use crate::output::{CliError, RunDir};

/// Options of `stripes single`. Material and contact law are Table 3.1's: rho = 2500 kg/m^3,
/// Y = 1e6 Pa, nu = 0.3, A = 8.5e-6 s, mu = 0.7, gamma_t = 0.007 N s/m, dt = 8e-6 s.
#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Shaking frequency (Hz).
    #[arg(long, default_value_t = 20.0)]
    pub frequency: f64,
    /// Shaking amplitude (m).
    #[arg(long, default_value_t = 0.025)]
    pub amplitude: f64,
    /// Sphere radius (m).
    #[arg(long, default_value_t = 5e-4)]
    pub radius: f64,
    /// Duration of the shaking runs (s).
    #[arg(long, default_value_t = 5.0)]
    pub duration: f64,
    /// Rolling friction mu_r of the run "with rolling friction" (s).
    #[arg(long, default_value_t = 8.5e-6)]
    pub mu_r: f64,
    /// Rolling friction coefficients of the stopping test (s), comma separated.
    #[arg(long, value_delimiter = ',', default_value = "0,2e-6,8.5e-6,2e-5,5e-5")]
    pub stop_mu_r: Vec<f64>,
    /// Launch speed of the stopping test (m/s).
    #[arg(long, default_value_t = 0.05)]
    pub stop_speed: f64,
    /// Duration of the stopping test (s).
    #[arg(long, default_value_t = 10.0)]
    pub stop_duration: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 8e-6)]
    pub dt: f64,
    #[arg(long, default_value = "out/single")]
    pub out: PathBuf,
}

fn law(mu_r: f64) -> ContactLaw {
    ContactLaw {
        normal: NormalLaw::hertz(1e6 / (1.0 - 0.09), 8.5e-6),
        tangential: TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 },
        rolling: if mu_r > 0.0 {
            RollingLaw::BrilliantovPoschel { mu_r }
        } else {
            RollingLaw::None
        },
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

pub fn run(args: Args) -> Result<String, CliError> {
    if !(args.frequency > 0.0 && args.amplitude >= 0.0 && args.radius > 0.0 && args.duration > 0.0 && args.dt > 0.0) {
        return Err("--frequency, --radius, --duration and --dt must be positive, --amplitude >= 0".into());
    }
    let period = 1.0 / args.frequency;
    if args.duration < 2.0 * period {
        return Err(format!("--duration must cover at least two periods ({} s)", 2.0 * period).into());
    }
    let mut dir = RunDir::create(&args.out, &args)?;
    let header = ["t", "x", "z", "vx", "vz", "omega_y", "floor_x", "floor_vx"];
    let every = ((period / args.dt) / 200.0).max(1.0) as u64; // about 200 samples per period

    let mut phase = LinePlot::new(
        &format!("Phase space of one sphere at {} Hz, {} m", args.frequency, args.amplitude),
        "x (m)",
        "v_x (m/s)",
    );
    let mut position = LinePlot::new("Position of one sphere on the shaken plate", "t (s)", "x (m)");
    let mut drifts = serde_json::Map::new();
    let mut runs = Vec::new();
    for (name, mu_r) in [("without_rolling_friction", 0.0), ("with_rolling_friction", args.mu_r)] {
        let sphere = SphereOnFloor {
            radius: args.radius,
            dt: args.dt,
            ..SphereOnFloor::thesis(law(mu_r))
        };
        let samples = sphere.shake(args.amplitude, args.frequency, args.duration, every)?;
        dir.csv(&format!("trajectory_{name}.csv"), &header, &table(&samples))?;
        let label = name.replace('_', " ");
        phase = phase.series(&label, samples.iter().map(|s| (s.x, s.vx)).collect(), Mark::Line);
        position = position.series(&label, samples.iter().map(|s| (s.t, s.x)).collect(), Mark::Line);
        let end = (args.duration / period).floor() * period;
        drifts.insert(
            format!("drift_{name}_m"),
            json!(mean_x(&samples, end - period, end) - mean_x(&samples, 0.0, period)),
        );
        runs.push((label, samples));
    }
    dir.plot("phase_space", &phase)?;
    dir.plot("position", &position)?;
    // Velocity against the floor's over the first three periods (Fig 3.7b, 3.10b).
    let window = 3.0 * period;
    let mut velocity = LinePlot::new("Sphere velocity and floor velocity", "t (s)", "v_x (m/s)");
    for (label, samples) in &runs {
        velocity = velocity.series(
            label,
            samples.iter().filter(|s| s.t <= window).map(|s| (s.t, s.vx)).collect(),
            Mark::Line,
        );
    }
    velocity = velocity.series(
        "floor",
        runs[0].1.iter().filter(|s| s.t <= window).map(|s| (s.t, s.floor_vx)).collect(),
        Mark::Dashed,
    );
    dir.plot("velocity_vs_floor", &velocity)?;

    // Rolling-friction stopping test.
    let mut stop_plot = LinePlot::new(
        &format!("Distance of a {} m sphere launched at {} m/s", args.radius, args.stop_speed),
        "t (s)",
        "distance (m)",
    );
    let mut stops = Vec::new();
    let mut stop_rows: Vec<Vec<f64>> = Vec::new();
    let stop_every = (0.01 / args.dt).max(1.0) as u64;
    for &mu_r in &args.stop_mu_r {
        let sphere = SphereOnFloor {
            radius: args.radius,
            dt: args.dt,
            ..SphereOnFloor::thesis(law(mu_r))
        };
        let samples = sphere.launch(args.stop_speed, args.stop_duration, stop_every)?;
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
        stops.push(json!({ "mu_r": mu_r, "distance_m": last.x - samples[0].x, "final_speed": last.vx }));
    }
    let mut stop_header = vec!["t".to_string()];
    stop_header.extend(args.stop_mu_r.iter().map(|m| format!("distance_mu_r_{m:e}")));
    let stop_header: Vec<&str> = stop_header.iter().map(String::as_str).collect();
    dir.csv("rolling_stop.csv", &stop_header, &stop_rows)?;
    dir.plot("rolling_stop", &stop_plot)?;

    let mut summary = serde_json::Map::new();
    summary.insert("drift".into(), drifts.into());
    summary.insert("rolling_stop".into(), stops.into());
    dir.finish(summary.into())
}
