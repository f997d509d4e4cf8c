//! The machine a run runs on: how many threads it can use ([`threads`]) and the on-CPU clock
//! of the speed measurements ([`clock`]).

pub mod clock;
pub mod threads;
