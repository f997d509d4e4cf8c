//! The time step of a tray scene: explicit (`run.dt = 8e-6`), or chosen by running the
//! collision lab on the scene's hardest impacts (`run.dt = "auto"`,
//! [`crate::experiment::step_control`]); either way checked against the scene's time scales
//! ([`crate::timescale`]) before a run starts. The tray ([`crate::tray::setup`]) takes the
//! chosen step as an input, so the setup layer runs no experiment.

use crate::contact::tangential::sphere_tangential_mass;
use crate::contact::TangentialLaw;
use crate::experiment::step_control;
use crate::scene::{Scene, TimeStep};
use crate::timescale::{check_step_resolution, shortest_contact_time, shortest_spring_half_period, MIN_STEPS_PER_CONTACT};
use crate::SimError;

/// The time step of a scene (s): explicit, or error-controlled for `dt = "auto"` (the
/// coarsest step meeting `run.restitution_tolerance`, no coarser than
/// `shortest_contact_time / run.steps_per_contact`; see
/// [`crate::experiment::step_control::choose`]). A step that leaves fewer than
/// [`MIN_STEPS_PER_CONTACT`] steps per contact, or per half period of a stuck tangential
/// spring, is refused before the run starts.
pub fn for_scene(scene: &Scene) -> Result<f64, SimError> {
    let dt = contact_step(scene)?;
    // An explicit step is checked against the contact time too; `auto` never gives fewer
    // steps per contact than the minimum.
    check_step_resolution(
        dt,
        MIN_STEPS_PER_CONTACT,
        shortest_contact_time(scene)?,
        shortest_spring_half_period(scene)?,
        "run.dt",
        "contact.tangential_stiffness",
    )?;
    Ok(dt)
}

fn contact_step(scene: &Scene) -> Result<f64, SimError> {
    match scene.run.dt {
        TimeStep::Seconds(dt) => Ok(dt),
        TimeStep::Auto(_) => {
            let floor = scene.run.steps_per_contact.max(MIN_STEPS_PER_CONTACT);
            let choice = step_control::choose(scene, scene.run.restitution_tolerance, floor)?;
            // Slow drives give slow impacts and long contacts; the step must still resolve
            // the Haff-Werner viscous branch of the smallest grains well enough for the
            // energy ledger (see [`VISCOUS_RATIO_AUTO`]).
            Ok(match viscous_friction_ratio(scene, choice.dt)? {
                Some(ratio) if ratio > VISCOUS_RATIO_AUTO => choice.dt * VISCOUS_RATIO_AUTO / ratio,
                _ => choice.dt,
            })
        }
    }
}

/// The largest [`viscous_friction_ratio`] `dt = "auto"` accepts. The implicit viscous
/// branch is stable at any step, but beyond about 2 the slip of the smallest grains relaxes
/// within a fraction of a step and the dissipation, booked once per step, drifts from the
/// energy the grains lose: on `scenes/stripes.toml` the restitution criterion alone chooses
/// 1.19e-5 s (ratio 3.4), where the ledger misses 1.07e-3 of the work within 2 s, against
/// 1.9e-4 at this bound (6.34e-6 s; docs/performance.md, issue 41). Until issue 41 the
/// bound kept the explicit viscous branch from its instability (which is at 1 under velocity
/// Verlet's force predictor, not at 2 as was thought).
pub const VISCOUS_RATIO_AUTO: f64 = 1.9;

/// Ratio `gamma_t dt / m_t` of the Haff-Werner viscous branch for two of the smallest grains
/// (`m_t` = [`sphere_tangential_mass`] of the pair), `None` without Haff-Werner friction
/// between grains: above 1 the slip of these grains relaxes faster than one step, and the
/// implicit update ([`crate::contact::tangential::implicit_damping`]) stops it within a few
/// steps where the explicit force `-gamma_t v_t` would overshoot zero slip (and, with
/// velocity Verlet's force predictor, let the overshoot grow).
pub fn viscous_friction_ratio(scene: &Scene, dt: f64) -> Result<Option<f64>, SimError> {
    let (pair, _) = scene.laws()?;
    match pair.tangential {
        TangentialLaw::HaffWerner { gamma_t, mu } if gamma_t > 0.0 && mu > 0.0 => {
            let m = scene.material().sphere_mass(scene.particles.radius_min);
            Ok(Some(gamma_t * dt / sphere_tangential_mass(0.5 * m)))
        }
        _ => Ok(None),
    }
}
