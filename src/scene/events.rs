//! The scene file of the event-driven model: a vertical box with a vibrated floor (and
//! optionally a lid and side walls), one or two species, and a collision rule per contact
//! class. It maps onto [`events::Config`]; the tray scenes of the DEM and the automaton are
//! a different kind and stay as they are. `docs/scenes.md` documents every key.

use std::path::Path;

use events::collision::{Restitution, Rule, Table};
use events::config::{Config, Guard, Rules, SideWalls, Species};
use events::wall::Motion;
use particles::scene::SceneError;
use serde::{Deserialize, Serialize};

use crate::scene::text::overrides;

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
    fn get(&self, k: usize, key: &str, n: usize) -> Result<f64, SceneError> {
        match self {
            PerSpecies::One(x) => Ok(*x),
            PerSpecies::Each(v) if v.len() == n => Ok(v[k]),
            PerSpecies::Each(v) => Err(SceneError {
                key: key.into(),
                message: format!("needs one number or a list of {n}, got a list of {}", v.len()),
            }),
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
    /// "fixed", "periodic" or "with-floor" (walls that move vertically with the floor).
    #[serde(default = "fixed_walls")]
    pub side_walls: String,
    /// Gravity (m/s^2).
    #[serde(default = "gravity")]
    pub gravity: f64,
}

fn fixed_walls() -> String {
    "fixed".into()
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
    /// "vibrated" or "fixed".
    #[serde(default = "vibrated")]
    pub floor: String,
    /// "vibrated", "fixed" or "none" (open top).
    #[serde(default = "no_lid")]
    pub lid: String,
    /// "sine" (the walls follow `A sin(2 pi f t + phase)`) or "sawtooth" (they stand at their
    /// mean lines and push every grain that strikes them at the peak speed `2 pi f A`).
    #[serde(default = "sine", skip_serializing_if = "is_sine")]
    pub waveform: String,
}

fn sine() -> String {
    "sine".into()
}

fn is_sine(waveform: &str) -> bool {
    waveform == "sine"
}

fn vibrated() -> String {
    "vibrated".into()
}

fn no_lid() -> String {
    "none".into()
}

/// `[base]`: a sawtooth base in place of the flat floor (the ratchet paper's Fig. 5),
/// moving with the floor's drive; absent, the floor is flat.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventBase {
    /// Must be "sawtooth".
    pub shape: String,
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
    /// "sphere" (q = 2/5) or "disk" (q = 1/2).
    #[serde(default = "sphere")]
    pub shape: String,
    /// The inertia factor q = I / (m R^2) in (0, 1], in place of the shape's (a hollow
    /// sphere 2/3, a ring 1, a grain with its mass at its centre near 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q: Option<f64>,
    pub species: Vec<EventSpecies>,
    /// Initial velocities uniform in [-v, v] per component (m/s).
    #[serde(default = "initial_speed")]
    pub initial_speed: f64,
}

fn sphere() -> String {
    "sphere".into()
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
    /// A CSV table of `(eps_n, beta)` against `g_n` and `g_t / g_n` (columns `g_n,
    /// g_t_over_g_n, eps_n, beta`, a full grid, as the DEM's collision lab measures it) in
    /// place of Walton's constants; a relative path is read from the working directory (and
    /// recorded absolute in the run's `scene.toml`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<std::path::PathBuf>,
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
    fn elastic_smooth() -> Self {
        EventRule {
            e: Some(PerSpecies::One(1.0)),
            table: None,
            mu: 0.0,
            beta0: -1.0,
            v0: None,
        }
    }

    fn rules(&self, count: usize, key: &str) -> Result<Vec<Rule>, SceneError> {
        if let Some(path) = &self.table {
            if self.e.is_some() || self.mu != 0.0 || self.beta0 != -1.0 || self.v0.is_some() {
                return Err(bad(
                    &format!("{key}.table"),
                    "a table replaces e, mu, beta0 and v0: give either the table or them",
                ));
            }
            let table = std::sync::Arc::new(read_table(path).map_err(|m| bad(&format!("{key}.table"), m))?);
            return Ok(vec![Rule::Table(table); count]);
        }
        let e = self.e.as_ref().ok_or_else(|| bad(&format!("{key}.e"), "required (or a table)"))?;
        (0..count)
            .map(|k| {
                let e = e.get(k, &format!("{key}.e"), count)?;
                Ok(Rule::Walton {
                    e: match self.v0 {
                        Some(v0) => Restitution::VelocityDependent { e0: e, v0 },
                        None => Restitution::Constant(e),
                    },
                    mu: self.mu,
                    beta0: self.beta0,
                })
            })
            .collect()
    }
}

/// Reads a restitution table (`g_n, g_t_over_g_n, eps_n, beta`, one header line) into the
/// engine's grid; every `(g_n, ratio)` pair of the grid must be present once.
pub fn read_table(path: &Path) -> Result<Table, String> {
    let (header, rows) = analysis::io::read_csv(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let want = ["g_n", "g_t_over_g_n", "eps_n", "beta"];
    if header.iter().map(|h| h.trim()).collect::<Vec<_>>() != want {
        return Err(format!(
            "{}: the columns must be {}, got {}",
            path.display(),
            want.join(", "),
            header.join(", ")
        ));
    }
    // Every value a finite number in its range, named by its line, before the grid is built
    // (a NaN would match no axis value, and a negative g_n is no speed).
    for (k, r) in rows.iter().enumerate() {
        let row = k + 1;
        for (c, name) in want.iter().enumerate() {
            if !r[c].is_finite() {
                return Err(format!("{}: row {row}: {name} is {}, not a finite number", path.display(), r[c]));
            }
        }
        let (lo, hi) = ([0.0, 0.0, 0.0, -1.0], [f64::INFINITY, f64::INFINITY, 1.0, 1.0]);
        for (c, name) in want.iter().enumerate() {
            if !(lo[c]..=hi[c]).contains(&r[c]) {
                let range = if hi[c].is_finite() {
                    format!("in [{}, {}]", lo[c], hi[c])
                } else {
                    format!(">= {}", lo[c])
                };
                return Err(format!("{}: row {row}: {name} = {} must be {range}", path.display(), r[c]));
            }
        }
    }
    let axis = |c: usize| {
        let mut v: Vec<f64> = rows.iter().map(|r| r[c]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (g_n, ratio) = (axis(0), axis(1));
    let mut eps_n = vec![vec![f64::NAN; ratio.len()]; g_n.len()];
    let mut beta = eps_n.clone();
    for r in &rows {
        let i = g_n.iter().position(|&x| x == r[0]).expect("on the axis");
        let j = ratio.iter().position(|&x| x == r[1]).expect("on the axis");
        if !eps_n[i][j].is_nan() {
            return Err(format!("{}: g_n = {}, g_t/g_n = {} appears twice", path.display(), r[0], r[1]));
        }
        (eps_n[i][j], beta[i][j]) = (r[2], r[3]);
    }
    if eps_n.iter().flatten().any(|x| x.is_nan()) {
        return Err(format!(
            "{}: not a full grid of {} g_n x {} ratios",
            path.display(),
            g_n.len(),
            ratio.len()
        ));
    }
    let t = Table { g_n, ratio, eps_n, beta };
    t.validate().map_err(|m| format!("{}: {m}", path.display()))?;
    Ok(t)
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
    /// Must be "events": the kind of this scene file.
    pub model: String,
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

/// Reads an event-driven scene with `--set` overrides; errors name the file or override.
pub fn load(path: &Path, set: &[String]) -> Result<EventScene, SceneError> {
    let (text, origin) = crate::scene::file::read(path)?;
    let mut scene = parse_text(&text, set, &origin)?;
    // A table's path is read from the working directory; made absolute here, the run's
    // scene.toml (and a rerun or --resume from another directory) names the same file.
    if let Ok(cwd) = std::env::current_dir() {
        let r = &mut scene.rules;
        for rule in [&mut r.pair, &mut r.floor, &mut r.side, &mut r.lid] {
            if let Some(p) = rule.table.as_mut().filter(|p| p.is_relative()) {
                *p = cwd.join(&*p);
            }
        }
    }
    Ok(scene)
}

/// The scene in `text` (named `origin` in messages) with `--set` overrides.
fn parse_text(text: &str, set: &[String], origin: &str) -> Result<EventScene, SceneError> {
    overrides::parse(text, set, origin, |doc| {
        // A tray scene (no `model`) would only be told of its first unknown table.
        match doc.get("model").and_then(|m| m.as_str()) {
            Some("events") => {}
            None if doc.get("model").is_none() => {
                return Err(
                    "this is a tray scene (no model = \"events\"), for `stripes run`, `automaton` or `compare`; \
                            `stripes events` and `events-sweep` take an event-driven scene such as scenes/mixture.toml"
                        .into(),
                )
            }
            _ => {}
        }
        EventScene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())
    })
}

/// The most samples (observer updates and frames) a run may take: about 5 us each and a
/// frame of 48 bytes per particle, so 1e7 samples are about a minute of sampling and 24 GB of
/// snapshots for the vibrated box's 50 spheres. The shipped scenes take at most 1.8e5.
const MAX_SAMPLES: f64 = 1e7;

fn bad(key: &str, message: impl Into<String>) -> SceneError {
    SceneError {
        key: key.into(),
        message: message.into(),
    }
}

impl EventDrive {
    /// The amplitude, given or from `peak_speed / (2 pi frequency)`.
    pub fn amplitude(&self) -> Result<f64, SceneError> {
        match (self.amplitude, self.peak_speed) {
            (Some(a), None) => Ok(a),
            (None, Some(v)) if v.is_finite() && v >= 0.0 => Ok(v / (2.0 * std::f64::consts::PI * self.frequency)),
            (None, Some(v)) => Err(bad("drive.peak_speed", format!("must be a speed >= 0 (m/s), got {v}"))),
            (Some(_), Some(_)) => Err(bad("drive.peak_speed", "give drive.amplitude or drive.peak_speed, not both")),
            (None, None) => Err(bad(
                "drive.amplitude",
                "missing: give drive.amplitude (m) or drive.peak_speed (m/s)",
            )),
        }
    }
}

impl EventScene {
    /// The engine's configuration; every value is checked (here or by the engine, whose
    /// errors name the field).
    pub fn config(&self) -> Result<Config, SceneError> {
        if self.model != "events" {
            return Err(bad(
                "model",
                format!("must be \"events\" for `stripes events`, got {:?}", self.model),
            ));
        }
        let motion = Motion {
            amplitude: self.drive.amplitude()?,
            frequency: self.drive.frequency,
            phase: self.drive.phase,
        };
        let wall = |key: &str, v: &str, allow_none: bool| match v {
            "vibrated" => Ok(Some(motion)),
            "fixed" => Ok(Some(Motion::FIXED)),
            "none" if allow_none => Ok(None),
            _ => Err(bad(
                key,
                format!(
                    "must be \"vibrated\", \"fixed\"{}, got {v:?}",
                    if allow_none { " or \"none\"" } else { "" }
                ),
            )),
        };
        let side_walls = match self.tray.side_walls.as_str() {
            "fixed" => SideWalls::Fixed,
            "periodic" => SideWalls::Periodic,
            "with-floor" => SideWalls::WithFloor,
            v => {
                return Err(bad(
                    "box.side_walls",
                    format!("must be \"fixed\", \"periodic\" or \"with-floor\", got {v:?}"),
                ))
            }
        };
        let shape_q = match self.particles.shape.as_str() {
            "sphere" => 0.4,
            "disk" => 0.5,
            v => return Err(bad("particles.shape", format!("must be \"sphere\" or \"disk\", got {v:?}"))),
        };
        let q = match self.particles.q {
            Some(q) if !(q > 0.0 && q <= 1.0) => {
                return Err(bad(
                    "particles.q",
                    format!("the inertia factor I/(m R^2) must lie in (0, 1], got {q}"),
                ))
            }
            Some(q) => q,
            None => shape_q,
        };
        let n = self.particles.species.len();
        if n == 0 || n > 2 {
            return Err(bad("particles.species", format!("one or two species, got {n}")));
        }
        let r = &self.rules;
        let pairs = if n == 2 { 3 } else { 1 };
        let rules = Rules {
            pair: r.pair.rules(pairs, "rules.pair")?,
            floor: r.floor.rules(n, "rules.floor")?,
            side: r.side.rules(n, "rules.side")?,
            lid: r.lid.rules(n, "rules.lid")?,
        };
        if !(self.run.duration.is_finite() && self.run.duration > 0.0) {
            return Err(bad(
                "run.duration",
                format!("must be a positive time (s), got {}", self.run.duration),
            ));
        }
        if !(self.run.transient.is_finite() && self.run.transient >= 0.0 && self.run.transient < self.run.duration) {
            return Err(bad(
                "run.transient",
                format!("must lie in [0, run.duration), got {}", self.run.transient),
            ));
        }
        if self.run.samples_per_period == 0 {
            return Err(bad("run.samples_per_period", "must be at least 1"));
        }
        let phase = self.run.phase;
        if !(0.0..1.0).contains(&phase) {
            return Err(bad(
                "run.phase",
                format!("must lie in [0, 1) (a fraction of the drive's period), got {phase}"),
            ));
        }
        let at = phase * f64::from(self.run.samples_per_period);
        if (at - at.round()).abs() > 1e-9 {
            return Err(bad(
                "run.phase",
                format!(
                    "must be a phase that is sampled, a multiple of 1 / run.samples_per_period = 1/{}, got {phase}",
                    self.run.samples_per_period
                ),
            ));
        }
        if !(self.run.bin.is_finite() && self.run.bin > 0.0) {
            return Err(bad("run.bin", format!("must be a positive height (m), got {}", self.run.bin)));
        }
        if !(self.drive.frequency.is_finite() && self.drive.frequency > 0.0) {
            return Err(bad(
                "drive.frequency",
                format!("must be positive (it sets the sampling phase), got {}", self.drive.frequency),
            ));
        }
        // Every sample stops the run, updates the observer and (after the transient) writes a
        // frame: an absurd count is a run that never ends or fills the disk, not a measurement.
        let samples = self.run.duration * self.drive.frequency * f64::from(self.run.samples_per_period);
        if samples > MAX_SAMPLES {
            return Err(bad(
                "run.samples_per_period",
                format!(
                    "run.duration x drive.frequency x run.samples_per_period = {} x {} x {} = {samples:.3e} samples, \
                     more than {MAX_SAMPLES:e}; lower one of them",
                    self.run.duration, self.drive.frequency, self.run.samples_per_period
                ),
            ));
        }
        self.check_sizes()?;
        let config = Config {
            width: self.tray.width,
            height: self.tray.height,
            side_walls,
            gravity: self.tray.gravity,
            q,
            species: self
                .particles
                .species
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    Ok(Species {
                        count: s.count,
                        radius_min: s.radius_min,
                        radius_max: s.radius_max,
                        mass: match (s.mass, s.density) {
                            (Some(m), None) => events::Mass::Each(m),
                            (None, Some(rho)) => events::Mass::Density(rho),
                            _ => {
                                return Err(bad(
                                    &format!("particles.species.{k}"),
                                    "give either mass (kg, every grain) or density (kg/m^3)",
                                ))
                            }
                        },
                    })
                })
                .collect::<Result<_, SceneError>>()?,
            floor: wall("drive.floor", &self.drive.floor, false)?,
            base: match &self.base {
                None => None,
                Some(b) if b.shape == "sawtooth" => Some(events::Sawtooth {
                    width: b.tooth_width,
                    height: b.tooth_height,
                    asymmetry: b.asymmetry,
                    tip_radius: b.tip_radius,
                }),
                Some(b) => {
                    return Err(bad(
                        "base.shape",
                        format!("must be \"sawtooth\" (leave [base] out for a flat floor), got {:?}", b.shape),
                    ))
                }
            },
            lid: wall("drive.lid", &self.drive.lid, true)?,
            waveform: match self.drive.waveform.as_str() {
                "sine" => events::Waveform::Sine,
                "sawtooth" => events::Waveform::Sawtooth,
                other => return Err(bad("drive.waveform", format!("must be \"sine\" or \"sawtooth\", got {other:?}"))),
            },
            rules,
            guard: Guard {
                min_rebound_speed: self.guard.min_rebound_speed,
                tc: self.guard.tc,
                collapse_speed: self.guard.collapse_speed,
                ..Guard::default()
            },
            initial_speed: self.particles.initial_speed,
            seed: self.run.seed,
        };
        config.validate().map_err(|e| match e {
            events::EventsError::Invalid { field, message } => bad(&engine_key(&field), message),
            other => bad("scene", other.to_string()),
        })?;
        Ok(config)
    }
}

/// The most lattice sites (spacing `2.02 R_max`) a box may hold: the engine places grains on
/// them and sizes its cell grid alike (about 40 bytes a cell), so 1e7 is 400 MB. The shipped
/// scenes hold at most a few thousand.
const MAX_SITES: f64 = 1e7;
/// The most profile bins (height and across, times the phases kept with `run.phase_resolved`).
const MAX_BINS: f64 = 1e6;
/// The widest drive phase (rad): beyond a few turns `sin(2 pi f t + phase)` loses the
/// precision the wall's collision times need.
const MAX_PHASE: f64 = 2.0 * std::f64::consts::TAU;
/// The grain masses (kg) whose products and squares the collision rule computes in range.
const MASS_RANGE: (f64, f64) = (1e-20, 1e20);
/// The most collisions a scene's speeds may imply (about a day at 1e6 collisions a second).
const MAX_COLLISIONS: f64 = 1e11;

impl EventScene {
    /// The sizes the scene implies, checked before the engine allocates anything (issue 43,
    /// bounds): the lattice sites and cells of the box, the profile bins, the drive phase and
    /// the snapshot bytes, each refused naming its key and the size. Values that are not
    /// finite are left to the checks that name them.
    fn check_sizes(&self) -> Result<(), SceneError> {
        let r_max = self.particles.species.iter().map(|s| s.radius_max).fold(0.0, f64::max);
        let (w, h) = (self.tray.width, self.tray.height);
        if r_max.is_finite() && r_max > 0.0 && w.is_finite() && h.is_finite() {
            let spacing = 2.02 * r_max;
            let (nx, nz) = ((w / spacing).max(1.0), (h / spacing).max(1.0));
            if nx * nz > MAX_SITES {
                return Err(bad(
                    if nx >= nz { "box.width" } else { "box.height" },
                    format!(
                        "box.width = {w} m by box.height = {h} m is {nx:.3e} x {nz:.3e} = {:.3e} lattice sites (and cells) of \
                         2.02 R_max = {spacing:e} m; at most {MAX_SITES:e} are allowed: a smaller box or larger grains",
                        nx * nz
                    ),
                ));
            }
        }
        // Without gravity and without a lid nothing keeps a grain in the box: the escaped
        // grains piled into the top profile bin and gave H = 0.171 m in a 0.05 m box.
        if self.tray.gravity == 0.0 && self.drive.lid == "none" {
            return Err(bad(
                "drive.lid",
                "is \"none\" with box.gravity = 0: nothing keeps the grains in the box, they escape through the open top \
                 and every profile and height is wrong; give a lid (\"fixed\" or \"vibrated\") or gravity",
            ));
        }
        // The walls' extreme positions must leave a row of sites between them (else the
        // engine's "N x 0 sites" would hide that the drive's swing fills the box).
        if let Ok(a) = self.drive.amplitude() {
            let swing = |wall: &str| if wall == "vibrated" { a.abs() } else { 0.0 };
            let room = h - swing(&self.drive.floor) - swing(&self.drive.lid);
            if a.is_finite() && h.is_finite() && r_max.is_finite() && room < 2.02 * r_max {
                let key = if self.drive.peak_speed.is_some() {
                    "drive.peak_speed"
                } else {
                    "drive.amplitude"
                };
                return Err(bad(
                    key,
                    format!(
                        "the drive's swing (A = {a:e} m for the floor{}) leaves {room:e} m of the box's {h} m (box.height) \
                         between the walls' extreme positions, less than a grain diameter: a smaller amplitude or a taller box",
                        if self.drive.lid == "vibrated" {
                            " and as much for the lid"
                        } else {
                            ""
                        },
                    ),
                ));
            }
        }
        let bin = self.run.bin;
        let lid = match (self.drive.lid.as_str(), self.drive.amplitude()) {
            ("vibrated", Ok(a)) => a,
            _ => 0.0,
        };
        if bin.is_finite() && bin > 0.0 && w.is_finite() && h.is_finite() {
            let phases = if self.run.phase_resolved {
                1.0 + f64::from(self.run.samples_per_period)
            } else {
                1.0
            };
            let bins = ((h + lid.abs()) / bin).ceil() + (w / bin).round();
            if bins * phases > MAX_BINS {
                return Err(bad(
                    "run.bin",
                    format!(
                        "run.bin = {bin} m over a box {w} m wide and {} m high is {bins:.3e} profile bins{}; \
                         at most {MAX_BINS:e} are allowed: a larger run.bin",
                        h + lid.abs(),
                        if phases > 1.0 {
                            format!(" for each of {phases} phases (run.phase_resolved)")
                        } else {
                            String::new()
                        }
                    ),
                ));
            }
        }
        let phase = self.drive.phase;
        if phase.is_finite() && phase.abs() > MAX_PHASE {
            return Err(bad(
                "drive.phase",
                format!(
                    "must lie in [-4 pi, 4 pi] rad, got {phase}: a phase of many turns loses the precision of the wall's \
                     collision times; give it modulo 2 pi ({})",
                    phase.rem_euclid(std::f64::consts::TAU)
                ),
            ));
        }
        // Masses whose products and squares stay finite (a density of 1e300 or 1e-300 made
        // the collision times NaN and the run endless).
        for (k, sp) in self.particles.species.iter().enumerate() {
            let volume = 4.0 / 3.0 * std::f64::consts::PI * sp.radius_max.powi(3);
            let (key, m) = match (sp.mass, sp.density) {
                (Some(m), _) => (format!("particles.species.{k}.mass"), m),
                (None, Some(rho)) => (format!("particles.species.{k}.density"), rho * volume),
                (None, None) => continue,
            };
            if m.is_finite() && volume.is_finite() && !(MASS_RANGE.0..=MASS_RANGE.1).contains(&m) {
                return Err(bad(
                    &key,
                    format!(
                        "gives grains of {m:e} kg; masses must lie in [{:e}, {:e}] kg for the collision arithmetic to stay finite",
                        MASS_RANGE.0, MASS_RANGE.1
                    ),
                ));
            }
        }
        // The collisions the scene's speeds imply: a grain at speed v meets another about
        // every d / v, so N v / d_min collisions per second. Past MAX_COLLISIONS the run takes
        // days; a collapse guard faster than the gas would pump energy in without end.
        let (speed, speed_key) = self.speed_scale();
        let d_min = 2.0 * self.particles.species.iter().map(|s| s.radius_min).fold(f64::INFINITY, f64::min);
        let grains: f64 = self.particles.species.iter().map(|s| s.count as f64).sum();
        let collisions = grains * speed / d_min * self.run.duration;
        if collisions.is_finite() && collisions > MAX_COLLISIONS {
            return Err(bad(
                speed_key,
                format!(
                    "grains at {speed:e} m/s (from {speed_key}) in this box meet about N v / d_min = {:.3e} times a second, \
                     {collisions:.3e} collisions over run.duration = {} s; at most {MAX_COLLISIONS:e} are allowed (a day of CPU or more)",
                    grains * speed / d_min,
                    self.run.duration
                ),
            ));
        }
        if let Some(v) = self.guard.min_rebound_speed.filter(|v| v.is_finite() && *v > speed) {
            return Err(bad(
                "guard.min_rebound_speed",
                format!(
                    "{v} m/s is faster than the scene's grains ({speed:e} m/s, from {speed_key}): every collision would leave \
                     faster than it met, adding energy without end; the guard is a small speed that keeps slow grains hopping"
                ),
            ));
        }
        let bytes = self.snapshot_bytes();
        if bytes > crate::scene::bounds::MAX_SNAPSHOT_BYTES {
            return Err(bad(
                "run.samples_per_period",
                format!(
                    "{} samples per period after run.transient is {:.1} GB of snapshots.bin; at most {:.0} GB are allowed: \
                     fewer samples per period or a shorter run",
                    self.run.samples_per_period,
                    bytes / 1e9,
                    crate::scene::bounds::MAX_SNAPSHOT_BYTES / 1e9
                ),
            ));
        }
        Ok(())
    }

    /// The largest speed the scene gives its grains, and the key that sets it: the initial
    /// speed (each component up to it), the drive's peak speed `2 pi f A`, or the fall
    /// `sqrt(2 g height)` through the box.
    fn speed_scale(&self) -> (f64, &'static str) {
        let peak = self
            .drive
            .amplitude()
            .map_or(0.0, |a| std::f64::consts::TAU * self.drive.frequency * a.abs());
        let fall = (2.0 * self.tray.gravity.max(0.0) * self.tray.height.abs()).sqrt();
        let drive_key = if self.drive.peak_speed.is_some() {
            "drive.peak_speed"
        } else {
            "drive.amplitude"
        };
        [
            (
                std::f64::consts::SQRT_2 * self.particles.initial_speed.abs(),
                "particles.initial_speed",
            ),
            (peak, drive_key),
            (fall, "box.gravity"),
        ]
        .into_iter()
        .filter(|(v, _)| v.is_finite())
        .fold((0.0, "particles.initial_speed"), |a, b| if b.0 > a.0 { b } else { a })
    }

    /// Bytes of the run's `snapshots.bin`: a frame (time, then position and velocity of every
    /// grain) per sample after `run.transient`.
    fn snapshot_bytes(&self) -> f64 {
        let grains: f64 = self.particles.species.iter().map(|s| s.count as f64).sum();
        let frames = ((self.run.duration - self.run.transient) * self.drive.frequency * f64::from(self.run.samples_per_period))
            .max(0.0)
            .floor();
        32.0 + 8.0 * grains + frames * (8.0 + 48.0 * grains)
    }

    /// What a run of this (valid) scene must say at its start: the disk its snapshots will
    /// fill when that is more than a gigabyte, and a drive too weak to move anything.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let bytes = self.snapshot_bytes();
        if bytes > crate::scene::bounds::DISK_NOTE_BYTES {
            out.push(format!(
                "this run writes about {:.1} GB of snapshots ({} samples per period after run.transient); make sure --out has the room",
                bytes / 1e9,
                self.run.samples_per_period
            ));
        }
        let (Ok(a), f) = (self.drive.amplitude(), self.drive.frequency) else {
            return out;
        };
        let moving = |wall: &str| wall == "vibrated";
        if a > 0.0 && (moving(&self.drive.floor) || moving(&self.drive.lid)) {
            let g = self.tray.gravity;
            let r_min = self.particles.species.iter().map(|s| s.radius_min).fold(f64::INFINITY, f64::min);
            let gamma = a * (std::f64::consts::TAU * f).powi(2) / g;
            if g > 0.0 && gamma < 1.0 {
                out.push(format!(
                    "drive too weak to lift any grain: Gamma = A (2 pi f)^2 / g = {gamma:.3e} < 1 (A = {a:e} m, f = {f} Hz): \
                     the grains settle on the floor, which an event-driven model approaches through ever more frequent \
                     collisions, so the run slows down as they settle"
                ));
            } else if g <= 0.0 && a < 1e-3 * r_min {
                out.push(format!(
                    "drive too weak to move anything: A = {a:e} m is less than a thousandth of the smallest grain radius"
                ));
            }
        }
        out
    }
}

/// The scene key of an engine field (`rules.pair[0].e` stays, `width` is `box.width`).
fn engine_key(field: &str) -> String {
    match field {
        "width" | "height" | "gravity" => format!("box.{field}"),
        "amplitude" => "drive.amplitude".into(),
        "waveform" => "drive.waveform".into(),
        "q" => "particles.shape".into(),
        "initial_speed" => "particles.initial_speed".into(),
        f if f.starts_with("species") => format!("particles.{f}"),
        f if f.starts_with("floor.") || f.starts_with("lid.") => format!("drive.{}", f.split_once('.').map_or(f, |x| x.1)),
        f => f.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mixture() -> String {
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mixture.toml")).unwrap()
    }

    fn ratchet() -> String {
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml")).unwrap()
    }

    #[test]
    fn the_ratchet_scene_maps_onto_the_paper_and_a_bad_base_names_its_key() {
        let c = parse(&ratchet(), &[]).unwrap().config().unwrap();
        let base = c.base.unwrap();
        assert_eq!((base.width, base.height, base.asymmetry), (6e-3, 3e-3, 0.1));
        assert!((c.width / base.width - 24.0).abs() < 1e-9);
        assert_eq!(c.q, 0.5);
        let key = |set: &[&str]| match parse(&ratchet(), set).and_then(|s| s.config()) {
            Err(e) => e.key,
            Ok(_) => "accepted".into(),
        };
        assert_eq!(key(&["base.tooth_width=0.007"]), "base.tooth_width");
        assert_eq!(key(&["base.tip_radius=0.004"]), "base.tip_radius");
        assert_eq!(key(&["base.asymmetry=-0.1"]), "base.asymmetry");
        assert_eq!(key(&["base.shape=\"sine\""]), "base.shape");
        assert_eq!(key(&["base.tooth_height=0.06"]), "base.tooth_height");
    }

    fn parse(text: &str, set: &[&str]) -> Result<EventScene, SceneError> {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        overrides::parse(text, &set, "test", |doc| {
            EventScene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())
        })
    }

    fn keys(prefix: &str, v: &toml::Value, out: &mut Vec<String>) {
        match v {
            toml::Value::Table(t) => {
                for (k, x) in t {
                    keys(&if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") }, x, out);
                }
            }
            toml::Value::Array(a) if a.iter().all(|x| x.is_table()) => {
                for x in a {
                    keys(prefix, x, out);
                }
            }
            _ => out.push(prefix.to_string()),
        }
    }

    #[test]
    fn every_event_scene_key_is_documented() {
        let mut all = Vec::new();
        let vibrated_box = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml")).unwrap();
        for text in [mixture(), ratchet(), vibrated_box] {
            let scene = parse(
                &text,
                &[
                    "guard.min_rebound_speed=1e-4",
                    "guard.tc=1e-6",
                    "guard.collapse_speed=1e-3",
                    "particles.q=0.5",
                    "run.phase=0.5",
                    "run.phase_resolved=true",
                ],
            )
            .unwrap();
            keys("", &toml::Value::try_from(&scene).unwrap(), &mut all);
        }
        all.sort();
        all.dedup();
        assert!(all.len() > 25, "{all:?}");
        let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md")).unwrap();
        let section = &docs[docs.find("## Event-driven scenes").expect("the events section")..];
        let missing: Vec<&String> = all
            .iter()
            .filter(|k| {
                // A wall rule's keys are documented with the pair's ("likewise for each wall").
                let k = k
                    .replace("rules.floor.", "rules.pair.")
                    .replace("rules.side.", "rules.pair.")
                    .replace("rules.lid.", "rules.pair.");
                !section.contains(&format!("`{k}`"))
            })
            .collect();
        assert!(missing.is_empty(), "docs/scenes.md does not document {missing:?}");
    }

    #[test]
    fn the_mixture_scene_maps_onto_the_paper_and_bad_values_name_their_key() {
        let c = parse(&mixture(), &[]).unwrap().config().unwrap();
        assert_eq!(c.species.len(), 2);
        assert_eq!(c.species[0].count + c.species[1].count, 300);
        assert!((c.width / 1.6e-3 - 48.0).abs() < 1e-9 && (c.height / 1.6e-3 - 32.0).abs() < 1e-9);
        assert_eq!(c.floor.unwrap().frequency, 50.0);
        let key = |set: &[&str]| match parse(&mixture(), set).and_then(|s| s.config()) {
            Err(e) => e.key,
            Ok(_) => "accepted".into(),
        };
        assert_eq!(key(&["rules.pair.e=[1.2, 0.8, 0.7]"]), "rules.pair[0].e");
        assert_eq!(key(&["rules.pair.beta0=1.5"]), "rules.pair[0].beta0");
        assert_eq!(key(&["rules.floor.mu=-1"]), "rules.floor[0].mu");
        assert_eq!(key(&["drive.amplitude=0.03"]), "drive.amplitude");
        assert_eq!(key(&["rules.pair.e=[0.9, 0.8]"]), "rules.pair.e");
        assert_eq!(key(&["box.side_walls=round"]), "box.side_walls");
        assert_eq!(key(&["model=tray"]), "model");
        // 1e9 Hz sampled 4 times a period for 10 s: 4e10 samples, a run that would never end.
        assert_eq!(key(&["drive.frequency=1e9"]), "run.samples_per_period");
        assert_eq!(key(&["run.duration=6e4"]), "run.samples_per_period");
        // The papers' observables and the inertia factor.
        for phase in ["1.0", "-0.25", "1.5"] {
            assert_eq!(key(&[&format!("run.phase={phase}")]), "run.phase");
        }
        assert_eq!(key(&["run.samples_per_period=4", "run.phase=0.3"]), "run.phase");
        for q in ["0.0", "-0.4", "1.01"] {
            assert_eq!(key(&[&format!("particles.q={q}")]), "particles.q");
        }
        assert_eq!(key(&["guard.collapse_speed=0.0"]), "guard.collapse_speed");
        assert_eq!(key(&["run.duration=4e4"]), "accepted");
        assert_eq!(key(&["run.transient=20"]), "run.transient");
        assert_eq!(key(&["rules.floor.e=[1.0, 1.0]", "rules.floor.table=x.csv"]), "rules.floor.table");
        assert_eq!(key(&["drive.peak_speed=0.5"]), "drive.peak_speed");
    }

    #[test]
    fn a_peak_speed_sets_the_amplitude_at_the_scene_frequency() {
        let box_scene = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml")).unwrap();
        for f in [40.0, 100.0, 500.0] {
            let s = parse(&box_scene, &[&format!("drive.frequency={f}"), "drive.peak_speed=0.8"]).unwrap();
            let a = s.config().unwrap().floor.unwrap().amplitude;
            assert!((a * 2.0 * std::f64::consts::PI * f - 0.8).abs() < 1e-12, "{f} Hz: A = {a}");
        }
        let both = parse(&box_scene, &["drive.amplitude=0.001"]).unwrap().config().unwrap_err();
        assert_eq!(both.key, "drive.peak_speed");
        let mut neither = parse(&box_scene, &[]).unwrap();
        neither.drive.peak_speed = None;
        assert_eq!(neither.config().unwrap_err().key, "drive.amplitude");
        assert_eq!(
            parse(&box_scene, &["drive.peak_speed=-1"]).unwrap().config().unwrap_err().key,
            "drive.peak_speed"
        );
    }

    #[test]
    fn a_restitution_table_is_read_as_a_full_grid_and_used_as_the_rule() {
        let d = std::env::temp_dir().join(format!("stripes-events-table-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("restitution.csv");
        std::fs::write(
            &p,
            "g_n,g_t_over_g_n,eps_n,beta\n0.1,0,0.9,-0.5\n0.1,2,0.8,-1\n1,0,0.7,0.5\n1,2,0.6,0\n",
        )
        .unwrap();
        let t = read_table(&p).unwrap();
        assert_eq!(t.at(0.55, 1.0).0, 0.75);
        let set = format!("rules.pair.table={}", p.display());
        let c = parse(&mixture(), &["rules.pair.e=[]", &set]);
        assert!(c.is_err() || c.unwrap().config().is_err(), "e beside a table is refused");
        let mut scene = parse(&mixture(), &[]).unwrap();
        scene.rules.pair = EventRule {
            e: None,
            table: Some(p.clone()),
            mu: 0.0,
            beta0: -1.0,
            v0: None,
        };
        let c = scene.config().unwrap();
        assert!(matches!(c.rules.pair[0], Rule::Table(_)) && c.rules.pair.len() == 3);
        std::fs::write(&p, "g_n,g_t_over_g_n,eps_n,beta\n0.1,0,0.9,-0.5\n1,2,0.6,0\n").unwrap();
        assert!(read_table(&p).unwrap_err().contains("not a full grid"));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_drive_waveform_is_a_sine_or_a_sawtooth_and_anything_else_names_its_key() {
        let key = |set: &[&str]| match parse(&mixture(), set).and_then(|s| s.config()) {
            Err(e) => e.key,
            Ok(c) => format!("{:?}", c.waveform),
        };
        assert_eq!(key(&[]), "Sine");
        assert_eq!(key(&["drive.waveform=sawtooth"]), "Sawtooth");
        assert_eq!(key(&["drive.waveform=square"]), "drive.waveform");
        // The engine's refusal (sides that move with the floor) names the scene key.
        assert_eq!(key(&["drive.waveform=sawtooth", "box.side_walls=with-floor"]), "drive.waveform");
        // The default leaves the scene's fingerprint (and its checkpoints) as they were.
        let scene = parse(&mixture(), &[]).unwrap();
        assert!(!serde_json::to_string(&scene.drive).unwrap().contains("waveform"));
    }
}
