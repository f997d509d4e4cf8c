//! `[automaton]`: the automaton's table of a scene file (`stripes automaton`, thesis 3.1). The
//! flight cap and the sliding threshold follow from the scene's `[drive]`, floor friction and
//! mean diameter; the keys here switch ingredients and hold the free parameters that
//! `stripes automaton --calibrate` fits. The DEM never sees this table.

use serde::{Deserialize, Serialize};

use crate::mapping::{FreeParams, GradedChoice};
use crate::params::{Lateral, RuleSet};
use crate::transport::SlopeTable;

/// How far a flying grain goes where grains roll (`[automaton] transport`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TransportKind {
    /// Up to the cap; `frustration` decides who flies (the default).
    Frustration,
    /// Each grain its own excursion against the packing of its strip, from the DEM's
    /// measured slope (`slope`), with the melt rule (`melt`, `melt_gamma`); replaces
    /// `frustration` ([`crate::transport`]).
    Graded,
}

/// The `[automaton]` table; every key is optional.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Spec {
    /// `physical` (default) or `strict`.
    pub rule: RuleSet,
    /// Nothing moves unless `A (2 pi nu)^2 > mu g` (with `rolling`, only a grain that cannot
    /// roll is held by this threshold, see [`crate::mapping`]).
    pub threshold: bool,
    /// Free grains roll: below the sliding threshold a free sphere still rolls without slip
    /// and moves by the single-sphere DEM's excursion (2 (5/7) A relative to the tray); which
    /// grains cannot roll is said by `frustration`. Off: the sliding reading, where nothing
    /// moves below the threshold.
    pub rolling: bool,
    /// Frustrated rolling (with `rolling`, while a free sphere rolls, Gamma <= 7 mu / 2): crowded grains cannot
    /// roll (two spheres rolling the same way rub at their contact, thesis 3.4); each occupied
    /// neighbouring cell holds a grain with probability `frustration_probability`, so a grain
    /// with `n` neighbours flies with probability `(1 - p)^n`.
    pub frustration: bool,
    /// Probability per half period that one occupied neighbouring cell holds a grain, in [0, 1].
    pub frustration_probability: f64,
    /// Trains (with `rolling`, while a free sphere rolls): free grains roll together with
    /// the floor, so flying grains do not stop one another; only resting grains do.
    pub trains: bool,
    /// Where grains roll: `frustration` (default) or `graded` transport.
    pub transport: TransportKind,
    /// With `transport = "graded"`: the DEM's slope table, `in-bands` (default, 19 s) or
    /// `before-bands` (1 s); chosen on the stripe scene's seed 1
    /// (`docs/results/automaton-pattern/report.md`).
    pub slope: SlopeTable,
    /// With `transport = "graded"`: agitation melts the crowding's hold above `melt_gamma`.
    pub melt: bool,
    /// `Gamma_c` of the melt rule: the peak tray acceleration over g at which the layer
    /// lifts off the floor and pair friction stops holding crowded grains (default 1.35,
    /// fitted on part of the phase map; the DEM brackets it between 0.64 and 1.42).
    pub melt_gamma: f64,
    /// With `transport = "graded"`: length of the strip over which a grain's local packing
    /// is taken (m; the DEM's measurement used 1 mm).
    pub packing_window: f64,
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
    pub lateral: Lateral,
    /// Sideways (y) moves.
    pub sideways: bool,
    /// Probability per half period of a sideways move, in [0, 1].
    pub sideways_probability: f64,
    /// Cell length (m); absent: the mean grain diameter.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cell: Option<f64>,
    /// Write a snapshot every this many drive periods (and at the last), so that long runs
    /// fit in memory and on disk; at least 1 and at most the run's periods.
    pub snapshot_every: u64,
    /// A parameter file written by `stripes mechanism RUN` (`RUN/mechanism/automaton.toml`);
    /// a relative path is read from the working directory. With it the rule is `measured`
    /// (or `strict`), and the cell the file's (in place of `cell`, said in the run's warnings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parameters: Option<std::path::PathBuf>,
    /// Use a parameter file measured on another scene (other grains, tray or drive); the run's
    /// summary then carries a warning.
    pub parameters_force: bool,
    /// The cell of the parameter file (`cell.size_m`, m), filled in by the root crate when it
    /// reads the file; never scene text.
    #[serde(skip)]
    pub parameters_cell: Option<f64>,
}

impl Default for Spec {
    fn default() -> Self {
        Self {
            rule: RuleSet::Physical,
            threshold: true,
            rolling: true,
            frustration: true,
            frustration_probability: 0.1,
            trains: true,
            transport: TransportKind::Frustration,
            slope: SlopeTable::InBands,
            melt: true,
            melt_gamma: 1.35,
            packing_window: 1e-3,
            flight_cap: true,
            stochastic: true,
            activation: 0.8,
            knock: true,
            knock_speed: 7.0,
            lateral: Lateral::Clusters,
            sideways: true,
            sideways_probability: 0.1,
            cell: None,
            snapshot_every: 1,
            parameters: None,
            parameters_force: false,
            parameters_cell: None,
        }
    }
}

/// A bad value in the table, naming its dotted key.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecError {
    pub key: String,
    pub message: String,
}

impl std::fmt::Display for SpecError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "scene `{}`: {}", self.key, self.message)
    }
}

impl std::error::Error for SpecError {}

impl Spec {
    /// Whether every key holds its default.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the values; errors name the key.
    pub fn validate(&self) -> Result<(), SpecError> {
        let err = |key: &str, message: String| SpecError { key: key.into(), message };
        if self.snapshot_every == 0 {
            return Err(err(
                "automaton.snapshot_every",
                "must be at least 1 (periods between snapshots), got 0".into(),
            ));
        }
        for (key, p) in [
            ("automaton.activation", self.activation),
            ("automaton.sideways_probability", self.sideways_probability),
            ("automaton.frustration_probability", self.frustration_probability),
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
        for (key, v) in [
            ("automaton.melt_gamma", self.melt_gamma),
            ("automaton.packing_window", self.packing_window),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(err(key, format!("must be positive and finite, got {v}")));
            }
        }
        if self.parameters_force && self.parameters.is_none() {
            return Err(err("automaton.parameters_force", "needs automaton.parameters".into()));
        }
        self.rule_with(None)?;
        if let Some(c) = self.cell {
            if !(c.is_finite() && c > 0.0) {
                return Err(err("automaton.cell", format!("must be a positive length (m), got {c}")));
            }
        }
        Ok(())
    }

    /// The rule that runs, given the command line's choice: with `parameters`, `physical`
    /// (the default) becomes `measured`, and `strict` stays; `measured` needs `parameters`.
    pub fn rule_with(&self, chosen: Option<RuleSet>) -> Result<RuleSet, SpecError> {
        let err = |key: &str, message: &str| SpecError {
            key: key.into(),
            message: message.into(),
        };
        match (chosen, self.rule, &self.parameters) {
            (Some(RuleSet::Physical), _, Some(_)) => Err(err(
                "automaton.parameters",
                "rule physical takes its numbers from the tray, not from a parameter file: use rule measured or strict, or drop automaton.parameters",
            )),
            (None, RuleSet::Physical, Some(_)) => Ok(RuleSet::Measured),
            (Some(r), _, None) | (None, r, None) if r.is_measured() => Err(err(
                "automaton.parameters",
                "rules measured and swing need a parameter file: automaton.parameters = \"RUN/mechanism/automaton.toml\" (written by `stripes mechanism RUN`)",
            )),
            (chosen, rule, _) => Ok(chosen.unwrap_or(rule)),
        }
    }

    /// The free parameters this table sets (ingredients switched off are `None`).
    pub fn free_params(&self) -> FreeParams {
        FreeParams {
            activation: self.stochastic.then_some(self.activation),
            knock_speed: self.knock.then_some(self.knock_speed),
            sideways: self.sideways.then_some(self.sideways_probability),
            lateral: self.lateral,
            threshold: self.threshold,
            rolling: self.rolling,
            frustration: self.frustration.then_some(self.frustration_probability),
            trains: self.trains,
            flight_cap: self.flight_cap,
            graded: (self.transport == TransportKind::Graded).then_some(GradedChoice {
                slope: self.slope,
                melt_gamma: self.melt.then_some(self.melt_gamma),
                window: self.packing_window,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_name_their_key() {
        for (spec, key) in [
            (
                Spec {
                    activation: 1.5,
                    ..Spec::default()
                },
                "automaton.activation",
            ),
            (
                Spec {
                    sideways_probability: -0.1,
                    ..Spec::default()
                },
                "automaton.sideways_probability",
            ),
            (
                Spec {
                    knock_speed: 0.0,
                    ..Spec::default()
                },
                "automaton.knock_speed",
            ),
            (
                Spec {
                    melt_gamma: 0.0,
                    ..Spec::default()
                },
                "automaton.melt_gamma",
            ),
            (
                Spec {
                    packing_window: f64::NAN,
                    ..Spec::default()
                },
                "automaton.packing_window",
            ),
            (
                Spec {
                    cell: Some(-1e-3),
                    ..Spec::default()
                },
                "automaton.cell",
            ),
        ] {
            assert_eq!(spec.validate().unwrap_err().key, key);
        }
        Spec::default().validate().unwrap();
    }
}
