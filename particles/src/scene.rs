//! Scene files: the complete description of a shaken-tray run, in TOML.
//!
//! Every key has a documented unit and default; unknown keys are errors. Any key can be
//! overridden from the command line as `--set dotted.key=value` (see [`Scene::load`]).
//! [`Scene::validate`] checks every value and names the offending key in its error.

use serde::{Deserialize, Serialize};

use crate::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use crate::integrate::Integrator;
use crate::material::{mix, Material};

/// A scene. Sections mirror the TOML tables.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(rename = "box")]
    pub tray: TrayBox,
    pub drive: Drive,
    pub particles: Particles,
    #[serde(default)]
    pub material: MaterialSpec,
    #[serde(default)]
    pub contact: ContactSpec,
    #[serde(default)]
    pub toggles: Toggles,
    #[serde(default)]
    pub prepare: Prepare,
    pub run: Run,
    /// `[automaton]`, read by `stripes automaton` only; omitted from the written scene (and
    /// so from the sample key) while it holds the defaults.
    #[serde(default, skip_serializing_if = "AutomatonSpec::is_default")]
    pub automaton: AutomatonSpec,
}

/// `[box]`: the tray. x is periodic; y has side walls (or is periodic with `toggles.walls = false`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrayBox {
    /// Length along the shaking direction x (m), periodic.
    pub length: f64,
    /// Width across, y (m).
    pub width: f64,
    /// Optional ceiling (m) for the escape check: a grain above it stops the run. Absent by
    /// default: the thesis' box is 0.1 m high but "open in positive direction" (sec 3.5.3),
    /// so a grain thrown higher simply falls back. The floor and the side walls always
    /// confine: a grain below the floor or outside the walls has escaped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
}

/// `[drive]`: tray motion `x_tray(t) = amplitude sin(2 pi frequency t)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Drive {
    /// Hz.
    pub frequency: f64,
    /// m.
    pub amplitude: f64,
}

/// `[particles]`: the population, radii uniform in `[radius_min, radius_max]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Particles {
    pub count: usize,
    /// m.
    pub radius_min: f64,
    /// m.
    pub radius_max: f64,
}

/// `[material]`: grains and walls (the thesis uses one material for both, Table 3.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// kg/m^3.
    #[serde(default = "d_density")]
    pub density: f64,
    /// Young's modulus Y (Pa).
    #[serde(default = "d_young")]
    pub young: f64,
    /// Poisson ratio; the thesis does not give it, 0.3 is glass.
    #[serde(default = "d_poisson")]
    pub poisson: f64,
    /// Dissipative constant A (s), eq 3.8.
    #[serde(default = "d_dissipation")]
    pub dissipation: f64,
}

/// Normal-law slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NormalKind {
    Hertz,
    Linear,
}

/// Tangential-law slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TangentialKind {
    None,
    HaffWerner,
    CundallStrack,
}

/// Rolling-law slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RollingKind {
    None,
    BrilliantovPoschel,
}

/// `[contact]`: one slot per sub-model, and their parameters (Table 3.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    #[serde(default = "d_normal")]
    pub normal: NormalKind,
    #[serde(default = "d_tangential")]
    pub tangential: TangentialKind,
    #[serde(default = "d_rolling")]
    pub rolling: RollingKind,
    /// Linear law: stiffness k_n (N/m) and damping gamma_n (kg/s).
    #[serde(default)]
    pub kn: Option<f64>,
    #[serde(default)]
    pub gamma_n: Option<f64>,
    /// Coulomb coefficient between particles; `inf` (TOML `inf`) for no Coulomb cap.
    #[serde(default = "d_mu")]
    pub friction: f64,
    /// Coulomb coefficient between particles and walls (floor and sides); `inf` for no
    /// Coulomb cap (with Haff-Werner: the viscous branch alone, the thesis-like floor).
    #[serde(default = "d_mu")]
    pub wall_friction: f64,
    /// Haff-Werner tangential damping gamma_t (N s/m).
    #[serde(default = "d_gamma_t")]
    pub tangential_damping: f64,
    /// Cundall-Strack tangential stiffness k_t (N/m).
    #[serde(default)]
    pub tangential_stiffness: Option<f64>,
    /// Brilliantov-Pöschel rolling friction mu_r (s).
    #[serde(default = "d_mu_r")]
    pub rolling_friction: f64,
}

/// `[toggles]`: the ablations of thesis 3.5.4 plus rolling friction. Each changes parameter
/// values only, never the code path of the physics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Toggles {
    /// Particle-particle friction (off: mu_pp = 0; the floor still drives).
    #[serde(default = "yes")]
    pub friction: bool,
    /// Vertical motion (off: particles pinned to z = R, a 2D model, eq 3.28).
    #[serde(default = "yes")]
    pub jumping: bool,
    /// Particle-particle normal dissipation (off: A_pp = 0, pure Hertz, eq 3.29).
    #[serde(default = "yes")]
    pub dissipation: bool,
    /// Side walls at y = 0 and y = W (off: periodic in y).
    #[serde(default = "yes")]
    pub walls: bool,
    /// Rolling friction (off: mu_r = 0 everywhere).
    #[serde(default = "yes")]
    pub rolling: bool,
}

/// `[prepare]`: sample preparation (thesis 3.5.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Prepare {
    /// Initial random velocities vx, vy uniform in `[-speed, speed]` (m/s).
    #[serde(default = "d_prep_speed")]
    pub speed: f64,
    /// Relaxation time without shaking (s).
    #[serde(default = "d_prep_duration")]
    pub duration: f64,
}

/// How the time step is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TimeStep {
    /// Explicit value (s).
    Seconds(f64),
    /// `"auto"`: error-controlled. The coarsest step whose restitution error (measured with
    /// the collision lab on the scene's hardest impacts, see
    /// [`crate::experiment::step_control`]) is at most `run.restitution_tolerance`, and never
    /// coarser than `shortest contact time / run.steps_per_contact`.
    Auto(AutoDt),
}

/// Marker for `dt = "auto"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AutoDt {
    Auto,
}

/// `[run]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Run {
    /// Simulated time (s).
    pub duration: f64,
    /// Time step (s), or `"auto"`.
    pub dt: TimeStep,
    /// Fewest steps per contact time `dt = "auto"` may give (the least accepted for an
    /// explicit dt is [`crate::timescale::MIN_STEPS_PER_CONTACT`]).
    #[serde(default = "d_steps_per_contact")]
    pub steps_per_contact: f64,
    /// Largest accepted error of the restitution coefficients (eps_n, eps_t; absolute) for
    /// `dt = "auto"`. The default, [`DEFAULT_RESTITUTION_TOLERANCE`], sits on the measured
    /// speed-against-error front (`stripes bench`).
    /// Left out of the serialised scene when it has its default, so that sample keys
    /// ([`crate::prepare::sample_key`]) of scenes written before this key existed still hold.
    #[serde(default = "d_restitution_tolerance", skip_serializing_if = "is_default_tolerance")]
    pub restitution_tolerance: f64,
    /// Random seed of the sample (radii, lattice, initial velocities).
    pub seed: u64,
    /// Worker threads (0: all cores). Results do not depend on it.
    #[serde(default)]
    pub threads: usize,
    /// Snapshots per shaking period, at the fixed phase of the turning point (1: thesis).
    #[serde(default = "d_one")]
    pub snapshots_per_period: u32,
    /// Simulated seconds between checkpoints (0: none).
    #[serde(default = "d_checkpoint")]
    pub checkpoint_interval: f64,
    /// Time integrator: `velocity-verlet` (default, second order) or `thesis` (the thesis'
    /// scheme, sec 3.5.1: Verlet positions eq 3.26, central-difference velocities eq 3.27,
    /// Euler rotation eq 3.22-3.23; first order). Left out of the serialised scene when it
    /// has its default, so that sample keys of older scenes still hold.
    #[serde(default = "d_integrator", skip_serializing_if = "is_default_integrator")]
    pub integrator: Integrator,
}

/// Rule set of the automaton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AutomatonRule {
    /// Thesis 3.1 exactly (a rigid translation in a submonolayer).
    Strict,
    /// Thesis 3.1 plus the tray's ingredients (SPEC section 3).
    Physical,
}

/// Lateral contacts of the automaton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AutomatonLateral {
    None,
    Neighbours,
    Clusters,
}

/// `[automaton]`: the cellular automaton on this scene (`stripes automaton`, thesis 3.1). The
/// flight cap and the sliding threshold follow from `[drive]`, the floor friction and the
/// mean diameter; the keys here switch ingredients and hold the free parameters that
/// `stripes automaton --calibrate` fits. The DEM ignores this table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AutomatonSpec {
    /// `physical` (default) or `strict`.
    pub rule: AutomatonRule,
    /// Nothing moves unless `A (2 pi nu)^2 > mu g`.
    pub threshold: bool,
    /// Flights end after the free grain's sliding displacement per half period.
    pub flight_cap: bool,
    /// Stochastic flights: each grain flies in a half period with probability `activation`.
    pub stochastic: bool,
    /// Activation probability per half period, in [0, 1].
    pub activation: f64,
    /// Knock-through along lines of touching grains.
    pub knock: bool,
    /// Knock-through speed scale v_knock (m/s): the far grain is knocked loose (and a
    /// lateral contact yields) with probability `1 - exp(-(v / v_knock)^2)`, v the peak
    /// sliding speed relative to the tray.
    pub knock_speed: f64,
    /// Which grains of the neighbouring rows (y) stop a flight: `none`, `neighbours` (all),
    /// `clusters` (those touching an x-neighbour, default).
    pub lateral: AutomatonLateral,
    /// Sideways (y) moves.
    pub sideways: bool,
    /// Probability per half period of a sideways move, in [0, 1].
    pub sideways_probability: f64,
    /// Cell length (m); absent: the mean grain diameter.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cell: Option<f64>,
}

impl Default for AutomatonSpec {
    fn default() -> Self {
        Self {
            rule: AutomatonRule::Physical,
            threshold: true,
            flight_cap: true,
            stochastic: true,
            activation: 0.8,
            knock: true,
            knock_speed: 7.0,
            lateral: AutomatonLateral::Clusters,
            sideways: true,
            sideways_probability: 0.1,
            cell: None,
        }
    }
}

impl AutomatonSpec {
    /// Whether every key holds its default.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the values; errors name the key.
    pub fn validate(&self) -> Result<(), SceneError> {
        for (key, p) in [
            ("automaton.activation", self.activation),
            ("automaton.sideways_probability", self.sideways_probability),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(err(key, format!("must lie in [0, 1], got {p}")));
            }
        }
        if !(self.knock_speed.is_finite() && self.knock_speed > 0.0) {
            return Err(err(
                "automaton.knock_speed",
                format!("must be a positive speed (m/s), got {}", self.knock_speed),
            ));
        }
        if let Some(c) = self.cell {
            if !(c.is_finite() && c > 0.0) {
                return Err(err("automaton.cell", format!("must be a positive length (m), got {c}")));
            }
        }
        Ok(())
    }
}
/// Default `run.restitution_tolerance`, picked from the speed-against-error front of
/// `stripes bench` (see the README's section on it).
pub const DEFAULT_RESTITUTION_TOLERANCE: f64 = 1e-2;

fn d_density() -> f64 {
    2500.0
}
fn d_young() -> f64 {
    1e6
}
fn d_poisson() -> f64 {
    0.3
}
fn d_dissipation() -> f64 {
    8.5e-6
}
fn d_normal() -> NormalKind {
    NormalKind::Hertz
}
fn d_tangential() -> TangentialKind {
    TangentialKind::HaffWerner
}
fn d_rolling() -> RollingKind {
    RollingKind::BrilliantovPoschel
}
fn d_mu() -> f64 {
    0.7
}
fn d_gamma_t() -> f64 {
    0.007
}
fn d_mu_r() -> f64 {
    8.5e-6
}
fn yes() -> bool {
    true
}
fn d_prep_speed() -> f64 {
    0.005
}
fn d_prep_duration() -> f64 {
    10.0
}
fn d_steps_per_contact() -> f64 {
    15.0
}
fn d_restitution_tolerance() -> f64 {
    DEFAULT_RESTITUTION_TOLERANCE
}
fn is_default_tolerance(x: &f64) -> bool {
    *x == DEFAULT_RESTITUTION_TOLERANCE
}
fn d_one() -> u32 {
    1
}
fn d_integrator() -> Integrator {
    Integrator::VelocityVerlet
}
fn is_default_integrator(x: &Integrator) -> bool {
    *x == d_integrator()
}
fn d_checkpoint() -> f64 {
    1.0
}

impl Default for MaterialSpec {
    fn default() -> Self {
        Self {
            density: d_density(),
            young: d_young(),
            poisson: d_poisson(),
            dissipation: d_dissipation(),
        }
    }
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            normal: d_normal(),
            tangential: d_tangential(),
            rolling: d_rolling(),
            kn: None,
            gamma_n: None,
            friction: d_mu(),
            wall_friction: d_mu(),
            tangential_damping: d_gamma_t(),
            tangential_stiffness: None,
            rolling_friction: d_mu_r(),
        }
    }
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

impl Default for Prepare {
    fn default() -> Self {
        Self {
            speed: d_prep_speed(),
            duration: d_prep_duration(),
        }
    }
}

/// A scene error, naming the key.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// Dotted key, or the file for syntax errors.
    pub key: String,
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "scene `{}`: {}", self.key, self.message)
    }
}

impl std::error::Error for SceneError {}

fn err(key: &str, message: impl Into<String>) -> SceneError {
    SceneError {
        key: key.into(),
        message: message.into(),
    }
}

/// Applies `key=value` to a TOML document; `value` is read as a TOML value (number, bool,
/// string, array) or, failing that, as a bare string.
fn apply_override(doc: &mut toml::Table, assignment: &str) -> Result<(), SceneError> {
    let (key, raw) = assignment
        .split_once('=')
        .ok_or_else(|| err(assignment, "an override must look like dotted.key=value"))?;
    let key = key.trim();
    let value = match toml::from_str::<toml::Table>(&format!("v = {}", raw.trim())) {
        Ok(mut t) => t.remove("v").expect("parsed"),
        Err(_) => toml::Value::String(raw.trim().to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut table = doc;
    for (depth, part) in parts.iter().enumerate() {
        if part.is_empty() {
            return Err(err(key, "empty component in dotted key"));
        }
        if depth + 1 == parts.len() {
            table.insert(part.to_string(), value);
            return Ok(());
        }
        let entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry
            .as_table_mut()
            .ok_or_else(|| err(key, format!("`{part}` is a value, not a table")))?;
    }
    unreachable!("a key has at least one component")
}

impl Scene {
    /// Parses a scene from TOML text with `--set`-style overrides applied first.
    /// `origin` names the source in messages.
    pub fn parse(text: &str, overrides: &[String], origin: &str) -> Result<Self, SceneError> {
        let mut doc: toml::Table = toml::from_str(text).map_err(|e| err(origin, format!("not valid TOML: {e}")))?;
        for o in overrides {
            apply_override(&mut doc, o)?;
        }
        Scene::deserialize(toml::Value::Table(doc)).map_err(|e| err(origin, e.to_string()))
    }

    /// Reads a scene file and applies overrides.
    pub fn load(path: &std::path::Path, overrides: &[String]) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| err(&path.display().to_string(), format!("cannot read: {e}")))?;
        Self::parse(&text, overrides, &path.display().to_string())
    }

    /// Checks every value. Errors name the key.
    pub fn validate(&self) -> Result<(), SceneError> {
        let positive = |key: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(err(key, format!("must be a positive number, got {x}")))
            }
        };
        let non_negative = |key: &str, x: f64| {
            if x.is_finite() && x >= 0.0 {
                Ok(())
            } else {
                Err(err(key, format!("must be >= 0, got {x}")))
            }
        };
        positive("box.length", self.tray.length)?;
        positive("box.width", self.tray.width)?;
        if let Some(h) = self.tray.height {
            positive("box.height", h)?;
        }
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
        if 2.0 * self.particles.radius_max > self.tray.width.min(self.tray.length) {
            return Err(err("particles.radius_max", "a particle does not fit in the box"));
        }
        positive("material.density", self.material.density)?;
        positive("material.young", self.material.young)?;
        if !(self.material.poisson > -1.0 && self.material.poisson <= 0.5) {
            return Err(err("material.poisson", "must lie in (-1, 0.5]"));
        }
        non_negative("material.dissipation", self.material.dissipation)?;
        // Friction coefficients may be `inf` (the viscous or spring branch alone, uncapped).
        let friction = |key: &str, x: f64| {
            if x >= 0.0 {
                Ok(())
            } else {
                Err(err(key, format!("must be >= 0 or inf, got {x}")))
            }
        };
        friction("contact.friction", self.contact.friction)?;
        friction("contact.wall_friction", self.contact.wall_friction)?;
        non_negative("contact.tangential_damping", self.contact.tangential_damping)?;
        non_negative("contact.rolling_friction", self.contact.rolling_friction)?;
        if self.contact.normal == NormalKind::Linear {
            positive(
                "contact.kn",
                self.contact.kn.ok_or_else(|| err("contact.kn", "needed by normal = \"linear\""))?,
            )?;
            non_negative("contact.gamma_n", self.contact.gamma_n.unwrap_or(0.0))?;
        }
        if self.contact.tangential == TangentialKind::CundallStrack {
            let kt = self
                .contact
                .tangential_stiffness
                .ok_or_else(|| err("contact.tangential_stiffness", "needed by tangential = \"cundall-strack\""))?;
            positive("contact.tangential_stiffness", kt)?;
        }
        non_negative("prepare.speed", self.prepare.speed)?;
        non_negative("prepare.duration", self.prepare.duration)?;
        positive("run.duration", self.run.duration)?;
        if let TimeStep::Seconds(dt) = self.run.dt {
            positive("run.dt", dt)?;
        }
        positive("run.steps_per_contact", self.run.steps_per_contact)?;
        positive("run.restitution_tolerance", self.run.restitution_tolerance)?;
        if self.run.snapshots_per_period == 0 {
            return Err(err("run.snapshots_per_period", "must be at least 1"));
        }
        non_negative("run.checkpoint_interval", self.run.checkpoint_interval)?;
        // Packing: the layer must fit on the floor.
        let area: f64 = self.projected_area();
        let phi = area / (self.tray.length * self.tray.width);
        if phi > 0.9 {
            return Err(err(
                "particles.count",
                format!("2D packing fraction {phi:.2} does not fit in one layer (max 0.9)"),
            ));
        }
        Ok(())
    }

    /// Expected projected area of the grains, `N pi <r^2>` (m^2).
    pub fn projected_area(&self) -> f64 {
        let (a, b) = (self.particles.radius_min, self.particles.radius_max);
        self.particles.count as f64 * std::f64::consts::PI * (a * a + a * b + b * b) / 3.0
    }

    /// Expected 2D packing fraction `N pi <r^2> / (L W)` (thesis: about 0.23).
    pub fn packing(&self) -> f64 {
        self.projected_area() / (self.tray.length * self.tray.width)
    }

    /// Material of grains and walls.
    pub fn material(&self) -> Material {
        Material {
            density: self.material.density,
            young: self.material.young,
            poisson: self.material.poisson,
            dissipation: self.material.dissipation,
        }
    }

    /// Contact laws `(particle-particle, particle-wall)` after the toggles.
    pub fn laws(&self) -> (ContactLaw, ContactLaw) {
        let m = self.material();
        let (reduced, a) = mix(&m, &m);
        let c = &self.contact;
        let t = &self.toggles;
        let normal = |dissipative: bool| match c.normal {
            NormalKind::Hertz => NormalLaw::hertz(reduced, if dissipative { a } else { 0.0 }),
            NormalKind::Linear => NormalLaw::Linear {
                kn: c.kn.unwrap_or(f64::NAN),
                gamma_n: if dissipative { c.gamma_n.unwrap_or(0.0) } else { 0.0 },
            },
        };
        let tangential = |mu: f64| match c.tangential {
            TangentialKind::None => TangentialLaw::None,
            TangentialKind::HaffWerner => TangentialLaw::HaffWerner {
                gamma_t: c.tangential_damping,
                mu,
            },
            TangentialKind::CundallStrack => TangentialLaw::CundallStrack {
                kt: c.tangential_stiffness.unwrap_or(f64::NAN),
                mu,
            },
        };
        let rolling = match (c.rolling, t.rolling) {
            (RollingKind::BrilliantovPoschel, true) => RollingLaw::BrilliantovPoschel { mu_r: c.rolling_friction },
            _ => RollingLaw::None,
        };
        let pair = ContactLaw {
            normal: normal(t.dissipation),
            tangential: tangential(if t.friction { c.friction } else { 0.0 }),
            rolling,
        };
        let wall = ContactLaw {
            normal: normal(true),
            tangential: tangential(c.wall_friction),
            rolling,
        };
        (pair, wall)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
        [box]
        length = 0.4
        width = 0.02
        [drive]
        frequency = 20.0
        amplitude = 0.025
        [particles]
        count = 4000
        radius_min = 0.25e-3
        radius_max = 0.5e-3
        [run]
        duration = 20.0
        dt = 8e-6
        seed = 1
    "#;

    #[test]
    fn defaults_are_the_thesis_values() {
        let s = Scene::parse(MINIMAL, &[], "test").unwrap();
        s.validate().unwrap();
        assert_eq!(s.material, MaterialSpec::default());
        assert!((s.packing() - 0.229).abs() < 0.002, "packing {}", s.packing());
        let (pp, pw) = s.laws();
        assert_eq!(pp, pw);
        assert_eq!(pp.tangential, TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 });
    }

    #[test]
    fn overrides_set_any_key_and_toggles_change_only_values() {
        let s = Scene::parse(
            MINIMAL,
            &[
                "toggles.friction=false".into(),
                "run.dt=auto".into(),
                "contact.rolling=none".into(),
                "run.threads=2".into(),
            ],
            "test",
        )
        .unwrap();
        let (pp, pw) = s.laws();
        assert_eq!(pp.tangential, TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.0 });
        assert_eq!(pw.tangential.mu(), 0.7, "the floor still drives");
        assert_eq!(pp.rolling, RollingLaw::None);
        assert_eq!(s.run.dt, TimeStep::Auto(AutoDt::Auto));
        assert_eq!(s.run.threads, 2);
    }

    #[test]
    fn the_default_restitution_tolerance_leaves_the_serialised_scene_unchanged() {
        // Sample keys hash the serialised scene: a new key at its default must not move them.
        let s = Scene::parse(MINIMAL, &[], "test").unwrap();
        assert!(!toml::to_string(&s).unwrap().contains("restitution_tolerance"));
        let t = Scene::parse(MINIMAL, &["run.restitution_tolerance=1e-3".into()], "test").unwrap();
        let again = Scene::parse(&toml::to_string(&t).unwrap(), &[], "test").unwrap();
        assert_eq!(again.run.restitution_tolerance, 1e-3);
    }

    #[test]
    fn unknown_keys_and_bad_values_name_the_key() {
        let e = Scene::parse(MINIMAL, &["toggles.jumpin=false".into()], "test").unwrap_err();
        assert!(e.message.contains("jumpin"), "{e}");
        let e = Scene::parse(MINIMAL, &["particles.radius_max=1e-4".into()], "test")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "particles.radius_max");
        let e = Scene::parse(MINIMAL, &["run.dt=-1".into()], "test")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "run.dt");
        let e = Scene::parse(MINIMAL, &["contact.normal=linear".into()], "test")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "contact.kn");
        let e = Scene::parse(MINIMAL, &["contact.wall_friction=-0.1".into()], "test")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "contact.wall_friction");
    }

    #[test]
    fn friction_accepts_inf_as_the_uncapped_law() {
        let s = Scene::parse(MINIMAL, &["contact.wall_friction=inf".into()], "test").unwrap();
        s.validate().unwrap();
        let (pair, wall) = s.laws();
        assert_eq!(
            wall.tangential,
            TangentialLaw::HaffWerner {
                gamma_t: 0.007,
                mu: f64::INFINITY
            }
        );
        assert_eq!(pair.tangential.mu(), 0.7);
        let e = Scene::parse(MINIMAL, &["contact.friction=nan".into()], "test")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "contact.friction");
    }
}
