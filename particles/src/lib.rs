//! Frictional soft-sphere DEM of a horizontally shaken submonolayer (thesis
//! sections 3.2 and 3.5) and the two-body collision laboratory of thesis chapter 4.
//!
//! Layout, one concept per module:
//! - [`material`]: material constants and their mixing (eq 3.9-3.10);
//! - [`contact`]: contact geometry and the force-law slots (normal, tangential, rolling),
//!   each a pure function of a precomputed [`contact::ContactGeometry`];
//! - [`wall`]: flat walls of infinite mass and their prescribed motion (eq 3.17-3.18);
//! - [`drive`]: a drive schedule, the tray shaken in consecutive harmonic stages;
//! - [`state`]: the particle state as a struct of arrays;
//! - [`boundary`]: periodic images;
//! - [`integrate`]: time integrators (velocity Verlet, and the thesis' scheme);
//! - `forces`: one force evaluation, gathered per particle in fixed blocks;
//! - [`setup`]: what defines the dynamics (laws, walls, step, boundaries), and contact records;
//! - [`timescale`], [`time_step`], [`tray`]: a scene's time scales; its step (explicit, or
//!   chosen with the collision lab); the tray built at that step;
//! - [`sim`]: the only module that knows the order of the stages of a time step;
//! - [`saved`]: a simulation's dynamic state as plain data, exported and imported so that a
//!   run continues bit for bit (the root crate stores it; this crate knows no byte layout);
//! - `parallel`: deterministic block parallelism (results independent of the thread count);
//! - [`measure`]: energy, momentum and angular momentum of a state, and the state hash;
//! - [`advance`]: [`advance::advance`] steps a run and hands it to observers after every
//!   step; they, outside this crate, write files (this crate knows no file format);
//! - [`experiment`]: the collision lab, the single sphere on the shaken plate, contact-time
//!   and eccentricity studies.

pub mod advance;
pub mod boundary;
pub mod clump;
pub mod constants;
pub mod contact;
pub mod drive;
pub mod error;
pub mod experiment;
mod forces;
pub mod integrate;
pub mod material;
pub mod measure;
pub mod neighbor;
pub mod pace;
mod parallel;
pub mod prepare;
pub mod rigid;
pub mod saved;
pub mod scene;
pub mod setup;
pub mod sim;
pub mod state;
pub mod time_step;
pub mod timescale;
pub mod tray;
pub mod wall;

pub use error::SimError;
pub use parallel::{waits, Waits};

/// Three-vector used throughout (metres, m/s, rad/s, newtons, ...).
pub type Vec3 = nalgebra::Vector3<f64>;
