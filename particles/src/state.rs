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
