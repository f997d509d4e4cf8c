//! The event-driven model (crate `events`) on an event-driven scene: its run with a run
//! directory ([`run_events`]), the same loop in memory for sweeps ([`measure`]), its
//! checkpoint and resume rule, and the records it writes (distributions, phase fields,
//! segregation, the side cluster).

pub mod checkpoint;
pub mod distributions;
pub mod fields;
pub mod impacts;
pub mod measure;
pub mod resume;
pub mod run;
pub mod segregation;
pub mod side;

pub use run::{run_events, EventsOptions};
