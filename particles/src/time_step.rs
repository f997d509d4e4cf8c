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
            // Slow drives give slow impacts and long contacts; the step stays within the
            // ratio of the Haff-Werner viscous branch at which the ledger was measured to
            // close (see [`VISCOUS_RATIO_AUTO`]).
            Ok(match viscous_friction_ratio(scene, choice.dt)? {
                Some(ratio) if ratio > VISCOUS_RATIO_AUTO => choice.dt * VISCOUS_RATIO_AUTO / ratio,
                _ => choice.dt,
            })
        }
    }
}

/// The largest [`viscous_friction_ratio`] `dt = "auto"` accepts. The viscous branch is
/// stable at any step (capped at two thirds of the slip per step beyond a ratio of 2/3), and
/// since the ledger books what velocity Verlet's kick takes back
/// ([`crate::integrate::verlet_excess`]) its dissipation holds where the slip of the smallest
/// grains relaxes within a fraction of a step: on `scenes/stripes.toml` the restitution
/// criterion alone chooses 1.19e-5 s (ratio 3.57), where the ledger misses 1.9e-4 of the
/// work over 10 s on each of seeds 1-3, without a warning (with the old booking it missed
/// 1.07e-3 within 2 s, which is why this bound was 1.9 and the step 6.34e-6 s;
/// docs/performance.md, issue 41). The bound stays just above the largest ratio measured,
/// for drives slower than that scene's.
pub const VISCOUS_RATIO_AUTO: f64 = 3.6;

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
