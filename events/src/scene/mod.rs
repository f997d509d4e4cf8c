//! The scene of the event-driven model: a vertical box with a vibrated floor (and optionally
//! a lid and side walls), one or two species, and a collision rule per contact class, as
//! serde types with `deny_unknown_fields`. [`EventScene::config`] checks it and maps it onto
//! the engine's [`Config`](crate::Config) ([`config`]); the sizes it implies are bounded by
//! key before anything is allocated ([`bounds`]). This crate reads no text: the root crate
//! turns a scene file and its `--set` overrides into these types. `docs/scenes.md` documents
//! every key.

pub mod bounds;
pub mod config;

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

pub use crate::error::SceneError;
use crate::wall::Waveform;
use crate::SideWalls;

/// The names of an enum's values in a scene file: `NAMES`, `name()`, and the serde
/// conversions from and to them (`#[serde(try_from = "String", into = "String")]` on the
/// enum), so that an unknown name is refused naming its key and the accepted names.
macro_rules! scene_names {
    ($ty:ident, $what:literal, $($variant:ident = $text:literal),+ $(,)?) => {
        impl $ty {
            /// The names in scene files.
            pub const NAMES: &'static [&'static str] = &[$($text),+];

            /// The name in scene files.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $text),+
                }
            }
        }

        impl TryFrom<String> for $ty {
            type Error = String;
            fn try_from(s: String) -> Result<Self, String> {
                match s.as_str() {
                    $($text => Ok($ty::$variant),)+
                    _ => Err(unknown($what, &s, $ty::NAMES)),
                }
            }
        }

        impl From<$ty> for String {
            fn from(v: $ty) -> String {
                v.name().to_string()
            }
        }
    };
}

/// `what must be "a", "b" or "c", got "given"`.
fn unknown(what: &str, given: &str, names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    let list = match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    };
    format!("{what} must be {list}, got {given:?}")
}

/// `model`: the kind of the scene file; only `"events"` is this model's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Model {
    Events,
}
scene_names!(Model, "model (`stripes events` takes an event-driven scene)", Events = "events");

scene_names!(
    SideWalls,
    "box.side_walls",
    Fixed = "fixed",
    Periodic = "periodic",
    WithFloor = "with-floor"
);

/// `drive.floor`: how the floor moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Floor {
    /// It follows the drive.
    Vibrated,
    /// It stands still.
    Fixed,
}
scene_names!(Floor, "drive.floor", Vibrated = "vibrated", Fixed = "fixed");

/// `drive.lid`: how the lid moves, or no lid (an open top).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Lid {
    /// It follows the drive.
    Vibrated,
    /// It stands still.
    Fixed,
    /// No lid: the box is open at the top.
    None,
}
scene_names!(Lid, "drive.lid", Vibrated = "vibrated", Fixed = "fixed", None = "none");

scene_names!(Waveform, "drive.waveform", Sine = "sine", Sawtooth = "sawtooth");

/// `base.shape`: the shape of a base in place of the flat floor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum BaseShape {
    /// Asymmetric teeth with rounded tips (the ratchet paper's Fig. 5).
    Sawtooth,
}
scene_names!(BaseShape, "base.shape (leave [base] out for a flat floor)", Sawtooth = "sawtooth");

/// `particles.shape`: what a grain is, which sets its inertia factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Shape {
    /// A sphere moving in the plane: q = I / (m R^2) = 2/5.
    Sphere,
    /// A disk: q = 1/2.
    Disk,
}
scene_names!(Shape, "particles.shape", Sphere = "sphere", Disk = "disk");

impl Shape {
    /// The inertia factor `I / (m R^2)` of the shape.
    pub fn q(self) -> f64 {
        match self {
            Shape::Sphere => 0.4,
            Shape::Disk => 0.5,
        }
    }
}

/// One number for every species (or species pair), or one per species.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "expected a number, or a list of numbers (one per species, or per species pair 1-1, 1-2, 2-2)"
)]
pub enum PerSpecies {
    One(f64),
    Each(Vec<f64>),
}

impl PerSpecies {
    /// The value of species (or pair) `k` of `n`; a list of another length names `key`.
    pub fn get(&self, k: usize, key: &str, n: usize) -> Result<f64, SceneError> {
        match self {
            PerSpecies::One(x) => Ok(*x),
            PerSpecies::Each(v) if v.len() == n => Ok(v[k]),
            PerSpecies::Each(v) => Err(SceneError::new(
                key,
                format!("needs one number or a list of {n}, got a list of {}", v.len()),
            )),
        }
    }
}

/// `[box]`: the vertical box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventBox {
    /// Width along x (m).
    pub width: f64,
    /// Height above the floor's mean position (m); the lid's mean position.
    pub height: f64,
    /// `fixed`, `periodic` or `with-floor` (walls that move vertically with the floor).
    #[serde(default = "fixed_walls")]
    pub side_walls: SideWalls,
    /// Gravity (m/s^2).
    #[serde(default = "gravity")]
    pub gravity: f64,
}

fn fixed_walls() -> SideWalls {
    SideWalls::Fixed
}

fn gravity() -> f64 {
    9.81
}

/// `[drive]`: the vibration `A sin(2 pi f t + phase)` and which walls follow it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventDrive {
    pub frequency: f64,
    /// The amplitude A (m); or give `peak_speed` instead, never both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// The peak speed V = 2 pi f A (m/s), which sets A at the scene's frequency: a sweep over
    /// the frequency at fixed V varies the amplitude with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_speed: Option<f64>,
    #[serde(default)]
    pub phase: f64,
    /// `vibrated` or `fixed`.
    #[serde(default = "vibrated")]
    pub floor: Floor,
    /// `vibrated`, `fixed` or `none` (open top).
    #[serde(default = "no_lid")]
    pub lid: Lid,
    /// `sine` (the walls follow `A sin(2 pi f t + phase)`) or `sawtooth` (they stand at their
    /// mean lines and push every grain that strikes them at the peak speed `2 pi f A`). The
    /// default is left out of the written scene, so the fingerprints of earlier runs hold.
    #[serde(default, skip_serializing_if = "is_sine")]
    pub waveform: Waveform,
}

fn is_sine(waveform: &Waveform) -> bool {
    *waveform == Waveform::Sine
}

fn vibrated() -> Floor {
    Floor::Vibrated
}

fn no_lid() -> Lid {
    Lid::None
}

/// `[base]`: a sawtooth base in place of the flat floor (the ratchet paper's Fig. 5),
/// moving with the floor's drive; absent, the floor is flat.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventBase {
    /// `sawtooth`, the one shape.
    pub shape: BaseShape,
    /// Tooth width w (m); the box width must hold a whole number of teeth.
    pub tooth_width: f64,
    /// Tooth height h above the valleys (m).
    pub tooth_height: f64,
    /// a = l / w: the horizontal projection of a tooth's left side over its width.
    pub asymmetry: f64,
    /// Radius of the arc rounding each tip (m).
    pub tip_radius: f64,
}

/// `[[particles.species]]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventSpecies {
    pub count: usize,
    pub radius_min: f64,
    pub radius_max: f64,
    /// Mass of each grain (kg); or give `density`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Material density (kg/m^3): each grain's mass is rho (4/3) pi R^3.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
}

/// `[particles]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventParticles {
    /// `sphere` (q = 2/5) or `disk` (q = 1/2).
    #[serde(default = "sphere")]
    pub shape: Shape,
    /// The inertia factor q = I / (m R^2) in (0, 1], in place of the shape's (a hollow
    /// sphere 2/3, a ring 1, a grain with its mass at its centre near 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q: Option<f64>,
    pub species: Vec<EventSpecies>,
    /// Initial velocities uniform in [-v, v] per component (m/s).
    #[serde(default = "initial_speed")]
    pub initial_speed: f64,
}

fn sphere() -> Shape {
    Shape::Sphere
}

fn initial_speed() -> f64 {
    0.1
}

/// One contact class' rule: Walton's, with `e` per species (walls) or per species pair
/// (1-1, 1-2, 2-2); with `v0` the restitution is the mixture paper's `e(g_n)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventRule {
    /// Required unless `table` is given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e: Option<PerSpecies>,
    /// A table of `(eps_n, beta)` against `g_n` and `g_t / g_n` (a full grid, as the DEM's
    /// collision lab measures it) in place of Walton's constants: the path of its file,
    /// which the root crate reads ([`EventScene::config`] takes the reader).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<PathBuf>,
    #[serde(default)]
    pub mu: f64,
    #[serde(default = "smooth")]
    pub beta0: f64,
    /// Speed below which collisions become elastic (m/s); absent: constant `e`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v0: Option<f64>,
}

fn smooth() -> f64 {
    -1.0
}

impl EventRule {
    /// Elastic and smooth: `e = 1`, no friction (a wall's rule when the scene gives none).
    pub fn elastic_smooth() -> Self {
        EventRule {
            e: Some(PerSpecies::One(1.0)),
            table: None,
            mu: 0.0,
            beta0: -1.0,
            v0: None,
        }
    }
}

/// `[rules]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventRules {
    pub pair: EventRule,
    #[serde(default = "EventRule::elastic_smooth")]
    pub floor: EventRule,
    #[serde(default = "EventRule::elastic_smooth")]
    pub side: EventRule,
    #[serde(default = "EventRule::elastic_smooth")]
    pub lid: EventRule,
}

impl EventRules {
    /// The rules with their keys (`rules.pair`, `rules.floor`, `rules.side`, `rules.lid`).
    pub fn named(&self) -> [(&'static str, &EventRule); 4] {
        [
            ("rules.pair", &self.pair),
            ("rules.floor", &self.floor),
            ("rules.side", &self.side),
            ("rules.lid", &self.lid),
        ]
    }

    /// The same, to edit.
    pub fn named_mut(&mut self) -> [(&'static str, &mut EventRule); 4] {
        [
            ("rules.pair", &mut self.pair),
            ("rules.floor", &mut self.floor),
            ("rules.side", &mut self.side),
            ("rules.lid", &mut self.lid),
        ]
    }
}

/// `[guard]`: the collapse guards (none by default).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventGuard {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_rebound_speed: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tc: Option<f64>,
    /// The approach speed below which a collision counts towards an inelastic collapse
    /// (m/s); absent: 1e-3 sqrt(g d_max). `inf` counts every collision.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collapse_speed: Option<f64>,
}

/// `[run]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventRun {
    /// Simulated time (s).
    pub duration: f64,
    /// Time before sampling starts (s).
    #[serde(default)]
    pub transient: f64,
    #[serde(default = "seed")]
    pub seed: u64,
    /// Samples per drive period, at fixed phases (phase 0 first).
    #[serde(default = "one")]
    pub samples_per_period: u32,
    /// Height bins of the profiles (m).
    #[serde(default = "bin")]
    pub bin: f64,
    /// The drive's phase (a fraction of a period, in [0, 1), a multiple of
    /// 1 / samples_per_period) at which the reduced height and K/R of the summary are
    /// taken; 0: the floor at its mean position moving up at its peak speed.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub phase: f64,
    /// Also keep every profile per phase of the drive (`profiles_phase.csv`,
    /// `profiles_across_phase.csv`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub phase_resolved: bool,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn seed() -> u64 {
    1
}

fn one() -> u32 {
    1
}

fn bin() -> f64 {
    1e-3
}

/// A scene of the event-driven model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventScene {
    /// `events`: the kind of this scene file.
    pub model: Model,
    #[serde(rename = "box")]
    pub tray: EventBox,
    pub drive: EventDrive,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<EventBase>,
    pub particles: EventParticles,
    pub rules: EventRules,
    #[serde(default)]
    pub guard: EventGuard,
    pub run: EventRun,
}

impl EventDrive {
    /// The amplitude, given or from `peak_speed / (2 pi frequency)`.
    pub fn amplitude(&self) -> Result<f64, SceneError> {
        match (self.amplitude, self.peak_speed) {
            (Some(a), None) => Ok(a),
            (None, Some(v)) if v.is_finite() && v >= 0.0 => Ok(v / (2.0 * std::f64::consts::PI * self.frequency)),
            (None, Some(v)) => Err(SceneError::new("drive.peak_speed", format!("must be a speed >= 0 (m/s), got {v}"))),
            (Some(_), Some(_)) => Err(SceneError::new(
                "drive.peak_speed",
                "give drive.amplitude or drive.peak_speed, not both",
            )),
            (None, None) => Err(SceneError::new(
                "drive.amplitude",
                "missing: give drive.amplitude (m) or drive.peak_speed (m/s)",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_name_is_refused_naming_its_key_and_the_accepted_names() {
        assert_eq!(
            SideWalls::try_from("round".to_string()).unwrap_err(),
            "box.side_walls must be \"fixed\", \"periodic\" or \"with-floor\", got \"round\""
        );
        assert_eq!(
            Model::try_from("tray".to_string()).unwrap_err(),
            "model (`stripes events` takes an event-driven scene) must be \"events\", got \"tray\""
        );
        for name in Lid::NAMES {
            assert_eq!(Lid::try_from(name.to_string()).unwrap().name(), *name);
        }
        assert_eq!(String::from(SideWalls::WithFloor), "with-floor");
    }
}
