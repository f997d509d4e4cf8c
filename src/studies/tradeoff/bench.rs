//! `stripes bench [--quick]`: speed against error of every accuracy-for-speed choice, on the
//! collision lab and on a small shaken tray (study in [`crate::studies::tradeoff`]).
//!
//! Also times each friction law (none, Haff-Werner, Haff-Werner with `friction = inf`,
//! Cundall-Strack) against Haff-Werner in the same run
//! ([`crate::studies::tradeoff::friction_laws`]): ratios, never absolute times.
//!
//! Writes `bench.md` (the Markdown tables), `bench.csv`, `friction_laws.csv`, `pareto.png` /
//! `pareto.svg` and `summary.json` (`rows`: `name`, `speed_ratio`, `error` and the other
//! columns; `friction_laws`: one entry per law).

use std::path::PathBuf;
use std::time::Instant;

use crate::studies::tradeoff::{self, Config, Row, Study};
use analysis::plot::{LegendCorner, LinePlot, Mark};
use serde::Serialize;
use serde_json::json;

use crate::rundir::output::Written;
use crate::rundir::output::{CliError, RunDir};
use crate::rundir::report::{Headline, Summary};
use crate::studies::tradeoff::friction::LawSpeed;

/// What the study is given (the command's arguments, without the command line); serialised
/// as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// Small and short: under a minute on a loaded two-core machine.
    pub quick: bool,
    /// Output directory.
    pub out: PathBuf,
    pub force: bool,
    pub quiet: bool,
    /// Grains in the tray study (default: 200 quick, 400 full); the tray is count/10000 m
    /// long and 2 cm wide (thesis packing 0.23).
    pub tray_count: Option<usize>,
    /// Simulated seconds of each tray run (default: 0.05 quick, 0.15 full).
    pub tray_duration: Option<f64>,
    /// Steps of the dense-packing hard case, 8000 grains (default: 600 quick, 3000 full; 0 skips it).
    pub dense_steps: Option<u64>,
    /// Worker threads (speed ratios are measured on this many; default 1, timed by the
    /// worker's on-CPU time, which is the wall time on an idle core; more: wall time).
    pub threads: usize,
}

/// Smallest error drawn on the log axis; rows with error exactly 0 (bit-identical results)
/// are drawn there.
const PLOT_FLOOR: f64 = 1e-9;

fn front_line(rows: &[&Row]) -> Vec<(f64, f64)> {
    let mut pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.on_front)
        .map(|r| (r.speed_ratio, r.error.max(PLOT_FLOOR)))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// What `stripes bench` measured: `summary.json`, field for field.
#[derive(Debug, Serialize)]
pub struct BenchSummary {
    pub quick: bool,
    pub threads: usize,
    pub wall_s: f64,
    /// The defaults (`dt = auto`) and whether each is on its study's Pareto front.
    pub defaults: Vec<OnFront>,
    pub rows: Vec<Row>,
    pub friction_laws: Vec<LawSpeed>,
    pub events: EventsSpeed,
    #[serde(flatten)]
    pub written: Written,
}

/// A default setting and whether it is on the Pareto front.
#[derive(Debug, Serialize)]
pub struct OnFront {
    pub name: String,
    pub study: Study,
    pub on_front: bool,
}

impl Summary for BenchSummary {
    fn headline(&self) -> Headline {
        Headline {
            wall_s: Some(self.wall_s),
            ..Headline::written(0, &self.written)
        }
    }
}

pub fn bench(args: &Options) -> Result<BenchSummary, CliError> {
    let mut config = if args.quick { Config::quick() } else { Config::full() };
    if let Some(n) = args.tray_count {
        config.tray_count = n;
    }
    if let Some(t) = args.tray_duration {
        config.tray_duration = t;
    }
    if let Some(n) = args.dense_steps {
        config.dense_steps = n;
    }
    // The tray is sampled four times per period of the 20 Hz drive.
    if config.tray_count < 10 || !(config.tray_duration.is_finite() && config.tray_duration >= 0.0125) {
        return Err("--tray-count must be at least 10 and --tray-duration at least 0.0125 s (one density sample)".into());
    }
    // On-CPU time of the one worker is the wall time on an idle core; with several workers
    // only wall time adds up.
    config.cpu_time = args.threads == 1;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads).build()?;
    crate::rundir::output::claim(&args.out, args.force)?;
    let mut dir = RunDir::create(&args.out, &json!({ "args": &args, "config": &config }))?;
    let t0 = Instant::now();
    let say = |name: &str| eprintln!("[{:6.1} s] {name}", t0.elapsed().as_secs_f64());
    let rows = pool.install(|| tradeoff::run(&config, say))?;
    let laws = pool.install(|| tradeoff::friction_laws(&config, &mut |name: &str| say(name)))?;
    say("event-driven model, mixture scene");
    let events = events_speed(if args.quick { 0.5 } else { 3.0 })?;

    let table = format!(
        "{}\n## Friction laws\n\nSpeed of each friction law against Haff-Werner, timed in this run (medians of back-to-back pairs).\n\n{}\n{}",
        tradeoff::markdown_table(&rows),
        tradeoff::friction_table(&laws),
        events.markdown()
    );
    analysis::io::write_atomic(&args.out.join("bench.md"), table.as_bytes())?;
    dir.note_files([args.out.join("bench.md")]);
    let csv_rows: Vec<Vec<f64>> = rows
        .iter()
        .map(|r| {
            vec![
                match r.study {
                    Study::Collision => 0.0,
                    Study::Tray => 1.0,
                    Study::HardCase => 2.0,
                },
                r.speed_ratio,
                r.error,
                r.wall_s,
                r.dt,
                r.steps_per_contact,
                r.eps_error.unwrap_or(f64::NAN),
                r.energy_error.unwrap_or(f64::NAN),
                r.density_distance.unwrap_or(f64::NAN),
                r.on_front as u8 as f64,
            ]
        })
        .collect();
    dir.csv(
        "bench.csv",
        &[
            "study(0=lab,1=tray,2=hard)",
            "speed_ratio",
            "error",
            "wall_s",
            "dt",
            "steps_per_contact",
            "eps_error",
            "energy_error",
            "density_distance",
            "on_front",
        ],
        &csv_rows,
    )?;

    let keys: Vec<&str> = tradeoff::friction_law_keys();
    let law_rows: Vec<Vec<f64>> = laws
        .iter()
        .map(|l| {
            let k = keys.iter().position(|key| *key == l.key).expect("a law of the table");
            vec![
                k as f64,
                l.frequency,
                l.amplitude,
                l.dt_auto,
                l.steps_per_contact_auto,
                l.speed_same_step,
                l.speed_auto,
            ]
        })
        .collect();
    let names: Vec<String> = keys.iter().enumerate().map(|(k, key)| format!("{k}={key}")).collect();
    let law_column = format!("law({})", names.join(";"));
    dir.csv(
        "friction_laws.csv",
        &[
            &law_column,
            "frequency",
            "amplitude",
            "dt_auto",
            "steps_per_contact_auto",
            "speed_same_step",
            "speed_auto",
        ],
        &law_rows,
    )?;

    let lab: Vec<&Row> = rows.iter().filter(|r| r.study == Study::Collision).collect();
    // The noise floor is not a setting: it stays in the table only.
    let tray: Vec<&Row> = rows.iter().filter(|r| r.study == Study::Tray && r.axis != "noise floor").collect();
    let points = |rs: &[&Row]| -> Vec<(f64, f64)> { rs.iter().map(|r| (r.speed_ratio, r.error.max(PLOT_FLOOR))).collect() };
    let defaults: Vec<&Row> = rows.iter().filter(|r| r.axis == "default").collect();
    let any_zero = lab.iter().chain(&tray).any(|r| r.error == 0.0);
    let title = if any_zero {
        "Speed against error (errors of exactly 0 drawn at 1e-9)"
    } else {
        "Speed against error"
    };
    let plot = LinePlot::new(
        title,
        "speed ratio (reference time / setting time, same simulated time)",
        "error (lab: restitution; tray: density-map distance)",
    )
    .series("collision lab", points(&lab), Mark::Points)
    .series("lab Pareto front", front_line(&lab), Mark::Dashed)
    .series("tray", points(&tray), Mark::Points)
    .series("tray Pareto front", front_line(&tray), Mark::Dashed)
    .series("defaults (dt = auto)", points(&defaults), Mark::Points)
    .legend(LegendCorner::LowerRight)
    .log_x()
    .log_y();
    dir.plot("pareto", &plot)?;

    let defaults = defaults
        .iter()
        .map(|r| OnFront {
            name: r.name.clone(),
            study: r.study,
            on_front: r.on_front,
        })
        .collect();
    let summary = BenchSummary {
        quick: args.quick,
        threads: args.threads,
        wall_s: t0.elapsed().as_secs_f64(),
        defaults,
        rows,
        friction_laws: laws,
        events,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// The event-driven row: collisions per second of one core on the mixture scene
/// (`scenes/mixture.toml`, built in), after a 1 s transient.
#[derive(Debug, Serialize)]
pub struct EventsSpeed {
    simulated_s: f64,
    collisions: u64,
    cpu_s: f64,
    collisions_per_s: f64,
}

impl EventsSpeed {
    fn markdown(&self) -> String {
        format!(
            "## Event-driven model\n\nThe mixture scene (300 spheres, `scenes/mixture.toml`), one core: {} collisions in {:.2} s of CPU for {} s simulated, **{:.3e} collisions per second**. The DEM has no scene of this vertical box, so there is no DEM row beside it.\n",
            self.collisions, self.cpu_s, self.simulated_s, self.collisions_per_s
        )
    }
}

fn events_speed(simulated: f64) -> Result<EventsSpeed, CliError> {
    const MIXTURE: &str = include_str!("../../../scenes/mixture.toml");
    let scene: events::scene::EventScene = toml::from_str(MIXTURE)?;
    let mut sim = events::Simulation::new(crate::scene::events::config(&scene)?)?;
    sim.run_until(1.0)?;
    let before = sim.collisions();
    let cpu = crate::host::clock::Stopwatch::start(true);
    sim.run_until(1.0 + simulated)?;
    let cpu_s = cpu.seconds();
    let collisions = sim.collisions() - before;
    Ok(EventsSpeed {
        simulated_s: simulated,
        collisions,
        cpu_s,
        collisions_per_s: collisions as f64 / cpu_s.max(1e-9),
    })
}
