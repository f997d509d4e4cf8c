//! Time integrators. Each splits a step into the part before the force evaluation and the
//! part after it, as per-particle kernels; [`crate::sim`] calls them in that order.

use crate::state::{State, StateBlock};
use crate::Vec3;

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

    /// Stage before the force evaluation for particle `k` of block `b`: position to `t + dt`,
    /// and velocity and spin to where the force evaluation needs them.
    #[inline]
    pub fn before_forces(&self, b: &mut StateBlock, k: usize, dt: f64, rotate: bool) {
        match self {
            Integrator::VelocityVerlet => {
                let half_kick = b.force[k] * (0.5 * dt * b.inv_mass[k]);
                b.vel_half[k] = b.vel[k] + half_kick;
                b.pos[k] += b.vel_half[k] * dt;
                b.vel[k] = b.vel_half[k] + half_kick; // predictor for the forces
                if rotate {
                    let half_kick = b.torque[k] * (0.5 * dt * b.inv_inertia[k]);
                    b.omega_half[k] = b.omega[k] + half_kick;
                    b.omega[k] = b.omega_half[k] + half_kick;
                }
            }
            Integrator::Thesis => {
                let a = b.force[k] * b.inv_mass[k];
                b.vel_half[k] += a * dt; // u_{n+1/2} = u_{n-1/2} + dt a_n
                b.pos[k] += b.vel_half[k] * dt; // eq 3.26
                b.vel[k] = b.vel_half[k] + a * (0.5 * dt); // eq 3.27
                if rotate {
                    b.omega[k] += b.torque[k] * (dt * b.inv_inertia[k]); // eq 3.23
                }
            }
        }
    }

    /// True if the scheme has a stage after the force evaluation ([`Self::after_kick`]).
    pub fn has_after_stage(&self) -> bool {
        match self {
            Integrator::VelocityVerlet => true,
            Integrator::Thesis => false,
        }
    }

    /// Stage after the force evaluation, for one velocity (or spin) of one particle: the
    /// value at `t + dt` from the half-step value `half` and the new force (or torque) `rate`
    /// with inverse mass (or inverse inertia) `inv`: `half + rate dt inv / 2` (velocity
    /// Verlet). A pure function, so [`crate::sim`] can write its result out of place while
    /// other particles still read the predicted velocities; the identity (`half`) for schemes
    /// without an after stage.
    #[inline]
    pub fn after_kick(&self, half: Vec3, rate: Vec3, inv: f64, dt: f64) -> Vec3 {
        match self {
            Integrator::VelocityVerlet => half + rate * (0.5 * dt * inv),
            Integrator::Thesis => half,
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
