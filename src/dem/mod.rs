//! The DEM (crate `particles`) on a tray scene: [`resolve`] checks the scene once and builds
//! what every consumer needs (laws, walls, step, sample key, checkpoint fingerprint), and
//! [`run_dem`] runs it with the file observers of a run directory and returns a typed summary.
//! Everything the root crate keeps of a DEM run lives here: its checkpoint bytes, the cache of
//! prepared samples, the observers (snapshots, thermo, VTK series).

pub mod checkpoint;
pub mod observers;
pub mod resolve;
pub mod run;
pub mod samples;
pub mod thermo;
pub mod vtk;

pub use resolve::resolve;
pub use run::{run_dem, RunOptions};
