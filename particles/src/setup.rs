//! What defines the dynamics apart from the particles' state ([`Setup`]), and the records
//! of single contacts that the force pass produces. Shared by [`crate::sim`] (which owns the
//! stage order) and the force pass, so neither needs the other's internals.

use crate::boundary::Boundary;
use crate::contact::{self, ContactGeometry, ContactLaw};
use crate::integrate::Integrator;
use crate::neighbor::NeighborSearch;
use crate::scene::SortInterval;
use crate::wall::{Motion, Wall};
use crate::Vec3;

/// Everything that defines the dynamics, independent of the particles' state.
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    /// Law between two particles.
    pub pair_law: ContactLaw,
    /// Law between a particle and a wall.
    pub wall_law: ContactLaw,
    pub walls: Vec<Wall>,
    /// Gravitational acceleration (m/s^2), e.g. `(0, 0, -10)`.
    pub gravity: Vec3,
    /// Time step (s).
    pub dt: f64,
    pub integrator: Integrator,
    pub boundary: Boundary,
    pub neighbors: NeighborSearch,
    /// Vertical freedom of the particles.
    pub vertical: Vertical,
    /// The box a particle must stay in on the non-periodic axes (escaped when outside).
    pub container: Option<Container>,
    /// Steps between spatial sorts of the grains, or none.
    pub sort: SortInterval,
    /// Each grain's rolling coefficient `mu_r` (dimensionless) for a spring-dashpot-slider
    /// law, by the grains' indices; a contact takes the mean of its grains' (a wall contact
    /// the grain's). Empty: every contact takes the law's `mu_r`.
    pub rolling_mu: Vec<f64>,
    /// The grains' shape when they are rigid clumps of spheres ([`crate::clump`]): each run of
    /// `spheres` particles of the state is one grain. `None`: every particle is a sphere.
    pub clump: Option<crate::clump::ClumpShape>,
}

/// The box `[lo, hi]` (m) a particle must stay in, at rest, moving with `motion`: at time t
/// its corners are `lo + u(t)` and `hi + u(t)` (the tray's displacement), so that end walls
/// on a horizontally shaken tray carry their escape check with them.
#[derive(Clone, Debug, PartialEq)]
pub struct Container {
    pub lo: Vec3,
    pub hi: Vec3,
    pub motion: Motion,
}

impl Container {
    /// The corners `(lo, hi)` at time `t` (s).
    pub fn at(&self, t: f64) -> (Vec3, Vec3) {
        let u = self.motion.displacement(t);
        (self.lo + u, self.hi + u)
    }
}

/// Vertical freedom of the particles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vertical {
    /// Full 3D translation.
    Free,
    /// Pinned to the floor at `z = R` (jumping off, eq 3.28): a 2D model. The floor (the wall
    /// whose normal is +z) carries each grain's weight as a constant normal load `m g`, which
    /// its friction and rolling resistance feel; vertical forces are dropped.
    Pinned,
}

impl Setup {
    /// True if some contact law produces torques, so spins must be integrated.
    pub fn needs_rotation(&self) -> bool {
        self.clump.is_some() || self.pair_law.produces_torque() || (!self.walls.is_empty() && self.wall_law.produces_torque())
    }
}

/// The partner of particle `i` in a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    Particle(usize),
    Wall(usize),
}

/// Diagnostics of one live contact at the last force evaluation (recorded on request).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactRecord {
    pub i: usize,
    pub partner: Partner,
    pub overlap: f64,
    pub overlap_rate: f64,
    /// Normal force before the no-attraction clamp (N).
    pub normal_raw: f64,
    /// Clamped normal force (N).
    pub normal: f64,
    /// Tangential force magnitude (N).
    pub tangential: f64,
    /// Friction coefficient of the law used.
    pub mu: f64,
}

/// Largest overlap accepted during a run, as a fraction of the smaller radius of the contact
/// (the grain's radius against a wall). Hertz theory assumes a contact face much smaller
/// than the grains; at half the radius the centre of the smaller grain is close to its
/// partner's surface and the forces mean nothing. A step that produces more stops the run
/// with [`crate::SimError::ExcessiveOverlap`]. (Thesis material, Y = 1e6 Pa: two of the smallest
/// grains meeting head-on at the tray's peak speed, 3.1 m/s, reach 45% at 25 steps per
/// contact, measured by `stripes bench`; coarser steps overshoot past the limit.)
pub const MAX_OVERLAP_FRACTION: f64 = 0.5;

impl ContactRecord {
    pub(crate) fn new<N: contact::Normal>(i: usize, partner: Partner, g: &ContactGeometry<N>, c: &contact::ContactForce, mu: f64) -> Self {
        Self {
            i,
            partner,
            overlap: g.overlap,
            overlap_rate: g.overlap_rate,
            normal_raw: c.normal_raw,
            normal: c.normal,
            tangential: c.tangential.norm(),
            mu,
        }
    }
}
