//! Speed against error: every choice that trades accuracy for speed, measured on the collision
//! lab and on a small shaken tray, against a converged reference computed in the same run.
//!
//! What varies: steps per contact (the time step), Young's modulus (softer contacts last
//! longer, so the same steps per contact give a larger step), the integrator (velocity Verlet
//! or the thesis' scheme), 3D against pinned 2D (tray), a cheaper normal law (a linear
//! spring-dashpot matched to the Hertz law's restitution and contact time: no square roots),
//! the neighbour skin and the rebuild policy (skin 0: rebuild every step), and the defaults
//! (`dt = "auto"` at the default restitution tolerance, see [`super::step_control`]).
//!
//! What is measured, per setting:
//! - `speed_ratio`: time of the reference setting divided by the setting's, both measured
//!   here, for the same simulated time. With one worker thread the times are the on-CPU
//!   times of that thread ([`Stopwatch`]), which is the wall time on an idle core. The lab's
//!   impacts last microseconds and their time is dominated by setting each one up, so its
//!   speed ratio counts steps per simulated second of contact instead (the wall-time ratio
//!   of a long run at equal cost per step; the tray rows time the cost per step);
//! - collision lab: `error` is the restitution error, the largest `|d eps_n|`, `|d eps_t|`
//!   over the probe impacts of [`super::step_control`] against velocity Verlet at
//!   [`super::step_control::REFERENCE_STEPS`] steps per contact with the reference material;
//!   `energy_error` is the largest relative energy error of the same impacts made elastic
//!   (no dissipation, no friction, no rolling resistance);
//! - tray: `error` is the distance between density maps, the mean over sampled times (four
//!   per period) of `mean_x |phi(x) - phi_ref(x)| / <phi>` on 1 mm cells of the exact area
//!   fraction ([`analysis::density::area_fraction_cells`]) against a run at
//!   `tray.reference_steps` steps per contact; also the stripe count at the end and the onset
//!   time ([`analysis::stripes`]), and `energy_error`, how far the energy ledger misses
//!   closing: `|E(t) - E(0) - (injected - dissipated)| / injected`.
//!
//! The tray is chaotic: two runs that differ in the last bit diverge, so the density distance
//! of any setting that changes the numbers has a floor set by that divergence over the
//! simulated time (reported as the `noise floor` row: the reference with one grain moved by
//! 1 nm, compared with the reference itself). Settings
//! that do not change a single bit (the neighbour skin) have error exactly 0.

use std::time::Instant;

/// A stopwatch of the time the calling thread spent on a CPU (Linux
/// `/proc/thread-self/schedstat`, nanoseconds), falling back to wall time where that file
/// is missing. On a shared machine, wall time mostly measures the neighbours' load; the
/// on-CPU time of the one worker thread is the wall time the same work takes on an idle
/// core. (With more than one worker thread, use wall time: see [`Config::cpu_time`].)
#[derive(Clone, Copy, Debug)]
pub struct Stopwatch {
    cpu: bool,
    wall: Instant,
    start_cpu: f64,
}

fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

impl Stopwatch {
    /// Starts; `cpu` asks for on-CPU time of this thread if available.
    pub fn start(cpu: bool) -> Self {
        let start_cpu = if cpu { thread_cpu_seconds() } else { None };
        Self {
            cpu: start_cpu.is_some(),
            wall: Instant::now(),
            start_cpu: start_cpu.unwrap_or(0.0),
        }
    }

    /// Seconds since the start.
    pub fn seconds(&self) -> f64 {
        match (self.cpu, thread_cpu_seconds()) {
            (true, Some(now)) => now - self.start_cpu,
            _ => self.wall.elapsed().as_secs_f64(),
        }
    }

    /// True if this stopwatch measures on-CPU time.
    pub fn is_cpu(&self) -> bool {
        self.cpu
    }
}

use analysis::density::area_fraction_cells;
use analysis::stripes::{detect, onset, StripeParams};
use serde::Serialize;

use crate::contact::{NormalLaw, TangentialLaw};
use crate::experiment::closed_form::{gamma_for_damping_ratio, linear_dashpot};
use crate::experiment::step_control::{self, REFERENCE_STEPS};
use crate::integrate::Integrator;
use crate::neighbor::NeighborSearch;
use crate::prepare::initial_state;
use crate::scene::{Scene, DEFAULT_RESTITUTION_TOLERANCE};
use crate::sim::Simulation;
use crate::state::State;
use crate::tray;
use crate::SimError;

/// Which study a row belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Study {
    Collision,
    Tray,
    /// A hard case run for its outcome (throughput and whether the method copes).
    HardCase,
}

/// One setting and what it cost and got wrong.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    pub name: String,
    pub study: Study,
    /// What the setting varies: `reference`, `time step`, `young`, `integrator`,
    /// `dimension`, `normal law`, `neighbour list`, `default`, `noise floor`, `hard case`.
    pub axis: String,
    /// Reference wall time / this setting's wall time, for the same simulated time.
    pub speed_ratio: f64,
    /// The headline error (see the module docs), dimensionless.
    pub error: f64,
    /// Wall time of the setting (s).
    pub wall_s: f64,
    /// Time step (s).
    pub dt: f64,
    /// Steps per shortest contact time of the setting's own material.
    pub steps_per_contact: f64,
    pub eps_error: Option<f64>,
    pub energy_error: Option<f64>,
    pub density_distance: Option<f64>,
    pub stripes: Option<usize>,
    pub onset_s: Option<f64>,
    pub neighbor_builds: Option<u64>,
    /// True if no other row of the same study is at least as fast and at least as accurate,
    /// and strictly better in one of them (rows of the `noise floor` axis excluded).
    pub on_front: bool,
    /// What happened, in words.
    pub outcome: String,
}

/// Sizes of the study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Config {
    /// Grains of the tray (radii 0.25-0.5 mm, thesis packing 0.23 at 100 grains per cm of
    /// length in a 2 cm wide tray).
    pub tray_count: usize,
    /// Simulated time of each tray run (s).
    pub tray_duration: f64,
    /// Steps per contact of the converged tray reference.
    pub reference_steps: f64,
    /// Minimum wall time of each timing of the lab's probes (s); repeats until reached.
    pub lab_min_wall: f64,
    /// Timing pairs (reference run, setting run) per tray setting; the median ratio counts.
    pub tray_repeats: u32,
    /// Steps of the dense-packing hard case (8000 grains at area fraction 0.46; 0: skip).
    pub dense_steps: u64,
    /// Time with the on-CPU time of the worker thread ([`Stopwatch`]) instead of wall time:
    /// right for one worker thread on a shared machine.
    pub cpu_time: bool,
}

impl Config {
    /// Under a minute on a loaded two-core machine.
    pub fn quick() -> Self {
        Self {
            tray_count: 200,
            tray_duration: 0.05,
            reference_steps: 50.0,
            lab_min_wall: 0.02,
            tray_repeats: 2,
            dense_steps: 600,
            cpu_time: true,
        }
    }

    /// A few minutes on one core.
    pub fn full() -> Self {
        Self {
            tray_count: 400,
            tray_duration: 0.2,
            reference_steps: 60.0,
            lab_min_wall: 0.2,
            tray_repeats: 1,
            dense_steps: 3000,
            cpu_time: true,
        }
    }
}

/// The thesis dt of 8e-6 s, the reference of the speed ratios.
pub const THESIS_DT: f64 = 8e-6;

/// The base scene of both studies: thesis material and laws (Table 3.3), a 2 cm wide tray
/// shaken at 20 Hz and 25 mm, with `count` grains in `count / 10000` m of length (packing
/// 0.23).
pub fn base_scene(count: usize, duration: f64) -> Scene {
    let text = format!(
        r#"
        [box]
        length = {length}
        width = 0.02
        [drive]
        frequency = 20.0
        amplitude = 0.025
        [particles]
        count = {count}
        radius_min = 0.25e-3
        radius_max = 0.5e-3
        [run]
        duration = {duration}
        dt = {THESIS_DT}
        seed = 1
    "#,
        length = count as f64 / 1e4
    );
    let scene = Scene::parse(&text, &[], "bench").expect("the bench scene parses");
    scene.validate().expect("the bench scene is valid");
    scene
}

fn with(scene: &Scene, overrides: &[String]) -> Result<Scene, SimError> {
    let text = toml::to_string(scene).expect("a scene serialises");
    let s = Scene::parse(&text, overrides, "bench").map_err(|e| SimError::InvalidParameter {
        field: e.key.clone(),
        message: e.message,
    })?;
    s.validate().map_err(|e| SimError::InvalidParameter {
        field: e.key,
        message: e.message,
    })?;
    Ok(s)
}

/// A linear spring-dashpot with the same head-on restitution `eps` and contact duration
/// `t_c` (s) as the given impact of effective mass `m_eff` (kg) at `v` (m/s): the damping
/// ratio from `eps` by bisection on [`linear_dashpot`], then `k_n` from `t_c ~ k^{-1/2}`.
/// Returns `(k_n, gamma_n)` in N/m and kg/s.
pub fn matched_linear(m_eff: f64, eps: f64, t_c: f64, v: f64) -> (f64, f64) {
    let eps_of = |ratio: f64| linear_dashpot(m_eff, 1.0, gamma_for_damping_ratio(m_eff, 1.0, ratio), v).1;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if eps_of(mid) > eps {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let ratio = 0.5 * (lo + hi);
    let t1 = linear_dashpot(m_eff, 1.0, gamma_for_damping_ratio(m_eff, 1.0, ratio), v).0;
    let k = (t1 / t_c).powi(2);
    (k, gamma_for_damping_ratio(m_eff, k, ratio))
}

/// A setting: scene overrides, integrator, steps per contact (of the setting's own
/// material), neighbour skin as a multiple of the largest radius.
#[derive(Clone, Debug)]
struct Setting {
    name: String,
    axis: &'static str,
    overrides: Vec<String>,
    integrator: Integrator,
    steps: Option<f64>,
    skin: f64,
    /// Move grain 0 by 1 nm along x (noise-floor probe).
    perturbed: bool,
}

impl Setting {
    fn new(name: impl Into<String>, axis: &'static str) -> Self {
        Self {
            name: name.into(),
            axis,
            overrides: Vec::new(),
            integrator: Integrator::VelocityVerlet,
            steps: None,
            skin: 0.4,
            perturbed: false,
        }
    }
    fn set(mut self, o: &str) -> Self {
        self.overrides.push(o.to_string());
        self
    }
    fn steps(mut self, s: f64) -> Self {
        self.steps = Some(s);
        self
    }
    fn integrator(mut self, i: Integrator) -> Self {
        self.integrator = i;
        self
    }
    fn skin(mut self, k: f64) -> Self {
        self.skin = k;
        self
    }
}

/// The time step of a setting's scene: its steps per contact, or the scene's own step.
fn setting_dt(scene: &Scene, steps: Option<f64>) -> Result<f64, SimError> {
    match steps {
        Some(s) => Ok(tray::shortest_contact_time(scene) / s),
        None => tray::time_step(scene),
    }
}

/// Marks the Pareto front within each study.
pub fn mark_front(rows: &mut [Row]) {
    let eligible = |r: &Row| r.axis != "noise floor" && r.study != Study::HardCase && r.error.is_finite();
    let flags: Vec<bool> = rows
        .iter()
        .map(|r| {
            eligible(r)
                && !rows.iter().any(|o| {
                    eligible(o)
                        && o.study == r.study
                        && o.speed_ratio >= r.speed_ratio
                        && o.error <= r.error
                        && (o.speed_ratio > r.speed_ratio || o.error < r.error)
                })
        })
        .collect();
    for (r, f) in rows.iter_mut().zip(flags) {
        r.on_front = f;
    }
}

/// Runs both studies and the dense-packing hard case. `progress` receives a line per row.
pub fn run(config: &Config, mut progress: impl FnMut(&str)) -> Result<Vec<Row>, SimError> {
    let mut rows = collision_study(config, &mut progress)?;
    rows.extend(tray_study(config, &mut progress)?);
    if config.dense_steps > 0 {
        rows.push(dense_packing(config.dense_steps, config.cpu_time)?);
        progress(&rows.last().expect("pushed").name);
    }
    mark_front(&mut rows);
    Ok(rows)
}

/// Probe impacts of a setting, with the Hertz law replaced by `linear` if given.
fn lab_probes(scene: &Scene, s: &Setting, dt: f64, elastic: bool) -> Vec<crate::experiment::collide::Collision> {
    let (mut pair, mut wall) = scene.laws();
    if elastic {
        for law in [&mut pair, &mut wall] {
            law.normal = match law.normal {
                NormalLaw::Hertz { reduced_modulus, .. } => NormalLaw::hertz(reduced_modulus, 0.0),
                NormalLaw::Linear { kn, .. } => NormalLaw::Linear { kn, gamma_n: 0.0 },
            };
            law.tangential = TangentialLaw::None;
            law.rolling = crate::contact::RollingLaw::None;
        }
    }
    let r = scene.particles.radius_min;
    step_control::probes(
        pair,
        wall,
        r,
        scene.material().sphere_mass(r),
        tray::max_impact_speed(scene),
        dt,
        s.integrator,
    )
}

/// The collision-lab study.
fn collision_study(config: &Config, progress: &mut impl FnMut(&str)) -> Result<Vec<Row>, SimError> {
    let base = base_scene(config.tray_count, config.tray_duration);
    let t_c = tray::shortest_contact_time(&base);
    let reference = step_control::run_all(&step_control::scene_probes(&base, REFERENCE_STEPS, Integrator::VelocityVerlet))?;
    // The linear law matched to the reference's head-on pair impact.
    let r = base.particles.radius_min;
    let m_eff = 0.5 * base.material().sphere_mass(r);
    let (kn, gamma_n) = matched_linear(m_eff, reference[0].eps_n, reference[0].t_c, tray::max_impact_speed(&base));
    let thesis_steps = t_c / THESIS_DT;
    let default_steps = step_control::choose(&base, DEFAULT_RESTITUTION_TOLERANCE, base.run.steps_per_contact)?.steps_per_contact;

    let mut settings = vec![Setting::new(format!("reference: thesis dt = {THESIS_DT:e} s"), "reference").steps(thesis_steps)];
    for s in [5.0, 8.0, 10.0, 20.0, 30.0, 50.0, 100.0, 300.0] {
        settings.push(Setting::new(format!("{s} steps/contact"), "time step").steps(s));
    }
    for s in [thesis_steps, 30.0, 100.0] {
        settings.push(
            Setting::new(format!("thesis integrator, {s:.1} steps/contact"), "integrator")
                .steps(s)
                .integrator(Integrator::Thesis),
        );
    }
    for y in [3e5, 1e5] {
        settings.push(
            Setting::new(format!("Y = {y:e} Pa, {thesis_steps:.1} steps/contact"), "young")
                .set(&format!("material.young={y:e}"))
                .steps(thesis_steps),
        );
    }
    settings.push(
        Setting::new(
            format!("linear law matched at v_max, {thesis_steps:.1} steps/contact"),
            "normal law",
        )
        .set("contact.normal=\"linear\"")
        .set(&format!("contact.kn={kn:e}"))
        .set(&format!("contact.gamma_n={gamma_n:e}"))
        .steps(thesis_steps),
    );
    settings.push(
        Setting::new(
            format!("default: dt = auto, tolerance {DEFAULT_RESTITUTION_TOLERANCE:e} ({default_steps} steps/contact)"),
            "default",
        )
        .steps(default_steps),
    );

    let ref_probes = lab_probes(&base, &settings[0], setting_dt(&base, settings[0].steps)?, false);
    let mut rows = Vec::new();
    for s in &settings {
        let row = lab_row(&base, s, config, &reference, &ref_probes).unwrap_or_else(|e| failed(s, Study::Collision, e));
        rows.push(row);
        progress(&s.name);
    }
    Ok(rows)
}

/// A row for a setting the method refused or that failed while running: the error says why.
fn failed(s: &Setting, study: Study, e: SimError) -> Row {
    Row {
        name: s.name.clone(),
        study,
        axis: s.axis.into(),
        speed_ratio: f64::NAN,
        error: f64::NAN,
        wall_s: f64::NAN,
        dt: f64::NAN,
        steps_per_contact: s.steps.unwrap_or(f64::NAN),
        eps_error: None,
        energy_error: None,
        density_distance: None,
        stripes: None,
        onset_s: None,
        neighbor_builds: None,
        on_front: false,
        outcome: format!("refused: {e}"),
    }
}

/// One collision-lab row; `ref_cost` is set by the first (reference) setting.
fn lab_row(
    base: &Scene,
    s: &Setting,
    config: &Config,
    reference: &[crate::experiment::collide::CollisionResult],
    ref_probes: &[crate::experiment::collide::Collision],
) -> Result<Row, SimError> {
    {
        let scene = with(base, &s.overrides)?;
        let dt = setting_dt(&scene, s.steps)?;
        let probes = lab_probes(&scene, s, dt, false);
        // The lab's impacts last microseconds and their time is dominated by setting each
        // one up, so the speed ratio counts steps per simulated second (the wall-time ratio
        // of a long run at equal cost per step; the cost per step of each integrator and law
        // is timed in the tray rows). The lab's own time is reported as `wall_s`.
        let ref_results = step_control::run_all(ref_probes)?;
        let rate = |r: &[crate::experiment::collide::CollisionResult]| {
            r.iter().map(|x| x.steps as f64).sum::<f64>() / r.iter().map(|x| x.t_c).sum::<f64>()
        };
        let clock = Stopwatch::start(config.cpu_time);
        let mut results = step_control::run_all(&probes)?;
        let mut reps = 1;
        while clock.seconds() < config.lab_min_wall {
            results = step_control::run_all(&probes)?;
            reps += 1;
        }
        let wall = clock.seconds();
        let speed_ratio = rate(&ref_results) / rate(&results);
        let eps_error = step_control::restitution_error(&results, reference);
        let elastic = step_control::run_all(&lab_probes(&scene, s, dt, true))?;
        let energy_error = elastic
            .iter()
            .map(|r| (r.energy_after - r.energy_before).abs() / r.energy_before)
            .fold(0.0, f64::max);
        let max_overlap = results.iter().map(|r| r.max_overlap / r1_of(&scene)).fold(0.0, f64::max);
        Ok(Row {
            name: s.name.clone(),
            study: Study::Collision,
            axis: s.axis.into(),
            speed_ratio,
            error: eps_error,
            wall_s: wall / reps as f64,
            dt,
            steps_per_contact: tray::shortest_contact_time(&scene) / dt,
            eps_error: Some(eps_error),
            energy_error: Some(energy_error),
            density_distance: None,
            stripes: None,
            onset_s: None,
            neighbor_builds: None,
            on_front: false,
            outcome: format!(
                "eps_n head-on {:.4} (ref {:.4}); max overlap {:.1}% of R",
                results[0].eps_n,
                reference[0].eps_n,
                100.0 * max_overlap
            ),
        })
    }
}

fn r1_of(scene: &Scene) -> f64 {
    scene.particles.radius_min
}

/// What one tray run produced.
struct TrayRun {
    wall_s: f64,
    dt: f64,
    profiles: Vec<Vec<f64>>,
    times: Vec<f64>,
    ledger_error: f64,
    builds: u64,
    mean_phi: f64,
    mean_d: f64,
}

fn run_tray(scene: &Scene, s: &Setting, base_state: &State, steps_override: Option<f64>, cpu_time: bool) -> Result<TrayRun, SimError> {
    let mut setup = tray::setup(scene, tray::drive(scene))?;
    setup.dt = setting_dt(scene, steps_override.or(s.steps))?;
    setup.integrator = s.integrator;
    setup.neighbors = NeighborSearch::VerletList {
        skin: s.skin * scene.particles.radius_max,
    };
    let n = base_state.len();
    let order: Vec<usize> = (0..n).collect();
    let mut state = State::default();
    for &i in &order {
        let nudge = if s.perturbed && i == 0 { 1e-9 } else { 0.0 };
        state.push(
            base_state.pos[i] + crate::Vec3::new(nudge, 0.0, 0.0),
            base_state.vel[i],
            base_state.omega[i],
            base_state.radius[i],
            base_state.mass(i),
        );
    }
    let mut sim = Simulation::new(setup, state)?;
    let e0 = sim.total_energy();
    let (l, w) = (scene.tray.length, scene.tray.width);
    let cells = ((l / 1e-3).round() as usize).max(1);
    // Radii in the original order, for the profiles.
    let radius: Vec<f64> = base_state.radius.clone();
    let sample_every = 0.25 / scene.drive.frequency;
    let total = (scene.run.duration / sim.setup.dt).round() as u64;
    let (mut profiles, mut times) = (Vec::new(), Vec::new());
    let mut next = sample_every;
    let clock = Stopwatch::start(cpu_time);
    while sim.steps < total {
        sim.step()?;
        if sim.time >= next - 0.5 * sim.setup.dt {
            let mut x = vec![0.0; n];
            for (k, &i) in order.iter().enumerate() {
                x[i] = sim.state.pos[k].x;
            }
            profiles.push(area_fraction_cells(&x, &radius, l, w, cells));
            times.push(sim.time);
            next += sample_every;
        }
    }
    let wall = clock.seconds();
    let de = sim.total_energy() - e0;
    let ledger = sim.ledger.injected - sim.ledger.dissipated;
    let mean_phi = radius.iter().map(|r| std::f64::consts::PI * r * r).sum::<f64>() / (l * w);
    Ok(TrayRun {
        wall_s: wall,
        dt: sim.setup.dt,
        profiles,
        times,
        ledger_error: (de - ledger).abs() / sim.ledger.injected.abs().max(f64::MIN_POSITIVE),
        builds: sim.neighbor_builds(),
        mean_phi,
        mean_d: 2.0 * radius.iter().sum::<f64>() / n as f64,
    })
}

/// Mean over common sample times of `mean_x |phi - phi_ref| / <phi>`.
pub fn density_distance(a: &[Vec<f64>], b: &[Vec<f64>], mean_phi: f64) -> f64 {
    let k = a.len().min(b.len());
    if k == 0 {
        return f64::NAN;
    }
    let per_frame = |p: &Vec<f64>, q: &Vec<f64>| p.iter().zip(q).map(|(x, y)| (x - y).abs()).sum::<f64>() / p.len() as f64;
    (0..k).map(|f| per_frame(&a[f], &b[f])).sum::<f64>() / k as f64 / mean_phi
}

/// The tray study.
fn tray_study(config: &Config, progress: &mut impl FnMut(&str)) -> Result<Vec<Row>, SimError> {
    let base = base_scene(config.tray_count, config.tray_duration);
    let state = initial_state(&base);
    let thesis_steps = tray::shortest_contact_time(&base) / THESIS_DT;
    let auto = with(&base, &["run.dt=\"auto\"".into()])?;
    let default_dt = tray::time_step(&auto)?;
    let default_steps = tray::shortest_contact_time(&base) / default_dt;
    // Linear law matched as in the lab.
    let reference_lab = step_control::run_all(&step_control::scene_probes(&base, REFERENCE_STEPS, Integrator::VelocityVerlet))?;
    let r = base.particles.radius_min;
    let (kn, gamma_n) = matched_linear(
        0.5 * base.material().sphere_mass(r),
        reference_lab[0].eps_n,
        reference_lab[0].t_c,
        tray::max_impact_speed(&base),
    );

    let converged = run_tray(
        &base,
        &Setting::new("converged", "reference"),
        &state,
        Some(config.reference_steps),
        config.cpu_time,
    )?;
    progress(&format!("converged tray reference ({} steps/contact)", config.reference_steps));

    let mut settings = vec![Setting::new(format!("reference: thesis dt = {THESIS_DT:e} s"), "reference").steps(thesis_steps)];
    let mut floor = Setting::new("noise floor: reference with one grain moved by 1 nm", "noise floor").steps(thesis_steps);
    floor.perturbed = true;
    settings.push(floor);
    for s in [8.0, 20.0, 30.0] {
        settings.push(Setting::new(format!("{s} steps/contact"), "time step").steps(s));
    }
    settings.push(
        Setting::new(format!("thesis integrator, {thesis_steps:.1} steps/contact"), "integrator")
            .steps(thesis_steps)
            .integrator(Integrator::Thesis),
    );
    for y in [3e5, 1e5] {
        settings.push(
            Setting::new(format!("Y = {y:e} Pa, {thesis_steps:.1} steps/contact"), "young")
                .set(&format!("material.young={y:e}"))
                .steps(thesis_steps),
        );
    }
    settings.push(
        Setting::new("pinned 2D (jumping off)", "dimension")
            .set("toggles.jumping=false")
            .steps(thesis_steps),
    );
    settings.push(
        Setting::new(
            format!("linear law matched at v_max, {thesis_steps:.1} steps/contact"),
            "normal law",
        )
        .set("contact.normal=\"linear\"")
        .set(&format!("contact.kn={kn:e}"))
        .set(&format!("contact.gamma_n={gamma_n:e}"))
        .steps(thesis_steps),
    );
    for k in [0.0, 0.1, 0.2, 1.0, 2.0] {
        let name = if k == 0.0 {
            "skin 0: rebuild every step".to_string()
        } else {
            format!("skin {k} R_max (rebuild at skin/2)")
        };
        settings.push(Setting::new(name, "neighbour list").steps(thesis_steps).skin(k));
    }
    settings.push(
        Setting::new(
            format!("default: dt = auto, tolerance {DEFAULT_RESTITUTION_TOLERANCE:e} ({default_steps:.1} steps/contact)"),
            "default",
        )
        .steps(default_steps),
    );

    let mut rows = Vec::new();
    let reference = (settings[0].clone(), run_tray(&base, &settings[0], &state, None, config.cpu_time)?);
    for s in &settings {
        let row = tray_row(&base, s, config, &state, &converged, &reference).unwrap_or_else(|e| failed(s, Study::Tray, e));
        rows.push(row);
        progress(&s.name);
    }
    Ok(rows)
}

/// One tray row; `reference` (wall time and profiles) is set by the first (reference)
/// setting. The noise-floor row is compared with the reference run, every other row with
/// the converged run.
fn tray_row(
    base: &Scene,
    s: &Setting,
    config: &Config,
    state: &State,
    converged: &TrayRun,
    reference: &(Setting, TrayRun),
) -> Result<Row, SimError> {
    {
        let scene = with(base, &s.overrides)?;
        let (ref_setting, ref_run) = reference;
        let ref_scene = with(base, &ref_setting.overrides)?;
        // Timing in pairs (reference, setting), run back to back so that both see the same
        // load; the median of the pair ratios counts.
        let mut run = run_tray(&scene, s, state, None, config.cpu_time)?;
        let mut ratios = Vec::new();
        for k in 0..config.tray_repeats.max(1) {
            let r = run_tray(&ref_scene, ref_setting, state, None, config.cpu_time)?;
            if k > 0 {
                let again = run_tray(&scene, s, state, None, config.cpu_time)?;
                run.wall_s = again.wall_s;
            }
            ratios.push(r.wall_s / run.wall_s);
        }
        ratios.sort_by(f64::total_cmp);
        let speed_ratio = if ratios.len() % 2 == 1 {
            ratios[ratios.len() / 2]
        } else {
            0.5 * (ratios[ratios.len() / 2 - 1] + ratios[ratios.len() / 2])
        };
        let ref_profiles = &ref_run.profiles;
        let params = StripeParams::default_for(run.mean_phi, run.mean_d);
        let counts: Vec<usize> = run.profiles.iter().map(|p| detect(p, scene.tray.length, &params).len()).collect();
        let against = if s.axis == "noise floor" {
            ref_profiles
        } else {
            &converged.profiles
        };
        let distance = density_distance(&run.profiles, against, run.mean_phi);
        let stripes = counts.last().copied();
        let onset_s = onset(&run.times, &counts);
        Ok(Row {
            name: s.name.clone(),
            study: Study::Tray,
            axis: s.axis.into(),
            // The reference is 1 by definition; its timed self-ratio (the timing noise) is
            // in the outcome.
            speed_ratio: if s.axis == "reference" { 1.0 } else { speed_ratio },
            error: distance,
            wall_s: run.wall_s,
            dt: run.dt,
            steps_per_contact: tray::shortest_contact_time(&scene) / run.dt,
            eps_error: None,
            energy_error: Some(run.ledger_error),
            density_distance: Some(distance),
            stripes,
            onset_s,
            neighbor_builds: Some(run.builds),
            on_front: false,
            outcome: format!(
                "{} samples; stripes at the end {} (converged run: {}); timed reference/setting ratio {:.2}; {} neighbour builds",
                run.times.len(),
                stripes.unwrap_or(0),
                converged
                    .profiles
                    .last()
                    .map(|p| detect(p, base.tray.length, &params).len())
                    .unwrap_or(0),
                speed_ratio,
                run.builds
            ),
        })
    }
}

/// Dense packing (hard case): 8000 grains at area fraction 0.46 in the thesis tray (0.4 m x
/// 0.02 m), started on the lattice (two layers), shaken for `steps` steps at the thesis dt.
/// `speed_ratio` is its throughput (particle-steps per second) relative to 4000 grains at
/// the thesis packing measured in the same call; `error` is the energy-ledger error.
pub fn dense_packing(steps: u64, cpu_time: bool) -> Result<Row, SimError> {
    let throughput = |count: usize| -> Result<(f64, Simulation), SimError> {
        let scene = with(&base_scene(4000, 1.0), &[format!("particles.count={count}")])?;
        let setup = tray::setup(&scene, tray::drive(&scene))?;
        let mut sim = Simulation::new(setup, initial_state(&scene))?;
        let t0 = Stopwatch::start(cpu_time);
        for _ in 0..steps {
            sim.step()?;
        }
        Ok((steps as f64 * count as f64 / t0.seconds(), sim))
    };
    let (base_rate, _) = throughput(4000)?;
    let e_start = {
        let scene = with(&base_scene(4000, 1.0), &["particles.count=8000".into()])?;
        let setup = tray::setup(&scene, tray::drive(&scene))?;
        Simulation::new(setup, initial_state(&scene))?.total_energy()
    };
    let (rate, sim) = throughput(8000)?;
    let packing = with(&base_scene(4000, 1.0), &["particles.count=8000".into()])?.packing();
    let ledger = sim.ledger.injected - sim.ledger.dissipated;
    let error = ((sim.total_energy() - e_start) - ledger).abs() / sim.ledger.injected.abs().max(f64::MIN_POSITIVE);
    Ok(Row {
        name: format!("dense packing: 8000 grains, area fraction {packing:.2}, {steps} steps"),
        study: Study::HardCase,
        axis: "hard case".into(),
        speed_ratio: rate / base_rate,
        error,
        wall_s: steps as f64 * 8000.0 / rate,
        dt: sim.setup.dt,
        steps_per_contact: f64::NAN,
        eps_error: None,
        energy_error: Some(error),
        density_distance: None,
        stripes: None,
        onset_s: None,
        neighbor_builds: Some(sim.neighbor_builds()),
        on_front: false,
        outcome: format!(
            "ran without error: {:.2e} particle-steps/s (4000 grains: {:.2e}); {} pair and {} wall contacts at the end; speed_ratio is the throughput ratio, error the energy-ledger error",
            rate, base_rate, sim.contacts.0, sim.contacts.1
        ),
    })
}

/// The rows as a Markdown table.
pub fn markdown_table(rows: &[Row]) -> String {
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2e}"));
    let mut out = String::from(
        "| study | setting | dt (s) | steps/contact | speed ratio | error | eps error | energy error | density distance | stripes | onset (s) | front |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let study = match r.study {
            Study::Collision => "lab",
            Study::Tray => "tray",
            Study::HardCase => "hard case",
        };
        out.push_str(&format!(
            "| {study} | {} | {:.2e} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.name,
            r.dt,
            if r.steps_per_contact.is_finite() {
                format!("{:.1}", r.steps_per_contact)
            } else {
                "-".into()
            },
            r.speed_ratio,
            if r.error == 0.0 {
                "0 (bit-identical)".to_string()
            } else if r.error.is_nan() {
                "refused, see below".to_string()
            } else {
                format!("{:.2e}", r.error)
            },
            opt(r.eps_error),
            opt(r.energy_error),
            opt(r.density_distance),
            r.stripes.map_or("-".into(), |s| s.to_string()),
            r.onset_s.map_or("-".into(), |t| format!("{t:.3}")),
            if r.on_front { "yes" } else { "" }
        ));
    }
    let notes: Vec<&Row> = rows
        .iter()
        .filter(|r| r.error.is_nan() || r.study == Study::HardCase || r.axis == "default")
        .collect();
    if !notes.is_empty() {
        out.push_str("\nOutcomes:\n\n");
        for r in notes {
            out.push_str(&format!("- {}: {}\n", r.name, r.outcome));
        }
    }
    out.replace("| NaN |", "| - |")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(study: Study, speed: f64, error: f64) -> Row {
        Row {
            name: format!("{speed} {error}"),
            study,
            axis: "time step".into(),
            speed_ratio: speed,
            error,
            wall_s: 1.0,
            dt: 1.0,
            steps_per_contact: 1.0,
            eps_error: None,
            energy_error: None,
            density_distance: None,
            stripes: None,
            onset_s: None,
            neighbor_builds: None,
            on_front: false,
            outcome: String::new(),
        }
    }

    #[test]
    fn the_front_keeps_exactly_the_undominated_rows_per_study() {
        let mut rows = vec![
            row(Study::Collision, 1.0, 1e-3),
            row(Study::Collision, 2.0, 1e-2),
            row(Study::Collision, 0.5, 1e-2), // dominated by the first
            row(Study::Collision, 2.0, 1e-1), // dominated by the second
            row(Study::Tray, 0.1, 1.0),       // alone in its study
        ];
        mark_front(&mut rows);
        let front: Vec<bool> = rows.iter().map(|r| r.on_front).collect();
        assert_eq!(front, vec![true, true, false, false, true]);
    }

    #[test]
    fn matched_linear_law_reproduces_restitution_and_contact_time() {
        let (m, eps, tc, v) = (8e-8, 0.83, 1e-4, 3.0);
        let (k, g) = matched_linear(m, eps, tc, v);
        let (tc2, eps2) = linear_dashpot(m, k, g, v);
        assert!((eps2 - eps).abs() < 1e-12, "{eps2}");
        assert!((tc2 - tc).abs() < 1e-12 * tc, "{tc2}");
    }

    #[test]
    fn identical_profiles_have_zero_distance() {
        let a = vec![vec![0.2, 0.3, 0.1]; 3];
        assert_eq!(density_distance(&a, &a, 0.2), 0.0);
        let mut b = a.clone();
        b[1][0] = 0.5;
        assert!((density_distance(&a, &b, 0.2) - 0.3 / 3.0 / 3.0 / 0.2).abs() < 1e-15);
    }
}
