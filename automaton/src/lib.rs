//! The Strassburger jump-and-rest cellular automaton (thesis 3.1) as a coarse model of the
//! horizontally shaken tray.
//!
//! A top view of the tray: cell `(i, j)`, `i` along the shaking direction x (periodic),
//! `j` across (side walls or periodic), each holding an integer pile height. One drive period
//! is two half steps; in each, top-layer grains fly one way (alternating), tested against an
//! unchanged copy L of the lattice, and then fall until they rest (thesis rules 1 and 2).
//!
//! - [`RuleSet::Strict`]: the thesis' two rules exactly. In a submonolayer every grain stops
//!   where the cell before the next grain's start is, so the pattern moves rigidly by one
//!   cell per half step (against the flight) and nothing ever forms.
//! - [`RuleSet::Measured`]: flights, band-edge escapes and sideways steps drawn from a DEM
//!   run's measured distributions ([`measured`], [`measured_rule`]).
//! - [`RuleSet::Swing`]: every floor grain swings out and back each half step by the swing a
//!   DEM run measured at its local packing, with the measured spread about its neighbours
//!   ([`swing`]); no grain is held.
//! - [`RuleSet::Physical`] (default): the same rules in the tray frame plus a flight cap, a
//!   sliding threshold, stochastic flights, knock-through along lines of touching grains,
//!   lateral contacts and optional sideways moves ([`Physical`]), each switchable.
//!
//! Modules: [`lattice`] (storage), [`params`] (rules and switches), [`mapping`] (tray to
//! parameters), [`transport`] (graded transport and melting, from the DEM's measured slope), `step` (bit-parallel submonolayer step, rows of up to 1024 cells), `scalar` (byte
//! step: any height, the resting rule, wider rows), `neighbours` (cells across rows), [`automaton`] (the driver), `rng` (counter-based random bits), `bits`
//! (periodic bit rows).

pub mod automaton;
mod bits;
pub mod lattice;
pub mod mapping;
pub mod measured;
pub mod measured_rule;
mod neighbours;
pub mod params;
mod rng;
mod scalar;
pub mod spec;
mod step;
pub mod swing;
pub mod tracks;
pub mod transport;

pub use automaton::{Automaton, Direction};
pub use lattice::Lattice;
pub use params::{
    Activation, FlightCap, Frustration, Knock, Lateral, Params, ParamsError, Physical, RuleSet, Sideways, Threshold, Transport, YBoundary,
};
pub use spec::{Spec, TransportKind};
pub use tracks::Tracks;
