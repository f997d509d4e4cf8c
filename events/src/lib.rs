//! An event-driven (hard-particle) model of vibrated granular layers: disks, or spheres
//! moving in a vertical plane (x along the floor, z up), under gravity, between walls that
//! may oscillate, colliding instantaneously with Walton's rough-particle rule.
//!
//! It is the coarse model of the vibrated-layer papers: a binary mixture in a vibrated box
//! (Pagnani, Marini Bettolo Marconi, Puglisi), and horizontal transport on a sawtooth base.
//! Collisions are exact where they are binary and short, and far cheaper than the DEM in a
//! fluidised layer. Where grains rest or roll on a floor for long (the stripe tray), a hard
//! collision cannot hold an enduring contact; there the cellular automaton stays the tray's
//! coarse model, and this crate's collapse guards only keep such grains from sinking.
//!
//! Modules, one concept each:
//! - [`scene`]: the scene as serde types, checked and mapped onto the [`config`] (errors
//!   name the scene's key);
//! - [`config`]: the validated parameters (typed errors name the field by its scene key);
//! - [`collision`]: the collision rules, pure functions of velocities, spins and the normal;
//! - [`impact`]: single wall and pair impacts from a given state, and the rule's closed forms;
//! - [`flight`]: parabolic flights and the exact pair contact time;
//! - [`wall`]: fixed and oscillating walls, and their robust contact times;
//! - [`sawtooth`]: the sawtooth base with rounded tips, and its contact times;
//! - [`cells`]: the cell grid and its crossing times;
//! - [`phase_field`]: mass and momentum over one tooth of a sawtooth, per drive phase;
//! - [`queue`]: the event queue (one predicted event per particle, generation counters);
//! - [`observe`]: profiles, histograms, free times and the energy ledger;
//! - [`side`]: which side of the box the grains crowd to, and for how long;
//! - [`thinned`]: a bounded, evenly thinned record of a stream (the free times);
//! - [`sim`]: the only place that knows the order of the event loop.
//!
//! This crate knows no file format (its scene types only derive serde) and no other crate of
//! the workspace.

pub mod cells;
pub mod collision;
pub mod config;
pub mod error;
pub mod flight;
pub mod impact;
pub mod observe;
pub mod phase_field;
pub mod queue;
pub mod sawtooth;
pub mod scene;
pub mod segregation;
pub mod side;
pub mod sim;
pub mod thinned;
pub mod wall;

/// A vector in the plane of motion: `x` along the floor, `y` = the vertical `z`.
pub type Vec2 = nalgebra::Vector2<f64>;

pub use collision::{Restitution, Rule, Table};
pub use config::{Config, Guard, Mass, Rules, SideWalls, Species};
pub use error::{EventsError, SceneError};
pub use sawtooth::Sawtooth;
pub use sim::{Next, Simulation, State};
pub use wall::{Motion, Wall, WallKind, Waveform};
