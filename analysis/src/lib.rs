//! The shared analysis of the suite: it reads DEM snapshots, automaton states and LAMMPS
//! dumps alike, so that both models (and LAMMPS) are judged by the same code.
//!
//! - [`io`]: atomic CSV and JSON output;
//! - [`plot`]: line plots and heat maps (PNG + SVG); the only place that draws;
//! - [`snapshot`]: the binary snapshot stream of DEM runs;
//! - [`vtk`]: legacy VTK frames for ParaView.

pub mod io;
pub mod plot;
pub mod snapshot;
pub mod vtk;
