//! Particle state as a struct of arrays.

use crate::Vec3;

/// Positions, velocities, spins, forces, torques and constant properties of all particles.
/// Index `i` addresses the same particle in every array.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct State {
    /// Centre positions (m).
    pub pos: Vec<Vec3>,
    /// Velocities (m/s).
    pub vel: Vec<Vec3>,
    /// Angular velocities (rad/s).
    pub omega: Vec<Vec3>,
    /// Total force of the last force evaluation (N).
    pub force: Vec<Vec3>,
    /// Total torque of the last force evaluation (N m).
    pub torque: Vec<Vec3>,
    /// Half-step velocities `v(t + dt/2)` (m/s), kept by the integrators between stages.
    pub vel_half: Vec<Vec3>,
    /// Half-step spins `omega(t + dt/2)` (rad/s), kept by velocity Verlet between stages.
    pub omega_half: Vec<Vec3>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Inverse masses (1/kg).
    pub inv_mass: Vec<f64>,
    /// Inverse moments of inertia of solid spheres, `1 / (2/5 m R^2)` (1/(kg m^2)).
    pub inv_inertia: Vec<f64>,
}

impl State {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Appends a solid sphere of radius `radius` (m) and mass `mass` (kg).
    pub fn push(&mut self, pos: Vec3, vel: Vec3, omega: Vec3, radius: f64, mass: f64) {
        self.pos.push(pos);
        self.vel.push(vel);
        self.omega.push(omega);
        self.force.push(Vec3::zeros());
        self.torque.push(Vec3::zeros());
        self.vel_half.push(vel);
        self.omega_half.push(omega);
        self.radius.push(radius);
        self.inv_mass.push(1.0 / mass);
        self.inv_inertia.push(1.0 / (0.4 * mass * radius * radius));
    }

    /// Mass of particle `i` (kg).
    pub fn mass(&self, i: usize) -> f64 {
        1.0 / self.inv_mass[i]
    }

    /// Moment of inertia of particle `i` (kg m^2).
    pub fn inertia(&self, i: usize) -> f64 {
        1.0 / self.inv_inertia[i]
    }
}

/// Mutable view of a contiguous block of particles `start..start + len`, for the parallel
/// per-particle stages of a step.
pub struct StateBlock<'a> {
    /// Index of the first particle of the block.
    pub start: usize,
    pub pos: &'a mut [Vec3],
    pub vel: &'a mut [Vec3],
    pub omega: &'a mut [Vec3],
    pub vel_half: &'a mut [Vec3],
    pub omega_half: &'a mut [Vec3],
    pub force: &'a [Vec3],
    pub torque: &'a [Vec3],
    pub inv_mass: &'a [f64],
    pub inv_inertia: &'a [f64],
}

impl State {
    /// Splits the state into blocks of `size` particles (the last may be shorter).
    pub fn blocks_mut(&mut self, size: usize) -> Vec<StateBlock<'_>> {
        let mut out = Vec::with_capacity(self.len().div_ceil(size));
        let mut start = 0;
        let pos = self.pos.chunks_mut(size);
        let mut vel = self.vel.chunks_mut(size);
        let mut omega = self.omega.chunks_mut(size);
        let mut vel_half = self.vel_half.chunks_mut(size);
        let mut omega_half = self.omega_half.chunks_mut(size);
        let mut force = self.force.chunks(size);
        let mut torque = self.torque.chunks(size);
        let mut inv_mass = self.inv_mass.chunks(size);
        let mut inv_inertia = self.inv_inertia.chunks(size);
        for p in pos {
            let len = p.len();
            out.push(StateBlock {
                start,
                pos: p,
                vel: vel.next().expect("same length"),
                omega: omega.next().expect("same length"),
                vel_half: vel_half.next().expect("same length"),
                omega_half: omega_half.next().expect("same length"),
                force: force.next().expect("same length"),
                torque: torque.next().expect("same length"),
                inv_mass: inv_mass.next().expect("same length"),
                inv_inertia: inv_inertia.next().expect("same length"),
            });
            start += len;
        }
        out
    }
}
