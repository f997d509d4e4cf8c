//! The shared analysis of the suite: it reads DEM snapshots, automaton states and LAMMPS
//! dumps alike, so that both models (and LAMMPS) are judged by the same code.
//!
//! - [`density`]: the binning-free count density and exact area fraction (Appendix A);
//! - [`io`]: atomic CSV and JSON output;
//! - [`plot`]: line plots and heat maps (PNG + SVG); the only place that draws;
//! - [`snapshot`]: the binary snapshot stream of DEM runs;
//! - [`stripes`]: stripe detection on a density profile;
//! - [`vtk`]: legacy VTK frames for ParaView.

pub mod density;
pub mod io;
pub mod plot;
pub mod snapshot;
pub mod stripes;
pub mod vtk;
