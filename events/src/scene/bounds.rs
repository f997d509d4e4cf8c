//! The sizes an event-driven scene implies, bounded by key before the engine allocates
//! anything (issue 43): lattice sites and cells, profile bins, the drive's phase and swing,
//! grain masses and the collisions its speeds imply; and the warnings its physics gives at
//! the start of a run. The bytes of a run's snapshots are the root crate's to bound (it
//! writes them).

use super::{EventScene, Floor, Lid, SceneError};

fn bad(key: &str, message: impl Into<String>) -> SceneError {
    SceneError::new(key, message)
}

/// The most lattice sites (spacing `2.02 R_max`) a box may hold: the engine places grains on
/// them and sizes its cell grid alike (about 40 bytes a cell), so 1e7 is 400 MB. The shipped
/// scenes hold at most a few thousand.
pub const MAX_SITES: f64 = 1e7;
/// The most profile bins (height and across, times the phases kept with `run.phase_resolved`).
pub const MAX_BINS: f64 = 1e6;
/// The widest drive phase (rad): beyond a few turns `sin(2 pi f t + phase)` loses the
/// precision the wall's collision times need.
pub const MAX_PHASE: f64 = 2.0 * std::f64::consts::TAU;
/// The grain masses (kg) whose products and squares the collision rule computes in range.
pub const MASS_RANGE: (f64, f64) = (1e-20, 1e20);
/// The most collisions a scene's speeds may imply (about a day at 1e6 collisions a second).
pub const MAX_COLLISIONS: f64 = 1e11;

impl EventScene {
    /// The sizes the scene implies, checked before the engine allocates anything (issue 43,
    /// bounds): the lattice sites and cells of the box, the profile bins, the drive phase and
    /// the grain masses and the collisions the speeds imply, each refused naming its key and
    /// the size. Values that are not
    /// finite are left to the checks that name them.
    pub(super) fn check_sizes(&self) -> Result<(), SceneError> {
        let r_max = self.particles.species.iter().map(|s| s.radius_max).fold(0.0, f64::max);
        let (w, h) = (self.tray.width, self.tray.height);
        if r_max.is_finite() && r_max > 0.0 && w.is_finite() && h.is_finite() {
            let spacing = 2.02 * r_max;
            let (nx, nz) = ((w / spacing).max(1.0), (h / spacing).max(1.0));
            if nx * nz > MAX_SITES {
                return Err(bad(
                    if nx >= nz { "box.width" } else { "box.height" },
                    format!(
                        "box.width = {w} m by box.height = {h} m is {nx:.3e} x {nz:.3e} = {:.3e} lattice sites (and cells) of \
                         2.02 R_max = {spacing:e} m; at most {MAX_SITES:e} are allowed: a smaller box or larger grains",
                        nx * nz
                    ),
                ));
            }
        }
        // Without gravity and without a lid nothing keeps a grain in the box: the escaped
        // grains piled into the top profile bin and gave H = 0.171 m in a 0.05 m box.
        if self.tray.gravity == 0.0 && self.drive.lid == Lid::None {
            return Err(bad(
                "drive.lid",
                "is \"none\" with box.gravity = 0: nothing keeps the grains in the box, they escape through the open top \
                 and every profile and height is wrong; give a lid (\"fixed\" or \"vibrated\") or gravity",
            ));
        }
        // The walls' extreme positions must leave a row of sites between them (else the
        // engine's "N x 0 sites" would hide that the drive's swing fills the box).
        if let Ok(a) = self.drive.amplitude() {
            let swing = |vibrated: bool| if vibrated { a.abs() } else { 0.0 };
            let room = h - swing(self.drive.floor == Floor::Vibrated) - swing(self.drive.lid == Lid::Vibrated);
            if a.is_finite() && h.is_finite() && r_max.is_finite() && room < 2.02 * r_max {
                let key = if self.drive.peak_speed.is_some() {
                    "drive.peak_speed"
                } else {
                    "drive.amplitude"
                };
                return Err(bad(
                    key,
                    format!(
                        "the drive's swing (A = {a:e} m for the floor{}) leaves {room:e} m of the box's {h} m (box.height) \
                         between the walls' extreme positions, less than a grain diameter: a smaller amplitude or a taller box",
                        if self.drive.lid == Lid::Vibrated {
                            " and as much for the lid"
                        } else {
                            ""
                        },
                    ),
                ));
            }
        }
        let bin = self.run.bin;
        let lid = match (self.drive.lid, self.drive.amplitude()) {
            (Lid::Vibrated, Ok(a)) => a,
            _ => 0.0,
        };
        if bin.is_finite() && bin > 0.0 && w.is_finite() && h.is_finite() {
            let phases = if self.run.phase_resolved {
                1.0 + f64::from(self.run.samples_per_period)
            } else {
                1.0
            };
            let bins = ((h + lid.abs()) / bin).ceil() + (w / bin).round();
            if bins * phases > MAX_BINS {
                return Err(bad(
                    "run.bin",
                    format!(
                        "run.bin = {bin} m over a box {w} m wide and {} m high is {bins:.3e} profile bins{}; \
                         at most {MAX_BINS:e} are allowed: a larger run.bin",
                        h + lid.abs(),
                        if phases > 1.0 {
                            format!(" for each of {phases} phases (run.phase_resolved)")
                        } else {
                            String::new()
                        }
                    ),
                ));
            }
        }
        let phase = self.drive.phase;
        if phase.is_finite() && phase.abs() > MAX_PHASE {
            return Err(bad(
                "drive.phase",
                format!(
                    "must lie in [-4 pi, 4 pi] rad, got {phase}: a phase of many turns loses the precision of the wall's \
                     collision times; give it modulo 2 pi ({})",
                    phase.rem_euclid(std::f64::consts::TAU)
                ),
            ));
        }
        // Masses whose products and squares stay finite (a density of 1e300 or 1e-300 made
        // the collision times NaN and the run endless).
        for (k, sp) in self.particles.species.iter().enumerate() {
            let volume = 4.0 / 3.0 * std::f64::consts::PI * sp.radius_max.powi(3);
            let (key, m) = match (sp.mass, sp.density) {
                (Some(m), _) => (format!("particles.species.{k}.mass"), m),
                (None, Some(rho)) => (format!("particles.species.{k}.density"), rho * volume),
                (None, None) => continue,
            };
            if m.is_finite() && volume.is_finite() && !(MASS_RANGE.0..=MASS_RANGE.1).contains(&m) {
                return Err(bad(
                    &key,
                    format!(
                        "gives grains of {m:e} kg; masses must lie in [{:e}, {:e}] kg for the collision arithmetic to stay finite",
                        MASS_RANGE.0, MASS_RANGE.1
                    ),
                ));
            }
        }
        // The collisions the scene's speeds imply: a grain at speed v meets another about
        // every d / v, so N v / d_min collisions per second. Past MAX_COLLISIONS the run takes
        // days; a collapse guard faster than the gas would pump energy in without end.
        let (speed, speed_key) = self.speed_scale();
        let d_min = 2.0 * self.particles.species.iter().map(|s| s.radius_min).fold(f64::INFINITY, f64::min);
        let grains: f64 = self.particles.species.iter().map(|s| s.count as f64).sum();
        let collisions = grains * speed / d_min * self.run.duration;
        if collisions.is_finite() && collisions > MAX_COLLISIONS {
            return Err(bad(
                speed_key,
                format!(
                    "grains at {speed:e} m/s (from {speed_key}) in this box meet about N v / d_min = {:.3e} times a second, \
                     {collisions:.3e} collisions over run.duration = {} s; at most {MAX_COLLISIONS:e} are allowed (a day of CPU or more)",
                    grains * speed / d_min,
                    self.run.duration
                ),
            ));
        }
        if let Some(v) = self.guard.min_rebound_speed.filter(|v| v.is_finite() && *v > speed) {
            return Err(bad(
                "guard.min_rebound_speed",
                format!(
                    "{v} m/s is faster than the scene's grains ({speed:e} m/s, from {speed_key}): every collision would leave \
                     faster than it met, adding energy without end; the guard is a small speed that keeps slow grains hopping"
                ),
            ));
        }
        Ok(())
    }

    /// The largest speed the scene gives its grains, and the key that sets it: the initial
    /// speed (each component up to it), the drive's peak speed `2 pi f A`, or the fall
    /// `sqrt(2 g height)` through the box.
    fn speed_scale(&self) -> (f64, &'static str) {
        let peak = self
            .drive
            .amplitude()
            .map_or(0.0, |a| std::f64::consts::TAU * self.drive.frequency * a.abs());
        let fall = (2.0 * self.tray.gravity.max(0.0) * self.tray.height.abs()).sqrt();
        let drive_key = if self.drive.peak_speed.is_some() {
            "drive.peak_speed"
        } else {
            "drive.amplitude"
        };
        [
            (
                std::f64::consts::SQRT_2 * self.particles.initial_speed.abs(),
                "particles.initial_speed",
            ),
            (peak, drive_key),
            (fall, "box.gravity"),
        ]
        .into_iter()
        .filter(|(v, _)| v.is_finite())
        .fold((0.0, "particles.initial_speed"), |a, b| if b.0 > a.0 { b } else { a })
    }

    /// What a run of this (valid) scene must say at its start about its physics: a drive too
    /// weak to move anything. (The disk its snapshots will fill is the root crate's to say:
    /// it writes them.)
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let (Ok(a), f) = (self.drive.amplitude(), self.drive.frequency) else {
            return out;
        };
        if a > 0.0 && (self.drive.floor == Floor::Vibrated || self.drive.lid == Lid::Vibrated) {
            let g = self.tray.gravity;
            let r_min = self.particles.species.iter().map(|s| s.radius_min).fold(f64::INFINITY, f64::min);
            let gamma = a * (std::f64::consts::TAU * f).powi(2) / g;
            if g > 0.0 && gamma < 1.0 {
                out.push(format!(
                    "drive too weak to lift any grain: Gamma = A (2 pi f)^2 / g = {gamma:.3e} < 1 (A = {a:e} m, f = {f} Hz): \
                     the grains settle on the floor, which an event-driven model approaches through ever more frequent \
                     collisions, so the run slows down as they settle"
                ));
            } else if g <= 0.0 && a < 1e-3 * r_min {
                out.push(format!(
                    "drive too weak to move anything: A = {a:e} m is less than a thousandth of the smallest grain radius"
                ));
            }
        }
        out
    }
}
