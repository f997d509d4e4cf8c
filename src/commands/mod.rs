//! One module per subcommand.

pub mod ablate;
pub mod analyze;
pub mod collect;
pub mod collide;
pub mod contact_time;
pub mod eccentricity;
pub mod phase_map;
pub mod run;
pub mod single;
