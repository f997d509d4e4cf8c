//! Tracer particle: the path of one grain through the snapshots (thesis Fig 3.24, 3.28,
//! 3.33), and its phase-space trajectory limited to x, `(x, v_x)`.
//!
//! Positions are those of the snapshots (one per period at a fixed phase, so the path is
//! the drift relative to the tray). `x` is periodic; `x_unwrapped` follows the grain
//! across the seam (minimum image between successive frames), so its net drift is visible.

/// One sample of the tracer.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TracerPoint {
    /// Time (s).
    pub time: f64,
    /// Position in the box (m), x in `[0, L)`.
    pub x: f64,
    pub y: f64,
    pub z: f64,
    /// x followed across the periodic seam (m).
    pub x_unwrapped: f64,
    /// Velocity along x (m/s), for the phase space.
    pub vx: f64,
}

/// The path of one grain.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Tracer {
    /// Grain index (0-based, in the input's order; LAMMPS: sorted by id).
    pub index: usize,
    /// Its radius (m).
    pub radius: f64,
    pub points: Vec<TracerPoint>,
}

impl Tracer {
    /// An empty path of grain `index` with radius `radius`.
    pub fn new(index: usize, radius: f64) -> Self {
        Self {
            index,
            radius,
            points: Vec::new(),
        }
    }

    /// Appends the grain's state at `time`; `length` is the periodic box length (m).
    pub fn push(&mut self, time: f64, pos: [f64; 3], vel: [f64; 3], length: f64) {
        let x = pos[0].rem_euclid(length);
        let x_unwrapped = match self.points.last() {
            None => x,
            Some(p) => {
                let d = x - p.x;
                p.x_unwrapped + d - length * (d / length).round()
            }
        };
        self.points.push(TracerPoint {
            time,
            x,
            y: pos[1],
            z: pos[2],
            x_unwrapped,
            vx: vel[0],
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unwrapping_follows_the_grain_across_the_seam() {
        let mut t = Tracer::new(3, 3e-4);
        for (k, x) in [0.39, 0.399, 0.005, 0.012, 0.395].iter().enumerate() {
            t.push(k as f64, [*x, 0.01, 3e-4], [0.1, 0.0, 0.0], 0.4);
        }
        let u: Vec<f64> = t.points.iter().map(|p| p.x_unwrapped).collect();
        let want = [0.39, 0.399, 0.405, 0.412, 0.395];
        for (a, b) in u.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{u:?}");
        }
        assert!((t.points[2].x - 0.005).abs() < 1e-15);
    }
}
