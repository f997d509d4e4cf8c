//! The shaken tray of a scene: walls moving with the drive, boundaries, gravity, and the
//! neighbour search. The time step is an input, chosen beforehand ([`crate::time_step`]).

use crate::boundary::Boundary;
use crate::constants::GRAVITY;
use crate::neighbor::NeighborSearch;
use crate::scene::{DriveDirection, Scene};
use crate::setup::{Container, Setup, Vertical};
use crate::wall::{Motion, Wall};
use crate::{SimError, Vec3};

/// Smallest neighbour-list skin of the tray scenes, in units of the largest radius: the skin
/// of a layer at rest, where lists last long and every extra candidate pair costs each step.
/// The skin never changes a result (a rebuild is due when some grain moved half the skin);
/// `stripes bench` timed 0.1 to 1 R_max within 10% of each other on a layer at rest, 0.2
/// fastest in two runs of three. A moving layer grows it up to [`MAX_SKIN`].
pub const DEFAULT_SKIN: f64 = 0.2;

/// Largest neighbour-list skin of the tray scenes, in units of the largest radius: the skin
/// grows from [`DEFAULT_SKIN`] towards it while the layer is a gas (see
/// [`NeighborSearch::VerletList`]).
pub const MAX_SKIN: f64 = 2.0;

/// The motion of the tray: `u(t) = A sin(2 pi nu t)` along `drive.direction` (x: the shaken
/// tray; z: the vibrated floor), or the stages of `[[drive.stages]]` ([`crate::drive`]).
pub fn drive(scene: &Scene) -> Motion {
    match scene.drive.schedule() {
        None => Motion::Harmonic {
            amplitude: scene.drive.amplitude,
            frequency: scene.drive.frequency,
            direction: scene.drive.direction.unit(),
        },
        Some(schedule) => Motion::Scheduled {
            schedule: std::sync::Arc::new(schedule),
            direction: scene.drive.direction.unit(),
        },
    }
}

/// Dynamics of a (validated) scene at time step `dt` (s, from [`crate::time_step::for_scene`]),
/// with the floor driven by `motion` (use [`Motion::Fixed`] for sample preparation). The
/// walls, in this order: the floor; the sides at y = 0 and y = W (`toggles.walls`); the ends
/// at x = 0 and x = L (`box.x_walls`). With a horizontal drive every wall moves with the
/// tray; with a vertical one (`drive.direction = "z"`) only the floor moves, and the floor's
/// height `A sin(2 pi nu t)` and vertical velocity enter its contacts through the wall's
/// position and velocity, as any wall's do. The escape check's box moves as the side and end
/// walls do (with the tray, or not at all).
pub fn setup(scene: &Scene, motion: Motion, dt: f64) -> Result<Setup, SimError> {
    let (pair_law, wall_law) = scene.laws()?;
    let (l, w, h) = (scene.tray.length, scene.tray.width, scene.tray.height.unwrap_or(f64::INFINITY));
    let sides = match scene.drive.direction {
        DriveDirection::X => motion.clone(),
        DriveDirection::Z => Motion::Fixed,
    };
    // A vibrated floor sinks to -A below its mean position.
    let floor_low = match scene.drive.direction {
        DriveDirection::X => 0.0,
        DriveDirection::Z => motion.displacement_bound(),
    };
    let mut walls = vec![Wall::new("floor", Vec3::zeros(), Vec3::z(), motion)];
    if scene.toggles.walls {
        walls.push(Wall::new("side y=0", Vec3::zeros(), Vec3::y(), sides.clone()));
        walls.push(Wall::new("side y=W", Vec3::new(0.0, w, 0.0), -Vec3::y(), sides.clone()));
    }
    if scene.tray.x_walls {
        walls.push(Wall::new("end x=0", Vec3::zeros(), Vec3::x(), sides.clone()));
        walls.push(Wall::new("end x=L", Vec3::new(l, 0.0, 0.0), -Vec3::x(), sides.clone()));
    }
    let boundary = Boundary {
        periodic: [
            if scene.tray.x_walls { None } else { Some(l) },
            if scene.toggles.walls { None } else { Some(w) },
            None,
        ],
    };
    Ok(Setup {
        pair_law,
        wall_law,
        walls,
        gravity: Vec3::new(0.0, 0.0, -GRAVITY),
        dt,
        integrator: scene.run.integrator,
        boundary,
        neighbors: NeighborSearch::VerletList {
            skin: DEFAULT_SKIN * scene.particles.radius_max,
            max_skin: MAX_SKIN * scene.particles.radius_max,
        },
        vertical: if scene.toggles.jumping { Vertical::Free } else { Vertical::Pinned },
        // Grains may sink into the floor by their overlap; anything below -R_max (below the
        // vibrated floor's lowest position), outside the side walls, or above the optional
        // ceiling `box.height` has escaped (open top by default, thesis 3.5.3). The box moves
        // with the side and end walls: on a shaken tray the end walls at x = u(t) and
        // L + u(t) hold the grains, and a grain pressed against the far one at its forward
        // turning point sits beyond L (the bug of end walls on a shaken tray, 2026-11-28).
        container: Some(Container {
            lo: Vec3::new(0.0, 0.0, -scene.particles.radius_max - floor_low),
            hi: Vec3::new(l, w, h),
            motion: sides,
        }),
        sort: scene.run.sort_interval,
        rolling_mu: match scene.clump_shape()? {
            // One value per grain, repeated for each of its members.
            Some(c) => scene
                .rolling_mu()
                .iter()
                .flat_map(|&mu| std::iter::repeat_n(mu, c.spheres))
                .collect(),
            None => scene.rolling_mu(),
        },
        clump: scene.clump_shape()?,
    })
}
