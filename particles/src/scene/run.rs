//! `[run]`: duration, time step, seed, threads, snapshots, checkpoints, integrator.

use serde::{Deserialize, Serialize};

use crate::integrate::Integrator;

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

/// Default `run.restitution_tolerance`, picked from the speed-against-error front of
/// `stripes bench` (see docs/performance.md).
pub const DEFAULT_RESTITUTION_TOLERANCE: f64 = 1e-2;
/// Default `run.steps_per_contact`.
pub const DEFAULT_STEPS_PER_CONTACT: f64 = 15.0;
/// Default `run.checkpoint_interval` (s).
pub const DEFAULT_CHECKPOINT_INTERVAL: f64 = 1.0;

/// How often the simulation relabels its grains internally in the order of space (see
/// [`crate::sim::Simulation`]): `"none"`, or every `n` steps. Readers never see it (a grain
/// keeps its index in the state, snapshots, checkpoints and contact records); the forces of
/// a grain's pairs are then added in another order, so the trajectory's bits change.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SortInterval {
    /// Every `n` steps (at the steps whose count is a multiple of `n`).
    Steps(std::num::NonZeroU64),
    /// `"none"`: the grains keep the order of the sample.
    Never(NoSort),
}

impl SortInterval {
    /// No sort.
    pub const NONE: SortInterval = SortInterval::Never(NoSort::None);
}

/// Marker for `sort_interval = "none"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NoSort {
    None,
}

/// Default `run.sort_interval`: 1000 steps. In the thesis scene's gas (10 s of shaking) a
/// third fewer L1 read misses and 9-14 % more steps per second on one thread; from the
/// lattice no change beyond 0.5 % more instructions; 200 and 5000 steps gave the same
/// within the spread (docs/performance-history.md, "Spatial sort").
pub const DEFAULT_SORT_INTERVAL: SortInterval = SortInterval::Steps(std::num::NonZeroU64::new(1000).unwrap());

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
    #[serde(default = "Run::steps_per_contact")]
    pub steps_per_contact: f64,
    /// Largest accepted error of the restitution coefficients (eps_n, eps_t; absolute) for
    /// `dt = "auto"`. Left out of the serialised scene when it has its default, so that
    /// sample keys (the root crate's `samples::sample_key`, a hash of the serialised scene) of
    /// scenes written before this key existed still hold.
    #[serde(default = "Run::restitution_tolerance", skip_serializing_if = "Run::is_default_tolerance")]
    pub restitution_tolerance: f64,
    /// Random seed of the sample (radii, lattice, initial velocities).
    pub seed: u64,
    /// Worker threads (0: all cores). Results do not depend on it.
    #[serde(default)]
    pub threads: usize,
    /// Snapshots per shaking period, the first of each at the turning point x_tray = +A and
    /// the others evenly spaced after it. Default 4, so that an onset is resolved to a
    /// quarter period; the thesis took 1 (`scenes/thesis-reference.toml`).
    #[serde(default = "Run::snapshots_per_period")]
    pub snapshots_per_period: u32,
    /// Simulated seconds between checkpoints (0: none).
    #[serde(default = "Run::checkpoint_interval")]
    pub checkpoint_interval: f64,
    /// Time integrator: `velocity-verlet` (default, second order) or `thesis` (the thesis'
    /// scheme, sec 3.5.1: Verlet positions eq 3.26, central-difference velocities eq 3.27,
    /// Euler rotation eq 3.22-3.23; first order). Left out of the serialised scene when it
    /// has its default, so that sample keys of older scenes still hold.
    #[serde(default, skip_serializing_if = "Run::is_default_integrator")]
    pub integrator: Integrator,
    /// Steps between spatial sorts of the grains ([`SortInterval`]), or `"none"`. Left out of
    /// the serialised scene when it has its default, so that sample keys of older scenes
    /// still hold.
    #[serde(default = "Run::sort_interval", skip_serializing_if = "Run::is_default_sort_interval")]
    pub sort_interval: SortInterval,
}

impl Run {
    fn steps_per_contact() -> f64 {
        DEFAULT_STEPS_PER_CONTACT
    }
    fn restitution_tolerance() -> f64 {
        DEFAULT_RESTITUTION_TOLERANCE
    }
    fn is_default_tolerance(x: &f64) -> bool {
        *x == DEFAULT_RESTITUTION_TOLERANCE
    }
    fn snapshots_per_period() -> u32 {
        4
    }
    fn checkpoint_interval() -> f64 {
        DEFAULT_CHECKPOINT_INTERVAL
    }
    fn is_default_integrator(x: &Integrator) -> bool {
        *x == Integrator::default()
    }
    fn sort_interval() -> SortInterval {
        DEFAULT_SORT_INTERVAL
    }
    fn is_default_sort_interval(x: &SortInterval) -> bool {
        *x == DEFAULT_SORT_INTERVAL
    }
}
