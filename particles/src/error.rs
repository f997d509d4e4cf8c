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
    /// Two grains (or a grain and a wall) overlap by more than
    /// [`crate::setup::MAX_OVERLAP_FRACTION`] of the smaller radius during the run: the soft-sphere
    /// picture (small, flat contact face) no longer holds, so the run stops rather than go on
    /// with meaningless forces.
    ExcessiveOverlap {
        step: u64,
        particle: usize,
        /// The partner, e.g. `particle 17` or `wall floor`.
        partner: String,
        overlap: f64,
        radius: f64,
        limit: f64,
    },
    /// The Cundall-Strack tangential spring oscillates faster than the time step resolves:
    /// its stuck half period `pi sqrt(m_t / k_t)` gives fewer than `minimum` steps.
    TangentialSpringTooStiff {
        /// The option or key that set `k_t`.
        field: String,
        dt: f64,
        half_period: f64,
        steps: f64,
        minimum: f64,
    },
    /// The collision lab cannot resolve this impact with these settings (the contact is
    /// shorter than a few steps, ends before it starts, gains energy, or the step is too small
    /// for the positions to move): its numbers would be meaningless.
    CollisionUnresolved { reason: String },
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
            SimError::ExcessiveOverlap {
                step,
                particle,
                partner,
                overlap,
                radius,
                limit,
            } => write!(
                f,
                "step {step}: particle {particle} overlaps {partner} by {overlap:e} m ({:.0}% of the radius {radius:e} m, limit {:.0}%): the impact is too hard for this Young's modulus; raise `material.young` or lower the speeds",
                100.0 * overlap / radius,
                100.0 * limit
            ),
            SimError::TangentialSpringTooStiff {
                field,
                dt,
                half_period,
                steps,
                minimum,
            } => write!(
                f,
                "tangential spring `{field}` is too stiff for the time step {dt:e} s: its stuck half period pi sqrt(m_t/k_t) = {half_period:e} s gives {steps:.2} steps; at least {minimum} are needed (lower `{field}` or the time step)"
            ),
            SimError::CollisionUnresolved { reason } => write!(f, "the collision is not resolved: {reason}"),
        }
    }
}

impl std::error::Error for SimError {}

/// A name that is none of an option's names, as a scene file or the command line wrote it,
/// e.g. `unknown integrator `leapfrog`, expected one of velocity-verlet, thesis`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownName {
    /// What the name should have named (`integrator`, `variant`).
    pub what: &'static str,
    /// The name as given.
    pub given: String,
    /// Every accepted name.
    pub expected: &'static [&'static str],
}

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown {} `{}`, expected one of {}",
            self.what,
            self.given,
            self.expected.join(", ")
        )
    }
}

impl std::error::Error for UnknownName {}

/// A saved state (`saved::SavedState`) that does not fit the simulation it is imported into.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StateMismatch {
    /// The saved state holds `saved` particles, the scene `scene`.
    ParticleCount { saved: usize, scene: usize },
    /// A per-particle field of the saved state does not hold one value per particle.
    FieldLength { particles: usize },
    /// The saved state holds `saved` wall springs, the simulation has `slots` wall slots.
    WallSlots { saved: usize, slots: usize },
    /// A saved spring joins grains `i` and `j`, which are not neighbours here.
    NotNeighbours { i: usize, j: usize },
    /// The saved places of the grains (`SavedState::order`) are not an order of the
    /// `particles` grains.
    Order { particles: usize },
    /// The saved state holds rolling springs, and the laws here have none.
    RollingSprings,
    /// The saved state holds `saved` rigid bodies (clumps), the simulation `bodies`.
    Clumps { saved: usize, bodies: usize },
}

impl fmt::Display for StateMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StateMismatch::ParticleCount { saved, scene } => {
                write!(f, "the checkpoint has {saved} particles, the scene {scene}")
            }
            StateMismatch::FieldLength { particles } => {
                write!(f, "a per-particle field of the checkpoint does not hold {particles} values")
            }
            StateMismatch::WallSlots { saved, slots } => write!(f, "{saved} wall histories for {slots} slots"),
            StateMismatch::NotNeighbours { i, j } => {
                write!(f, "pair ({i}, {j}) of the checkpoint is not a neighbour pair")
            }
            StateMismatch::Clumps { saved, bodies } => write!(
                f,
                "the checkpoint holds {saved} rigid clumps, the scene {bodies} (particles.shape, particles.count)"
            ),
            StateMismatch::Order { particles } => {
                write!(f, "the grains' places in the checkpoint are not an order of {particles} grains")
            }
            StateMismatch::RollingSprings => write!(
                f,
                "the checkpoint holds rolling springs (contact.rolling = \"sds\"), and this scene's rolling law has none"
            ),
        }
    }
}

impl std::error::Error for StateMismatch {}
