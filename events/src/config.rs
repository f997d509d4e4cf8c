//! The parameters of an event-driven run, validated once: every error names its field by
//! the key of the scene that sets it ([`crate::scene`]), `box.width`, `drive.amplitude`.
//!
//! The box spans `0 <= x <= width` (periodic, or between side walls) and `0 <= z <= height`
//! above the floor's mean position; the lid, if any, stands at `z = height`. Horizontal walls
//! oscillate as `A sin(2 pi f t + phi)`, or stand still and push every grain that strikes them
//! at `A 2 pi f` (a sawtooth of negligible excursion, [`Waveform::Sawtooth`]). Particles are disks or spheres (the inertia factor
//! `q`) of up to two species, with radii uniform in a range and a mass per particle.

use crate::collision::Rule;
use crate::error::{invalid, EventsError};
use crate::sawtooth::Sawtooth;
use crate::wall::{Motion, Waveform};

/// One species.
#[derive(Clone, Debug, PartialEq)]
pub struct Species {
    pub count: usize,
    /// Radii uniform in `[radius_min, radius_max]` (m).
    pub radius_min: f64,
    pub radius_max: f64,
    /// Mass of each particle (kg), or how it follows from the radius.
    pub mass: Mass,
}

/// The mass of a species' particles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mass {
    /// The same mass for every particle (kg).
    Each(f64),
    /// A material density (kg/m^3): `m = rho (4/3) pi R^3`, the mass of a bead of radius R
    /// (for disks as for spheres; the shape sets only the inertia factor).
    Density(f64),
}

impl Mass {
    /// The mass of a particle of radius `r` (kg).
    pub fn of(&self, r: f64) -> f64 {
        match *self {
            Mass::Each(m) => m,
            Mass::Density(rho) => rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3),
        }
    }
}

/// The side walls (`box.side_walls` of a scene: `fixed`, `periodic` or `with-floor`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum SideWalls {
    /// No side walls: x is periodic.
    Periodic,
    /// Fixed walls at x = 0 and x = width.
    Fixed,
    /// Walls at x = 0 and x = width that move vertically with the floor (friction only).
    WithFloor,
}

/// The collision rule of every contact class. Pair rules are indexed by species pair:
/// `pair[0]` for 1-1, `pair[1]` for 1-2, `pair[2]` for 2-2; wall rules by species.
#[derive(Clone, Debug, PartialEq)]
pub struct Rules {
    pub pair: Vec<Rule>,
    pub floor: Vec<Rule>,
    pub side: Vec<Rule>,
    pub lid: Vec<Rule>,
}

impl Rules {
    /// One rule for every pair and one for every wall, for `species` species.
    pub fn uniform(pair: Rule, wall: Rule, species: usize) -> Self {
        let pairs = if species == 2 { 3 } else { 1 };
        Rules {
            pair: vec![pair; pairs],
            floor: vec![wall.clone(); species],
            side: vec![wall.clone(); species],
            lid: vec![wall; species],
        }
    }

    /// The rule between species `a` and `b`.
    pub fn pair(&self, a: usize, b: usize) -> &Rule {
        &self.pair[a + b]
    }
}

/// Guards against inelastic collapse, each a choice with its cost:
/// - `min_rebound_speed` (the sawtooth paper): a collision never leaves a normal relative
///   speed below it, even after a slower approach, so a grain resting on a floor keeps
///   hopping with this speed (it adds energy where grains should rest: hops of `v^2 / 2g`,
///   and a grain riding a plate leaves it about `sqrt(v / (A omega^3))` early);
/// - `tc` (the TC model of Luding and McNamara): a particle that collided less than `tc`
///   ago collides elastically (it keeps the gas from collapsing; dense clusters are too
///   elastic below the time scale `tc`).
///
/// Without a guard, a run that collapses stops: more than `collapse_events` slow collisions
/// of one particle within `collapse_window` seconds is an error naming the particles. A
/// collision is slow when its normal approach speed is below `collapse_speed`: an inelastic
/// collapse drives the approach speeds of its collisions to zero, while fast, dense dynamics
/// (a grain rattling between a neighbour and a wall that moves at metres per second, at
/// Gamma in the hundreds) can collide as often at finite speeds, and is not a collapse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guard {
    pub min_rebound_speed: Option<f64>,
    pub tc: Option<f64>,
    pub collapse_window: f64,
    pub collapse_events: u32,
    /// The approach speed below which a collision counts towards a collapse (m/s); `None`:
    /// [`Guard::DEFAULT_COLLAPSE_FRACTION`] of `sqrt(g d_max)`, or of `initial_speed`
    /// without gravity (every collision counts when both are zero).
    pub collapse_speed: Option<f64>,
}

impl Guard {
    /// The default slow collision, as a fraction of the speed scale `sqrt(g d_max)`.
    pub const DEFAULT_COLLAPSE_FRACTION: f64 = 1e-3;
}

impl Default for Guard {
    fn default() -> Self {
        Guard {
            min_rebound_speed: None,
            tc: None,
            collapse_window: 1e-6,
            collapse_events: 1000,
            collapse_speed: None,
        }
    }
}

/// Everything that defines a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// Box width along x (m).
    pub width: f64,
    /// Box height above the floor's mean position (m): the lid's mean position, and the top
    /// of the region particles are placed in.
    pub height: f64,
    pub side_walls: SideWalls,
    /// Gravity (m/s^2, >= 0, pointing to -z).
    pub gravity: f64,
    /// Inertia factor `I / (m R^2)` (2/5 spheres, 1/2 disks).
    pub q: f64,
    pub species: Vec<Species>,
    /// The floor at `z = 0` and its motion (`None`: no floor, allowed only without gravity).
    pub floor: Option<Motion>,
    /// A sawtooth base in place of the flat floor, moving with the floor's motion, its
    /// valleys at `z = 0`; the box width must hold a whole number of teeth.
    pub base: Option<Sawtooth>,
    /// The lid at `z = height` and its motion (`None`: open top).
    pub lid: Option<Motion>,
    /// How the vibrated floor and lid move: the sinusoid of their motions, or a sawtooth of
    /// negligible excursion at the sinusoid's peak speed.
    pub waveform: Waveform,
    pub rules: Rules,
    pub guard: Guard,
    /// Initial velocities uniform in `[-initial_speed, initial_speed]` per component (m/s).
    pub initial_speed: f64,
    pub seed: u64,
}

impl Config {
    /// The largest radius of all species (m).
    pub fn radius_max(&self) -> f64 {
        self.species.iter().map(|s| s.radius_max).fold(0.0, f64::max)
    }

    /// The approach speed below which a collision counts towards a collapse (m/s): the
    /// guard's `collapse_speed`, or its default from the speed scale of the run.
    pub fn collapse_speed(&self) -> f64 {
        if let Some(v) = self.guard.collapse_speed {
            return v;
        }
        let scale = if self.gravity > 0.0 {
            (self.gravity * 2.0 * self.radius_max()).sqrt()
        } else {
            self.initial_speed
        };
        if scale > 0.0 {
            Guard::DEFAULT_COLLAPSE_FRACTION * scale
        } else {
            f64::INFINITY
        }
    }

    /// Checks every parameter; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), EventsError> {
        let positive = |field: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(invalid(field, format!("must be a positive number, got {x}")))
            }
        };
        positive("box.width", self.width)?;
        positive("box.height", self.height)?;
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(invalid("box.gravity", format!("must be >= 0, got {}", self.gravity)));
        }
        if !(self.q > 0.0 && self.q <= 1.0) {
            return Err(invalid(
                "particles.q",
                format!("the inertia factor I/(m R^2) must lie in (0, 1], got {}", self.q),
            ));
        }
        if self.species.is_empty() || self.species.len() > 2 {
            return Err(invalid(
                "particles.species",
                format!("one or two species, got {}", self.species.len()),
            ));
        }
        for (k, s) in self.species.iter().enumerate() {
            let f = |name: &str| format!("particles.species[{k}].{name}");
            if s.count == 0 {
                return Err(invalid(&f("count"), "must be at least 1"));
            }
            positive(&f("radius_min"), s.radius_min)?;
            positive(&f("radius_max"), s.radius_max)?;
            if s.radius_max < s.radius_min {
                return Err(invalid(&f("radius_max"), "must be >= radius_min"));
            }
            match s.mass {
                Mass::Each(m) => positive(&f("mass"), m)?,
                Mass::Density(rho) => positive(&f("density"), rho)?,
            }
        }
        let d = 2.0 * self.radius_max();
        if d >= self.width || d >= self.height {
            return Err(invalid(
                "particles.species.radius_max",
                format!(
                    "a particle of diameter {d} m does not fit in the box {} x {} m",
                    self.width, self.height
                ),
            ));
        }
        // The floor's and the lid's motions are the scene's one drive.
        for m in [self.floor, self.lid].into_iter().flatten() {
            if !(m.amplitude.is_finite() && m.amplitude >= 0.0) {
                return Err(invalid("drive.amplitude", format!("must be >= 0, got {}", m.amplitude)));
            }
            if m.amplitude > 0.0 && !(m.frequency.is_finite() && m.frequency > 0.0) {
                return Err(invalid("drive.frequency", format!("must be positive, got {}", m.frequency)));
            }
            if !m.phase.is_finite() {
                return Err(invalid("drive.phase", "must be finite"));
            }
        }
        let swing = self.floor.map_or(0.0, |m| m.amplitude) + self.lid.map_or(0.0, |m| m.amplitude);
        if self.lid.is_some() && 2.0 * swing + d >= self.height {
            return Err(invalid(
                "drive.amplitude",
                format!(
                    "floor and lid swing by {swing} m each way: they would meet a particle of diameter {d} m in a box {} m high",
                    self.height
                ),
            ));
        }
        if let Some(base) = &self.base {
            base.validate().map_err(|(field, message)| invalid(field, message))?;
            if self.floor.is_none() {
                return Err(invalid("base", "a sawtooth base moves with the floor: it needs a floor"));
            }
            let teeth = self.width / base.width;
            if (teeth - teeth.round()).abs() > 1e-9 * teeth.max(1.0) {
                return Err(invalid(
                    "base.tooth_width",
                    format!("the box width {} m must hold a whole number of teeth, got {teeth}", self.width),
                ));
            }
            if self.lid.is_some() && base.height + 2.0 * swing + d >= self.height {
                return Err(invalid(
                    "base.tooth_height",
                    format!(
                        "teeth {} m high swinging by {swing} m leave no room for a particle of diameter {d} m under the lid at {} m",
                        base.height, self.height
                    ),
                ));
            }
        }
        if self.floor.is_none() && self.gravity > 0.0 {
            return Err(invalid("drive.floor", "gravity needs a floor"));
        }
        if self.waveform == Waveform::Sawtooth {
            if self.base.is_some() {
                return Err(invalid(
                    "drive.waveform",
                    "a sawtooth drive stands the floor still, which a sawtooth base cannot follow: use the sine",
                ));
            }
            if self.side_walls == SideWalls::WithFloor {
                return Err(invalid(
                    "drive.waveform",
                    "a sawtooth drive has no wall velocity for side walls that move with the floor: use fixed or periodic sides",
                ));
            }
        }
        let n = self.species.len();
        let pairs = if n == 2 { 3 } else { 1 };
        if self.rules.pair.len() != pairs {
            return Err(invalid("rules.pair", format!("needs {pairs} rule(s) for {n} species")));
        }
        for (name, rules) in [
            ("rules.floor", &self.rules.floor),
            ("rules.side", &self.rules.side),
            ("rules.lid", &self.rules.lid),
        ] {
            if rules.len() != n {
                return Err(invalid(name, format!("needs one rule per species ({n})")));
            }
        }
        for (k, r) in self.rules.pair.iter().enumerate() {
            r.validate(&format!("rules.pair[{k}]"))?;
        }
        for (name, rules) in [
            ("rules.floor", &self.rules.floor),
            ("rules.side", &self.rules.side),
            ("rules.lid", &self.rules.lid),
        ] {
            for (k, r) in rules.iter().enumerate() {
                r.validate(&format!("{name}[{k}]"))?;
            }
        }
        if let Some(v) = self.guard.min_rebound_speed {
            positive("guard.min_rebound_speed", v)?;
        }
        if let Some(tc) = self.guard.tc {
            positive("guard.tc", tc)?;
        }
        positive("guard.collapse_window", self.guard.collapse_window)?;
        if let Some(v) = self.guard.collapse_speed {
            if v.is_nan() || v <= 0.0 {
                return Err(invalid(
                    "guard.collapse_speed",
                    format!("must be a positive speed (or inf: every collision counts), got {v}"),
                ));
            }
        }
        if self.guard.collapse_events < 2 {
            return Err(invalid("guard.collapse_events", "must be at least 2"));
        }
        if !(self.initial_speed.is_finite() && self.initial_speed >= 0.0) {
            return Err(invalid(
                "particles.initial_speed",
                format!("must be >= 0, got {}", self.initial_speed),
            ));
        }
        Ok(())
    }
}
