//! `stripes compare` on a vibrated box (a DEM scene with `drive.direction = "z"`): the
//! three-way check of the vibrated-box study. The DEM runs the box; the collision lab
//! measures the DEM's restitution table with the scene's laws (pairs and walls); the
//! event-driven model runs the same box with that table as its collision rule, and with the
//! constant-coefficient Walton rule fitted to the table. All three are sampled alike (the
//! same phases, bins and definitions of H, K/R, density and temperature) and set side by side
//! in `report.md` with each model's speed per simulated second.
//!
//! Layout of the output directory: `dem-scene.toml` (the resolved DEM scene),
//! `restitution.csv` and `restitution_floor.csv` (the DEM's tables), `events-table.toml` and
//! `events-walton.toml` (the event-driven scenes run), `runs.csv` (one row per model and
//! seed), `profiles.csv`, the plots `density.{png,svg}` and `temperature.{png,svg}`,
//! `report.md` and `summary.json`.

use std::path::{Path, PathBuf};

use analysis::plot::{LinePlot, Mark};
use events::observe::Observer;
use events::scene::{
    EventBox, EventDrive, EventGuard, EventParticles, EventRule, EventRules, EventRun, EventScene, EventSpecies, Floor, Lid, Model,
    PerSpecies, Shape,
};
use events::{SideWalls, Waveform};
use particles::advance::{advance_to, AtTimes};
use particles::constants::GRAVITY;
use particles::experiment::collide::{Collision, Impact, StepSize, Target};
use particles::experiment::restitution::{self, Row};
use particles::integrate::Integrator;
use particles::scene::{DriveDirection, Scene};
use particles::sim::Simulation;
use particles::{time_step, tray, Vec3};
use serde::Serialize;

use crate::host::clock::Stopwatch;
use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Summary};
use crate::scene::file::SceneFile;

/// Normal impact speeds of the restitution table (m/s): from a grain resting on the floor to
/// twice the fastest the drive gives.
const TABLE_G_N: [f64; 8] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0];
/// Ratios g_t / g_n of the table (those of `stripes collide --table`).
const TABLE_RATIOS: [f64; 12] = [0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0];
/// Steps per contact of the lab's impacts (its converged default).
const TABLE_STEPS: f64 = 1000.0;
/// Height bins of the profiles (m), and the range they cover above the floor's mean position.
const BIN: f64 = 0.5e-3;
const TOP: f64 = 0.05;
/// The event-driven model's collapse guard (the TC model), as in `scenes/vibrated-box.toml`.
const TC: f64 = 1e-5;
/// Initial speeds of the event-driven grains (m/s), as in `scenes/vibrated-box.toml`.
const EVENTS_INITIAL_SPEED: f64 = 0.1;

/// What the comparison needs besides the scene.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    pub scene: PathBuf,
    pub out: PathBuf,
    /// Runs per model, seeds `run.seed`, `run.seed + 1`, ...
    pub seeds: u64,
    /// Simulated time before sampling starts (s).
    pub transient: f64,
    pub sample_cache: PathBuf,
    pub force: bool,
    pub quiet: bool,
}

/// True if `scene` is a vibrated box, which `stripes compare` hands to [`compare`].
pub fn is_vibrated_box(scene: &Scene) -> bool {
    scene.drive.direction == DriveDirection::Z
}

/// Sums over samples of one height profile (per bin), as the event-driven observer keeps them.
#[derive(Clone, Debug, Default)]
struct Bins {
    count: Vec<f64>,
    m: Vec<f64>,
    mvx2: Vec<f64>,
    mvz2: Vec<f64>,
    vx: Vec<f64>,
    vz: Vec<f64>,
    samples: u64,
}

impl Bins {
    fn new() -> Self {
        let n = (TOP / BIN).ceil() as usize;
        let z = vec![0.0; n];
        Bins {
            count: z.clone(),
            m: z.clone(),
            mvx2: z.clone(),
            mvz2: z.clone(),
            vx: z.clone(),
            vz: z,
            samples: 0,
        }
    }

    /// Adds a grain of mass `m` at height `z` with in-plane velocity `(vx, vz)`.
    fn add(&mut self, z: f64, m: f64, vx: f64, vz: f64) {
        let b = ((z / BIN).floor().max(0.0) as usize).min(self.count.len() - 1);
        self.count[b] += 1.0;
        self.m[b] += m;
        self.mvx2[b] += m * vx * vx;
        self.mvz2[b] += m * vz * vz;
        self.vx[b] += vx;
        self.vz[b] += vz;
    }

    /// Adds another model run's sums (pooled over seeds).
    fn merge(&mut self, o: &Bins) {
        for (a, b) in [
            (&mut self.count, &o.count),
            (&mut self.m, &o.m),
            (&mut self.mvx2, &o.mvx2),
            (&mut self.mvz2, &o.mvz2),
            (&mut self.vx, &o.vx),
            (&mut self.vz, &o.vz),
        ] {
            a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        }
        self.samples += o.samples;
    }

    /// The event-driven observer's height profile of species 0, as sums.
    fn of_events(obs: &Observer) -> Self {
        let p = &obs.species[0];
        let mut b = Bins::new();
        let n = b.count.len().min(p.count.len());
        b.count[..n].copy_from_slice(&p.count[..n]);
        b.m[..n].copy_from_slice(&p.m[..n]);
        b.mvx2[..n].copy_from_slice(&p.mvx2[..n]);
        b.mvz2[..n].copy_from_slice(&p.mvz2[..n]);
        b.vx[..n].copy_from_slice(&p.vx[..n]);
        b.vz[..n].copy_from_slice(&p.vz[..n]);
        b.samples = obs.samples;
        b
    }

    /// Per bin: `(z, grains per mm of height, T / m0)`, where `T = (T_x + T_z) / 2` is the
    /// temperature about the bin's mean flow, `m <(v - <v>)^2>` per degree of freedom (the
    /// event-driven observer's definition), over `m0` the mass of a grain of diameter 1 mm
    /// (m^2/s^2); NaN in empty bins.
    fn rows(&self, m0: f64) -> Vec<[f64; 3]> {
        let s = self.samples.max(1) as f64;
        (0..self.count.len())
            .map(|b| {
                let c = self.count[b];
                let mean_m = self.m[b] / c;
                let (ux, uz) = (self.vx[b] / c, self.vz[b] / c);
                let tx = self.mvx2[b] / c - mean_m * ux * ux;
                let tz = self.mvz2[b] / c - mean_m * uz * uz;
                [(b as f64 + 0.5) * BIN, c / s / (BIN * 1e3), 0.5 * (tx + tz) / m0]
            })
            .collect()
    }
}

/// One run of one model, measured.
#[derive(Clone, Debug, Serialize)]
struct Measured {
    model: &'static str,
    seed: u64,
    /// Mean height of the centres above the floor's mean position (m).
    mean_height_m: f64,
    /// In-plane translational over in-plane rotational kinetic energy: `sum m (v_x^2 + v_z^2)`
    /// over `sum I w_y^2`, the only spin a grain has in the plane.
    k_over_r: f64,
    /// The DEM only: the same with every component (`v_y`, and spins about x and z).
    k_over_r_3d: Option<f64>,
    /// The DEM only: `sum m v_y^2 / sum m v_x^2`, the motion across the plane that the y walls
    /// confine, against the motion along the floor.
    vy2_over_vx2: Option<f64>,
    /// On-CPU seconds per simulated second of the whole run (transient included).
    cpu_s_per_simulated_s: f64,
    /// Collisions (event-driven) or steps (DEM) per simulated second.
    work_per_simulated_s: f64,
    samples: u64,
    #[serde(skip)]
    bins: Bins,
}

/// Sample times: `k / (f samples_per_period)` for `k >= 1`, those at or after `transient`.
fn sample_times(frequency: f64, per_period: u32, duration: f64) -> Vec<f64> {
    let dt = 1.0 / (frequency * per_period as f64);
    let n = (duration / dt + 1e-9).floor() as u64;
    (1..=n).map(|k| k as f64 * dt).collect()
}

/// The DEM on the box, seed `seed`, from the scene's prepared sample.
fn run_dem(scene: &Scene, seed: u64, opts: &Options) -> Result<Measured, CliError> {
    let mut scene = scene.clone();
    scene.run.seed = seed;
    let (state, _) = crate::dem::samples::load_or_prepare(&scene, &opts.sample_cache, |_| {})?;
    let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene)?)?;
    let mut sim = Simulation::new(setup, state)?;
    let mut bins = Bins::new();
    let (mut h, mut k, mut r, mut k3, mut r3) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut vx2, mut vy2) = (0.0, 0.0);
    let clock = Stopwatch::start(true);
    let times = sample_times(scene.drive.frequency, scene.run.snapshots_per_period, scene.run.duration);
    let mut sample = AtTimes::new(times, |sim: &Simulation, t: f64| {
        if t < opts.transient {
            return Ok(());
        }
        let state = sim.state();
        let s = &*state;
        let n = s.len();
        let mut zsum = 0.0;
        for i in 0..n {
            let (m, inertia) = (s.mass(i), s.inertia(i));
            let (v, w) = (s.vel[i], s.omega[i]);
            zsum += s.pos[i].z;
            bins.add(s.pos[i].z, m, v.x, v.z);
            k += m * (v.x * v.x + v.z * v.z);
            r += inertia * w.y * w.y;
            k3 += m * v.norm_squared();
            vx2 += m * v.x * v.x;
            vy2 += m * v.y * v.y;
            r3 += inertia * w.norm_squared();
        }
        h += zsum / n as f64;
        bins.samples += 1;
        Ok(())
    });
    if let Some(end) = sample.last() {
        advance_to(&mut sim, end, &mut [&mut sample])?;
    }
    let cpu = clock.seconds();
    Ok(Measured {
        model: "dem",
        seed,
        mean_height_m: h / bins.samples.max(1) as f64,
        k_over_r: k / r,
        k_over_r_3d: Some(k3 / r3),
        vy2_over_vx2: Some(vy2 / vx2),
        cpu_s_per_simulated_s: cpu / scene.run.duration,
        work_per_simulated_s: sim.steps as f64 / sim.time,
        samples: bins.samples,
        bins,
    })
}

/// The event-driven model on `scene`.
fn run_events(scene: &EventScene, model: &'static str) -> Result<Measured, CliError> {
    let (m, obs) = crate::events::measure::observe(scene)?;
    Ok(Measured {
        model,
        seed: scene.run.seed,
        mean_height_m: m.mean_height_m,
        k_over_r: m.k_over_r,
        k_over_r_3d: None,
        vy2_over_vx2: None,
        cpu_s_per_simulated_s: m.cpu_s / scene.run.duration,
        work_per_simulated_s: m.collisions as f64 / scene.run.duration,
        samples: m.samples,
        bins: Bins::of_events(&obs),
    })
}

/// The restitution tables of the scene's laws for two grains of the mean radius (pairs) and
/// for one such grain against a wall (floor and sides), as `stripes collide --table --scene`.
fn tables(scene: &Scene) -> Result<(Vec<Row>, Vec<Row>), CliError> {
    let (pair_law, wall_law) = scene.laws()?;
    let r = 0.5 * (scene.particles.radius_min + scene.particles.radius_max);
    let m = scene.material().sphere_mass(r);
    let pair = Collision {
        law: pair_law,
        r1: r,
        m1: m,
        omega1: Vec3::zeros(),
        target: Target::Sphere {
            r,
            m,
            omega: Vec3::zeros(),
        },
        impact: Impact::Components { vn: 1.0, vt: 0.0 },
        step: StepSize::PerContact(TABLE_STEPS),
        integrator: Integrator::VelocityVerlet,
    };
    let floor = Collision {
        law: wall_law,
        target: Target::Wall,
        ..pair
    };
    Ok((
        within_bounds(restitution::table(&pair, &TABLE_G_N, &TABLE_RATIOS)?),
        within_bounds(restitution::table(&floor, &TABLE_G_N, &TABLE_RATIOS)?),
    ))
}

/// The table's coefficients brought within their physical bounds, eps_n in [0, 1] and beta
/// in [-1, 1], which the event-driven model's table requires: the lab's integration measures
/// a frictionless contact (mu = 0) at beta = -1.001 to -0.984, some of it a hair below smooth.
/// The same clamp as `stripes collide --table` ([`crate::studies::collide::clamp_to_rule`]).
fn within_bounds(mut rows: Vec<Row>) -> Vec<Row> {
    crate::studies::collide::clamp_to_rule("restitution", &mut rows);
    rows
}

/// The constant-coefficient Walton rule fitted to a table: `e` the mean normal restitution of
/// the most nearly normal impacts (the smallest ratio), `beta0` the mean tangential
/// restitution there (sticking impacts; -1 for a law without friction), and `mu` the law's
/// Coulomb coefficient, which sets Walton's sliding branch.
#[derive(Clone, Copy, Debug, Serialize)]
struct Walton {
    e: f64,
    mu: f64,
    beta0: f64,
}

fn fit_walton(rows: &[Row], mu: f64) -> Walton {
    let slow = TABLE_RATIOS[0];
    let normal: Vec<&Row> = rows.iter().filter(|r| r.g_t_over_g_n == slow).collect();
    let n = normal.len() as f64;
    let e = normal.iter().map(|r| r.eps_n).sum::<f64>() / n;
    let beta0 = if mu > 0.0 {
        normal.iter().map(|r| r.beta).sum::<f64>() / n
    } else {
        -1.0
    };
    Walton { e, mu, beta0 }
}

fn walton_rule(w: Walton) -> EventRule {
    EventRule {
        e: Some(PerSpecies::One(w.e)),
        table: None,
        mu: w.mu,
        beta0: w.beta0,
        v0: None,
    }
}

fn table_rule(path: &Path) -> EventRule {
    EventRule {
        e: None,
        table: Some(path.to_path_buf()),
        mu: 0.0,
        beta0: -1.0,
        v0: None,
    }
}

/// The event-driven scene of the DEM's box, with the pairs' rule `pair`, the walls' rule
/// `wall` (floor and sides; the DEM has one wall law), seed `seed`.
fn events_scene(scene: &Scene, (pair, wall): (EventRule, EventRule), seed: u64, transient: f64) -> EventScene {
    EventScene {
        model: Model::Events,
        tray: EventBox {
            width: scene.tray.length,
            height: TOP,
            side_walls: SideWalls::Fixed,
            gravity: GRAVITY,
        },
        drive: EventDrive {
            frequency: scene.drive.frequency,
            amplitude: Some(scene.drive.amplitude),
            peak_speed: None,
            phase: 0.0,
            floor: Floor::Vibrated,
            lid: Lid::None,
            waveform: Waveform::Sine,
        },
        base: None,
        particles: EventParticles {
            shape: Shape::Sphere,
            q: None,
            species: vec![EventSpecies {
                count: scene.particles.count,
                radius_min: scene.particles.radius_min,
                radius_max: scene.particles.radius_max,
                mass: None,
                density: Some(scene.material().density),
            }],
            initial_speed: EVENTS_INITIAL_SPEED,
        },
        rules: EventRules {
            pair,
            floor: wall.clone(),
            side: wall.clone(),
            lid: wall,
        },
        guard: EventGuard {
            min_rebound_speed: None,
            tc: Some(TC),
            collapse_speed: None,
        },
        run: EventRun {
            duration: scene.run.duration,
            transient,
            seed,
            samples_per_period: scene.run.snapshots_per_period,
            bin: BIN,
            phase: 0.0,
            phase_resolved: false,
        },
    }
}

/// The three models' statistics over seeds.
#[derive(Clone, Debug, Serialize)]
struct ModelSummary {
    model: &'static str,
    seeds: usize,
    mean_height_mm: (f64, f64),
    k_over_r: (f64, f64),
    k_over_r_3d: Option<(f64, f64)>,
    vy2_over_vx2: Option<(f64, f64)>,
    cpu_s_per_simulated_s: (f64, f64),
    work_per_simulated_s: f64,
    samples_per_seed: u64,
}

fn summarise(model: &'static str, runs: &[Measured]) -> ModelSummary {
    let of = |f: fn(&Measured) -> f64| analysis::stats::mean_stderr(&runs.iter().map(f).collect::<Vec<_>>());
    ModelSummary {
        model,
        seeds: runs.len(),
        mean_height_mm: {
            let (m, s) = of(|r| r.mean_height_m);
            (1e3 * m, 1e3 * s)
        },
        k_over_r: of(|r| r.k_over_r),
        k_over_r_3d: runs[0].k_over_r_3d.map(|_| of(|r| r.k_over_r_3d.unwrap_or(f64::NAN))),
        vy2_over_vx2: runs[0].vy2_over_vx2.map(|_| of(|r| r.vy2_over_vx2.unwrap_or(f64::NAN))),
        cpu_s_per_simulated_s: of(|r| r.cpu_s_per_simulated_s),
        work_per_simulated_s: of(|r| r.work_per_simulated_s).0,
        samples_per_seed: runs[0].samples,
    }
}

fn stage(opts: &Options, what: &str) {
    if !opts.quiet {
        eprintln!("compare (vibrated box) {what}");
    }
}

/// What the three-way comparison found: `summary.json`, field for field.
#[derive(Clone, Debug, Serialize)]
pub struct BoxSummary {
    scene: PathBuf,
    kind: &'static str,
    seeds: Vec<u64>,
    transient_s: f64,
    simulated_s: f64,
    models: Vec<ModelSummary>,
    walton_fit: WaltonFit,
    /// The smallest and largest eps_n of the DEM's tables.
    table_pair_eps_n: [f64; 2],
    table_wall_eps_n: [f64; 2],
    h_table_vs_dem: f64,
    h_walton_vs_dem: f64,
    h_within_10_percent: bool,
    speedup_table: f64,
    speedup_walton: f64,
    speedup_at_least_100: bool,
    wall_s: f64,
    #[serde(flatten)]
    written: Written,
}

/// The Walton rules fitted to the pair and the wall tables.
#[derive(Clone, Debug, Serialize)]
struct WaltonFit {
    pair: Walton,
    wall: Walton,
}

impl Summary for BoxSummary {
    fn headline(&self) -> Headline {
        Headline {
            simulated_s: Some(self.simulated_s),
            wall_s: Some(self.wall_s),
            ..Headline::written(0, &self.written)
        }
    }
}

/// Runs the three-way comparison of the vibrated box `file` (already validated) into
/// `opts.out`.
pub fn compare(file: &SceneFile, opts: &Options) -> Result<BoxSummary, CliError> {
    let scene = &file.dem;
    if !scene.drive.stages.is_empty() {
        return Err("scene `drive.stages`: the vibrated box's comparison runs one drive, not a schedule".into());
    }
    if opts.seeds == 0 {
        return Err("--seeds must be at least 1".into());
    }
    if !(opts.transient.is_finite() && opts.transient >= 0.0 && opts.transient < scene.run.duration) {
        return Err(format!(
            "--transient must lie in [0, run.duration = {} s), got {}",
            scene.run.duration, opts.transient
        )
        .into());
    }
    if !scene.tray.x_walls || !scene.toggles.walls {
        return Err(
            "a vibrated box needs walls on every side: box.x_walls = true and toggles.walls = true (the event-driven box has fixed side walls)"
                .into(),
        );
    }
    // The step is checked before anything is written.
    time_step::for_scene(scene)?;
    crate::rundir::output::claim(&opts.out, opts.force)?;
    let started = std::time::Instant::now();
    let mut dir = RunDir::create(&opts.out, opts)?;
    let dem_toml = file.to_toml()?;
    std::fs::write(opts.out.join("dem-scene.toml"), &dem_toml)?;
    dir.note_files([opts.out.join("dem-scene.toml")]);

    stage(opts, "[1/4] the DEM's restitution tables");
    let (pair_rows, floor_rows) = tables(scene)?;
    let header = ["g_n", "g_t_over_g_n", "eps_n", "beta"];
    let as_rows = |rows: &[Row]| {
        rows.iter()
            .map(|r| vec![r.g_n, r.g_t_over_g_n, r.eps_n, r.beta])
            .collect::<Vec<_>>()
    };
    dir.csv("restitution.csv", &header, &as_rows(&pair_rows))?;
    dir.csv("restitution_floor.csv", &header, &as_rows(&floor_rows))?;
    let pair_fit = fit_walton(&pair_rows, scene.contact.friction);
    let wall_fit = fit_walton(&floor_rows, scene.contact.wall_friction);

    let seeds: Vec<u64> = (0..opts.seeds).map(|k| scene.run.seed + k).collect();
    let rules = [
        (
            "events-table",
            (
                table_rule(&opts.out.join("restitution.csv")),
                table_rule(&opts.out.join("restitution_floor.csv")),
            ),
        ),
        ("events-walton", (walton_rule(pair_fit), walton_rule(wall_fit))),
    ];
    for (name, rule) in &rules {
        let text = toml::to_string(&events_scene(scene, rule.clone(), seeds[0], opts.transient))?;
        let path = opts.out.join(format!("{name}.toml"));
        std::fs::write(&path, text)?;
        dir.note_files([path]);
    }

    // The DEM of 50 grains is one block: one thread, timed on the CPU.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let mut runs: Vec<Measured> = Vec::new();
    for &seed in &seeds {
        stage(opts, &format!("[2/4] the DEM, seed {seed} ({} s simulated)", scene.run.duration));
        runs.push(pool.install(|| run_dem(scene, seed, opts))?);
    }
    for (name, rule) in &rules {
        for &seed in &seeds {
            stage(opts, &format!("[3/4] the event-driven model ({name}), seed {seed}"));
            runs.push(run_events(&events_scene(scene, rule.clone(), seed, opts.transient), name)?);
        }
    }

    stage(opts, "[4/4] report");
    let m0 = scene.material().sphere_mass(0.5e-3);
    let models = ["dem", "events-table", "events-walton"];
    let mut summaries = Vec::new();
    let mut profiles = Vec::new();
    for model in models {
        let these: Vec<Measured> = runs.iter().filter(|r| r.model == model).cloned().collect();
        summaries.push(summarise(model, &these));
        let mut pooled = Bins::new();
        for r in &these {
            pooled.merge(&r.bins);
        }
        profiles.push(pooled.rows(m0));
    }
    let run_rows: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| {
            vec![
                models.iter().position(|m| *m == r.model).unwrap_or(0) as f64,
                r.seed as f64,
                1e3 * r.mean_height_m,
                r.k_over_r,
                r.cpu_s_per_simulated_s,
                r.work_per_simulated_s,
            ]
        })
        .collect();
    dir.csv(
        "runs.csv",
        &[
            "model_0dem_1table_2walton",
            "seed",
            "H_mm",
            "K_over_R",
            "cpu_s_per_simulated_s",
            "steps_or_collisions_per_simulated_s",
        ],
        &run_rows,
    )?;
    let profile_rows: Vec<Vec<f64>> = (0..profiles[0].len())
        .map(|b| {
            let mut row = vec![1e3 * profiles[0][b][0]];
            for p in &profiles {
                row.extend([p[b][1], p[b][2]]);
            }
            row
        })
        .collect();
    dir.csv(
        "profiles.csv",
        &[
            "z_mm",
            "dem_per_mm",
            "dem_T_over_m0",
            "table_per_mm",
            "table_T_over_m0",
            "walton_per_mm",
            "walton_T_over_m0",
        ],
        &profile_rows,
    )?;
    // Plot up to the height where the DEM's density falls below 1 % of its peak.
    let peak = profiles[0].iter().map(|r| r[1]).fold(0.0, f64::max);
    let top = profiles[0]
        .iter()
        .rposition(|r| r[1] > 0.01 * peak)
        .map_or(TOP, |b| (b + 2) as f64 * BIN);
    let labels = ["DEM", "event-driven, DEM table", "event-driven, fitted Walton"];
    let marks = [Mark::LinePoints, Mark::Line, Mark::Dashed];
    let mut density = LinePlot::new("Density against height", "z (mm)", "grains per mm of height");
    let mut temperature = LinePlot::new("Temperature against height", "z (mm)", "(T_x + T_z) / 2 / m0 (m^2/s^2)");
    for ((p, label), mark) in profiles.iter().zip(labels).zip(marks) {
        let within = |r: &&[f64; 3]| r[0] <= top;
        density = density.series(label, p.iter().filter(within).map(|r| (1e3 * r[0], r[1])).collect(), mark);
        temperature = temperature.series(
            label,
            p.iter()
                .filter(within)
                .filter(|r| r[1] > 0.01 * peak)
                .map(|r| (1e3 * r[0], r[2]))
                .collect(),
            mark,
        );
    }
    dir.plot("density", &density)?;
    dir.plot("temperature", &temperature)?;

    let (dem, table, walton) = (&summaries[0], &summaries[1], &summaries[2]);
    let h_diff = table.mean_height_mm.0 / dem.mean_height_mm.0 - 1.0;
    let h_diff_walton = walton.mean_height_mm.0 / dem.mean_height_mm.0 - 1.0;
    let speedup = dem.cpu_s_per_simulated_s.0 / table.cpu_s_per_simulated_s.0;
    let speedup_walton = dem.cpu_s_per_simulated_s.0 / walton.cpu_s_per_simulated_s.0;
    let wall_s = started.elapsed().as_secs_f64();
    let report = report(
        scene,
        opts,
        (&summaries, (pair_fit, wall_fit)),
        (h_diff, h_diff_walton, speedup, speedup_walton),
        (&pair_rows, &floor_rows),
        wall_s,
    );
    std::fs::write(opts.out.join("report.md"), report)?;
    dir.note_files([opts.out.join("report.md")]);
    let eps_range = |rows: &[Row]| {
        let eps = rows.iter().map(|r| r.eps_n);
        [eps.clone().fold(f64::INFINITY, f64::min), eps.fold(f64::NEG_INFINITY, f64::max)]
    };
    let summary = BoxSummary {
        scene: opts.scene.clone(),
        kind: "vibrated box: DEM, event-driven with the DEM's table, event-driven with the fitted Walton rule",
        seeds,
        transient_s: opts.transient,
        simulated_s: scene.run.duration,
        models: summaries,
        walton_fit: WaltonFit {
            pair: pair_fit,
            wall: wall_fit,
        },
        table_pair_eps_n: eps_range(&pair_rows),
        table_wall_eps_n: eps_range(&floor_rows),
        h_table_vs_dem: h_diff,
        h_walton_vs_dem: h_diff_walton,
        h_within_10_percent: h_diff.abs() <= 0.1,
        speedup_table: speedup,
        speedup_walton,
        speedup_at_least_100: speedup >= 100.0,
        wall_s,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// `value +- error` with the error's leading digits.
fn pm((m, s): (f64, f64)) -> String {
    if s > 0.0 {
        let digits = (-(s.log10().floor()) + 1.0).max(0.0) as usize;
        format!("{m:.digits$} +- {s:.digits$}")
    } else {
        format!("{m:.3}")
    }
}

fn report(
    scene: &Scene,
    opts: &Options,
    (summaries, (pair_fit, wall_fit)): (&[ModelSummary], (Walton, Walton)),
    (h_diff, h_diff_walton, speedup, speedup_walton): (f64, f64, f64, f64),
    (pair_rows, floor_rows): (&[Row], &[Row]),
    wall_s: f64,
) -> String {
    let v = 2.0 * std::f64::consts::PI * scene.drive.frequency * scene.drive.amplitude;
    let gamma = scene.drive.amplitude * (2.0 * std::f64::consts::PI * scene.drive.frequency).powi(2) / GRAVITY;
    let range = |rows: &[Row], f: fn(&Row) -> f64| {
        let lo = rows.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = rows.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        format!("{lo:.3} to {hi:.3}")
    };
    let mut s = String::new();
    s.push_str("# The vibrated box: DEM against the event-driven model\n\n");
    s.push_str(&format!(
        "Scene `{}`: {} spheres, radii {:.3}-{:.3} mm, in a box {} mm wide between two walls {} mm apart; the floor moves as \
         z_f = A sin(2 pi f t) with f = {} Hz, A = {:.4} mm (V = {:.3} m/s, Gamma = {:.1}). {} seed(s) per model (from seed {}), \
         {} s simulated each, the first {} s discarded, sampled {} times per period. Errors are standard errors over the seeds. \
         Wall time of this comparison: {:.0} s.\n\n",
        opts.scene.display(),
        scene.particles.count,
        1e3 * scene.particles.radius_min,
        1e3 * scene.particles.radius_max,
        1e3 * scene.tray.length,
        1e3 * scene.tray.width,
        scene.drive.frequency,
        1e3 * scene.drive.amplitude,
        v,
        gamma,
        opts.seeds,
        scene.run.seed,
        scene.run.duration,
        opts.transient,
        scene.run.snapshots_per_period,
        wall_s
    ));
    s.push_str("## The models\n\n");
    s.push_str(&format!(
        "- **DEM**: the scene's laws (`dem-scene.toml`), spheres in 3D held in the plane by the two y walls.\n\
         - **event-driven, DEM table**: hard spheres in the plane (q = 2/5), each collision's (eps_n, beta) read from the \
         DEM's restitution tables measured by the collision lab with the scene's laws at the mean radius: pairs \
         (`restitution.csv`, eps_n {}, beta {}) and a grain against a wall for the floor and the sides \
         (`restitution_floor.csv`, eps_n {}).\n\
         - **event-driven, fitted Walton**: constant coefficients read off those tables: pairs e = {:.4}, mu = {}, beta0 = {:.3}; \
         walls e = {:.4}, mu = {}, beta0 = {:.3}.\n\n\
         Both event-driven runs use gravity {GRAVITY} m/s^2 (the DEM's), the TC collapse guard (t_c = {TC:e} s) and start from \
         a lattice at the bottom with speeds up to {EVENTS_INITIAL_SPEED} m/s (`events-table.toml`, `events-walton.toml`).\n\n",
        range(pair_rows, |r| r.eps_n),
        range(pair_rows, |r| r.beta),
        range(floor_rows, |r| r.eps_n),
        pair_fit.e,
        pair_fit.mu,
        pair_fit.beta0,
        wall_fit.e,
        wall_fit.mu,
        wall_fit.beta0
    ));
    s.push_str("## Results\n\n");
    s.push_str(
        "| model | H (mm) | K/R (in plane) | CPU s per simulated s | steps or collisions per simulated s | samples per seed |\n|---|---|---|---|---|---|\n",
    );
    for m in summaries {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.3e} | {} |\n",
            m.model,
            pm(m.mean_height_mm),
            pm(m.k_over_r),
            pm(m.cpu_s_per_simulated_s),
            m.work_per_simulated_s,
            m.samples_per_seed
        ));
    }
    if let (Some(k3), Some(y)) = (summaries[0].k_over_r_3d, summaries[0].vy2_over_vx2) {
        s.push_str(&format!(
            "\nThe DEM's K/R with every component (v_y, spins about x and z): {}; its motion across the plane, \
             sum m v_y^2 / sum m v_x^2: {}.\n",
            pm(k3),
            pm(y)
        ));
    }
    let se = |m: &ModelSummary| m.mean_height_mm.1;
    let (dem, table) = (&summaries[0], &summaries[1]);
    let sigma = (se(dem).powi(2) + se(table).powi(2)).sqrt();
    let errors = if sigma > 0.0 {
        format!(
            "{:.1} combined standard errors",
            (table.mean_height_mm.0 - dem.mean_height_mm.0).abs() / sigma
        )
    } else {
        "no error bar with one seed".into()
    };
    s.push_str(&format!(
        "\n**H**: the tabulated event-driven model gives {:+.1} % against the DEM ({errors}); \
         the goal of 10 % {}. The fitted Walton rule gives {:+.1} %.\n\n",
        100.0 * h_diff,
        if h_diff.abs() <= 0.1 { "holds" } else { "does not hold" },
        100.0 * h_diff_walton
    ));
    s.push_str(&format!(
        "**Speed**: per simulated second the tabulated event-driven model is {:.0} times faster than the DEM, the fitted Walton \
         rule {:.0} times; the goal of 100 times {}. The DEM's cost is its step count (set by the contact time of its springs), the \
         event-driven model's its collision count.\n\n",
        speedup,
        speedup_walton,
        if speedup >= 100.0 { "holds" } else { "does not hold" }
    ));
    s.push_str("![density](density.png)\n\n![temperature](temperature.png)\n\n");
    s.push_str(
        "Profiles (`profiles.csv`) are pooled over seeds; T = (T_x + T_z) / 2 is the temperature about each bin's mean flow, \
         `m <(v - <v>)^2>` per degree of freedom, divided by m0, the mass of a grain of diameter 1 mm; bins holding under 1 % of \
         the DEM's peak density are left out of the temperature plot.\n\n",
    );
    s.push_str("## Why the models can differ\n\n");
    s.push_str(
        "- Soft against hard contacts: a DEM contact lasts a finite time, so in the dense layers near the floor grains meet \
         more than one partner at once and the floor's kick is spread over the contact; the event-driven model's collisions \
         are instantaneous and binary, and its TC guard makes collisions elastic for grains that collided within t_c.\n\
         - The tables are measured at the mean radius; the DEM's restitution depends on the pair's reduced mass (a linear \
         law), so small and large grains differ from the table.\n\
         - The DEM's spheres are 3D between two walls: pairs meeting slightly off the plane give the grains a small \
         velocity across it, which the y walls reflect with their restitution, and spins about x and z; the event-driven \
         grains stay in the plane.\n\
         - The fitted Walton rule keeps one e and one beta0; the table follows the DEM's beta as the impact turns from \
         sticking to sliding, and any speed dependence of eps_n.\n",
    );
    s
}
