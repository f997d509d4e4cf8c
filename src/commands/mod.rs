//! One module per subcommand.

pub mod analyze;
pub mod automaton;
pub mod calibrate;
pub mod collide;
pub mod compare;
pub mod contact_time;
pub mod eccentricity;
pub mod run;
pub mod single;
