//! Observables of a state: energies, momentum and angular momentum.

use crate::state::State;
use crate::Vec3;

/// Translational kinetic energy `sum m v^2 / 2` (J).
pub fn kinetic_energy(s: &State) -> f64 {
    (0..s.len()).map(|i| 0.5 * s.mass(i) * s.vel[i].norm_squared()).sum()
}

/// Rotational kinetic energy `sum I omega^2 / 2` (J).
pub fn rotational_energy(s: &State) -> f64 {
    (0..s.len()).map(|i| 0.5 * s.inertia(i) * s.omega[i].norm_squared()).sum()
}

/// Potential energy in the uniform field `gravity` (m/s^2): `-sum m g . r` (J).
pub fn potential_energy(s: &State, gravity: Vec3) -> f64 {
    (0..s.len()).map(|i| -s.mass(i) * gravity.dot(&s.pos[i])).sum()
}

/// Total linear momentum (kg m/s).
pub fn momentum(s: &State) -> Vec3 {
    (0..s.len()).fold(Vec3::zeros(), |p, i| p + s.vel[i] * s.mass(i))
}

/// Total angular momentum about the origin, orbital plus spin, `sum m r x v + I omega` (kg m^2/s).
pub fn angular_momentum(s: &State) -> Vec3 {
    (0..s.len()).fold(Vec3::zeros(), |l, i| {
        l + s.pos[i].cross(&s.vel[i]) * s.mass(i) + s.omega[i] * s.inertia(i)
    })
}
