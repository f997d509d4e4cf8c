//! The simulation loop: the only place that knows the order of the stages of a time step.
//!
//! One step of [`Simulation::step`]:
//! 1. integrator stage before the forces (positions to `t + dt`);
//! 2. `t += dt`, periodic wrap of positions;
//! 3. neighbour list rebuilt if some particle moved more than half the skin;
//! 4. force evaluation, gathered per particle in fixed blocks on the rayon pool: gravity,
//!    particle pairs from the neighbour list, walls at their position and velocity at the new
//!    time; contact history kept for live contacts only; energy ledger (work of moving walls,
//!    dissipation) advanced by `power * dt`, summed in block order so that results are
//!    bit-identical for any number of threads;
//! 5. integrator stage after the forces (velocities to `t + dt`);
//! 6. checks: every position, velocity and spin finite.

use rayon::prelude::*;

use crate::boundary::Boundary;
use crate::contact::{self, ContactGeometry, ContactLaw};
use crate::integrate::Integrator;
use crate::neighbor::{NeighborList, NeighborSearch};
use crate::state::State;
use crate::wall::Wall;
use crate::{SimError, Vec3};

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
    /// Box `[lo, hi]` (m) on the non-periodic axes: a particle outside it has escaped.
    pub container: Option<(Vec3, Vec3)>,
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
        self.pair_law.produces_torque() || (!self.walls.is_empty() && self.wall_law.produces_torque())
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

/// Energy exchanged with the outside since the start (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Ledger {
    /// Work done on the particles by moving walls.
    pub injected: f64,
    /// Energy dissipated in contacts.
    pub dissipated: f64,
}

/// Largest overlap between two grains accepted at the start, as a fraction of the smaller
/// radius (a prepared sample at rest overlaps by about 1e-3).
pub const MAX_INITIAL_OVERLAP: f64 = 0.05;

/// Largest overlap accepted during a run, as a fraction of the smaller radius of the contact
/// (the grain's radius against a wall). Hertz theory assumes a contact face much smaller
/// than the grains; at half the radius the centre of the smaller grain is close to its
/// partner's surface and the forces mean nothing. A step that produces more stops the run
/// with [`SimError::ExcessiveOverlap`]. (Thesis material at the tray's peak speed, 3.1 m/s,
/// reaches about 13%.)
pub const MAX_OVERLAP_FRACTION: f64 = 0.5;

/// Particles per block of the parallel force loop. Fixed, so that the block partial sums, and
/// therefore every result, do not depend on the number of threads.
const BLOCK: usize = 128;

/// A running simulation.
#[derive(Clone, Debug)]
pub struct Simulation {
    pub setup: Setup,
    pub state: State,
    /// Simulated time (s).
    pub time: f64,
    /// Completed steps.
    pub steps: u64,
    pub ledger: Ledger,
    /// Elastic energy stored in contacts at the last force evaluation (J).
    pub stored_energy: f64,
    /// Live contacts at the last force evaluation: `(particle pairs, particle-wall)`.
    pub contacts: (u64, u64),
    rotate: bool,
    neighbors: NeighborList,
    /// Tangential spring of each neighbour-list slot (pair history), aligned with
    /// `neighbors.partners`; zero for pairs not in contact.
    pair_history: Vec<Vec3>,
    /// Tangential spring of each particle-wall contact, `i * max(walls, 1) + k` (one unused
    /// slot per particle without walls, so the per-block chunks always line up).
    wall_history: Vec<Vec3>,
    record: bool,
    records: Vec<ContactRecord>,
    /// The worst contact beyond [`MAX_OVERLAP_FRACTION`] at the last force evaluation:
    /// `(particle, partner, overlap, radius)`.
    overlap_violation: Option<(usize, Partner, f64, f64)>,
}

/// Per-block partial results of a force evaluation.
#[derive(Default)]
struct BlockSums {
    pair_contacts: u64,
    wall_contacts: u64,
    stored: f64,
    dissipated: f64,
    injected: f64,
    records: Vec<ContactRecord>,
    /// Worst overlap beyond the limit: `(fraction, particle, partner, overlap, radius)`.
    violation: Option<(f64, usize, Partner, f64, f64)>,
}

impl BlockSums {
    /// Notes a contact whose overlap exceeds [`MAX_OVERLAP_FRACTION`] of `radius`.
    #[inline]
    fn check_overlap(&mut self, i: usize, partner: Partner, overlap: f64, radius: f64) {
        if overlap > MAX_OVERLAP_FRACTION * radius {
            let frac = overlap / radius;
            if self.violation.is_none_or(|v| frac > v.0) {
                self.violation = Some((frac, i, partner, overlap, radius));
            }
        }
    }
}

impl Simulation {
    /// Checks the setup and the state, evaluates the initial forces and prepares the integrator.
    pub fn new(setup: Setup, state: State) -> Result<Self, SimError> {
        if !(setup.dt.is_finite() && setup.dt > 0.0) {
            return Err(SimError::InvalidParameter {
                field: "run.dt".into(),
                message: format!("must be a positive number of seconds, got {}", setup.dt),
            });
        }
        let rotate = setup.needs_rotation();
        let n_walls = setup.walls.len();
        let n = state.len();
        let mut state = state;
        if setup.vertical == Vertical::Pinned {
            // eq 3.28: pinned grains sit at z = R and do not move vertically.
            for i in 0..n {
                state.pos[i].z = state.radius[i];
                state.vel[i].z = 0.0;
            }
        }
        let mut sim = Self {
            setup,
            state,
            time: 0.0,
            steps: 0,
            ledger: Ledger::default(),
            stored_energy: 0.0,
            contacts: (0, 0),
            rotate,
            neighbors: NeighborList::default(),
            pair_history: Vec::new(),
            wall_history: vec![Vec3::zeros(); n * n_walls.max(1)],
            record: false,
            records: Vec::new(),
            overlap_violation: None,
        };
        sim.check_finite()?;
        sim.refresh_neighbors();
        sim.check_overlaps()?;
        sim.compute_forces(0.0);
        let dt = sim.setup.dt;
        sim.setup.integrator.start(&mut sim.state, dt);
        Ok(sim)
    }

    /// Records per-contact diagnostics at every force evaluation from the next step on (see
    /// [`Self::contacts`]). The forces are not re-evaluated: that would advance the
    /// Cundall-Strack springs a second time and change the trajectory.
    pub fn record_contacts(&mut self, on: bool) {
        self.record = on;
        self.records.clear();
    }

    /// Contacts of the last force evaluation (empty unless recording); each pair once.
    pub fn contacts(&self) -> &[ContactRecord] {
        &self.records
    }

    /// True if spins are integrated.
    pub fn rotates(&self) -> bool {
        self.rotate
    }

    /// Number of neighbour-list builds so far.
    pub fn neighbor_builds(&self) -> u64 {
        self.neighbors.builds
    }

    /// Advances one time step.
    pub fn step(&mut self) -> Result<(), SimError> {
        let (dt, rotate, integrator) = (self.setup.dt, self.rotate, self.setup.integrator);
        let boundary = self.setup.boundary;
        // Stage 1, fused per particle: integrator before the forces, periodic wrap, and the
        // largest displacement since the neighbour list was built.
        let limit = NeighborList::rebuild_distance2(&self.setup.neighbors);
        let anchor = self.neighbors.anchor();
        let anchored = limit.is_some() && anchor.len() == self.state.len();
        let moved_too_far = self
            .state
            .blocks_mut(BLOCK)
            .into_par_iter()
            .map(|mut b| {
                let mut far = false;
                for k in 0..b.pos.len() {
                    integrator.before_forces(&mut b, k, dt, rotate);
                    b.pos[k] = boundary.wrap(b.pos[k]);
                    if anchored {
                        far |= boundary.min_image(b.pos[k] - anchor[b.start + k]).norm_squared() > limit.unwrap_or(0.0);
                    }
                }
                far
            })
            .reduce(|| false, |a, b| a || b);
        self.time += dt;
        // Stage 2: neighbour list, if due.
        if moved_too_far || (!anchored && self.neighbors.needs_rebuild(&self.setup.neighbors, &self.state.pos, &boundary)) {
            self.rebuild_neighbors();
        }
        // Stage 3: forces.
        self.compute_forces(dt);
        // Stage 4, fused per particle: integrator after the forces, and the checks.
        let (container, steps) = (self.setup.container, self.steps + 1);
        let first_bad = self
            .state
            .blocks_mut(BLOCK)
            .into_par_iter()
            .map(|mut b| {
                let mut bad = None;
                for k in 0..b.pos.len() {
                    integrator.after_forces(&mut b, k, dt, rotate);
                    // A NaN or an infinity in any component survives the sum.
                    let finite = (b.pos[k].sum() + b.vel[k].sum() + b.omega[k].sum()).is_finite();
                    let x = &b.pos[k];
                    let inside = container.as_ref().is_none_or(|(lo, hi)| {
                        (boundary.periodic[0].is_some() || (x.x >= lo.x && x.x <= hi.x))
                            && (boundary.periodic[1].is_some() || (x.y >= lo.y && x.y <= hi.y))
                            && (boundary.periodic[2].is_some() || (x.z >= lo.z && x.z <= hi.z))
                    });
                    if bad.is_none() && !(finite && inside) {
                        bad = Some(b.start + k);
                    }
                }
                bad
            })
            .reduce(|| None, |a, b| a.or(b));
        self.steps = steps;
        match (first_bad, self.overlap_violation) {
            (Some(i), _) => Err(self.describe_bad(i)),
            (None, Some((i, partner, overlap, radius))) => Err(SimError::ExcessiveOverlap {
                step: self.steps,
                particle: i,
                partner: match partner {
                    Partner::Particle(j) => format!("particle {j}"),
                    Partner::Wall(w) => format!("wall `{}`", self.setup.walls[w].name),
                },
                overlap,
                radius,
                limit: MAX_OVERLAP_FRACTION,
            }),
            (None, None) => Ok(()),
        }
    }

    /// Total mechanical energy: kinetic, rotational, gravitational and stored in contacts (J).
    pub fn total_energy(&self) -> f64 {
        crate::observe::kinetic_energy(&self.state)
            + crate::observe::rotational_energy(&self.state)
            + crate::observe::potential_energy(&self.state, self.setup.gravity)
            + self.stored_energy
    }

    /// Every position, velocity and spin finite, and every particle inside the container.
    fn check_finite(&self) -> Result<(), SimError> {
        let s = &self.state;
        let bad = (0..s.len()).find(|&i| {
            let finite = s.pos[i]
                .iter()
                .chain(s.vel[i].iter())
                .chain(s.omega[i].iter())
                .all(|c| c.is_finite());
            let inside = self.setup.container.as_ref().is_none_or(|(lo, hi)| {
                (0..3).all(|k| self.setup.boundary.periodic[k].is_some() || (s.pos[i][k] >= lo[k] && s.pos[i][k] <= hi[k]))
            });
            !(finite && inside)
        });
        bad.map_or(Ok(()), |i| Err(self.describe_bad(i)))
    }

    /// The error for particle `i`, which is non-finite or outside the container.
    fn describe_bad(&self, i: usize) -> SimError {
        let s = &self.state;
        for (field, v) in [("position", &s.pos[i]), ("velocity", &s.vel[i]), ("spin", &s.omega[i])] {
            if !v.iter().all(|c| c.is_finite()) {
                return SimError::NonFinite {
                    step: self.steps,
                    particle: i,
                    field,
                };
            }
        }
        let x = &s.pos[i];
        SimError::Escaped {
            step: self.steps,
            particle: i,
            position: [x.x, x.y, x.z],
        }
    }

    /// Refuses a start with grains overlapping by more than [`MAX_INITIAL_OVERLAP`] of the
    /// smaller radius: such a state would explode on the first step.
    fn check_overlaps(&self) -> Result<(), SimError> {
        let s = &self.state;
        for i in 0..s.len() {
            for &j in self.neighbors.of(i) {
                let j = j as usize;
                if j < i {
                    continue;
                }
                let d = self.setup.boundary.min_image(s.pos[i] - s.pos[j]).norm();
                let overlap = s.radius[i] + s.radius[j] - d;
                let r = s.radius[i].min(s.radius[j]);
                if overlap > MAX_INITIAL_OVERLAP * r {
                    return Err(SimError::InitialOverlap { i, j, overlap, radius: r });
                }
            }
        }
        Ok(())
    }

    /// Non-zero pair histories as `(i, j, zeta)`.
    pub(crate) fn pair_histories(&self) -> Vec<(usize, usize, Vec3)> {
        let mut out = Vec::new();
        for i in 0..self.state.len() {
            for (slot, &j) in self.neighbors.of(i).iter().enumerate() {
                let h = self.pair_history[self.neighbors.offsets[i] + slot];
                if h != Vec3::zeros() {
                    out.push((i, j as usize, h));
                }
            }
        }
        out
    }

    /// Wall histories, `i * max(walls, 1) + k`.
    pub(crate) fn wall_histories(&self) -> &[Vec3] {
        &self.wall_history
    }

    /// Rebuilds the neighbour list for the current positions and installs histories.
    pub(crate) fn set_histories(&mut self, pairs: &[(usize, usize, Vec3)], walls: Vec<Vec3>) -> Result<(), String> {
        if walls.len() != self.wall_history.len() {
            return Err(format!("{} wall histories for {} slots", walls.len(), self.wall_history.len()));
        }
        self.wall_history = walls;
        self.neighbors = NeighborList::default();
        self.neighbors
            .build(&self.setup.neighbors, &self.state.pos, &self.state.radius, &self.setup.boundary);
        self.pair_history = vec![Vec3::zeros(); self.neighbors.partners.len()];
        for &(i, j, h) in pairs {
            let slot = self
                .neighbors
                .of(i)
                .binary_search(&(j as u32))
                .map_err(|_| format!("pair ({i}, {j}) of the checkpoint is not a neighbour pair"))?;
            self.pair_history[self.neighbors.offsets[i] + slot] = h;
        }
        Ok(())
    }

    /// Rebuilds the neighbour list if needed.
    fn refresh_neighbors(&mut self) {
        if self
            .neighbors
            .needs_rebuild(&self.setup.neighbors, &self.state.pos, &self.setup.boundary)
        {
            self.rebuild_neighbors();
        }
    }

    /// Rebuilds the neighbour list, carrying the pair history over to the new slots.
    fn rebuild_neighbors(&mut self) {
        let s = &self.state;
        let search = self.setup.neighbors;
        let old = std::mem::take(&mut self.neighbors);
        let mut list = old.clone();
        list.build(&search, &s.pos, &s.radius, &self.setup.boundary);
        let mut history = vec![Vec3::zeros(); list.partners.len()];
        if self.setup.pair_law.has_history() && !old.offsets.is_empty() {
            for i in 0..s.len() {
                let (old_j, old_h) = (old.of(i), &self.pair_history[old.offsets[i]..old.offsets[i + 1]]);
                let mut k = 0;
                for (slot, &j) in list.of(i).iter().enumerate() {
                    while k < old_j.len() && old_j[k] < j {
                        k += 1;
                    }
                    if k < old_j.len() && old_j[k] == j {
                        history[list.offsets[i] + slot] = old_h[k];
                    }
                }
            }
        }
        self.neighbors = list;
        self.pair_history = history;
    }

    /// Evaluates all forces and torques at the current positions; `ledger_dt` is the time
    /// over which the resulting powers are booked (0 for a re-evaluation).
    fn compute_forces(&mut self, ledger_dt: f64) {
        let setup = &self.setup;
        let n = self.state.len();
        let n_walls = setup.walls.len();
        let wall_stride = n_walls.max(1);
        let walls: Vec<(Vec3, Vec3, Vec3)> = setup
            .walls
            .iter()
            .map(|w| (w.origin_at(self.time), w.normal, w.motion.velocity(self.time)))
            .collect();
        let (record, dt) = (self.record, setup.dt);
        let pinned = setup.vertical == Vertical::Pinned;
        let support: Vec<bool> = setup.walls.iter().map(|w| pinned && w.normal == Vec3::z()).collect();
        let weight = -setup.gravity.z;
        let list = &self.neighbors;
        let State {
            pos,
            vel,
            omega,
            force,
            torque,
            radius,
            inv_mass,
            ..
        } = &mut self.state;
        let (pos, vel, omega, radius, inv_mass) = (&*pos, &*vel, &*omega, &*radius, &*inv_mass);

        // Split the per-slot histories into the ranges owned by each block.
        let mut pair_blocks: Vec<&mut [Vec3]> = Vec::with_capacity(n / BLOCK + 1);
        let mut rest = self.pair_history.as_mut_slice();
        for b in 0..n.div_ceil(BLOCK) {
            let (lo, hi) = (list.offsets[b * BLOCK], list.offsets[((b + 1) * BLOCK).min(n)]);
            let (head, tail) = rest.split_at_mut(hi - lo);
            pair_blocks.push(head);
            rest = tail;
        }

        debug_assert_eq!(self.wall_history.len(), n * wall_stride);
        let sums: Vec<BlockSums> = force
            .par_chunks_mut(BLOCK)
            .zip(torque.par_chunks_mut(BLOCK))
            .zip(pair_blocks.into_par_iter())
            .zip(self.wall_history.par_chunks_mut(BLOCK * wall_stride))
            .enumerate()
            .map(|(b, (((f_blk, t_blk), ph_blk), wh_blk))| {
                let mut sums = BlockSums::default();
                let base_slot = list.offsets[b * BLOCK];
                for (k, (f_out, t_out)) in f_blk.iter_mut().zip(t_blk.iter_mut()).enumerate() {
                    let i = b * BLOCK + k;
                    let mut f = setup.gravity / inv_mass[i];
                    let mut t = Vec3::zeros();
                    // Particle pairs (each evaluated from both sides; half the energies each).
                    let slots = list.offsets[i] - base_slot..list.offsets[i + 1] - base_slot;
                    for (&j, zeta) in list.of(i).iter().zip(&mut ph_blk[slots]) {
                        let j = j as usize;
                        let d = setup.boundary.min_image(pos[i] - pos[j]);
                        let Some(g) = ContactGeometry::pair(pos[i], pos[i] - d, vel[i], vel[j], omega[i], omega[j], radius[i], radius[j])
                        else {
                            *zeta = Vec3::zeros();
                            continue;
                        };
                        let c = contact::evaluate(&setup.pair_law, &g, zeta, dt);
                        f += c.force;
                        t += c.torque_i;
                        sums.pair_contacts += (i < j) as u64;
                        sums.check_overlap(i, Partner::Particle(j), g.overlap, radius[i].min(radius[j]));
                        sums.stored += 0.5 * c.stored_energy;
                        sums.dissipated += 0.5 * c.dissipation_rate;
                        if record && i < j {
                            sums.records
                                .push(ContactRecord::new(i, Partner::Particle(j), &g, &c, setup.pair_law.tangential.mu()));
                        }
                    }
                    // Walls.
                    for (w, &(origin, normal, v_wall)) in walls.iter().enumerate() {
                        let zeta = &mut wh_blk[k * wall_stride + w];
                        let Some(g) = ContactGeometry::wall(pos[i], vel[i], omega[i], radius[i], origin, normal, v_wall) else {
                            *zeta = Vec3::zeros();
                            continue;
                        };
                        let c = if support[w] {
                            contact::evaluate_with_normal(&setup.wall_law, &g, weight / inv_mass[i], zeta, dt)
                        } else {
                            contact::evaluate(&setup.wall_law, &g, zeta, dt)
                        };
                        f += c.force;
                        t += c.torque_i;
                        sums.wall_contacts += 1;
                        sums.check_overlap(i, Partner::Wall(w), g.overlap, radius[i]);
                        sums.stored += c.stored_energy;
                        sums.dissipated += c.dissipation_rate;
                        sums.injected += c.force.dot(&v_wall);
                        if record {
                            sums.records
                                .push(ContactRecord::new(i, Partner::Wall(w), &g, &c, setup.wall_law.tangential.mu()));
                        }
                    }
                    if pinned {
                        f.z = 0.0;
                    }
                    *f_out = f;
                    *t_out = t;
                }
                sums
            })
            .collect();
        assert_eq!(sums.len(), n.div_ceil(BLOCK), "every block of particles must be evaluated");

        let (mut stored, mut dissipated, mut injected) = (0.0, 0.0, 0.0);
        self.records.clear();
        self.overlap_violation = None;
        let mut worst = 0.0;
        self.contacts = (0, 0);
        for s in sums {
            self.contacts.0 += s.pair_contacts;
            self.contacts.1 += s.wall_contacts;
            stored += s.stored;
            dissipated += s.dissipated;
            injected += s.injected;
            self.records.extend(s.records);
            if let Some((frac, i, partner, overlap, radius)) = s.violation {
                if frac > worst {
                    worst = frac;
                    self.overlap_violation = Some((i, partner, overlap, radius));
                }
            }
        }
        self.stored_energy = stored;
        self.ledger.injected += injected * ledger_dt;
        self.ledger.dissipated += dissipated * ledger_dt;
    }
}

impl ContactRecord {
    fn new(i: usize, partner: Partner, g: &ContactGeometry, c: &contact::ContactForce, mu: f64) -> Self {
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
