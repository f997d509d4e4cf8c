//! Run directories: the claim and lock of an output directory (one claim of a resumable run,
//! `output::claim_run`, for the DEM and the event-driven model), the one rule of `--resume`
//! for every model ([`resume`]), the atomic writers of `config.json`, `summary.json`, tables
//! and plots ([`output`]), the checked byte codec of the root crate's binary files
//! ([`bytes`]), and what a command returns ([`report`]).

pub mod bytes;
pub mod lock;
pub mod output;
pub mod report;
pub mod resume;
