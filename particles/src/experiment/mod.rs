//! Experiments built on [`crate::sim`]: they set up a scene, run it and return numbers.
//! Output files and plots are the caller's business.

pub mod closed_form;
pub mod collide;
pub mod contact_time;
pub mod eccentricity;
pub mod restitution;
pub mod single;
pub mod step_control;
