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
            // Slow drives give slow impacts and long contacts; the step must still keep the
            // Haff-Werner viscous branch stable for the smallest grains.
            Ok(match viscous_friction_ratio(scene, choice.dt)? {
                Some(ratio) if ratio > VISCOUS_RATIO_AUTO => choice.dt * VISCOUS_RATIO_AUTO / ratio,
                _ => choice.dt,
            })
        }
    }
}

/// The largest [`viscous_friction_ratio`] `dt = "auto"` accepts: below the instability at 2,
/// with a margin.
pub const VISCOUS_RATIO_AUTO: f64 = 1.9;

/// Ratio `gamma_t dt / m_t` of the Haff-Werner viscous branch for two of the smallest grains
/// (`m_t` = [`sphere_tangential_mass`] of the pair), `None` without Haff-Werner friction
/// between grains. The viscous friction force `-gamma_t v_t` is integrated explicitly: above
/// 1 it reverses the slip within one step (it overshoots zero slip), above 2 the overshoot
/// grows every step and the force chatters at the Coulomb limit.
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

/// Problems of a scene at time step `dt` (s) that do not stop the run but make some
/// results inaccurate, in words (empty when there are none). Today: the Haff-Werner viscous
/// branch unstable at the step (ratio above 2, see [`viscous_friction_ratio`]; between 1
/// and 2 it overshoots but decays, and the restitution tolerance of `dt = "auto"` accounts
/// for what that costs); at the thesis step of
/// 8e-6 s the ratio is 2.4, and the tangential restitution of the smallest grains at the
/// tray's peak speed is off by a factor 2 (`stripes bench`).
pub fn warnings(scene: &Scene, dt: f64) -> Result<Vec<String>, SimError> {
    let mut out = Vec::new();
    if let Some(ratio) = viscous_friction_ratio(scene, dt)? {
        if ratio > 2.0 {
            let what = "is unstable at this step: the friction force chatters at the Coulomb limit instead of stopping the slip";
            out.push(format!(
                "`contact.tangential_damping` with `run.dt` = {dt:e} s: gamma_t dt / m_t = {ratio:.2} for two of the smallest grains, so the viscous branch of the Haff-Werner friction {what}; friction near zero slip is wrong for these grains. A step below {:.2e} s resolves it (`run.dt = \"auto\"` does).",
                2.0 * dt / ratio
            ));
        }
    }
    Ok(out)
}
