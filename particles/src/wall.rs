//! Flat walls of infinite mass (eq 3.17-3.18) and their prescribed motion.

use crate::drive::Schedule;
use crate::Vec3;
use std::f64::consts::PI;
use std::sync::Arc;

/// Prescribed motion of a wall.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// At rest.
    Fixed,
    /// Harmonic shaking `u(t) = amplitude sin(2 pi frequency t) direction` (thesis 3.5);
    /// `amplitude` in m, `frequency` in Hz, `direction` a unit vector.
    Harmonic { amplitude: f64, frequency: f64, direction: Vec3 },
    /// Harmonic shaking in stages ([`Schedule`]) along `direction`, a unit vector: the
    /// experiment's protocol.
    Scheduled { schedule: Arc<Schedule>, direction: Vec3 },
}

impl Motion {
    /// `(direction, amplitude, angular frequency w, phase w t)` of a harmonic motion at
    /// time `t`; `None` at rest.
    fn harmonic(&self, t: f64) -> Option<(Vec3, f64, f64, f64)> {
        match *self {
            Motion::Fixed => None,
            Motion::Harmonic {
                amplitude,
                frequency,
                direction,
            } => {
                let w = 2.0 * PI * frequency;
                Some((direction, amplitude, w, w * t))
            }
            Motion::Scheduled { ref schedule, direction } => {
                let (amplitude, w, phase) = schedule.phase(t);
                Some((direction, amplitude, w, phase))
            }
        }
    }

    /// Displacement from the rest position at time `t` (m).
    pub fn displacement(&self, t: f64) -> Vec3 {
        self.harmonic(t).map_or(Vec3::zeros(), |(direction, amplitude, _, phase)| {
            direction * (amplitude * phase.sin())
        })
    }

    /// Velocity at time `t` (m/s).
    pub fn velocity(&self, t: f64) -> Vec3 {
        self.harmonic(t).map_or(Vec3::zeros(), |(direction, amplitude, w, phase)| {
            direction * (amplitude * w * phase.cos())
        })
    }

    /// Largest displacement from the rest position (m): the (largest stage's) amplitude, 0
    /// at rest.
    pub fn displacement_bound(&self) -> f64 {
        match *self {
            Motion::Fixed => 0.0,
            Motion::Harmonic { amplitude, .. } => amplitude.abs(),
            Motion::Scheduled { ref schedule, .. } => schedule.largest_amplitude(),
        }
    }

    /// Peak acceleration (m/s^2; of the strongest stage of a schedule).
    pub fn peak_acceleration(&self) -> f64 {
        match *self {
            Motion::Fixed => 0.0,
            Motion::Harmonic { amplitude, frequency, .. } => amplitude * (2.0 * PI * frequency).powi(2),
            Motion::Scheduled { ref schedule, .. } => schedule.peak_acceleration(),
        }
    }
}

/// An infinite flat wall: the plane through `origin + motion.displacement(t)` with unit normal
/// `normal` pointing into the domain. Particles touch it with `R_eff = R`, `m_eff = m`.
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    /// Name used in messages ("floor", "side y=0", ...).
    pub name: String,
    pub origin: Vec3,
    pub normal: Vec3,
    pub motion: Motion,
}

impl Wall {
    /// A wall; `normal` is normalised.
    pub fn new(name: &str, origin: Vec3, normal: Vec3, motion: Motion) -> Self {
        Self {
            name: name.to_string(),
            origin,
            normal: normal.normalize(),
            motion,
        }
    }

    /// A point of the plane at time `t`.
    pub fn origin_at(&self, t: f64) -> Vec3 {
        self.origin + self.motion.displacement(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_velocity_is_derivative_of_displacement() {
        let m = Motion::Harmonic {
            amplitude: 0.025,
            frequency: 20.0,
            direction: Vec3::x(),
        };
        let (t, h) = (0.0123, 1e-7);
        let fd = (m.displacement(t + h) - m.displacement(t - h)) / (2.0 * h);
        assert!((fd - m.velocity(t)).norm() < 1e-6);
        assert!((m.peak_acceleration() / 10.0 - 39.478).abs() < 1e-3); // about 40 g
    }
}
