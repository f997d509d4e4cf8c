//! What the studies share: the bench's scene and its typed edits, a setting of the study,
//! and the rows and sizes of the tables.

use serde::Serialize;

use particles::contact::choice::NormalKind;
use particles::integrate::Integrator;
use particles::scene::{Scene, TimeStep, DEFAULT_RESTITUTION_TOLERANCE};
use particles::time_step;
use particles::timescale;
use particles::SimError;

use crate::scene::edit::DemEdit;

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
    /// Time with the on-CPU time of the worker thread ([`crate::host::clock::Stopwatch`]) instead of wall time:
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

/// The base scene of both studies: the thesis' literal scene (`scenes/thesis-reference.toml`:
/// material and laws of Table 3.3, a 2 cm wide tray shaken at 20 Hz and 25 mm) with `count`
/// grains in `count / 10000` m of length (packing 0.23), run for `duration` at the thesis' step.
pub fn base_scene(count: usize, duration: f64) -> Scene {
    let mut scene = crate::scene::text::parse_scene(THESIS_SCENE, &[], "bench").expect("the bench scene parses");
    scene.tray.length = count as f64 / 1e4;
    scene.particles.count = count;
    scene.run.duration = duration;
    scene.run.dt = TimeStep::Seconds(THESIS_DT);
    scene.validate().expect("the bench scene is valid");
    scene
}

/// The thesis' literal scene, of which the bench keeps the material, laws and drive.
const THESIS_SCENE: &str = include_str!("../../../scenes/thesis-reference.toml");

/// `scene` with `edits` applied, checked.
pub(crate) fn with(scene: &Scene, edits: &[DemEdit]) -> Result<Scene, SimError> {
    let mut s = scene.clone();
    for e in edits {
        e.apply(&mut s);
    }
    s.validate().map_err(|e| SimError::InvalidParameter {
        field: e.key,
        message: e.message,
    })?;
    Ok(s)
}

/// A setting: scene edits, integrator, steps per contact (of the setting's own
/// material), and a fixed neighbour skin as a multiple of the largest radius, or none: the
/// tray's own list, whose skin adapts as in every run of `stripes run`.
#[derive(Clone, Debug)]
pub(crate) struct Setting {
    pub(crate) name: String,
    pub(crate) axis: &'static str,
    pub(crate) edits: Vec<DemEdit>,
    pub(crate) integrator: Integrator,
    pub(crate) steps: Option<f64>,
    pub(crate) skin: Option<f64>,
    /// Move grain 0 by 1 nm along x (noise-floor probe).
    pub(crate) perturbed: bool,
}

impl Setting {
    pub(crate) fn new(name: impl Into<String>, axis: &'static str) -> Self {
        Self {
            name: name.into(),
            axis,
            edits: Vec::new(),
            integrator: Integrator::VelocityVerlet,
            steps: None,
            skin: None,
            perturbed: false,
        }
    }
    pub(crate) fn edit(mut self, e: DemEdit) -> Self {
        self.edits.push(e);
        self
    }
    pub(crate) fn steps(mut self, s: f64) -> Self {
        self.steps = Some(s);
        self
    }
    pub(crate) fn integrator(mut self, i: Integrator) -> Self {
        self.integrator = i;
        self
    }
    pub(crate) fn skin(mut self, k: f64) -> Self {
        self.skin = Some(k);
        self
    }

    /// The settings both studies share, in table order: the thesis step as reference, the
    /// softer materials and the matched linear law (`kn`, `gamma_n`) at the thesis' steps per
    /// contact. The default (error-controlled dt) is [`Setting::default_step`].
    pub(crate) fn reference(thesis_steps: f64) -> Self {
        Setting::new(format!("reference: thesis dt = {THESIS_DT:e} s"), "reference").steps(thesis_steps)
    }
    pub(crate) fn softer(thesis_steps: f64) -> Vec<Self> {
        [3e5, 1e5]
            .iter()
            .map(|y| {
                Setting::new(format!("Y = {y:e} Pa, {thesis_steps:.1} steps/contact"), "young")
                    .edit(DemEdit::Young(*y))
                    .steps(thesis_steps)
            })
            .collect()
    }
    pub(crate) fn matched_linear(kn: f64, gamma_n: f64, thesis_steps: f64) -> Self {
        Setting::new(
            format!("linear law matched at v_max, {thesis_steps:.1} steps/contact"),
            "normal law",
        )
        .edit(DemEdit::Normal(NormalKind::Linear))
        .edit(DemEdit::Kn(kn))
        .edit(DemEdit::GammaN(gamma_n))
        .steps(thesis_steps)
    }
    pub(crate) fn default_step(default_steps: f64) -> Self {
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
