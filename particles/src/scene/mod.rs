//! Scenes: the complete description of a shaken-tray run, as typed tables.
//!
//! Every key has a documented unit and a default written once (the `Default` impls below and
//! the `run` constants); unknown keys are errors. The types derive serde and mirror the
//! tables of a scene file; this crate reads no text: the root crate parses scene files and
//! their `--set dotted.key=value` overrides. [`Scene::validate`] checks every value and names
//! the offending key in its error; [`Scene::laws`] builds the contact laws whole. Every key is
//! listed in `docs/scenes.md` (a test keeps the two in step).

mod run;

pub use run::{
    AutoDt, NoSort, Run, SortInterval, TimeStep, DEFAULT_CHECKPOINT_INTERVAL, DEFAULT_RESTITUTION_TOLERANCE, DEFAULT_SORT_INTERVAL,
    DEFAULT_STEPS_PER_CONTACT,
};

use serde::{Deserialize, Serialize};

use crate::contact::choice::{LawChoice, LawParameters, Missing, NormalKind, RollingKind, TangentialKind};
use crate::contact::{ContactLaw, RollingLaw, TangentialLaw};
use crate::material::{mix, Material};

/// The ChaCha stream of the per-grain rolling coefficients ([`Scene::rolling_mu`]).
const ROLLING_MU_STREAM: u64 = 0x726f_6c6c; // "roll"

/// A scene. Sections mirror the tables of a scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(rename = "box")]
    pub tray: TrayBox,
    pub drive: Drive,
    pub particles: Particles,
    /// `[material]`: grains and walls (the thesis uses one material for both, Table 3.3).
    #[serde(default)]
    pub material: Material,
    #[serde(default)]
    pub contact: ContactSpec,
    #[serde(default)]
    pub toggles: Toggles,
    #[serde(default)]
    pub prepare: Prepare,
    pub run: Run,
}

/// `[box]`: the tray. x is periodic (or closed by end walls with `box.x_walls = true`); y has
/// side walls (or is periodic with `toggles.walls = false`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrayBox {
    /// Length along x (m), the horizontal shaking direction: periodic, or between the end
    /// walls of `x_walls`.
    pub length: f64,
    /// Width across, y (m).
    pub width: f64,
    /// Optional ceiling (m) for the escape check: a grain above it stops the run. Absent by
    /// default: the thesis' box is 0.1 m high but "open in positive direction" (sec 3.5.3),
    /// so a grain thrown higher simply falls back. The floor and the side walls always
    /// confine: a grain below the floor or outside the walls has escaped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Flat walls at x = 0 and x = length in place of the periodic seam (the vibrated box's
    /// fixed sides). Off by default (periodic x); left out of the serialised scene when off,
    /// so that the sample keys of the tray scenes still hold.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub x_walls: bool,
}

/// `drive.direction`: the axis along which the floor moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum DriveDirection {
    /// Horizontal, along x: the shaken tray (thesis 3.5). The floor and every wall move with it.
    #[default]
    X,
    /// Vertical, along z: the vibrated box. Only the floor moves, `z_f(t) = A sin(2 pi f t)`;
    /// the side and end walls stay fixed.
    Z,
}

impl DriveDirection {
    /// The names in scene files.
    pub const NAMES: &'static [&'static str] = &["x", "z"];

    /// The unit vector of the motion.
    pub fn unit(self) -> crate::Vec3 {
        match self {
            DriveDirection::X => crate::Vec3::x(),
            DriveDirection::Z => crate::Vec3::z(),
        }
    }

    fn is_x(&self) -> bool {
        *self == DriveDirection::X
    }
}

impl TryFrom<String> for DriveDirection {
    type Error = crate::error::UnknownName;
    fn try_from(s: String) -> Result<Self, Self::Error> {
        match s.as_str() {
            "x" => Ok(DriveDirection::X),
            "z" => Ok(DriveDirection::Z),
            _ => Err(crate::error::UnknownName {
                what: "drive.direction (x: the horizontally shaken tray, z: a vertically vibrated floor)",
                given: s,
                expected: &["x", "z"],
            }),
        }
    }
}

impl From<DriveDirection> for String {
    fn from(d: DriveDirection) -> String {
        match d {
            DriveDirection::X => "x",
            DriveDirection::Z => "z",
        }
        .into()
    }
}

/// `[drive]`: tray motion `x_tray(t) = amplitude sin(2 pi frequency t)` along `direction`,
/// or a schedule of such stages, `[[drive.stages]]` ([`crate::drive`]).
///
/// In a scene file, either `frequency` and `amplitude` (one stage for the whole run) or
/// `stages`. With stages, `frequency` and `amplitude` are the last stage's (filled in when
/// left out, and checked against it when given): the drive whose period the analysis uses.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "DriveFile", into = "DriveFile")]
pub struct Drive {
    /// Hz (with stages: the last stage's).
    pub frequency: f64,
    /// m (with stages: the last stage's).
    pub amplitude: f64,
    /// `"x"` (default: the horizontally shaken tray) or `"z"` (a vertically vibrated floor).
    /// Left out of the serialised scene when `"x"`, so that the tray scenes' sample keys hold.
    pub direction: DriveDirection,
    /// The schedule, stage after stage from t = 0 (empty: one stage, `frequency` and
    /// `amplitude`, for the whole run). Left out of the serialised scene when empty.
    pub stages: Vec<DriveStage>,
}

/// `[[drive.stages]]`: one stage of a drive schedule. Each starts at a zero crossing of the
/// tray, where the one before it ended ([`crate::drive`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveStage {
    /// Hz.
    pub frequency: f64,
    /// m.
    pub amplitude: f64,
    /// s: a whole number of periods, except for the last stage.
    pub duration: f64,
}

/// `[drive]` as written in a scene file (see [`Drive`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DriveFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    frequency: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    amplitude: Option<f64>,
    #[serde(default, skip_serializing_if = "DriveDirection::is_x")]
    direction: DriveDirection,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    stages: Vec<DriveStage>,
}

impl TryFrom<DriveFile> for Drive {
    type Error = String;
    fn try_from(f: DriveFile) -> Result<Self, String> {
        let missing = |key: &str, unit: &str| {
            format!("missing field `{key}` (drive.{key}, {unit}; or a schedule of [[drive.stages]] with frequency, amplitude and duration)")
        };
        let last = f.stages.last();
        Ok(Drive {
            frequency: f
                .frequency
                .or(last.map(|s| s.frequency))
                .ok_or_else(|| missing("frequency", "Hz"))?,
            amplitude: f.amplitude.or(last.map(|s| s.amplitude)).ok_or_else(|| missing("amplitude", "m"))?,
            direction: f.direction,
            stages: f.stages,
        })
    }
}

impl From<Drive> for DriveFile {
    fn from(d: Drive) -> Self {
        DriveFile {
            frequency: Some(d.frequency),
            amplitude: Some(d.amplitude),
            direction: d.direction,
            stages: d.stages,
        }
    }
}

impl Drive {
    /// The schedule of a drive with stages, `None` for the single stage.
    pub fn schedule(&self) -> Option<crate::drive::Schedule> {
        let stages: Vec<(f64, f64, f64)> = self.stages.iter().map(|s| (s.frequency, s.amplitude, s.duration)).collect();
        crate::drive::Schedule::new(&stages)
    }

    /// The stages as `(start (s), frequency (Hz), amplitude (m))`: one starting at 0 for the
    /// single drive.
    pub fn stage_starts(&self) -> Vec<(f64, f64, f64)> {
        match self.schedule() {
            Some(s) => s.stages().iter().map(|s| (s.start, s.frequency, s.amplitude)).collect(),
            None => vec![(0.0, self.frequency, self.amplitude)],
        }
    }

    /// Total duration of the schedule (s), `None` for the single drive (which lasts the run).
    pub fn schedule_duration(&self) -> Option<f64> {
        (!self.stages.is_empty()).then(|| self.stages.iter().map(|s| s.duration).sum())
    }

    /// Peak speed of the tray `2 pi nu A` (m/s): the fastest stage's.
    pub fn peak_speed(&self) -> f64 {
        if self.stages.is_empty() {
            return 2.0 * std::f64::consts::PI * self.frequency * self.amplitude;
        }
        self.stages
            .iter()
            .map(|s| 2.0 * std::f64::consts::PI * s.frequency * s.amplitude)
            .fold(0.0, f64::max)
    }

    /// Highest frequency of any stage (Hz): the one whose snapshots come closest together.
    pub fn highest_frequency(&self) -> f64 {
        self.stages.iter().map(|s| s.frequency).fold(self.frequency, f64::max)
    }

    /// Checks the schedule: each stage's frequency, amplitude and duration positive, every
    /// stage but the last a whole number of its periods (so that it ends at a zero crossing,
    /// where the next one starts), and `drive.frequency` / `drive.amplitude`, when given, the
    /// last stage's. Stages carry no start times (each starts where the one before ends), so
    /// they can neither overlap nor leave gaps.
    fn validate_stages(&self) -> Result<(), SceneError> {
        let n = self.stages.len();
        for (i, s) in self.stages.iter().enumerate() {
            let key = |k: &str| format!("drive.stages[{i}].{k}");
            for (k, x, unit) in [
                ("frequency", s.frequency, "Hz"),
                ("amplitude", s.amplitude, "m"),
                ("duration", s.duration, "s"),
            ] {
                if !(x.is_finite() && x > 0.0) {
                    return Err(err(&key(k), format!("must be a positive number ({unit}), got {x}")));
                }
            }
            let periods = s.duration * s.frequency;
            if i + 1 < n && (periods - periods.round()).abs() > 1e-9 * periods.max(1.0) {
                return Err(err(
                    &key("duration"),
                    format!(
                        "must be a whole number of the stage's periods ({} s at {} Hz), so that the stage ends at a zero \
                         crossing of the tray where the next one starts; got {} s = {periods} periods",
                        1.0 / s.frequency,
                        s.frequency,
                        s.duration
                    ),
                ));
            }
        }
        if let Some(last) = self.stages.last() {
            for (k, given, wanted) in [
                ("frequency", self.frequency, last.frequency),
                ("amplitude", self.amplitude, last.amplitude),
            ] {
                if given != wanted {
                    return Err(err(
                        &format!("drive.{k}"),
                        format!(
                            "with [[drive.stages]], drive.{k} is the last stage's ({wanted}); got {given}: leave it out, \
                             or change drive.stages[{}].{k}",
                            n - 1
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `[particles]`: the population, radii uniform in `[radius_min, radius_max]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Particles {
    /// Number of grains (with clumps: of clumps, each of `clump_spheres` spheres).
    pub count: usize,
    /// m (with clumps: the radius of a clump's spheres, one per grain).
    pub radius_min: f64,
    /// m.
    pub radius_max: f64,
    /// `"sphere"` (default) or `"clump"`: grains with flat sides, rigid clumps of
    /// `clump_spheres` overlapping spheres ([`crate::clump`]). The shape keys are left out of
    /// the serialised scene for spheres, so that sample keys and checkpoint fingerprints of
    /// sphere scenes still hold.
    #[serde(default, skip_serializing_if = "Shape::is_sphere")]
    pub shape: Shape,
    /// Clumps: 2 (a dimer) or 3 (an equilateral triangle); needed by `shape = "clump"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clump_spheres: Option<usize>,
    /// Clumps: distance between neighbouring sphere centres over their radius, in (0, 2)
    /// (below 2 the spheres overlap); needed by `shape = "clump"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clump_spacing: Option<f64>,
}

/// `particles.shape`: what a grain is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Shape {
    /// One sphere.
    #[default]
    Sphere,
    /// A rigid clump of overlapping spheres (`particles.clump_spheres`, `particles.clump_spacing`).
    Clump,
}

impl Shape {
    fn is_sphere(&self) -> bool {
        *self == Shape::Sphere
    }
}

impl TryFrom<String> for Shape {
    type Error = crate::error::UnknownName;
    fn try_from(s: String) -> Result<Self, Self::Error> {
        match s.as_str() {
            "sphere" => Ok(Shape::Sphere),
            "clump" => Ok(Shape::Clump),
            _ => Err(crate::error::UnknownName {
                what: "particles.shape (sphere, or clump: rigid overlapping spheres)",
                given: s,
                expected: &["sphere", "clump"],
            }),
        }
    }
}

impl From<Shape> for String {
    fn from(s: Shape) -> String {
        match s {
            Shape::Sphere => "sphere",
            Shape::Clump => "clump",
        }
        .into()
    }
}

/// `[contact]`: one slot per sub-model, and their parameters (Table 3.3). Particle pairs and
/// particle-wall contacts use the same slots; only the Coulomb coefficient differs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSpec {
    pub normal: NormalKind,
    pub tangential: TangentialKind,
    pub rolling: RollingKind,
    /// Linear law: stiffness k_n (N/m), needed by `normal = "linear"`.
    pub kn: Option<f64>,
    /// Linear law: damping gamma_n (kg/s); absent: 0.
    pub gamma_n: Option<f64>,
    /// Coulomb coefficient between particles; `inf` for no Coulomb cap.
    pub friction: f64,
    /// Coulomb coefficient between particles and walls (floor and sides); `inf` for no
    /// Coulomb cap (with Haff-Werner: the viscous branch alone, the thesis-like floor).
    pub wall_friction: f64,
    /// Haff-Werner tangential damping gamma_t (N s/m).
    pub tangential_damping: f64,
    /// Cundall-Strack tangential stiffness k_t (N/m), needed by `tangential = "cundall-strack"`.
    pub tangential_stiffness: Option<f64>,
    /// Brilliantov-Pöschel rolling friction mu_r (s).
    pub rolling_friction: f64,
    /// Spring-dashpot-slider (`rolling = "sds"`): the rolling resistance mu_r
    /// (dimensionless), the mean of the grains' values; needed by `rolling = "sds"`. A grain
    /// at rest holds on an incline up to `tan(theta) = mu_r`. (This key and the three below
    /// are left out of the serialised scene at their defaults, so that sample keys and
    /// checkpoint fingerprints of older scenes still hold.)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rolling_resistance: Option<f64>,
    /// Spring-dashpot-slider: half-width of the uniform distribution of the per-grain mu_r
    /// around `rolling_resistance` (dimensionless, at most the mean); 0: every grain the
    /// mean. Drawn from `run.seed`; a contact takes the mean of its two grains' values.
    #[serde(skip_serializing_if = "is_zero")]
    pub rolling_resistance_spread: f64,
    /// Spring-dashpot-slider: rolling stiffness k_roll (N/m), LAMMPS' `k_roll`; the spring
    /// torque per rolling angle is `k_roll R_eff^2`. Absent: `2.25 mu_r^2 k_n` (Ai et al.
    /// 2011), with k_n the normal law's tangent stiffness at the current overlap.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rolling_stiffness: Option<f64>,
    /// Spring-dashpot-slider: rolling damping gamma_roll (N s/m), LAMMPS' `gamma_roll`: a
    /// torque `-gamma_roll R_eff^2 omega_roll` while the spring is below its limit.
    #[serde(skip_serializing_if = "is_zero")]
    pub rolling_damping: f64,
}

/// Whether a key is at its default of 0 (left out of the serialised scene).
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            normal: NormalKind::Hertz,
            tangential: TangentialKind::HaffWerner,
            rolling: RollingKind::BrilliantovPoschel,
            kn: None,
            gamma_n: None,
            friction: 0.7,
            wall_friction: 0.7,
            tangential_damping: 0.007,
            tangential_stiffness: None,
            rolling_friction: 8.5e-6,
            rolling_resistance: None,
            rolling_resistance_spread: 0.0,
            rolling_stiffness: None,
            rolling_damping: 0.0,
        }
    }
}

/// `[toggles]`: the ablations of thesis 3.5.4 plus rolling friction. Each is one edit of a
/// law slot ([`Toggles::apply`]) or of the tray ([`crate::tray::setup`]), never a code path
/// of the physics of its own.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Toggles {
    /// Particle-particle friction (off: the pair's tangential slot is `none`; the floor still
    /// drives).
    pub friction: bool,
    /// Vertical motion (off: particles pinned to z = R, a 2D model, eq 3.28).
    pub jumping: bool,
    /// Particle-particle normal dissipation (off: the pair's normal law is elastic, pure
    /// Hertz, eq 3.29).
    pub dissipation: bool,
    /// Side walls at y = 0 and y = W (off: periodic in y).
    pub walls: bool,
    /// Rolling friction (off: both rolling slots are `none`, as `contact.rolling = "none"`).
    pub rolling: bool,
}

impl Default for Toggles {
    fn default() -> Self {
        Self {
            friction: true,
            jumping: true,
            dissipation: true,
            walls: true,
            rolling: true,
        }
    }
}

impl Toggles {
    /// The one place where toggles change contact laws; each toggle is one slot edit.
    pub fn apply(&self, pair: &mut ContactLaw, wall: &mut ContactLaw) {
        if !self.friction {
            pair.tangential = TangentialLaw::None;
        }
        if !self.dissipation {
            pair.normal = pair.normal.elastic();
        }
        if !self.rolling {
            pair.rolling = RollingLaw::None;
            wall.rolling = RollingLaw::None;
        }
    }
}

/// `[prepare]`: sample preparation (thesis 3.5.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Prepare {
    /// Initial random velocities vx, vy uniform in `[-speed, speed]` (m/s).
    pub speed: f64,
    /// Relaxation time without shaking (s).
    pub duration: f64,
}

impl Default for Prepare {
    fn default() -> Self {
        Self {
            speed: 0.005,
            duration: 10.0,
        }
    }
}

/// A scene error, naming the key (or, for a file that does not parse, the file or the
/// `--set` override to blame).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// Dotted key, the file, or `--set KEY=VALUE`.
    pub key: String,
    pub message: String,
}

/// A scene's error where a simulation's is expected: the field and what is wrong with it.
impl From<SceneError> for crate::error::SimError {
    fn from(e: SceneError) -> Self {
        crate::error::SimError::InvalidParameter {
            field: e.key,
            message: e.message,
        }
    }
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "scene `{}`: {}", self.key, self.message)
    }
}

impl std::error::Error for SceneError {}

pub(crate) fn err(key: &str, message: impl Into<String>) -> SceneError {
    SceneError {
        key: key.into(),
        message: message.into(),
    }
}

impl Scene {
    /// Checks every value. Errors name the key.
    pub fn validate(&self) -> Result<(), SceneError> {
        let check = |key: &str, x: f64, ok: bool, what: &str| {
            if ok {
                Ok(())
            } else {
                Err(err(key, format!("must be {what}, got {x}")))
            }
        };
        let positive = |key: &str, x: f64| check(key, x, x.is_finite() && x > 0.0, "a positive number");
        let non_negative = |key: &str, x: f64| check(key, x, x.is_finite() && x >= 0.0, ">= 0");
        // Friction coefficients may be `inf` (the viscous or spring branch alone, uncapped).
        let friction = |key: &str, x: f64| check(key, x, x >= 0.0, ">= 0 or inf");
        positive("box.length", self.tray.length)?;
        positive("box.width", self.tray.width)?;
        if let Some(h) = self.tray.height {
            positive("box.height", h)?;
        }
        self.drive.validate_stages()?;
        positive("drive.frequency", self.drive.frequency)?;
        non_negative("drive.amplitude", self.drive.amplitude)?;
        if self.particles.count == 0 {
            return Err(err("particles.count", "must be at least 1"));
        }
        positive("particles.radius_min", self.particles.radius_min)?;
        positive("particles.radius_max", self.particles.radius_max)?;
        if self.particles.radius_max < self.particles.radius_min {
            return Err(err("particles.radius_max", "must be >= particles.radius_min"));
        }
        let clump = self.clump_shape()?;
        // A grain's reach in the plane: its radius, or a clump's circle about its centre.
        let reach = self.particles.radius_max * clump.map_or(1.0, |c| c.reach());
        if 2.0 * reach > self.tray.width.min(self.tray.length) {
            return Err(err("particles.radius_max", "a particle does not fit in the box"));
        }
        if clump.is_some() {
            if !self.toggles.jumping {
                return Err(err(
                    "toggles.jumping",
                    "must stay true with particles.shape = \"clump\": a clump is integrated as a rigid body in 3D",
                ));
            }
            if self.run.integrator != crate::integrate::Integrator::VelocityVerlet {
                return Err(err(
                    "run.integrator",
                    "must be \"velocity-verlet\" with particles.shape = \"clump\" (the bodies' rotation is NO_SQUISH's)",
                ));
            }
        }
        if self.drive.direction == DriveDirection::Z && !self.toggles.jumping {
            return Err(err(
                "toggles.jumping",
                "must stay true with drive.direction = \"z\": a pinned layer cannot follow a vertically vibrated floor",
            ));
        }
        // The preparation shuffles the sites of one lattice layer (spacing 2.1 R_max, or 2.1
        // times a clump's reach): a tray far larger than its grains need would size that
        // from the box alone.
        let spacing = 2.1 * reach;
        let sites = (self.tray.length / spacing).floor() * ((self.tray.width / spacing).floor() + 1.0);
        let most = 64.0 * self.particles.count as f64 + (1u64 << 20) as f64;
        if sites > most {
            return Err(err(
                "box.length",
                format!(
                    "with box.width = {} m the tray holds {sites:.3e} lattice sites of 2.1 R_max for {} grains \
                     (preparing it would need {:.1e} bytes); at most {most:.3e} sites (64 per grain) are allowed: \
                     shrink the box or add grains",
                    self.tray.width,
                    self.particles.count,
                    8.0 * sites
                ),
            ));
        }
        positive("material.density", self.material.density)?;
        positive("material.young", self.material.young)?;
        if !(self.material.poisson > -1.0 && self.material.poisson <= 0.5) {
            return Err(err("material.poisson", "must lie in (-1, 0.5]"));
        }
        non_negative("material.dissipation", self.material.dissipation)?;
        let c = &self.contact;
        friction("contact.friction", c.friction)?;
        friction("contact.wall_friction", c.wall_friction)?;
        non_negative("contact.tangential_damping", c.tangential_damping)?;
        non_negative("contact.rolling_friction", c.rolling_friction)?;
        if let Some(mu_r) = c.rolling_resistance {
            non_negative("contact.rolling_resistance", mu_r)?;
        }
        non_negative("contact.rolling_resistance_spread", c.rolling_resistance_spread)?;
        let mean = c.rolling_resistance.unwrap_or(0.0);
        if c.rolling_resistance_spread > mean {
            return Err(err(
                "contact.rolling_resistance_spread",
                format!(
                    "must be at most contact.rolling_resistance = {mean} (a uniform half-width wider than the mean would draw a negative mu_r), got {}",
                    c.rolling_resistance_spread
                ),
            ));
        }
        if let Some(k) = c.rolling_stiffness {
            positive("contact.rolling_stiffness", k)?;
        }
        non_negative("contact.rolling_damping", c.rolling_damping)?;
        non_negative("contact.gamma_n", c.gamma_n.unwrap_or(0.0))?;
        if let Some(kn) = c.kn {
            positive("contact.kn", kn)?;
        }
        if let Some(kt) = c.tangential_stiffness {
            positive("contact.tangential_stiffness", kt)?;
        }
        self.laws()?;
        non_negative("prepare.speed", self.prepare.speed)?;
        non_negative("prepare.duration", self.prepare.duration)?;
        positive("run.duration", self.run.duration)?;
        if let Some(total) = self.drive.schedule_duration() {
            // A shorter run stops inside the schedule (a first look at a long protocol); a
            // longer one would shake past the schedule's end with no stage to say how.
            if self.run.duration > total * (1.0 + 1e-12) {
                return Err(err(
                    "run.duration",
                    format!(
                        "{} s is longer than the drive schedule's {total} s (the sum of drive.stages[..].duration): \
                         lengthen the last stage, or shorten the run",
                        self.run.duration
                    ),
                ));
            }
        }
        if let TimeStep::Seconds(dt) = self.run.dt {
            positive("run.dt", dt)?;
        }
        positive("run.steps_per_contact", self.run.steps_per_contact)?;
        positive("run.restitution_tolerance", self.run.restitution_tolerance)?;
        if self.run.snapshots_per_period == 0 {
            return Err(err("run.snapshots_per_period", "must be at least 1"));
        }
        non_negative("run.checkpoint_interval", self.run.checkpoint_interval)?;
        // Packing: the layer must fit on the floor (a vertically vibrated box stacks its grains
        // in layers by design, open at the top).
        let phi = self.packing();
        if phi > 0.9 && self.drive.direction == DriveDirection::X {
            return Err(err(
                "particles.count",
                format!(
                    "2D packing fraction {phi:.2} does not fit in one layer (max 0.9{})",
                    if clump.is_some() { "; clumps counted lying flat" } else { "" }
                ),
            ));
        }
        Ok(())
    }

    /// Expected projected area of the grains, `N pi <r^2>` (m^2); for clumps lying flat,
    /// `N a <r^2>` with `a` the area of the union of the clump's unit discs.
    pub fn projected_area(&self) -> f64 {
        let (a, b) = (self.particles.radius_min, self.particles.radius_max);
        let unit = match self.clump_shape() {
            Ok(Some(c)) => c.projected_area(),
            _ => std::f64::consts::PI,
        };
        self.particles.count as f64 * unit * (a * a + a * b + b * b) / 3.0
    }

    /// The grains' clump shape (`particles.shape = "clump"`), `None` for spheres; an error
    /// names the key that is missing, out of range, or given for spheres.
    pub fn clump_shape(&self) -> Result<Option<crate::clump::ClumpShape>, SceneError> {
        let p = &self.particles;
        match p.shape {
            Shape::Sphere => {
                for (key, given) in [
                    ("particles.clump_spheres", p.clump_spheres.is_some()),
                    ("particles.clump_spacing", p.clump_spacing.is_some()),
                ] {
                    if given {
                        return Err(err(key, "is a clump's key: it needs particles.shape = \"clump\""));
                    }
                }
                Ok(None)
            }
            Shape::Clump => {
                let spheres = p
                    .clump_spheres
                    .ok_or_else(|| err("particles.clump_spheres", "needed by particles.shape = \"clump\" (2 or 3)"))?;
                let spacing = p.clump_spacing.ok_or_else(|| {
                    err(
                        "particles.clump_spacing",
                        "needed by particles.shape = \"clump\" (distance between sphere centres in radii, below 2)",
                    )
                })?;
                crate::clump::ClumpShape::new(spheres, spacing)
                    .map(Some)
                    .map_err(|e| err(e.key, e.message))
            }
        }
    }

    /// Expected 2D packing fraction `N pi <r^2> / (L W)` (thesis: about 0.23).
    pub fn packing(&self) -> f64 {
        self.projected_area() / (self.tray.length * self.tray.width)
    }

    /// Each grain's rolling coefficient for a spring-dashpot-slider (`rolling = "sds"`,
    /// [`crate::setup::Setup::rolling_mu`]): uniform in `rolling_resistance +-
    /// rolling_resistance_spread`, drawn from `run.seed` on a stream of its own (the sample's
    /// draws do not move); empty without a spread or without the law.
    pub fn rolling_mu(&self) -> Vec<f64> {
        use rand::{Rng, SeedableRng};
        let c = &self.contact;
        let spread = c.rolling_resistance_spread;
        let mean = c.rolling_resistance.unwrap_or(0.0);
        if c.rolling != RollingKind::SpringDashpotSlider || !self.toggles.rolling || spread <= 0.0 {
            return Vec::new();
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(self.run.seed);
        rng.set_stream(ROLLING_MU_STREAM);
        (0..self.particles.count)
            .map(|_| mean + spread * (2.0 * rng.gen::<f64>() - 1.0))
            .collect()
    }

    /// Material of grains and walls.
    pub fn material(&self) -> Material {
        self.material
    }

    /// Contact laws `(particle-particle, particle-wall)`, built whole from the slots and
    /// their parameters, then edited by the toggles ([`Toggles::apply`]). A slot whose
    /// parameter is missing is an error naming the key.
    pub fn laws(&self) -> Result<(ContactLaw, ContactLaw), SceneError> {
        let c = &self.contact;
        let (reduced_modulus, dissipation) = mix(&self.material, &self.material);
        let choice = LawChoice {
            normal: c.normal,
            tangential: c.tangential,
            rolling: c.rolling,
        };
        let build = |mu: f64| {
            let parameters = LawParameters {
                reduced_modulus,
                dissipation,
                kn: c.kn,
                gamma_n: c.gamma_n.unwrap_or(0.0),
                mu,
                gamma_t: c.tangential_damping,
                kt: c.tangential_stiffness,
                mu_r: c.rolling_friction,
                rolling_resistance: c.rolling_resistance,
                k_roll: c.rolling_stiffness,
                gamma_roll: c.rolling_damping,
            };
            choice.build(&parameters).map_err(|m| match m {
                Missing::Kn => err("contact.kn", "needed by normal = \"linear\""),
                Missing::Kt => err("contact.tangential_stiffness", "needed by tangential = \"cundall-strack\""),
                Missing::RollingResistance => err("contact.rolling_resistance", "needed by rolling = \"sds\" (dimensionless mu_r)"),
            })
        };
        let (mut pair, mut wall) = (build(c.friction)?, build(c.wall_friction)?);
        self.toggles.apply(&mut pair, &mut wall);
        Ok((pair, wall))
    }
}
