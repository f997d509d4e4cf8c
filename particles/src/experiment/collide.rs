//! The collision laboratory: one binary impact of two spheres, or of a sphere on a flat wall,
//! integrated in full 3D with the DEM of [`crate::sim`] (thesis 3.2.5, 3.5.2 and chapter 4).
//!
//! Geometry (Fig 4.2): particle i rests at the origin; particle j touches it at
//! `r_0 = r_j - r_i = l (sqrt(1 - e^2), e, 0)`, `l = R_i + R_j`, and moves with the relative
//! velocity `v_j - v_i = (-v, 0, 0)`, so the impact parameter is `d = e l`, the normal
//! approach speed `v sqrt(1 - e^2)` and the orbital angular momentum `m_eff d v` (eq 4.13).
//! Given normal and tangential speeds instead, `r_0 = l (1, 0, 0)` and
//! `v_j - v_i = (-v_n, v_t, 0)`. Against a wall (the plane z = 0), the sphere touches it at
//! `z = R` and moves with `(v_t, 0, -v_n)`.
//!
//! The contact starts at `t = 0` and ends when the normal force returns to zero while the
//! spheres separate (eq 4.8); the end time is interpolated between steps on the smooth
//! [`crate::contact::NormalLaw::release_margin`].
//!
//! Reported coefficients, with `e_r = (r_j - r_i)/|r_j - r_i|` and `g = v_j - v_i`:
//! - `eps_n_hs` (eq 4.1): `-(g' . e_r0) / (g_0 . e_r0)`, normal fixed at impact;
//! - `eps_n` (eq 4.2): `-(g' . e_r') / (g_0 . e_r0)`, normal at the end of the contact;
//! - `eps_t`: `-(c' . c_0) / |c_0|^2`, with `c` the tangential contact-point velocity of eq 3.11
//!   (undeformed radii, normal of the moment): -1 for smooth spheres, +1 for a perfectly rough
//!   reversal, `null` when `c_0 = 0`;
//! - `phi` (eq 4.3): `acos(e_r0 . e_r')`, rad.

use serde::Serialize;

use crate::boundary::Boundary;
use crate::contact::tangential::sphere_tangential_mass;
use crate::contact::{geometry::tangential_velocity, ContactLaw};
use crate::integrate::Integrator;
use crate::measure;
use crate::neighbor::NeighborSearch;
use crate::setup::{Setup, Vertical};
use crate::sim::Simulation;
use crate::state::State;
use crate::timescale::check_step_resolution;
use crate::wall::{Motion, Wall};
use crate::{SimError, Vec3};

/// Fewest steps per (estimated) contact time the lab accepts.
pub const MIN_STEPS_PER_CONTACT: f64 = 5.0;

/// Most steps per (estimated) contact time the lab accepts: beyond about 1e8 the step's
/// displacement falls below the positions' resolution in double precision.
pub const MAX_STEPS_PER_CONTACT: f64 = 1e8;

/// How the impact is specified.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Impact {
    /// Normal approach speed `vn > 0` and tangential speed `vt` at impact (m/s).
    Components { vn: f64, vt: f64 },
    /// Relative speed `v` (m/s) with eccentricity `e = d / (R_i + R_j)` in `[0, 1)` (Fig 4.2).
    Eccentric { v: f64, e: f64 },
}

/// The second body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// A sphere of radius `r` (m), mass `m` (kg) and initial spin `omega` (rad/s).
    Sphere { r: f64, m: f64, omega: Vec3 },
    /// A fixed flat wall.
    Wall,
}

/// Time-step choice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepSize {
    /// Explicit time step (s).
    Dt(f64),
    /// Steps per estimated contact time (undamped, eq 3.19 or `pi sqrt(m/k)`, at the normal
    /// approach speed).
    PerContact(f64),
}

/// A complete collision experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collision {
    pub law: ContactLaw,
    /// Radius (m), mass (kg) and initial spin (rad/s) of the first sphere (i).
    pub r1: f64,
    pub m1: f64,
    pub omega1: Vec3,
    pub target: Target,
    pub impact: Impact,
    pub step: StepSize,
    pub integrator: Integrator,
}

impl Collision {
    /// Two equal spheres of radius `radius` (m) and density `density` (kg/m^3), without
    /// spin, meeting with `impact` under `law`, at `steps` steps per contact time, with
    /// velocity Verlet.
    pub fn equal_spheres(law: ContactLaw, radius: f64, density: f64, impact: Impact, steps: f64) -> Self {
        let m = density * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
        Collision {
            law,
            r1: radius,
            m1: m,
            omega1: Vec3::zeros(),
            target: Target::Sphere {
                r: radius,
                m,
                omega: Vec3::zeros(),
            },
            impact,
            step: StepSize::PerContact(steps),
            integrator: Integrator::VelocityVerlet,
        }
    }
}

/// Outcome of a collision; serialised as the summary of `stripes collide`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CollisionResult {
    pub eps_n: f64,
    pub eps_n_hs: f64,
    pub eps_t: Option<f64>,
    /// Contact duration (s).
    pub t_c: f64,
    /// Reorientation of the normal (rad).
    pub phi: f64,
    /// Largest overlap (m).
    pub max_overlap: f64,
    pub steps: u64,
    /// Time step used (s).
    pub dt: f64,
    /// Undamped contact-time estimate used for the step (s).
    pub contact_time_estimate: f64,
    /// Kinetic + rotational energy before and after (J).
    pub energy_before: f64,
    pub energy_after: f64,
    /// `|P' - P| / (m_1 v)`; `null` against a wall (which takes momentum).
    pub momentum_error: Option<f64>,
    /// `|L' - L| / (m_eff v l)`, orbital plus spin about the origin; `null` against a wall.
    pub angular_momentum_error: Option<f64>,
    /// Largest `|F_t| / (mu |F_n|)` over all steps: `<= 1` up to round-off (0 when smooth;
    /// infinite if a tangential force ever acted without a normal force).
    pub max_friction_ratio: f64,
    /// Smallest clamped normal force over the contact (N).
    pub min_normal_force: f64,
    /// Final velocities and spins (m/s, rad/s); the second body is absent for a wall.
    pub v1: [f64; 3],
    pub omega1: [f64; 3],
    pub v2: Option<[f64; 3]>,
    pub omega2: Option<[f64; 3]>,
}

impl Collision {
    fn target_sphere(&self) -> Option<(f64, f64, Vec3)> {
        match self.target {
            Target::Sphere { r, m, omega } => Some((r, m, omega)),
            Target::Wall => None,
        }
    }

    /// Effective mass and radius of the contact.
    pub fn effective(&self) -> (f64, f64) {
        match self.target_sphere() {
            Some((r2, m2, _)) => (self.m1 * m2 / (self.m1 + m2), self.r1 * r2 / (self.r1 + r2)),
            None => (self.m1, self.r1),
        }
    }

    /// Normal approach speed and relative speed at impact (m/s).
    pub fn speeds(&self) -> (f64, f64) {
        match self.impact {
            Impact::Components { vn, vt } => (vn, vn.hypot(vt)),
            Impact::Eccentric { v, e } => (v * (1.0 - e * e).sqrt(), v),
        }
    }

    /// Undamped head-on contact time at the normal approach speed (s).
    pub fn contact_time_estimate(&self) -> f64 {
        let (m_eff, r_eff) = self.effective();
        let (vn, v) = self.speeds();
        // For grazing impacts keep the speed from vanishing (Hertz t_c ~ v^{-1/5}).
        self.law.normal.undamped_contact_time(m_eff, r_eff, vn.max(1e-3 * v))
    }

    fn validate(&self) -> Result<(), SimError> {
        let bad = |field: &str, message: &str| {
            Err(SimError::InvalidParameter {
                field: field.into(),
                message: message.into(),
            })
        };
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !positive(self.r1) {
            return bad("r1", "radius must be positive");
        }
        if !positive(self.m1) {
            return bad("m1", "mass must be positive");
        }
        if let Some((r2, m2, _)) = self.target_sphere() {
            if !positive(r2) {
                return bad("r2", "radius must be positive");
            }
            if !positive(m2) {
                return bad("m2", "mass must be positive");
            }
        }
        match self.impact {
            Impact::Components { vn, vt } => {
                if !positive(vn) {
                    return bad("v", "the normal approach speed must be positive");
                }
                if !vt.is_finite() {
                    return bad("vt", "must be finite");
                }
            }
            Impact::Eccentric { v, e } => {
                if !positive(v) {
                    return bad("v", "the relative speed must be positive");
                }
                if !(0.0..1.0).contains(&e) {
                    return bad("eccentricity", "must lie in [0, 1)");
                }
                if self.target == Target::Wall {
                    return bad("eccentricity", "needs two spheres; use --v and --vt against a wall");
                }
            }
        }
        Ok(())
    }

    /// Runs the experiment.
    pub fn run(&self) -> Result<CollisionResult, SimError> {
        self.validate()?;
        let t_est = self.contact_time_estimate();
        let dt = match self.step {
            StepSize::Dt(dt) => dt,
            StepSize::PerContact(n) => t_est / n,
        };
        if !(dt.is_finite() && dt > 0.0) {
            return Err(SimError::InvalidParameter {
                field: "dt".into(),
                message: format!("time step must be positive, got {dt}"),
            });
        }
        let (m_eff, _) = self.effective();
        let spring = self.law.tangential.spring_half_period(sphere_tangential_mass(m_eff));
        check_step_resolution(dt, MIN_STEPS_PER_CONTACT, t_est, spring, "dt", "kt")?;
        let (_, v) = self.speeds();
        let (_, r_eff) = self.effective();
        if v * dt > r_eff {
            return Err(SimError::CollisionUnresolved {
                reason: format!(
                    "at v = {v:e} m/s the bodies move {:e} m per step of {dt:e} s, more than the effective radius {r_eff:e} m: \
                     they pass through each other; no step resolves an impact this fast for this law (lower the speed or stiffen the law)",
                    v * dt
                ),
            });
        }
        if t_est / dt > MAX_STEPS_PER_CONTACT {
            return Err(SimError::CollisionUnresolved {
                reason: format!(
                    "dt = {dt:e} s gives {:.2e} steps per contact time {t_est:e} s; at most {MAX_STEPS_PER_CONTACT:e} \
                     (below that the positions no longer move in double precision): raise dt or lower the steps per contact",
                    t_est / dt
                ),
            });
        }

        let mut state = State::default();
        let (walls, r0, g0) = match self.target_sphere() {
            Some((r2, m2, w2)) => {
                let l = self.r1 + r2;
                let (r0, g0) = match self.impact {
                    Impact::Components { vn, vt } => (Vec3::new(l, 0.0, 0.0), Vec3::new(-vn, vt, 0.0)),
                    Impact::Eccentric { v, e } => (Vec3::new(l * (1.0 - e * e).sqrt(), l * e, 0.0), Vec3::new(-v, 0.0, 0.0)),
                };
                state.push(Vec3::zeros(), Vec3::zeros(), self.omega1, self.r1, self.m1);
                state.push(r0, g0, w2, r2, m2);
                (Vec::new(), r0, g0)
            }
            None => {
                let Impact::Components { vn, vt } = self.impact else {
                    unreachable!("validated")
                };
                let g0 = -Vec3::new(vt, 0.0, -vn); // wall velocity minus sphere velocity
                state.push(Vec3::new(0.0, 0.0, self.r1), -g0, self.omega1, self.r1, self.m1);
                let floor = Wall::new("wall z=0", Vec3::zeros(), Vec3::z(), Motion::Fixed);
                (vec![floor], Vec3::new(0.0, 0.0, -self.r1), g0)
            }
        };
        let e0 = r0.normalize();
        let c0 = self.contact_velocity(&state, e0);

        let energy = |s: &State| measure::kinetic_energy(s) + measure::rotational_energy(s);
        let (energy_before, p0, l0) = (energy(&state), measure::momentum(&state), measure::angular_momentum(&state));
        let setup = Setup {
            pair_law: self.law,
            wall_law: self.law,
            walls,
            gravity: Vec3::zeros(),
            dt,
            integrator: self.integrator,
            boundary: Boundary::open(),
            neighbors: NeighborSearch::AllPairs,
            vertical: Vertical::Free,
            container: None,
            sort: crate::scene::SortInterval::NONE,
            rolling_mu: Vec::new(),
            clump: None,
        };
        let mut sim = Simulation::new(setup, state)?;
        sim.record_contacts(true);

        let max_steps = (1000.0 * t_est / dt) as u64 + 1_000_000;
        let mut prev_margin = 0.0;
        let mut max_overlap: f64 = 0.0;
        let mut max_friction_ratio: f64 = 0.0;
        let mut min_normal_force = f64::INFINITY;
        let t_c = loop {
            sim.step()?;
            for c in sim.contact_records() {
                if c.tangential > 0.0 {
                    max_friction_ratio = max_friction_ratio.max(c.tangential / (c.mu * c.normal));
                }
                min_normal_force = min_normal_force.min(c.normal);
            }
            let (overlap, rate) = self.overlap(&sim.state());
            max_overlap = max_overlap.max(overlap);
            let margin = self.law.normal.release_margin(overlap, rate);
            if sim.steps > 1 && (overlap <= 0.0 || (margin <= 0.0 && rate < 0.0)) {
                let frac = prev_margin / (prev_margin - margin);
                break sim.time - dt + frac * dt;
            }
            if sim.steps >= max_steps {
                return Err(SimError::ContactDidNotEnd { steps: sim.steps });
            }
            prev_margin = margin;
        };

        // What the lab cannot resolve is refused, not reported: a contact that ends before
        // it starts or within a few steps (an overdamped law, or a step too coarse), one
        // that gains energy, and one that never touched.
        if t_c.is_nan() || t_c <= 0.0 {
            return Err(SimError::CollisionUnresolved {
                reason: format!(
                    "the contact ended before it began (t_c = {t_c:e} s): the bodies passed through each other, or the damping reversed the approach, within one step; lower the speed, the damping (gamma_n or the dissipation) or the step"
                ),
            });
        }
        if (t_c / dt) < MIN_STEPS_PER_CONTACT {
            return Err(SimError::CollisionUnresolved {
                reason: format!(
                    "the contact lasted {t_c:e} s, {:.1} steps of {dt:e} s (at least {MIN_STEPS_PER_CONTACT} needed): \
                     the normal law is overdamped at this speed (lower the damping: gamma_n or the dissipation) or the step is too large",
                    t_c / dt
                ),
            });
        }
        if max_overlap <= 1e-9 * r_eff {
            return Err(SimError::CollisionUnresolved {
                reason: format!("the bodies never overlapped (largest overlap {max_overlap:e} m): no contact was resolved"),
            });
        }
        let energy_after = energy(&sim.state());
        if energy_after > energy_before * (1.0 + 1e-3) {
            return Err(SimError::CollisionUnresolved {
                reason: format!(
                    "the impact gained energy ({energy_before:e} J before, {energy_after:e} J after): the step does not resolve the law's damping; lower dt or the damping"
                ),
            });
        }
        let state = sim.state();
        let s = &*state;
        let g1 = self.relative_velocity(s);
        // Normal at the end of the contact; a wall's never turns.
        let e1 = match self.target {
            Target::Sphere { .. } => (self.separation(s) - g1 * (sim.time - t_c)).normalize(),
            Target::Wall => e0,
        };
        let c1 = self.contact_velocity(s, e1);
        let m_scale = self.m1 * v;
        let (m_eff, _) = self.effective();
        let l_scale = m_eff * v * r0.norm();
        let c0n2 = c0.norm_squared();
        Ok(CollisionResult {
            eps_n: -g1.dot(&e1) / g0.dot(&e0),
            eps_n_hs: -g1.dot(&e0) / g0.dot(&e0),
            eps_t: (c0n2 > 1e-24 * v * v).then(|| -c1.dot(&c0) / c0n2),
            t_c,
            phi: e0.dot(&e1).clamp(-1.0, 1.0).acos(),
            max_overlap,
            steps: sim.steps,
            dt,
            contact_time_estimate: t_est,
            energy_before,
            energy_after,
            momentum_error: (s.len() > 1).then(|| (measure::momentum(s) - p0).norm() / m_scale),
            angular_momentum_error: (s.len() > 1).then(|| (measure::angular_momentum(s) - l0).norm() / l_scale),
            max_friction_ratio,
            min_normal_force,
            v1: s.vel[0].into(),
            omega1: s.omega[0].into(),
            v2: (s.len() > 1).then(|| s.vel[1].into()),
            omega2: (s.len() > 1).then(|| s.omega[1].into()),
        })
    }

    /// `r_j - r_i` (towards the wall's contact point for a wall).
    fn separation(&self, s: &State) -> Vec3 {
        if s.len() > 1 {
            s.pos[1] - s.pos[0]
        } else {
            Vec3::new(0.0, 0.0, -s.pos[0].z)
        }
    }

    /// `v_j - v_i` (the wall is at rest).
    fn relative_velocity(&self, s: &State) -> Vec3 {
        if s.len() > 1 {
            s.vel[1] - s.vel[0]
        } else {
            -s.vel[0]
        }
    }

    /// Overlap and its rate, valid (negative) outside contact too.
    fn overlap(&self, s: &State) -> (f64, f64) {
        let r = self.separation(s);
        let g = self.relative_velocity(s);
        let dist = r.norm();
        let l = match self.target_sphere() {
            Some((r2, _, _)) => self.r1 + r2,
            None => self.r1,
        };
        (l - dist, -g.dot(&r) / dist)
    }

    /// Tangential contact-point velocity `c` of j relative to i, with the normal `e` from i to j.
    fn contact_velocity(&self, s: &State, e: Vec3) -> Vec3 {
        // Geometry's convention: n from j to i, velocity of i relative to j; c is its negative.
        let n = -e;
        match self.target_sphere() {
            Some((r2, _, _)) => -tangential_velocity(n, s.vel[0] - s.vel[1], s.omega[0] * self.r1 + s.omega[1] * r2),
            None => -tangential_velocity(n, s.vel[0], s.omega[0] * self.r1),
        }
    }
}
