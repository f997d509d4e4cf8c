//! The analysis of a finished run (DEM, automaton, event-driven or a LAMMPS dump), with the
//! formats and plots of crate `analysis`: [`analyze`] writes an analysis directory and returns
//! its typed summary; [`read`] reads one back for the studies that put runs side by side.

pub mod files;
pub mod read;
pub mod run;

pub use run::{analyze, AnalysisOptions, AnalysisSummary, MapFrame};
