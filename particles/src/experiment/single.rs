//! One sphere on the horizontally shaken plate (thesis 3.3, Table 3.1, Figs 3.7-3.12), its
//! steady amplitudes next to the closed forms of rolling and sliding, and the
//! rolling-friction stopping test (thesis 3.5.2, Fig 3.19).
//!
//! # What a free sphere on a shaken floor does
//!
//! The floor moves as `x_f = A sin(w t)`, `w = 2 pi nu`; `Gamma = A w^2 / g`. The floor's
//! only horizontal force on the sphere is the friction `F` at the contact point. With
//! `I = (2/5) m R^2`, `m dv/dt = F` and `R d(omega_y)/dt = -(5/2) F / m`, so:
//! - `v + (2/5) R omega_y` never changes (angular momentum about the contact point): from
//!   rest it stays 0, and the centre velocity is always `v = (2/7) u_c`, where
//!   `u_c = v - R omega_y` is the contact point's velocity. Rolling friction (a torque
//!   without a force) breaks this; without it the relation holds in every regime.
//! - The slip `u_c - v_f` changes at `(7/2) F / m - a_f`.
//!
//! **Rolling without slip** (`u_c = v_f`): `v = (2/7) v_f`, so the centre moves 2/7 of the
//! floor's displacement at every frequency: `x` peak-to-peak `2 (2/7) A`, velocity amplitude
//! `(2/7) A w`. It needs the friction `F = (2/7) m a_f`, at most `(2/7) m A w^2`, which a
//! Coulomb floor (`|F| <= mu m g`) gives while `Gamma <= 7 mu / 2` (2.45 for `mu = 0.7`;
//! nu <= 4.98 Hz at A = 25 mm). An uncapped floor (`friction = inf`) gives it at every
//! frequency, up to the small slip `F / gamma_t` that Haff-Werner's viscous branch needs.
//!
//! **Sliding** (continuous, Coulomb): `F = mu m g sgn(v_f - u_c)`, a square wave, so the
//! centre's acceleration is `+-mu g` and `v` a triangle wave. By the half-period symmetry
//! of the steady state, `F` switches sign twice per period, half a period apart: `v` then
//! climbs by `mu g T/2` from `-V` to `V`, so `V = mu g / (4 nu)`, and `x` moves by the area
//! of one half-triangle, `x` peak-to-peak `= V T / 4 = mu g / (16 nu^2)`: both independent
//! of the amplitude and of the phase of the switches. The switches sit where
//! `u_c = v_f`; with `u_c = (7/2) v` peaking at `(7/2) V` there, the switch phase `theta`
//! obeys `cos theta = (7/2) V / (A w) = 7 pi mu / (4 Gamma)`, and the slip must keep its new
//! sign after the switch, `A w^2 sin theta > (7/2) mu g`. Both hold, and the grain slides
//! all the time, for `Gamma >= (7 mu / 2) sqrt(1 + pi^2 / 4)` (4.56 for `mu = 0.7`; nu >=
//! 6.8 Hz at 25 mm). (A block that cannot roll obeys the same formulas above
//! `Gamma >= mu sqrt(1 + pi^2 / 4)`.) Between `7 mu / 2` and that bound the sphere
//! alternates between rolling and sliding, and its amplitudes lie between the two closed
//! forms.

use serde::Serialize;

use crate::boundary::Boundary;
use crate::constants::GRAVITY;
use crate::contact::ContactLaw;
use crate::integrate::Integrator;
use crate::neighbor::NeighborSearch;
use crate::scene::Scene;
use crate::setup::{Setup, Vertical};
use crate::sim::Simulation;
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
    /// Time integrator.
    pub integrator: Integrator,
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
            integrator: Integrator::VelocityVerlet,
        }
    }

    /// A sphere of radius `radius` (m) on the floor of `scene`: the scene's particle-wall
    /// law (after its toggles), grain density, integrator and the tray's gravity, with the
    /// step `dt` (s).
    pub fn on_scene(scene: &Scene, radius: f64, dt: f64) -> Result<Self, SimError> {
        Ok(Self {
            radius,
            density: scene.material.density,
            law: scene.laws()?.1,
            gravity: GRAVITY,
            dt,
            integrator: scene.run.integrator,
        })
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
            integrator: self.integrator,
            boundary: Boundary::open(),
            neighbors: NeighborSearch::AllPairs,
            vertical: Vertical::Free,
            container: None,
            sort: crate::scene::SortInterval::NONE,
            rolling_mu: Vec::new(),
            clump: None,
        };
        Simulation::new(setup, state)
    }

    fn sample(sim: &Simulation, motion: &Motion) -> Sample {
        let s = sim.state();
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
        let mut sim = self.simulation(motion.clone(), v0)?;
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

/// Steady amplitudes of the sphere's motion along x.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Amplitudes {
    /// Peak-to-peak displacement of the centre (m).
    pub x_peak_to_peak: f64,
    /// Half the peak-to-peak velocity of the centre (m/s).
    pub vx_amplitude: f64,
}

impl Amplitudes {
    /// Rolling without slip (module docs): `x` peak-to-peak `2 (2/7) A`, velocity amplitude
    /// `(2/7) A w`, for the floor amplitude `amplitude` (m) at `frequency` (Hz).
    pub fn rolling(amplitude: f64, frequency: f64) -> Self {
        let w = 2.0 * std::f64::consts::PI * frequency;
        Self {
            x_peak_to_peak: 2.0 * (2.0 / 7.0) * amplitude,
            vx_amplitude: (2.0 / 7.0) * amplitude * w,
        }
    }

    /// Continuous Coulomb sliding (module docs): `x` peak-to-peak `mu g / (16 nu^2)`,
    /// velocity amplitude `mu g / (4 nu)`, for the friction coefficient `mu`, gravity `g`
    /// (m/s^2) and `frequency` (Hz). Exact for a sphere above [`continuous_sliding_gamma`].
    pub fn sliding(mu: f64, gravity: f64, frequency: f64) -> Self {
        Self {
            x_peak_to_peak: mu * gravity / (16.0 * frequency * frequency),
            vx_amplitude: mu * gravity / (4.0 * frequency),
        }
    }
}

/// Largest `Gamma = A w^2 / g` at which a sphere on a Coulomb floor rolls without slip:
/// `7 mu / 2` (2.45 for `mu = 0.7`).
pub fn rolling_gamma(mu: f64) -> f64 {
    3.5 * mu
}

/// Smallest `Gamma` at which a sphere on a Coulomb floor slides all the time:
/// `(7 mu / 2) sqrt(1 + pi^2 / 4)` (4.56 for `mu = 0.7`; module docs).
pub fn continuous_sliding_gamma(mu: f64) -> f64 {
    3.5 * mu * (1.0 + std::f64::consts::PI.powi(2) / 4.0).sqrt()
}

/// `Gamma = A (2 pi nu)^2 / g` of a drive.
pub fn gamma(amplitude: f64, frequency: f64, gravity: f64) -> f64 {
    amplitude * (2.0 * std::f64::consts::PI * frequency).powi(2) / gravity
}

/// The amplitudes of a shaking run at `frequency` (Hz), measured over its last half: the
/// means, over the whole periods that end in the last half of the samples, of the
/// peak-to-peak `x` and half the peak-to-peak `v_x` within each period (per period, so that
/// a slow drift, from rolling friction for example, does not count as oscillation).
/// `None` without a whole period in the last half.
pub fn amplitudes(samples: &[Sample], frequency: f64) -> Option<Amplitudes> {
    let end = samples.last()?.t;
    let period = 1.0 / frequency;
    let first = (0.5 * end / period).ceil() as usize;
    let last = (end / period + 1e-9).floor() as usize;
    if last <= first {
        return None;
    }
    let (mut x_sum, mut v_sum) = (0.0, 0.0);
    for k in first..last {
        let (t0, t1) = (k as f64 * period, (k + 1) as f64 * period);
        let within = samples.iter().filter(|s| s.t >= t0 && s.t <= t1);
        let (mut x_lo, mut x_hi, mut v_lo, mut v_hi) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for s in within {
            (x_lo, x_hi) = (x_lo.min(s.x), x_hi.max(s.x));
            (v_lo, v_hi) = (v_lo.min(s.vx), v_hi.max(s.vx));
        }
        x_sum += x_hi - x_lo;
        v_sum += 0.5 * (v_hi - v_lo);
    }
    let n = (last - first) as f64;
    Some(Amplitudes {
        x_peak_to_peak: x_sum / n,
        vx_amplitude: v_sum / n,
    })
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
