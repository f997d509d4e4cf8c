//! Rules and parameters of the automaton. Every ingredient of the `physical` rule set is a
//! slot with an explicit `None` variant, so the automaton has its own ablations.

use serde::{Deserialize, Serialize};

use crate::measured_rule::MeasuredRule;
use crate::transport::Graded;

/// Which rule set runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RuleSet {
    /// Thesis 3.1 exactly: every top-layer grain flies, alternately left and right, until it
    /// touches a grain of the unchanged copy L; then grains fall until they rest. In a
    /// submonolayer this is a rigid translation of the pattern by one cell per half step.
    Strict,
    /// The strict rules plus what a shaken tray supplies, in the tray frame ([`Physical`]).
    Physical,
    /// Flights, band-edge escapes and sideways steps drawn from the distributions measured on
    /// a DEM run ([`crate::measured_rule`]); needs [`Params::measured`].
    Measured,
    /// Every floor grain flies each half step by the swing measured at its local packing,
    /// with the measured spread about its neighbours ([`crate::swing`]); sideways steps as
    /// `measured`, no grain held. Needs [`Params::measured`] with a swing field.
    Swing,
}

impl RuleSet {
    /// Every name, as scene files and the command line write it.
    pub const NAMES: &'static [&'static str] = &["strict", "physical", "measured", "swing"];

    /// Whether the rule takes its numbers from a parameter file.
    pub fn is_measured(self) -> bool {
        matches!(self, RuleSet::Measured | RuleSet::Swing)
    }
}

impl std::str::FromStr for RuleSet {
    type Err = ParamsError;
    fn from_str(s: &str) -> Result<Self, ParamsError> {
        match s {
            "strict" => Ok(RuleSet::Strict),
            "physical" => Ok(RuleSet::Physical),
            "measured" => Ok(RuleSet::Measured),
            "swing" => Ok(RuleSet::Swing),
            _ => Err(ParamsError::UnknownRuleSet { given: s.into() }),
        }
    }
}

/// Parameters the automaton refuses; each names the field and the value.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamsError {
    /// A rule-set name that is neither of [`RuleSet::NAMES`].
    UnknownRuleSet { given: String },
    /// A probability outside [0, 1] (`field`: `activation`, `knock probability`, ...).
    Probability { field: &'static str, value: f64 },
    /// A length or area fraction that must be positive and finite (`field`: `graded window`,
    /// ...).
    Positive { field: &'static str, value: f64 },
    /// A sliding threshold with a negative or non-finite acceleration (m/s^2).
    Threshold {
        tray_acceleration: f64,
        friction_acceleration: f64,
    },
    /// The `measured` rule without its measured numbers (`automaton.parameters`).
    NoMeasurements,
    /// The `swing` rule with a parameter file that holds no swing field.
    NoSwingField,
    /// End walls in x under a rule whose rows wrap round.
    XWalls { rule: RuleSet },
}

impl std::fmt::Display for ParamsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamsError::UnknownRuleSet { given } => {
                write!(f, "unknown rule set `{given}`, expected one of {}", RuleSet::NAMES.join(", "))
            }
            ParamsError::Probability { field, value } => write!(f, "automaton.{field} must lie in [0, 1], got {value}"),
            ParamsError::XWalls { rule } => write!(
                f,
                "box.x_walls: the automaton's `{}` rule runs on rows that wrap round in x; end walls are modelled by the measured and swing rules only",
                format!("{rule:?}").to_lowercase()
            ),
            ParamsError::NoSwingField => write!(
                f,
                "rule `swing` needs a parameter file with a [swing_field]: run `stripes mechanism RUN --coarse-only` again"
            ),
            ParamsError::NoMeasurements => {
                write!(
                    f,
                    "rule `measured` needs a parameter file: set automaton.parameters (written by `stripes mechanism RUN`)"
                )
            }
            ParamsError::Positive { field, value } => write!(f, "automaton.{field} must be positive and finite, got {value}"),
            ParamsError::Threshold {
                tray_acceleration,
                friction_acceleration,
            } => write!(
                f,
                "automaton threshold: accelerations must be finite and >= 0, got {tray_acceleration} and {friction_acceleration}"
            ),
        }
    }
}

impl std::error::Error for ParamsError {}

/// Sliding threshold: grains slide on the tray only when its peak acceleration
/// `A (2 pi nu)^2` exceeds what floor friction can transmit, `mu g`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Threshold {
    /// Grains always fly.
    None,
    /// Nothing moves unless `tray_acceleration > friction_acceleration` (both m/s^2).
    Coulomb {
        tray_acceleration: f64,
        friction_acceleration: f64,
    },
}

/// Flight cap: the farthest a grain flies in one half period.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum FlightCap {
    /// Fly until contact (thesis rule 1).
    None,
    /// At most `cells` cells: a free grain's sliding displacement relative to the tray over
    /// one half period, in cells ([`crate::mapping`]).
    Cells { cells: usize },
}

/// Stochastic flights.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Activation {
    /// Every top-layer grain flies every half period.
    None,
    /// Each grain flies in a given half period with probability `p` (quantised to 1/64, [`crate::rng::ONE`]):
    /// the size-dependent drift terms of the DEM (rolling friction, viscous friction branch,
    /// walls, bouncing) that decide whether a grain keeps up with its neighbours.
    Bernoulli { p: f64 },
}

/// Momentum transfer through a line of touching grains.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Knock {
    /// Impacts stop the flying grain and nothing else.
    None,
    /// A grain whose flight ends on a line of touching grains knocks the far grain of the
    /// line loose with probability `p` (it flies at once, up to the cap, if it was resting):
    /// `p = 1 - exp(-(v / v_knock)^2)` with `v` the impact speed ([`crate::mapping`]). A
    /// lateral contact (see [`Lateral`]) holds only with probability `1 - p`.
    Bernoulli { p: f64 },
}

/// Frustrated rolling (thesis 3.4): two touching spheres rolling the same way rub at their
/// contact (their surfaces there move in opposite directions), so a crowded grain cannot roll
/// freely and rests with the tray, while a free grain rolls. In the DEM the rolling amplitude
/// falls steadily with the local packing (`docs/results/mechanism/report.md`, section 3); here
/// each occupied cell of the 8 around a grain (at its level) holds it independently, so a
/// grain with `n` neighbours flies with probability `(1 - p)^n`. Applies in the rolling
/// regime only ([`crate::mapping::physical`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Frustration {
    /// Touching grains fly like free ones.
    None,
    /// Each occupied neighbouring cell holds the grain with probability `p` (quantised to
    /// 1/64), on top of its activation.
    Bernoulli { p: f64 },
}

/// How far a flying grain goes (rolling regime only, [`crate::mapping::physical`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Transport {
    /// Every flying grain goes up to the cap; [`Frustration`] decides who flies.
    Uniform,
    /// Every grain goes its own excursion against the packing of its strip, from the DEM's
    /// measured slope `a(phi)`, scaled by the hold agitation leaves ([`crate::transport`]).
    /// Replaces [`Frustration`]; runs on the byte lattice, without knock-through.
    Graded(Graded),
}

/// Contacts with the neighbouring rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Lateral {
    /// A grain is stopped only by grains in its own row.
    None,
    /// Grains in rows `j - 1` and `j + 1` also stop a flight (disks one cell wide overlap
    /// their neighbouring rows in y). At the thesis packing this jams almost everything.
    Neighbours,
    /// Only grains of the neighbouring rows that touch an x-neighbour of their own row (part
    /// of a cluster, locked by friction) stop a flight; lone grains are passed. A cluster in
    /// one row so catches grains of the next: this couples rows into stripes across the tray.
    Clusters,
}

/// Sideways (y) moves after each flight.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Sideways {
    None,
    /// A top grain moves to the +y (or the -y) neighbour, each with probability `p / 2`,
    /// if that cell is lower.
    Bernoulli {
        p: f64,
    },
}

/// The y boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum YBoundary {
    /// Side walls: no row beyond 0 and ny - 1.
    Walls,
    /// Periodic in y.
    Periodic,
}

/// The `physical` ingredients.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Physical {
    pub threshold: Threshold,
    pub cap: FlightCap,
    pub activation: Activation,
    pub knock: Knock,
    pub lateral: Lateral,
    pub sideways: Sideways,
    pub frustration: Frustration,
    /// Trains: flying grains do not stop each other. Free grains roll with the floor and so
    /// move together (in the DEM they all follow 5/7 of the floor); only resting grains stop
    /// a flight, and a train queues up behind one. Off: every grain of the unchanged copy L
    /// is an obstacle (thesis 3.1 rule 1). Runs on the byte lattice ([`crate::scalar`]).
    pub trains: bool,
    /// How far a flying grain goes.
    #[serde(default = "uniform", skip_serializing_if = "is_uniform")]
    pub transport: Transport,
}

fn uniform() -> Transport {
    Transport::Uniform
}

fn is_uniform(t: &Transport) -> bool {
    *t == Transport::Uniform
}

impl Physical {
    /// Every ingredient off: the `physical` rules then equal the `strict` ones.
    pub fn off() -> Self {
        Self {
            threshold: Threshold::None,
            cap: FlightCap::None,
            activation: Activation::None,
            knock: Knock::None,
            lateral: Lateral::None,
            sideways: Sideways::None,
            frustration: Frustration::None,
            trains: false,
            transport: Transport::Uniform,
        }
    }
}

/// Everything an automaton run needs besides its lattice.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    pub rule: RuleSet,
    /// Used by `physical` only.
    pub physical: Physical,
    pub y: YBoundary,
    /// End walls at x = 0 and x = L (`box.x_walls`): rows end there instead of wrapping
    /// round. Only the `measured` and `swing` rules model them.
    #[serde(default)]
    pub x_walls: bool,
    /// Seed of the counter-based random bits.
    pub seed: u64,
    /// Used by `measured` only: the rule's numbers from a DEM run's parameter file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured: Option<MeasuredRule>,
}

/// Which half step runs: the run's seed and the half step's number `t` (they key the random
/// bits), and whether grains fly towards -x.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tick {
    pub seed: u64,
    pub t: u64,
    pub left: bool,
}

/// The resolved per-half-step numbers both update paths use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Resolved {
    /// Nothing moves (below the sliding threshold, or a zero flight cap).
    pub frozen: bool,
    /// Flight cap in cells (`usize::MAX`: none).
    pub cap: usize,
    /// Probabilities in units of 1/64 ([`crate::rng::ONE`]).
    pub activation: u32,
    pub knock: u32,
    pub sideways: u32,
    /// Probability that one occupied neighbouring cell holds a grain (0: no frustration).
    pub hold: u32,
    /// Flying grains of the own row are no obstacles ([`Physical::trains`]).
    pub trains: bool,
    pub lateral: Lateral,
    pub periodic_y: bool,
    /// Graded transport ([`Transport::Graded`]); `None`: every flight goes up to the cap.
    pub graded: Option<Graded>,
    /// The measured rule ([`crate::measured_rule`]); `None`: another rule set.
    pub measured: Option<MeasuredRule>,
    /// The measured rule's flights are the `swing` rule's ([`crate::swing`]).
    pub swing: bool,
    /// End walls in x ([`Params::x_walls`]).
    pub x_walls: bool,
}

impl Params {
    /// Checks the parameters; errors name the field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        let prob = |field: &'static str, value: f64| {
            if (0.0..=1.0).contains(&value) {
                Ok(())
            } else {
                Err(ParamsError::Probability { field, value })
            }
        };
        if self.x_walls && !self.rule.is_measured() {
            return Err(ParamsError::XWalls { rule: self.rule });
        }
        if self.rule.is_measured() {
            let m = self.measured.ok_or(ParamsError::NoMeasurements)?;
            if self.rule == RuleSet::Swing && m.swing.is_none() {
                return Err(ParamsError::NoSwingField);
            }
            prob("edge escape", m.edge_escape)?;
            for (field, value) in [("measured cell", m.cell_m), ("measured cell across", m.cell_y_m)] {
                if !(value.is_finite() && value > 0.0) {
                    return Err(ParamsError::Positive { field, value });
                }
            }
        }
        let ph = &self.physical;
        if let Activation::Bernoulli { p } = ph.activation {
            prob("activation", p)?;
        }
        if let Knock::Bernoulli { p } = ph.knock {
            prob("knock probability", p)?;
        }
        if let Sideways::Bernoulli { p } = ph.sideways {
            prob("sideways", p)?;
        }
        if let Frustration::Bernoulli { p } = ph.frustration {
            prob("frustration", p)?;
        }
        if let Transport::Graded(g) = ph.transport {
            prob("graded hold", g.hold)?;
            for (field, value) in [("graded grain fraction", g.grain_fraction), ("graded window", g.window_cells)] {
                if !(value.is_finite() && value > 0.0) {
                    return Err(ParamsError::Positive { field, value });
                }
            }
        }
        if let Threshold::Coulomb {
            tray_acceleration: a,
            friction_acceleration: f,
        } = ph.threshold
        {
            if !(a.is_finite() && a >= 0.0 && f.is_finite() && f >= 0.0) {
                return Err(ParamsError::Threshold {
                    tray_acceleration: a,
                    friction_acceleration: f,
                });
            }
        }
        Ok(())
    }

    pub(crate) fn resolve(&self) -> Resolved {
        let periodic_y = self.y == YBoundary::Periodic;
        match self.rule {
            RuleSet::Strict => Resolved {
                frozen: false,
                cap: usize::MAX,
                activation: crate::rng::ONE,
                knock: 0,
                sideways: 0,
                hold: 0,
                trains: false,
                lateral: Lateral::None,
                periodic_y,
                graded: None,
                measured: None,
                swing: false,
                x_walls: false,
            },
            // The measured rule draws its own flights and sideways steps; every grain of the
            // top layer is a candidate, as with `strict`.
            RuleSet::Measured | RuleSet::Swing => Resolved {
                frozen: false,
                cap: usize::MAX,
                activation: crate::rng::ONE,
                knock: 0,
                sideways: 0,
                hold: 0,
                trains: true,
                lateral: Lateral::None,
                periodic_y,
                graded: None,
                measured: self.measured,
                swing: self.rule == RuleSet::Swing,
                x_walls: self.x_walls,
            },
            RuleSet::Physical => {
                let p = &self.physical;
                let below = match p.threshold {
                    Threshold::None => false,
                    Threshold::Coulomb {
                        tray_acceleration,
                        friction_acceleration,
                    } => tray_acceleration <= friction_acceleration,
                };
                let cap = match p.cap {
                    FlightCap::None => usize::MAX,
                    FlightCap::Cells { cells } => cells,
                };
                Resolved {
                    frozen: below || cap == 0,
                    cap,
                    activation: match p.activation {
                        Activation::None => crate::rng::ONE,
                        Activation::Bernoulli { p } => crate::rng::quantise(p),
                    },
                    knock: match p.knock {
                        Knock::None => 0,
                        Knock::Bernoulli { p } => crate::rng::quantise(p),
                    },
                    sideways: match p.sideways {
                        Sideways::None => 0,
                        Sideways::Bernoulli { p } => crate::rng::quantise(p),
                    },
                    trains: p.trains,
                    hold: match p.frustration {
                        Frustration::None => 0,
                        Frustration::Bernoulli { p } => crate::rng::quantise(p),
                    },
                    lateral: p.lateral,
                    periodic_y,
                    graded: match p.transport {
                        Transport::Uniform => None,
                        Transport::Graded(g) => Some(g),
                    },
                    measured: None,
                    swing: false,
                    x_walls: false,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refused_parameters_name_the_field_and_value() {
        assert_eq!(
            "loose".parse::<RuleSet>().unwrap_err().to_string(),
            "unknown rule set `loose`, expected one of strict, physical, measured, swing"
        );
        let mut params = Params {
            rule: RuleSet::Physical,
            physical: Physical {
                activation: Activation::Bernoulli { p: 1.5 },
                ..Physical::off()
            },
            y: YBoundary::Walls,
            x_walls: false,
            seed: 1,
            measured: None,
        };
        let e = params.validate().unwrap_err();
        assert_eq!(
            e,
            ParamsError::Probability {
                field: "activation",
                value: 1.5
            }
        );
        assert_eq!(e.to_string(), "automaton.activation must lie in [0, 1], got 1.5");
        params.physical.activation = Activation::None;
        params.physical.threshold = Threshold::Coulomb {
            tray_acceleration: -1.0,
            friction_acceleration: 7.0,
        };
        assert!(params.validate().unwrap_err().to_string().contains("got -1 and 7"));
    }
}
