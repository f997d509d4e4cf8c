//! Scene text, the one place that reads it: the tray scene file (the DEM's scene and the
//! automaton's table, [`file`]), the text of the event-driven scene, whose types are the `events` crate's
//! ([`events`]), TOML and `--set`
//! overrides ([`text`]), typed edits for sweeps and studies ([`edit`]), and the sizes a scene
//! implies, bounded before anything is allocated ([`bounds`]).

pub mod bounds;
pub mod edit;
pub mod events;
#[cfg(test)]
mod events_checks;
pub mod file;
pub mod text;
