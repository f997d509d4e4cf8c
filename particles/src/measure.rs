//! Measures of a state: energies, momentum and angular momentum, and the state hash.

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

/// FNV-1a, 64 bit: a stable, dependency-free hash for cache keys and state fingerprints.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Bit-exact fingerprint of all positions and velocities (FNV-1a of their IEEE bytes in
/// particle order). Equal hashes mean identical trajectories, whatever the thread count.
pub fn state_hash(s: &State) -> u64 {
    let mut bytes = Vec::with_capacity(s.len() * 48);
    for i in 0..s.len() {
        for v in [&s.pos[i], &s.vel[i]] {
            for c in v.iter() {
                bytes.extend_from_slice(&c.to_bits().to_le_bytes());
            }
        }
    }
    fnv1a(&bytes)
}
