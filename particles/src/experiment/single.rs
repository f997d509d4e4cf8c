//! One sphere on the horizontally shaken plate (thesis 3.3, Table 3.1) and the
//! rolling-friction stopping test (thesis 3.5.2, Fig 3.19).

use serde::Serialize;

use crate::boundary::Boundary;
use crate::contact::ContactLaw;
use crate::integrate::Integrator;
use crate::neighbor::NeighborSearch;
use crate::sim::{Setup, Simulation, Vertical};
use crate::state::State;
use crate::wall::{Motion, Wall};
use crate::{SimError, Vec3};

/// A single sphere resting on a floor (the plane z = 0) under gravity `-g e_z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereOnFloor {
    /// Radius (m) and density (kg/m^3).
    pub radius: f64,
    pub density: f64,
    /// Sphere-floor contact law.
    pub law: ContactLaw,
    /// Gravitational acceleration g (m/s^2).
    pub gravity: f64,
    /// Time step (s).
    pub dt: f64,
}

/// One sample of a trajectory (SI units; `omega_y` in rad/s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sample {
    pub t: f64,
    pub x: f64,
    pub z: f64,
    pub vx: f64,
    pub vz: f64,
    pub omega_y: f64,
    /// Floor displacement and velocity along x.
    pub floor_x: f64,
    pub floor_vx: f64,
}

impl SphereOnFloor {
    /// The thesis' single-particle parameters (Table 3.1): R = 0.5 mm, rho = 2500 kg/m^3,
    /// g = 10 m/s^2, dt = 8e-6 s, with the given floor law.
    pub fn thesis(law: ContactLaw) -> Self {
        Self {
            radius: 5e-4,
            density: 2500.0,
            law,
            gravity: 10.0,
            dt: 8e-6,
        }
    }

    /// Mass (kg).
    pub fn mass(&self) -> f64 {
        self.density * 4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
    }

    /// A simulation with the sphere at rest in its static equilibrium on a floor that moves
    /// with `motion`, with initial velocity `v0` and no spin.
    fn simulation(&self, motion: Motion, v0: Vec3) -> Result<Simulation, SimError> {
        let m = self.mass();
        let sink = self.law.normal.static_overlap(m * self.gravity, self.radius);
        let mut state = State::default();
        state.push(Vec3::new(0.0, 0.0, self.radius - sink), v0, Vec3::zeros(), self.radius, m);
        let setup = Setup {
            pair_law: self.law,
            wall_law: self.law,
            walls: vec![Wall::new("floor", Vec3::zeros(), Vec3::z(), motion)],
            gravity: Vec3::new(0.0, 0.0, -self.gravity),
            dt: self.dt,
            integrator: Integrator::VelocityVerlet,
            boundary: Boundary::open(),
            neighbors: NeighborSearch::AllPairs,
            vertical: Vertical::Free,
            container: None,
        };
        Simulation::new(setup, state)
    }

    fn sample(sim: &Simulation, motion: &Motion) -> Sample {
        let s = &sim.state;
        Sample {
            t: sim.time,
            x: s.pos[0].x,
            z: s.pos[0].z,
            vx: s.vel[0].x,
            vz: s.vel[0].z,
            omega_y: s.omega[0].y,
            floor_x: motion.displacement(sim.time).x,
            floor_vx: motion.velocity(sim.time).x,
        }
    }

    /// Shakes the floor with `x_tray = amplitude sin(2 pi frequency t)` for `duration` s,
    /// sampling every `every` steps.
    pub fn shake(&self, amplitude: f64, frequency: f64, duration: f64, every: u64) -> Result<Vec<Sample>, SimError> {
        let motion = Motion::Harmonic {
            amplitude,
            frequency,
            direction: Vec3::x(),
        };
        self.run(motion, Vec3::zeros(), duration, every)
    }

    /// Launches the sphere along x at `v0` (m/s) without spin on a fixed floor (Fig 3.19).
    pub fn launch(&self, v0: f64, duration: f64, every: u64) -> Result<Vec<Sample>, SimError> {
        self.run(Motion::Fixed, Vec3::new(v0, 0.0, 0.0), duration, every)
    }

    fn run(&self, motion: Motion, v0: Vec3, duration: f64, every: u64) -> Result<Vec<Sample>, SimError> {
        let mut sim = self.simulation(motion, v0)?;
        let steps = (duration / self.dt).round() as u64;
        let every = every.max(1);
        let mut out = vec![Self::sample(&sim, &motion)];
        for k in 1..=steps {
            sim.step()?;
            if k % every == 0 || k == steps {
                out.push(Self::sample(&sim, &motion));
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{NormalLaw, RollingLaw, TangentialLaw};

    fn law(mu_r: f64) -> ContactLaw {
        ContactLaw {
            normal: NormalLaw::hertz(1e6 / 0.91, 8.5e-6),
            tangential: TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 },
            rolling: if mu_r > 0.0 {
                RollingLaw::BrilliantovPoschel { mu_r }
            } else {
                RollingLaw::None
            },
        }
    }

    #[test]
    fn resting_sphere_stays_put() {
        let s = SphereOnFloor::thesis(law(8.5e-6));
        let traj = s.launch(0.0, 0.05, 100).unwrap();
        let last = traj.last().unwrap();
        assert!(last.x.abs() < 1e-12 && (last.z - traj[0].z).abs() < 1e-12, "{last:?}");
    }

    #[test]
    fn sliding_sphere_rolls_at_five_sevenths_then_rolling_friction_stops_it() {
        // Sliding friction turns v0 into rolling at (5/7) v0 (solid sphere, angular momentum
        // about the contact point conserved); without rolling friction it then rolls forever.
        let free = SphereOnFloor::thesis(law(0.0)).launch(0.05, 0.3, 1000).unwrap();
        let v_roll = free.last().unwrap().vx;
        assert!((v_roll / 0.05 - 5.0 / 7.0).abs() < 1e-3, "rolling speed {v_roll}");
        // With rolling friction and no slip, the energy balance (7/5) m v dv/dt = -M omega =
        // -mu_r (R omega) m g omega gives dv/dt = -(5/7) (mu_r g / R) v: after 1 s the speed
        // is exp(-(5/7) 8.5e-6 * 10 / 5e-4) = 0.886 of the rolling speed.
        let braked = SphereOnFloor::thesis(law(8.5e-6)).launch(0.05, 1.0, 1000).unwrap();
        let ratio = braked.last().unwrap().vx / v_roll;
        let expect = (-5.0 / 7.0 * 8.5e-6 * 10.0 / 5e-4f64).exp();
        assert!((ratio - expect).abs() < 2e-3, "speed ratio {ratio}, expected about {expect}");
    }
}
