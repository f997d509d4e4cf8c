//! Time scales of a tray scene that the time step must resolve: the largest impact speed,
//! the shortest contact time and the fastest tangential spring, and the one check of a step
//! against them (used by the tray, the error-controlled step and the collision lab).

use crate::contact::tangential::sphere_tangential_mass;
use crate::scene::Scene;
use crate::SimError;

/// Fewest steps per contact time an explicit dt may give (the thesis uses 15-20, sec 3.5.1).
pub const MIN_STEPS_PER_CONTACT: f64 = 8.0;

/// Refuses a step `dt` (s) that resolves the contact time `contact_time` (s), or the half
/// period `spring_half_period` (s) of a stuck tangential spring, with fewer than `minimum`
/// steps ([`MIN_STEPS_PER_CONTACT`] for a tray); `dt_field` and `spring_field` name the keys
/// to blame. The one check of the tray's scenes and the collision lab.
pub fn check_step_resolution(
    dt: f64,
    minimum: f64,
    contact_time: f64,
    spring_half_period: Option<f64>,
    dt_field: &str,
    spring_field: &str,
) -> Result<(), SimError> {
    if contact_time / dt < minimum {
        return Err(SimError::TimeStepTooLarge {
            field: dt_field.into(),
            dt,
            contact_time,
            steps_per_contact: contact_time / dt,
            minimum,
        });
    }
    match spring_half_period {
        Some(half) if half / dt < minimum => Err(SimError::TangentialSpringTooStiff {
            field: spring_field.into(),
            dt,
            half_period: half,
            steps: half / dt,
            minimum,
        }),
        _ => Ok(()),
    }
}

/// Largest impact speed expected in a scene (m/s): the tray's peak speed `V = 2 pi nu A` (of
/// the fastest stage of a schedule), the
/// speed at which a side wall or a grain carried by the floor can hit a grain at rest; for a
/// vertically vibrated floor `2 V`, the speed at which a grain thrown at `V` meets the floor
/// rising at `V`. At least 0.1 m/s, so that a tray at rest still gets a finite step.
pub fn max_impact_speed(scene: &Scene) -> f64 {
    let v = scene.drive.peak_speed();
    let v = match scene.drive.direction {
        crate::scene::DriveDirection::X => v,
        crate::scene::DriveDirection::Z => 2.0 * v,
    };
    v.max(0.1)
}

/// Shortest contact time of the scene (s): the undamped time (eq 3.19, or `pi sqrt(m/k)`)
/// of two of the smallest grains meeting at [`max_impact_speed`]; contact time grows with
/// size, and a pair is shorter than a grain on a wall.
pub fn shortest_contact_time(scene: &Scene) -> Result<f64, SimError> {
    let (pair, _) = scene.laws()?;
    let r = scene.particles.radius_min;
    let m = scene.material().sphere_mass(r);
    Ok(pair.normal.undamped_contact_time(0.5 * m, 0.5 * r, max_impact_speed(scene)))
}

/// Stuck half period `pi sqrt(m_t / k_t)` (s) of the Cundall-Strack spring between two of
/// the smallest grains (the fastest tangential oscillation of the scene), `None` without a
/// tangential spring.
pub fn shortest_spring_half_period(scene: &Scene) -> Result<Option<f64>, SimError> {
    let (pair, _) = scene.laws()?;
    let m = scene.material().sphere_mass(scene.particles.radius_min);
    Ok(pair.tangential.spring_half_period(sphere_tangential_mass(0.5 * m)))
}
