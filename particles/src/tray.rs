//! The shaken tray of a scene: walls moving with the drive, boundaries, time step.

use crate::boundary::Boundary;
use crate::integrate::Integrator;
use crate::neighbor::NeighborSearch;
use crate::scene::{Scene, TimeStep, MIN_STEPS_PER_CONTACT};
use crate::sim::{Setup, Vertical};
use crate::wall::{Motion, Wall};
use crate::{SimError, Vec3};

/// Gravitational acceleration of the tray scenes (m/s^2, SPEC section 2).
pub const GRAVITY: f64 = 10.0;

/// Largest impact speed expected in a scene (m/s): the tray's peak speed `2 pi nu A`, the
/// speed at which a side wall or a grain carried by the floor can hit a grain at rest. At
/// least 0.1 m/s, so that a tray at rest still gets a finite step.
pub fn max_impact_speed(scene: &Scene) -> f64 {
    (2.0 * std::f64::consts::PI * scene.drive.frequency * scene.drive.amplitude).max(0.1)
}

/// Shortest contact time of the scene (s): the undamped time (eq 3.19, or `pi sqrt(m/k)`)
/// of two of the smallest grains meeting at [`max_impact_speed`]; contact time grows with
/// size, and a pair is shorter than a grain on a wall.
pub fn shortest_contact_time(scene: &Scene) -> f64 {
    let (pair, _) = scene.laws();
    let r = scene.particles.radius_min;
    let m = scene.material().sphere_mass(r);
    pair.normal.undamped_contact_time(0.5 * m, 0.5 * r, max_impact_speed(scene))
}

/// The time step of a scene (s): explicit, or `shortest_contact_time / run.steps_per_contact`.
/// An explicit step that leaves fewer than [`MIN_STEPS_PER_CONTACT`] steps per contact is
/// refused before the run starts.
pub fn time_step(scene: &Scene) -> Result<f64, SimError> {
    let t_c = shortest_contact_time(scene);
    match scene.run.dt {
        TimeStep::Seconds(dt) => {
            let steps = t_c / dt;
            if steps < MIN_STEPS_PER_CONTACT {
                return Err(SimError::TimeStepTooLarge {
                    field: "run.dt".into(),
                    dt,
                    contact_time: t_c,
                    steps_per_contact: steps,
                    minimum: MIN_STEPS_PER_CONTACT,
                });
            }
            Ok(dt)
        }
        TimeStep::Auto(_) => Ok(t_c / scene.run.steps_per_contact),
    }
}

/// The motion of the tray: `x_tray(t) = A sin(2 pi nu t)` along x.
pub fn drive(scene: &Scene) -> Motion {
    Motion::Harmonic {
        amplitude: scene.drive.amplitude,
        frequency: scene.drive.frequency,
        direction: Vec3::x(),
    }
}

/// Dynamics of a (validated) scene, with the tray driven by `motion` (use
/// [`Motion::Fixed`] for sample preparation).
pub fn setup(scene: &Scene, motion: Motion) -> Result<Setup, SimError> {
    let (pair_law, wall_law) = scene.laws();
    let (l, w, h) = (scene.tray.length, scene.tray.width, scene.tray.height.unwrap_or(f64::INFINITY));
    let mut walls = vec![Wall::new("floor", Vec3::zeros(), Vec3::z(), motion)];
    if scene.toggles.walls {
        walls.push(Wall::new("side y=0", Vec3::zeros(), Vec3::y(), motion));
        walls.push(Wall::new("side y=W", Vec3::new(0.0, w, 0.0), -Vec3::y(), motion));
    }
    let boundary = Boundary {
        periodic: [Some(l), if scene.toggles.walls { None } else { Some(w) }, None],
    };
    Ok(Setup {
        pair_law,
        wall_law,
        walls,
        gravity: Vec3::new(0.0, 0.0, -GRAVITY),
        dt: time_step(scene)?,
        integrator: Integrator::VelocityVerlet,
        boundary,
        neighbors: NeighborSearch::VerletList {
            skin: 0.4 * scene.particles.radius_max,
        },
        vertical: if scene.toggles.jumping { Vertical::Free } else { Vertical::Pinned },
        // Grains may sink into the floor by their overlap; anything below -R_max, outside the
        // side walls, or above the optional ceiling `box.height` has escaped (open top by
        // default, thesis 3.5.3).
        container: Some((Vec3::new(0.0, 0.0, -scene.particles.radius_max), Vec3::new(l, w, h))),
    })
}
