//! The command line: the options several commands share ([`args`]), value parsers that name
//! the flag ([`values`]), and one thin adapter per subcommand.

pub mod ablate;
pub mod analyze;
pub mod args;
pub mod automaton;
pub mod bench;
pub mod collect;
pub mod collide;
pub mod compare;
pub mod contact_time;
pub mod eccentricity;
pub mod events;
pub mod events_collide;
pub mod events_sweep;
pub mod laws;
pub mod mechanism;
pub mod phase_map;
pub mod run;
pub mod seeds;
pub mod single;
pub mod values;
pub mod windows;
