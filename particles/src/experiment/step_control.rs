//! Error-controlled time step: the coarsest step whose restitution error stays within a
//! requested tolerance, found with the collision lab ([`super::collide`]).
//!
//! The probes are the hardest impacts a scene can produce: two of its smallest grains (the
//! shortest contact) and one smallest grain against the floor, meeting at the scene's largest
//! impact speed `v = 2 pi nu A` ([`crate::timescale::max_impact_speed`]), once head-on and once at
//! 45 degrees (`v_n = v_t = v / sqrt 2`), each with the scene's own contact laws (friction and
//! rolling resistance included). Every probe runs with the same time step
//! `dt = t_c / s`, `t_c` = [`crate::timescale::shortest_contact_time`], exactly as the tray would.
//!
//! The restitution error of a step is the largest absolute deviation of `eps_n` (eq 4.2) and
//! `eps_t` (tangential contact-point velocity ratio) over the probes from the same probes at
//! [`REFERENCE_STEPS`] steps per contact (velocity Verlet converges there to about 1e-7).
//! Restitution coefficients are O(1), so the tolerance is absolute and relative alike.

use crate::contact::ContactLaw;
use crate::experiment::collide::{Collision, CollisionResult, Impact, StepSize, Target};
use crate::integrate::Integrator;
use crate::scene::Scene;
use crate::timescale;
use crate::{SimError, Vec3};

/// Steps per contact tried, coarsest first (the lab accepts no fewer than 5; the tray
/// accepts no fewer than [`crate::timescale::MIN_STEPS_PER_CONTACT`]).
pub const CANDIDATE_STEPS: [f64; 17] = [
    8.0, 10.0, 12.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0, 70.0, 100.0, 140.0, 200.0, 300.0, 500.0, 700.0, 1000.0,
];

/// Steps per contact of the converged reference.
pub const REFERENCE_STEPS: f64 = 4000.0;

/// The step chosen for a tolerance.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StepChoice {
    /// Steps per shortest contact time.
    pub steps_per_contact: f64,
    /// Time step (s).
    pub dt: f64,
    /// Restitution error measured at that step (dimensionless).
    pub restitution_error: f64,
    /// Shortest contact time of the scene (s).
    pub contact_time: f64,
}

/// The probe impacts of a scene with the given laws, for an explicit step `dt` (s).
/// `radius` and `mass` are those of the smallest grain, `v` the impact speed (m/s).
pub fn probes(pair: ContactLaw, wall: ContactLaw, radius: f64, mass: f64, v: f64, dt: f64, integrator: Integrator) -> Vec<Collision> {
    let oblique = Impact::Components {
        vn: v / 2f64.sqrt(),
        vt: v / 2f64.sqrt(),
    };
    let head_on = Impact::Components { vn: v, vt: 0.0 };
    let sphere = Target::Sphere {
        r: radius,
        m: mass,
        omega: Vec3::zeros(),
    };
    let mut out = Vec::new();
    for (law, target) in [(pair, sphere), (wall, Target::Wall)] {
        for impact in [head_on, oblique] {
            out.push(Collision {
                law,
                r1: radius,
                m1: mass,
                omega1: Vec3::zeros(),
                target,
                impact,
                step: StepSize::Dt(dt),
                integrator,
            });
        }
    }
    out
}

/// The probes of a scene at `steps` per shortest contact time.
pub fn scene_probes(scene: &Scene, steps: f64, integrator: Integrator) -> Result<Vec<Collision>, SimError> {
    let (pair, wall) = scene.laws()?;
    let r = scene.particles.radius_min;
    let dt = timescale::shortest_contact_time(scene)? / steps;
    Ok(probes(
        pair,
        wall,
        r,
        scene.material().sphere_mass(r),
        timescale::max_impact_speed(scene),
        dt,
        integrator,
    ))
}

/// Runs every probe.
pub fn run_all(probes: &[Collision]) -> Result<Vec<CollisionResult>, SimError> {
    probes.iter().map(Collision::run).collect()
}

/// Largest `|eps_n - eps_n_ref|` and `|eps_t - eps_t_ref|` over matching probes (`eps_t` only
/// where both define it).
pub fn restitution_error(results: &[CollisionResult], reference: &[CollisionResult]) -> f64 {
    results
        .iter()
        .zip(reference)
        .map(|(a, b)| {
            let dt = match (a.eps_t, b.eps_t) {
                (Some(x), Some(y)) => (x - y).abs(),
                _ => 0.0,
            };
            (a.eps_n - b.eps_n).abs().max(dt)
        })
        .fold(0.0, f64::max)
}

/// The coarsest of `min_steps` and the larger [`CANDIDATE_STEPS`] whose
/// restitution error is at most `tolerance`, with velocity Verlet (the tray's integrator).
/// Fails, naming `run.restitution_tolerance`, if even 1000 steps per contact miss it.
pub fn choose(scene: &Scene, tolerance: f64, min_steps: f64) -> Result<StepChoice, SimError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(SimError::InvalidParameter {
            field: "run.restitution_tolerance".into(),
            message: format!("must be a positive number, got {tolerance}"),
        });
    }
    let integrator = Integrator::VelocityVerlet;
    let reference = run_all(&scene_probes(scene, REFERENCE_STEPS, integrator)?)?;
    let t_c = timescale::shortest_contact_time(scene)?;
    let mut best = f64::INFINITY;
    let candidates = std::iter::once(min_steps).chain(CANDIDATE_STEPS.iter().copied().filter(|&s| s > min_steps));
    for s in candidates {
        // A step so coarse that a probe overshoots the overlap limit fails the tolerance;
        // a finer one may not (the reference itself failing stops the search above).
        let Ok(results) = run_all(&scene_probes(scene, s, integrator)?) else {
            continue;
        };
        let err = restitution_error(&results, &reference);
        best = best.min(err);
        if err <= tolerance {
            return Ok(StepChoice {
                steps_per_contact: s,
                dt: t_c / s,
                restitution_error: err,
                contact_time: t_c,
            });
        }
    }
    Err(SimError::InvalidParameter {
        field: "run.restitution_tolerance".into(),
        message: format!(
            "{tolerance:e} cannot be met with up to {} steps per contact (best restitution error {best:e}); ask for a looser tolerance or set `run.dt` explicitly",
            CANDIDATE_STEPS[CANDIDATE_STEPS.len() - 1]
        ),
    })
}
