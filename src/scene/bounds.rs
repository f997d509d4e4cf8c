//! The sizes a tray scene implies, checked before anything is allocated or written: grains,
//! steps, snapshot frames and their bytes, for the DEM and for the automaton. A size past its
//! bound is refused with the key that sets it and the size; a long run is told at its start
//! how much disk it will fill; a drive too weak to move a grain is said to be one.

use particles::scene::{DriveDirection, Scene, SceneError};

/// Grains a run may hold (about 1 kB of state and contacts each: 20 GB).
pub const MAX_GRAINS: usize = 20_000_000;
/// Snapshot bytes a run may write (the run is refused above this).
pub const MAX_SNAPSHOT_BYTES: f64 = 200e9;
/// Snapshot bytes above which the run is told its disk use at the start.
pub const DISK_NOTE_BYTES: f64 = 1e9;
/// Steps a run may take (at 1e7 particle-steps per second, 1e12 steps of one grain is a day).
pub const MAX_STEPS: f64 = 1e12;

fn refuse(key: &str, message: String) -> SceneError {
    SceneError { key: key.into(), message }
}

/// Bytes of a snapshot file of `frames` frames of `grains` grains (`analysis::snapshot`).
pub fn snapshot_bytes(frames: f64, grains: f64) -> f64 {
    32.0 + 8.0 * grains + frames * (8.0 + 24.0 * grains)
}

fn gigabytes(b: f64) -> String {
    format!("{:.1} GB", b / 1e9)
}

/// The DEM run of `scene` with step `dt`: its grains, steps and snapshot bytes within their
/// bounds (else an error naming the key and the size), and the warnings a run must give at
/// its start (the disk it will fill, a drive too weak to move anything).
pub fn dem(scene: &Scene, dt: f64) -> Result<Vec<String>, SceneError> {
    // Spheres: a clump is as many as it has.
    let n = scene.particles.count * scene.clump_shape()?.map_or(1, |c| c.spheres);
    if n > MAX_GRAINS {
        return Err(refuse(
            "particles.count",
            format!(
                "{n} grains need about {} of memory; at most {MAX_GRAINS} are allowed",
                gigabytes(1e3 * n as f64)
            ),
        ));
    }
    let steps = scene.run.duration / dt;
    if steps > MAX_STEPS {
        return Err(refuse(
            "run.duration",
            format!(
                "{} s at dt = {dt:e} s is {steps:.3e} steps; at most {MAX_STEPS:e} are allowed",
                scene.run.duration
            ),
        ));
    }
    // A schedule's fastest stage, as if it lasted the whole run: an upper bound.
    let frames = 1.0 + (scene.run.duration * scene.drive.highest_frequency() * scene.run.snapshots_per_period as f64).floor();
    let bytes = snapshot_bytes(frames, n as f64);
    if bytes > MAX_SNAPSHOT_BYTES {
        return Err(refuse(
            "run.snapshots_per_period",
            format!(
                "{} per period over run.duration = {} s at {} Hz is {frames:.3e} snapshots of {n} grains, {} of snapshots.bin; \
                 at most {} are allowed: fewer snapshots per period or a shorter run",
                scene.run.snapshots_per_period,
                scene.run.duration,
                scene.drive.highest_frequency(),
                gigabytes(bytes),
                gigabytes(MAX_SNAPSHOT_BYTES)
            ),
        ));
    }
    let mut warnings = Vec::new();
    if bytes > DISK_NOTE_BYTES {
        warnings.push(format!(
            "this run writes about {} of snapshots ({frames:.0} frames of {n} grains, run.snapshots_per_period = {}); \
             make sure --out has the room",
            gigabytes(bytes),
            scene.run.snapshots_per_period
        ));
    }
    warnings.extend(weak_drive(scene));
    Ok(warnings)
}

/// The automaton's run of `scene` (one frame per drive period, one record per grain): its
/// periods and snapshot bytes within their bounds.
pub fn automaton(scene: &Scene) -> Result<Vec<String>, SceneError> {
    let periods = (scene.run.duration * scene.drive.frequency).round().max(1.0);
    let n = scene.particles.count as f64;
    let bytes = snapshot_bytes(periods + 1.0, n);
    if periods > 1e9 || bytes > MAX_SNAPSHOT_BYTES {
        return Err(refuse(
            "run.duration",
            format!(
                "{} s at {} Hz is {periods:.3e} drive periods, {} of automaton snapshots; at most 1e9 periods and {} are allowed",
                scene.run.duration,
                scene.drive.frequency,
                gigabytes(bytes),
                gigabytes(MAX_SNAPSHOT_BYTES)
            ),
        ));
    }
    Ok(if bytes > DISK_NOTE_BYTES {
        vec![format!(
            "the automaton writes about {} of snapshots ({periods:.0} periods of {n} grains)",
            gigabytes(bytes)
        )]
    } else {
        Vec::new()
    })
}

/// A drive too weak to move anything, said as such: a tray that does not move (amplitude or
/// frequency 0) or moves by less than a thousandth of the smallest grain's radius, or a
/// vertically vibrated floor that never lifts a grain (Gamma = A (2 pi f)^2 / g below 1).
pub fn weak_drive(scene: &Scene) -> Option<String> {
    let (a, f) = (scene.drive.amplitude, scene.drive.frequency);
    let r = scene.particles.radius_min;
    if a == 0.0 || f == 0.0 {
        return Some(format!(
            "nothing moves the grains (drive.amplitude = {a} m, drive.frequency = {f} Hz): they stay where the sample put them"
        ));
    }
    if a < 1e-3 * r {
        return Some(format!(
            "drive too weak to move anything: drive.amplitude = {a:e} m is less than a thousandth of the smallest grain radius ({r:e} m), \
             so no grain moves measurably; the run only costs time"
        ));
    }
    if scene.drive.direction == DriveDirection::Z {
        let gamma = a * (2.0 * std::f64::consts::PI * f).powi(2) / 9.81;
        if gamma < 1.0 {
            return Some(format!(
                "drive too weak to lift any grain: Gamma = A (2 pi f)^2 / g = {gamma:.3} < 1 (drive.amplitude = {a} m, drive.frequency = {f} Hz), \
                 so the floor never throws a grain"
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(set: &[&str]) -> Scene {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/quick.toml")).unwrap();
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        crate::scene::file::parse(&text, &set, "quick.toml").unwrap().dem
    }

    /// Issue 43, bounds: each size a tray scene implies is refused past its bound naming its
    /// key and the size, before anything is allocated; a large output is announced; a drive
    /// too weak to move anything is said to be one.
    #[test]
    fn sizes_are_bounded_by_key_and_weak_drives_are_named() {
        let dt = 8e-6;
        let quick = scene(&[]);
        assert!(dem(&quick, dt).unwrap().is_empty(), "the quick scene is small and driven");
        assert!(automaton(&quick).unwrap().is_empty());
        let e = dem(&scene(&["particles.count=100000000"]), dt).unwrap_err();
        assert_eq!(e.key, "particles.count");
        assert!(e.message.contains("100000000 grains need about 100.0 GB"), "{e}");
        let e = dem(&scene(&["run.snapshots_per_period=100000", "run.duration=10"]), dt).unwrap_err();
        assert_eq!(e.key, "run.snapshots_per_period");
        assert!(e.message.contains("GB of snapshots.bin"), "{e}");
        let e = dem(&scene(&["run.duration=1e9"]), dt).unwrap_err();
        assert_eq!(e.key, "run.duration");
        let e = automaton(&scene(&["run.duration=1e12"])).unwrap_err();
        assert_eq!(e.key, "run.duration");
        assert!(e.message.contains("drive periods"), "{e}");
        // A long run is told its disk use: 1000 grains, 4 per period at 20 Hz for 1e4 s.
        let w = dem(&scene(&["run.duration=1e4", "run.snapshots_per_period=4"]), 1e-3).unwrap();
        assert!(w.iter().any(|w| w.contains("GB of snapshots")), "{w:?}");
        let expect = snapshot_bytes(1.0 + (1e4 * quick.drive.frequency * 4.0), quick.particles.count as f64);
        assert!(w[0].contains(&gigabytes(expect)), "{w:?}");
        for (set, want) in [
            ("drive.amplitude=1e-12", "drive too weak to move anything"),
            ("drive.amplitude=0", "nothing moves"),
        ] {
            let w = dem(&scene(&[set]), dt).unwrap();
            assert!(w.iter().any(|w| w.contains(want)), "{set}: {w:?}");
        }
        let mut vertical = quick.clone();
        vertical.drive.direction = DriveDirection::Z;
        vertical.drive.amplitude = 1e-4;
        assert!(weak_drive(&vertical).unwrap().contains("never throws a grain"));
        vertical.drive.amplitude = 1e-2;
        assert!(weak_drive(&vertical).is_none(), "Gamma > 1 at 20 Hz and 1 cm");
    }
}
