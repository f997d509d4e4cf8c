//! An event-driven scene checked and mapped onto the engine's [`Config`]: every value is
//! checked here or by [`Config::validate`], and every error names the scene's dotted key
//! (the engine names its fields by the same keys).

use std::path::Path;
use std::sync::Arc;

use super::{BaseShape, EventRule, EventScene, Floor, Lid, SceneError};
use crate::collision::{Restitution, Rule, Table};
use crate::config::{Config, Guard, Mass, Rules, Species};
use crate::error::EventsError;
use crate::sawtooth::Sawtooth;
use crate::wall::Motion;

/// The most samples (observer updates and frames) a run may take: about 5 us each and a
/// frame of 48 bytes per particle, so 1e7 samples are about a minute of sampling and 24 GB of
/// snapshots for the vibrated box's 50 spheres. The shipped scenes take at most 1.8e5.
pub const MAX_SAMPLES: f64 = 1e7;

fn bad(key: &str, message: impl Into<String>) -> SceneError {
    SceneError::new(key, message)
}

impl EventRule {
    /// The engine's rules of this contact class (`key`, e.g. `rules.pair`) for `count`
    /// species or pairs; a table is read by `read_table` from its path (an error names
    /// `key.table`).
    fn rules(&self, count: usize, key: &str, read_table: &dyn Fn(&Path) -> Result<Table, String>) -> Result<Vec<Rule>, SceneError> {
        if let Some(path) = &self.table {
            if self.e.is_some() || self.mu != 0.0 || self.beta0 != -1.0 || self.v0.is_some() {
                return Err(bad(
                    &format!("{key}.table"),
                    "a table replaces e, mu, beta0 and v0: give either the table or them",
                ));
            }
            let table = Arc::new(read_table(path).map_err(|m| bad(&format!("{key}.table"), m))?);
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

impl EventScene {
    /// The engine's configuration; every value is checked (here or by the engine, whose
    /// errors name the same keys). `read_table` reads a restitution table from the path a
    /// rule's `table` names (this crate reads no file; the root crate gives its reader).
    pub fn config(&self, read_table: &dyn Fn(&Path) -> Result<Table, String>) -> Result<Config, SceneError> {
        let motion = Motion {
            amplitude: self.drive.amplitude()?,
            frequency: self.drive.frequency,
            phase: self.drive.phase,
        };
        let q = match self.particles.q {
            Some(q) if !(q > 0.0 && q <= 1.0) => {
                return Err(bad(
                    "particles.q",
                    format!("the inertia factor I/(m R^2) must lie in (0, 1], got {q}"),
                ))
            }
            Some(q) => q,
            None => self.particles.shape.q(),
        };
        let n = self.particles.species.len();
        if n == 0 || n > 2 {
            return Err(bad("particles.species", format!("one or two species, got {n}")));
        }
        let r = &self.rules;
        let pairs = if n == 2 { 3 } else { 1 };
        let rules = Rules {
            pair: r.pair.rules(pairs, "rules.pair", read_table)?,
            floor: r.floor.rules(n, "rules.floor", read_table)?,
            side: r.side.rules(n, "rules.side", read_table)?,
            lid: r.lid.rules(n, "rules.lid", read_table)?,
        };
        self.check_run()?;
        self.check_sizes()?;
        let config = Config {
            width: self.tray.width,
            height: self.tray.height,
            side_walls: self.tray.side_walls,
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
                            (Some(m), None) => Mass::Each(m),
                            (None, Some(rho)) => Mass::Density(rho),
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
            floor: Some(match self.drive.floor {
                Floor::Vibrated => motion,
                Floor::Fixed => Motion::FIXED,
            }),
            base: self.base.as_ref().map(|b| match b.shape {
                BaseShape::Sawtooth => Sawtooth {
                    width: b.tooth_width,
                    height: b.tooth_height,
                    asymmetry: b.asymmetry,
                    tip_radius: b.tip_radius,
                },
            }),
            lid: match self.drive.lid {
                Lid::Vibrated => Some(motion),
                Lid::Fixed => Some(Motion::FIXED),
                Lid::None => None,
            },
            waveform: self.drive.waveform,
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
            EventsError::Invalid { field, message } => bad(&field, message),
            other => bad("scene", other.to_string()),
        })?;
        Ok(config)
    }

    /// `[run]` and the drive's frequency: the duration, the transient, the sampling and the
    /// phase of the summary, and the samples they imply.
    fn check_run(&self) -> Result<(), SceneError> {
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
        Ok(())
    }
}
