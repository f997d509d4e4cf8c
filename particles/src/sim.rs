//! The simulation loop: the only place that knows the order of the stages of a time step.
//!
//! One step of [`Simulation::step`]:
//! 1. integrator stage before the forces (positions to `t + dt`);
//! 2. `t += dt`, periodic wrap of positions;
//! 3. force evaluation: gravity, particle pairs from the neighbour search, walls at their
//!    position and velocity at the new time; contact history kept for live contacts only;
//!    energy ledger (work of moving walls, dissipation) advanced by `power * dt`;
//! 4. integrator stage after the forces (velocities to `t + dt`);
//! 5. checks: every position, velocity and spin finite.

use std::collections::HashMap;

use crate::boundary::Boundary;
use crate::contact::{self, ContactGeometry, ContactLaw};
use crate::integrate::Integrator;
use crate::neighbor::NeighborSearch;
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
    rotate: bool,
    pair_history: HashMap<(usize, usize), Vec3>,
    wall_history: HashMap<(usize, usize), Vec3>,
    spare_history: HashMap<(usize, usize), Vec3>,
    record: bool,
    records: Vec<ContactRecord>,
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
        let mut sim = Self {
            setup,
            state,
            time: 0.0,
            steps: 0,
            ledger: Ledger::default(),
            stored_energy: 0.0,
            rotate,
            pair_history: HashMap::new(),
            wall_history: HashMap::new(),
            spare_history: HashMap::new(),
            record: false,
            records: Vec::new(),
        };
        sim.check_finite()?;
        sim.compute_forces(0.0);
        let dt = sim.setup.dt;
        sim.setup.integrator.start(&mut sim.state, dt);
        Ok(sim)
    }

    /// Records per-contact diagnostics at every force evaluation (see [`Self::contacts`]).
    pub fn record_contacts(&mut self, on: bool) {
        self.record = on;
        self.records.clear();
        if on {
            let dt = self.setup.dt;
            self.compute_forces(0.0 * dt);
        }
    }

    /// Contacts of the last force evaluation (empty unless recording).
    pub fn contacts(&self) -> &[ContactRecord] {
        &self.records
    }

    /// True if spins are integrated.
    pub fn rotates(&self) -> bool {
        self.rotate
    }

    /// Advances one time step.
    pub fn step(&mut self) -> Result<(), SimError> {
        let dt = self.setup.dt;
        self.setup.integrator.before_forces(&mut self.state, dt, self.rotate);
        self.time += dt;
        for x in self.state.pos.iter_mut() {
            *x = self.setup.boundary.wrap(*x);
        }
        self.compute_forces(dt);
        self.setup.integrator.after_forces(&mut self.state, dt, self.rotate);
        self.steps += 1;
        self.check_finite()
    }

    /// Total mechanical energy: kinetic, rotational, gravitational and stored in contacts (J).
    pub fn total_energy(&self) -> f64 {
        crate::observe::kinetic_energy(&self.state)
            + crate::observe::rotational_energy(&self.state)
            + crate::observe::potential_energy(&self.state, self.setup.gravity)
            + self.stored_energy
    }

    fn check_finite(&self) -> Result<(), SimError> {
        let s = &self.state;
        for i in 0..s.len() {
            for (field, v) in [("position", &s.pos[i]), ("velocity", &s.vel[i]), ("spin", &s.omega[i])] {
                if !v.iter().all(|c| c.is_finite()) {
                    return Err(SimError::NonFinite {
                        step: self.steps,
                        particle: i,
                        field,
                    });
                }
            }
        }
        Ok(())
    }

    /// Evaluates all forces and torques at the current positions; `ledger_dt` is the time
    /// over which the resulting powers are booked (0 for the initial evaluation).
    fn compute_forces(&mut self, ledger_dt: f64) {
        let setup = &self.setup;
        let s = &mut self.state;
        let dt = setup.dt;
        for i in 0..s.len() {
            s.force[i] = setup.gravity / s.inv_mass[i];
            s.torque[i] = Vec3::zeros();
        }
        self.records.clear();
        let mut stored = 0.0;
        let mut dissipated = 0.0;
        let mut injected = 0.0;

        // Particle pairs.
        let keep_history = setup.pair_law.has_history();
        let mut next = std::mem::take(&mut self.spare_history);
        next.clear();
        let old = &self.pair_history;
        let records = &mut self.records;
        let record = self.record;
        setup.neighbors.for_each_pair(&s.pos, |i, j| {
            let d = setup.boundary.min_image(s.pos[i] - s.pos[j]);
            let xj = s.pos[i] - d;
            let Some(g) = ContactGeometry::pair(s.pos[i], xj, s.vel[i], s.vel[j], s.omega[i], s.omega[j], s.radius[i], s.radius[j]) else {
                return;
            };
            let mut zeta = if keep_history {
                old.get(&(i, j)).copied().unwrap_or_else(Vec3::zeros)
            } else {
                Vec3::zeros()
            };
            let f = contact::evaluate(&setup.pair_law, &g, &mut zeta, dt);
            if keep_history {
                next.insert((i, j), zeta);
            }
            s.force[i] += f.force;
            s.force[j] -= f.force;
            s.torque[i] += f.torque_i;
            s.torque[j] += f.torque_j;
            stored += f.stored_energy;
            dissipated += f.dissipation_rate;
            if record {
                records.push(ContactRecord {
                    i,
                    partner: Partner::Particle(j),
                    overlap: g.overlap,
                    overlap_rate: g.overlap_rate,
                    normal_raw: f.normal_raw,
                    normal: f.normal,
                    tangential: f.tangential.norm(),
                    mu: setup.pair_law.tangential.mu(),
                });
            }
        });
        self.spare_history = std::mem::replace(&mut self.pair_history, next);

        // Walls.
        let keep_history = setup.wall_law.has_history();
        let mut next = std::mem::take(&mut self.spare_history);
        next.clear();
        for (k, wall) in setup.walls.iter().enumerate() {
            let origin = wall.origin_at(self.time);
            let v_wall = wall.motion.velocity(self.time);
            for i in 0..s.len() {
                let Some(g) = ContactGeometry::wall(s.pos[i], s.vel[i], s.omega[i], s.radius[i], origin, wall.normal, v_wall) else {
                    continue;
                };
                let mut zeta = if keep_history {
                    self.wall_history.get(&(i, k)).copied().unwrap_or_else(Vec3::zeros)
                } else {
                    Vec3::zeros()
                };
                let f = contact::evaluate(&setup.wall_law, &g, &mut zeta, dt);
                if keep_history {
                    next.insert((i, k), zeta);
                }
                s.force[i] += f.force;
                s.torque[i] += f.torque_i;
                stored += f.stored_energy;
                dissipated += f.dissipation_rate;
                injected += f.force.dot(&v_wall);
                if self.record {
                    self.records.push(ContactRecord {
                        i,
                        partner: Partner::Wall(k),
                        overlap: g.overlap,
                        overlap_rate: g.overlap_rate,
                        normal_raw: f.normal_raw,
                        normal: f.normal,
                        tangential: f.tangential.norm(),
                        mu: setup.wall_law.tangential.mu(),
                    });
                }
            }
        }
        self.spare_history = std::mem::replace(&mut self.wall_history, next);

        self.stored_energy = stored;
        self.ledger.injected += injected * ledger_dt;
        self.ledger.dissipated += dissipated * ledger_dt;
    }
}
