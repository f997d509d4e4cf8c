//! The errors of the event-driven model, each naming what went wrong and where.

use std::fmt;

/// Everything that stops a configuration or a run.
#[derive(Clone, Debug, PartialEq)]
pub enum EventsError {
    /// A parameter out of its range, named by its dotted path (`rules.pair.e`).
    Invalid { field: String, message: String },
    /// The particles do not fit into the box at the start.
    DoNotFit { placed: usize, wanted: usize, message: String },
    /// The run would collapse: too many collisions in too short a time.
    Collapse {
        /// The particles with the most collisions in the last window.
        particles: Vec<usize>,
        time: f64,
        events: u64,
        message: String,
    },
    /// A particle ended up inside a wall or another particle (a bug or round-off beyond the
    /// tolerances): the run stops rather than go on.
    Overlap {
        particle: usize,
        partner: String,
        time: f64,
        depth: f64,
    },
}

impl fmt::Display for EventsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EventsError::Invalid { field, message } => write!(f, "invalid `{field}`: {message}"),
            EventsError::DoNotFit { placed, wanted, message } => {
                write!(f, "the particles do not fit: {placed} of {wanted} placed; {message}")
            }
            EventsError::Collapse {
                particles,
                time,
                events,
                message,
            } => write!(
                f,
                "inelastic collapse at t = {time} s after {events} events, particles {particles:?}: {message}"
            ),
            EventsError::Overlap {
                particle,
                partner,
                time,
                depth,
            } => write!(f, "t = {time} s: particle {particle} is inside {partner} by {depth:e} m"),
        }
    }
}

impl std::error::Error for EventsError {}

/// Shorthand for an [`EventsError::Invalid`].
pub(crate) fn invalid(field: &str, message: impl Into<String>) -> EventsError {
    EventsError::Invalid {
        field: field.into(),
        message: message.into(),
    }
}

/// A scene key and what is wrong with it: the error of [`crate::scene::EventScene::config`].
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The dotted key (`box.width`, `rules.pair[0].e`, `particles.species.0.density`).
    pub key: String,
    pub message: String,
}

impl SceneError {
    pub fn new(key: &str, message: impl Into<String>) -> Self {
        SceneError {
            key: key.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "scene `{}`: {}", self.key, self.message)
    }
}

impl std::error::Error for SceneError {}
