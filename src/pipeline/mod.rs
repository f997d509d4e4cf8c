//! The typed pipeline from a scene to a report, which every command and study calls:
//!
//! scene file -> [`SceneFile`](crate::scene_file::SceneFile) -> [`resolve`] ->
//! `Resolved` (checked once: laws, walls, step, sample key) -> [`run_dem`] ->
//! `DemSummary`; the automaton's run and the analysis likewise return typed summaries.
//!
//! Commands are adapters around it: they parse their arguments into a scene and options,
//! call the pipeline and print the summary it returns. Nothing here parses a command line,
//! and no module of the pipeline imports a command. Errors are messages for the user
//! ([`crate::output::CliError`]) naming the file, key or option at fault.

mod analysis_files;
mod analyze;
mod automaton;
pub mod coarse;
mod dem;
mod events;
mod resolve;

pub use analyze::{analyze, AnalysisOptions, AnalysisSummary, MapFrame};
pub use automaton::{resolve_lattice, run_automaton, AutomatonOptions};
pub use dem::{no_checkpoint, run_dem, RunOptions};
pub use events::{run_events, EventsOptions};
pub use resolve::resolve;
