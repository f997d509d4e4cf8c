//! Run directories: the claim and lock of an output directory, the rule of `--resume`, the
//! atomic writers of `config.json`, `summary.json`, tables and plots ([`output`]), and the
//! checked byte codec of the root crate's binary files ([`bytes`]), and what a command
//! returns ([`report`]).

pub mod bytes;
pub mod lock;
pub mod output;
pub mod report;
pub mod resume;
