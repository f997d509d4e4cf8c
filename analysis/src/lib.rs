//! The shared analysis of the suite: it reads DEM snapshots, automaton states and LAMMPS
//! dumps alike, so that both models (and LAMMPS) are judged by the same code.
//!
//! Entry points: [`input::load`] reads any run, [`report::analyze`] (or the streaming
//! [`report::Analyzer`]) returns everything below as one [`report::Report`].
//!
//! - [`density`]: the binning-free count density and exact area fraction (Appendix A);
//! - [`stripes`]: stripe detection, onset and coarsening;
//! - [`camera`]: the run as the experiment's camera saw it: stroboscopic tray-frame profiles
//!   at the drive's turning points ([`drive`]), the stripe count, onsets, the coarsening law
//!   ([`coarsening_law`]) and the stripes' lifetimes ([`lifetime`]);
//! - [`msd`]: mean square displacement per period (eq 3.30-3.31) and plateau fits;
//! - [`autocorr`]: autocorrelation (eq 3.32);
//! - [`tracer`]: tracer trajectory and phase space;
//! - [`segregation`]: radius distribution inside stripes against the whole layer;
//! - [`mechanism`]: held, rolling and sliding grains inside and outside bands (thesis 3.4);
//! - [`classify`]: the phase of a run, `nothing | stripes | gas`, with its metrics;
//! - [`report`]: all of the above for one run;
//! - [`input`], [`snapshot`], [`lammps`]: reading runs (DEM and automaton snapshots, LAMMPS dumps);
//! - [`io`]: atomic CSV and JSON output;
//! - [`plot`]: line plots and heat maps (PNG + SVG); the only place that draws;
//! - [`vtk`]: legacy VTK frames for ParaView.

pub mod autocorr;
pub mod camera;
pub mod classify;
pub mod coarse;
pub mod coarsening_law;
pub mod density;
pub mod drive;
pub mod histogram;
pub mod input;
pub mod io;
pub mod lammps;
pub mod lammps_data;
pub mod lifetime;
pub mod mechanism;
pub mod msd;
pub mod plot;
pub mod report;
pub mod segregation;
pub mod snapshot;
pub mod stats;
pub mod stripes;
pub mod structure;
pub mod thresholds;
pub mod tracer;
pub mod vtk;
