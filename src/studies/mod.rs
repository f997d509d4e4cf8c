//! Studies: what runs many scenes or models and puts them side by side. Sweeps (ablations,
//! phase maps), the coarse model's measurements of a DEM run ([`coarse`]) and the automaton
//! derived from them ([`derived`]), the vibrated box's
//! three-way check ([`vibrated_box`]) and speed against error ([`tradeoff`]).

pub mod coarse;
pub mod collide;
pub mod compare;
pub mod derived;
pub mod events_sweep;
pub mod mechanism;
pub mod seeds;
pub mod single;
pub mod sweep;
pub mod tradeoff;
pub mod vibrated_box;
pub mod windows;
