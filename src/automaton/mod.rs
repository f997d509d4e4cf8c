//! The cellular automaton (crate `automaton`) on a tray scene: its lattice and parameters
//! mapped from the scene and its prepared sample ([`lattice`]), its run with a run directory
//! ([`run_automaton`]), and the fit of its free parameters to DEM runs ([`calibrate`]).

pub mod bench;
pub mod calibrate;
pub mod lattice;
pub mod parameters;
pub mod run;

pub use run::{resolve_lattice, run_automaton, AutomatonOptions};
