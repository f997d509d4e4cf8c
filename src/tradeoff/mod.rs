//! Speed against error: every choice that trades accuracy for speed, measured on the collision
//! lab and on a small shaken tray, against a converged reference computed in the same run.
//!
//! What varies: steps per contact (the time step), Young's modulus (softer contacts last
//! longer, so the same steps per contact give a larger step), the integrator (velocity Verlet
//! or the thesis' scheme), 3D against pinned 2D (tray), a cheaper normal law (a linear
//! spring-dashpot matched to the Hertz law's restitution and contact time: no square roots),
//! the neighbour skin and the rebuild policy (skin 0: rebuild every step), and the defaults
//! (`dt = "auto"` at the default restitution tolerance, see [`particles::experiment::step_control`]).
//!
//! What is measured, per setting:
//! - `speed_ratio`: time of the reference setting divided by the setting's, both measured
//!   here, for the same simulated time. With one worker thread the times are the on-CPU
//!   times of that thread ([`Stopwatch`]), which is the wall time on an idle core. The lab's
//!   impacts last microseconds and their time is dominated by setting each one up, so its
//!   speed ratio counts steps per simulated second of contact instead (the wall-time ratio
//!   of a long run at equal cost per step; the tray rows time the cost per step);
//! - collision lab: `error` is the restitution error, the largest `|d eps_n|`, `|d eps_t|`
//!   over the probe impacts of [`particles::experiment::step_control`] against velocity Verlet at
//!   [`particles::experiment::step_control::REFERENCE_STEPS`] steps per contact with the reference material;
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
//! 1 nm, compared with the reference itself). Settings that do not change a single bit (the
//! neighbour skin and rebuild policy) have exactly the reference's error.

mod friction;
mod lab;
mod shaken;

pub use crate::clock::Stopwatch;
pub use friction::{friction_law_keys, friction_laws, friction_table};
pub use lab::matched_linear;
pub use shaken::dense_packing;

use serde::Serialize;

use particles::integrate::Integrator;
use particles::scene::Scene;
use particles::scene::DEFAULT_RESTITUTION_TOLERANCE;
use particles::time_step;
use particles::timescale;
use particles::SimError;

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
            tray_duration: 0.15,
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
    let scene = crate::scene_text::parse_scene(&text, &[], "bench").expect("the bench scene parses");
    scene.validate().expect("the bench scene is valid");
    scene
}

pub(crate) fn with(scene: &Scene, overrides: &[String]) -> Result<Scene, SimError> {
    let text = toml::to_string(scene).expect("a scene serialises");
    let s = crate::scene_text::parse_scene(&text, overrides, "bench").map_err(|e| SimError::InvalidParameter {
        field: e.key.clone(),
        message: e.message,
    })?;
    s.validate().map_err(|e| SimError::InvalidParameter {
        field: e.key,
        message: e.message,
    })?;
    Ok(s)
}

/// A setting: scene overrides, integrator, steps per contact (of the setting's own
/// material), and a fixed neighbour skin as a multiple of the largest radius, or none: the
/// tray's own list, whose skin adapts as in every run of `stripes run`.
#[derive(Clone, Debug)]
pub(crate) struct Setting {
    name: String,
    axis: &'static str,
    overrides: Vec<String>,
    integrator: Integrator,
    steps: Option<f64>,
    skin: Option<f64>,
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
            skin: None,
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
        self.skin = Some(k);
        self
    }

    /// The settings both studies share, in table order: the thesis step as reference, the
    /// softer materials and the matched linear law (`kn`, `gamma_n`) at the thesis' steps per
    /// contact. The default (error-controlled dt) is [`Setting::default_step`].
    fn reference(thesis_steps: f64) -> Self {
        Setting::new(format!("reference: thesis dt = {THESIS_DT:e} s"), "reference").steps(thesis_steps)
    }
    fn softer(thesis_steps: f64) -> Vec<Self> {
        [3e5, 1e5]
            .iter()
            .map(|y| {
                Setting::new(format!("Y = {y:e} Pa, {thesis_steps:.1} steps/contact"), "young")
                    .set(&format!("material.young={y:e}"))
                    .steps(thesis_steps)
            })
            .collect()
    }
    fn matched_linear(kn: f64, gamma_n: f64, thesis_steps: f64) -> Self {
        Setting::new(
            format!("linear law matched at v_max, {thesis_steps:.1} steps/contact"),
            "normal law",
        )
        .set("contact.normal=\"linear\"")
        .set(&format!("contact.kn={kn:e}"))
        .set(&format!("contact.gamma_n={gamma_n:e}"))
        .steps(thesis_steps)
    }
    fn default_step(default_steps: f64) -> Self {
        Setting::new(
            format!("default: dt = auto, tolerance {DEFAULT_RESTITUTION_TOLERANCE:e} ({default_steps:.1} steps/contact)"),
            "default",
        )
        .steps(default_steps)
    }
}

/// The time step of a setting's scene: its steps per contact, or the scene's own step.
pub(crate) fn setting_dt(scene: &Scene, steps: Option<f64>) -> Result<f64, SimError> {
    match steps {
        Some(s) => Ok(timescale::shortest_contact_time(scene)? / s),
        None => time_step::for_scene(scene),
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
    let mut rows = lab::collision_study(config, &mut progress)?;
    rows.extend(shaken::tray_study(config, &mut progress)?);
    if config.dense_steps > 0 {
        rows.push(dense_packing(config.dense_steps, config.cpu_time)?);
        progress(&rows.last().expect("pushed").name);
    }
    mark_front(&mut rows);
    Ok(rows)
}

/// A row for a setting the method refused or that failed while running: the error says why.
pub(crate) fn failed(s: &Setting, study: Study, e: SimError) -> Row {
    Row {
        steps_per_contact: s.steps.unwrap_or(f64::NAN),
        outcome: format!("refused: {e}"),
        ..Row::blank(s.name.clone(), study, s.axis)
    }
}

impl Row {
    /// A row that measured nothing yet: numbers NaN, optional measures absent, off the front.
    pub(crate) fn blank(name: String, study: Study, axis: &str) -> Row {
        Row {
            name,
            study,
            axis: axis.into(),
            speed_ratio: f64::NAN,
            error: f64::NAN,
            wall_s: f64::NAN,
            dt: f64::NAN,
            steps_per_contact: f64::NAN,
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
    use particles::experiment::closed_form::linear_dashpot;

    fn row(study: Study, speed: f64, error: f64) -> Row {
        Row {
            speed_ratio: speed,
            error,
            wall_s: 1.0,
            dt: 1.0,
            steps_per_contact: 1.0,
            ..Row::blank(format!("{speed} {error}"), study, "time step")
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
        use super::shaken::density_distance;
        let a = vec![vec![0.2, 0.3, 0.1]; 3];
        assert_eq!(density_distance(&a, &a, 0.2), 0.0);
        let mut b = a.clone();
        b[1][0] = 0.5;
        assert!((density_distance(&a, &b, 0.2) - 0.3 / 3.0 / 3.0 / 0.2).abs() < 1e-15);
    }
}
