//! One module per subcommand.

pub mod analyze;
pub mod bench;
pub mod collide;
pub mod contact_time;
pub mod eccentricity;
pub mod run;
pub mod single;
