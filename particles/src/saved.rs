//! The dynamic state of a [`Simulation`] as plain data: what a run continued from it needs to
//! go on bit for bit as if it had never stopped. This crate knows no byte layout; whoever
//! stores the state (the root crate's checkpoints) chooses one.

use crate::error::StateMismatch;
use crate::sim::{Ledger, Simulation};
use crate::Vec3;

/// Everything of a running simulation that its scene and sample do not give back: time,
/// step count, ledger, per-particle kinematics and forces, and the tangential and rolling
/// springs.
#[derive(Clone, Debug, PartialEq)]
pub struct SavedState {
    /// Simulated time (s).
    pub time: f64,
    /// Completed steps.
    pub steps: u64,
    pub ledger: Ledger,
    /// Elastic energy stored in contacts at the last force evaluation (J).
    pub stored_energy: f64,
    /// Per particle: position, velocity, spin, half-step velocity, half-step spin, force and
    /// torque, in the order of [`crate::state::State`].
    pub pos: Vec<Vec3>,
    pub vel: Vec<Vec3>,
    pub omega: Vec<Vec3>,
    pub vel_half: Vec<Vec3>,
    pub omega_half: Vec<Vec3>,
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    /// Non-zero tangential springs of particle pairs, `(i, j, zeta)` with `i < j`, the spring
    /// seen from `i`, ordered by `i`, then `j`. States saved while each pair was evaluated
    /// from both sides also hold `(j, i, -zeta)`; an import takes the smaller index's entry
    /// and the other only where it is alone.
    pub pair_histories: Vec<(usize, usize, Vec3)>,
    /// Tangential springs of particle-wall contacts, slot `i * max(walls, 1) + k`.
    pub wall_histories: Vec<Vec3>,
    /// Non-zero rolling springs (rad) of particle pairs (spring-dashpot-slider), as
    /// `pair_histories`; empty without a rolling spring.
    pub pair_rolls: Vec<(usize, usize, Vec3)>,
    /// Rolling springs of particle-wall contacts, as `wall_histories`; empty without a
    /// rolling spring (a law with one then starts from zero springs).
    pub wall_rolls: Vec<Vec3>,
    /// Where the simulation keeps each grain (`run.sort_interval`): `order[k]` is the grain
    /// at place `k` of its arrays; empty while every grain is at its own index. Every other
    /// field is in the grains' own order; a resumed run takes these places back, so that it
    /// adds each grain's forces in the same order as the run it continues.
    pub order: Vec<u32>,
    /// The rigid bodies' states when the grains are clumps ([`crate::rigid::SavedBody`]);
    /// empty for spheres.
    pub bodies: Vec<crate::rigid::SavedBody>,
}

impl SavedState {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True if the state holds no particle.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }
}

impl Simulation {
    /// The dynamic state as plain data (see [`SavedState`]).
    pub fn export_state(&self) -> SavedState {
        let s = self.state();
        SavedState {
            time: self.time,
            steps: self.steps,
            ledger: self.ledger,
            stored_energy: self.stored_energy,
            pos: s.pos.clone(),
            vel: s.vel.clone(),
            omega: s.omega.clone(),
            vel_half: s.vel_half.clone(),
            omega_half: s.omega_half.clone(),
            force: s.force.clone(),
            torque: s.torque.clone(),
            pair_histories: self.pair_histories(),
            wall_histories: self.wall_histories(),
            pair_rolls: self.pair_rolls(),
            wall_rolls: self.wall_rolls(),
            order: self.order().to_vec(),
            bodies: self.bodies().map_or_else(Vec::new, |b| b.export()),
        }
    }

    /// Continues this simulation, built from the same scene and sample as the one that
    /// exported `saved`, from that state. An error names what does not match; the simulation
    /// is then left in an unspecified state and must not be stepped.
    pub fn import_state(&mut self, saved: SavedState) -> Result<(), StateMismatch> {
        if self.bodies().map_or(0, |b| b.len()) != saved.bodies.len() {
            return Err(StateMismatch::Clumps {
                saved: saved.bodies.len(),
                bodies: self.bodies().map_or(0, |b| b.len()),
            });
        }
        let n = self.len();
        if saved.len() != n {
            return Err(StateMismatch::ParticleCount {
                saved: saved.len(),
                scene: n,
            });
        }
        let per_particle = [
            &saved.vel,
            &saved.omega,
            &saved.vel_half,
            &saved.omega_half,
            &saved.force,
            &saved.torque,
        ];
        if per_particle.iter().any(|v| v.len() != n) {
            return Err(StateMismatch::FieldLength { particles: n });
        }
        self.unsort();
        self.time = saved.time;
        self.steps = saved.steps;
        self.ledger = saved.ledger;
        self.stored_energy = saved.stored_energy;
        let s = self.state_mut();
        s.pos = saved.pos;
        s.vel = saved.vel;
        s.omega = saved.omega;
        s.vel_half = saved.vel_half;
        s.omega_half = saved.omega_half;
        s.force = saved.force;
        s.torque = saved.torque;
        self.set_histories((&saved.pair_histories, saved.wall_histories), (&saved.pair_rolls, saved.wall_rolls))?;
        self.import_bodies(&saved.bodies);
        if saved.order.is_empty() {
            Ok(())
        } else {
            self.place_grains(&saved.order)
        }
    }
}
