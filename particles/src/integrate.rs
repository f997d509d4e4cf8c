//! Time integrators. Each splits a step into the part before the force evaluation and the
//! part after it; [`crate::sim`] calls them in that order.

use crate::state::State;

/// Integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Velocity Verlet for translation and rotation (default). Positions advance with the
    /// half-step velocity `v(t + dt/2)`; velocity-dependent forces (damping, friction) are
    /// evaluated with the predicted full-step velocity `v(t + dt/2) + a(t) dt/2` rather than
    /// the half-step one (which lags by `dt/2` and makes restitution only first order).
    /// Second order for dissipative contacts, symplectic for conservative ones, and exact
    /// conservation of linear and angular momentum.
    VelocityVerlet,
    /// The thesis' scheme (sec 3.5.1): Verlet positions (eq 3.26, written in its leapfrog
    /// form), velocities from the central-difference estimator eq 3.27, Euler rotation
    /// (eq 3.22-3.23), started by the backward Euler step below eq 3.27.
    Thesis,
}

impl Integrator {
    /// Prepares the first step after the initial force evaluation.
    pub fn start(&self, s: &mut State, dt: f64) {
        match self {
            Integrator::VelocityVerlet => {}
            Integrator::Thesis => {
                // r(t - dt) = r - dt (v - dt a)  =>  u_{-1/2} = (r - r(t-dt)) / dt = v - dt a.
                for i in 0..s.len() {
                    s.vel_half[i] = s.vel[i] - s.force[i] * (dt * s.inv_mass[i]);
                }
            }
        }
    }

    /// Stage before the force evaluation: positions to `t + dt`, and velocities to where the
    /// force evaluation needs them.
    pub fn before_forces(&self, s: &mut State, dt: f64, rotate: bool) {
        match self {
            Integrator::VelocityVerlet => {
                for i in 0..s.len() {
                    let half_kick = s.force[i] * (0.5 * dt * s.inv_mass[i]);
                    s.vel_half[i] = s.vel[i] + half_kick;
                    s.pos[i] += s.vel_half[i] * dt;
                    s.vel[i] = s.vel_half[i] + half_kick; // predictor for the forces
                }
                if rotate {
                    for i in 0..s.len() {
                        let half_kick = s.torque[i] * (0.5 * dt * s.inv_inertia[i]);
                        s.omega_half[i] = s.omega[i] + half_kick;
                        s.omega[i] = s.omega_half[i] + half_kick;
                    }
                }
            }
            Integrator::Thesis => {
                for i in 0..s.len() {
                    let a = s.force[i] * s.inv_mass[i];
                    s.vel_half[i] += a * dt; // u_{n+1/2} = u_{n-1/2} + dt a_n
                    s.pos[i] += s.vel_half[i] * dt; // eq 3.26
                    s.vel[i] = s.vel_half[i] + a * (0.5 * dt); // eq 3.27
                }
                if rotate {
                    for i in 0..s.len() {
                        s.omega[i] += s.torque[i] * (dt * s.inv_inertia[i]); // eq 3.23
                    }
                }
            }
        }
    }

    /// Stage after the force evaluation.
    pub fn after_forces(&self, s: &mut State, dt: f64, rotate: bool) {
        match self {
            Integrator::VelocityVerlet => {
                for i in 0..s.len() {
                    s.vel[i] = s.vel_half[i] + s.force[i] * (0.5 * dt * s.inv_mass[i]);
                }
                if rotate {
                    for i in 0..s.len() {
                        s.omega[i] = s.omega_half[i] + s.torque[i] * (0.5 * dt * s.inv_inertia[i]);
                    }
                }
            }
            Integrator::Thesis => {}
        }
    }

    /// Formal order of accuracy of the trajectory.
    pub fn order(&self) -> u32 {
        match self {
            Integrator::VelocityVerlet => 2,
            Integrator::Thesis => 1,
        }
    }
}
