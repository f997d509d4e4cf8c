//! Errors of the DEM. Every error names what went wrong, where (particle, field) and when (step).

use std::fmt;

/// A failure that stops a simulation or refuses to start it.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// A parameter is out of its valid range (named by its dotted config path).
    InvalidParameter { field: String, message: String },
    /// The time step is too large for the contact time.
    TimeStepTooLarge {
        /// The option or key that set the step.
        field: String,
        dt: f64,
        contact_time: f64,
        steps_per_contact: f64,
        minimum: f64,
    },
    /// A position, velocity or spin became NaN or infinite.
    NonFinite { step: u64, particle: usize, field: &'static str },
    /// Two particles overlap by more than allowed at the start.
    InitialOverlap { i: usize, j: usize, overlap: f64, radius: f64 },
    /// A particle left the box.
    Escaped { step: u64, particle: usize, position: [f64; 3] },
    /// A contact did not end within the allowed number of steps.
    ContactDidNotEnd { steps: u64 },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::InvalidParameter { field, message } => write!(f, "invalid `{field}`: {message}"),
            SimError::TimeStepTooLarge {
                field,
                dt,
                contact_time,
                steps_per_contact,
                minimum,
            } => write!(
                f,
                "time step `{field}` = {dt:e} s is too large: the shortest contact lasts {contact_time:e} s, giving {steps_per_contact:.2} steps per contact; at least {minimum} are needed"
            ),
            SimError::NonFinite { step, particle, field } => {
                write!(f, "step {step}: particle {particle} has a non-finite {field}")
            }
            SimError::InitialOverlap { i, j, overlap, radius } => write!(
                f,
                "particles {i} and {j} overlap by {overlap:e} m ({:.1}% of the smaller radius) in the initial state",
                100.0 * overlap / radius
            ),
            SimError::Escaped { step, particle, position } => write!(
                f,
                "step {step}: particle {particle} left the box at ({:e}, {:e}, {:e}) m",
                position[0], position[1], position[2]
            ),
            SimError::ContactDidNotEnd { steps } => write!(f, "the contact did not end within {steps} steps"),
        }
    }
}

impl std::error::Error for SimError {}
