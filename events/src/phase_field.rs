//! The mass and momentum of the grains over one tooth of a sawtooth base, per phase of the
//! drive: the ratchet paper's Figs 13-14 (seed 004). The paper averages "the momentum and
//! the mass carried by a particle whose center is in the box" over boxes of width `w / 6`
//! and over six phase frames of the oscillation `A sin(2 pi f t)`: frame `j` holds the
//! phases `j 2 pi / 6 <= phi < (j + 1) 2 pi / 6`.
//!
//! Here every tooth is folded onto one (x modulo the tooth width `w`), boxes are squares of
//! side `w / 6`, and heights are taken from the base's position at the sample, so that the
//! teeth stand still in the picture while the momentum is the grains' own (the lab frame).
//! A frame collects the samples whose phase falls in it: with `run.samples_per_period` a
//! multiple of 6, every frame gets the same number.

use crate::sim::Simulation;

/// Sums per frame and box, over the samples of each frame.
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseField {
    /// Phase frames per period (6, as the paper).
    pub frames: usize,
    /// The tooth width `w` (m): x is folded modulo it.
    pub tooth: f64,
    /// Boxes across the tooth and up from the valleys; each box is `tooth / across` wide
    /// and as high.
    pub across: usize,
    pub up: usize,
    /// Teeth folded onto one: the box's width over the tooth width.
    pub teeth: f64,
    /// Per frame, box (row-major: frame, then height, then x): the sums of `m`, `m v_x`
    /// and `m v_z` over the grains whose centres lie in the box, over the frame's samples.
    pub mass: Vec<f64>,
    pub px: Vec<f64>,
    pub pz: Vec<f64>,
    /// Samples per frame.
    pub samples: Vec<u64>,
}

impl PhaseField {
    /// Frames per period, as the paper.
    pub const FRAMES: usize = 6;
    /// Boxes across one tooth, as the paper (`w / 6`).
    pub const ACROSS: usize = 6;

    /// An empty field over teeth of width `tooth` in a box `width` wide, up to `height` above
    /// the valleys.
    pub fn new(tooth: f64, width: f64, height: f64) -> Self {
        let side = tooth / Self::ACROSS as f64;
        let up = (height / side).ceil().max(1.0) as usize;
        let cells = Self::FRAMES * up * Self::ACROSS;
        PhaseField {
            frames: Self::FRAMES,
            tooth,
            across: Self::ACROSS,
            up,
            teeth: width / tooth,
            mass: vec![0.0; cells],
            px: vec![0.0; cells],
            pz: vec![0.0; cells],
            samples: vec![0; Self::FRAMES],
        }
    }

    /// The side of a box (m).
    pub fn side(&self) -> f64 {
        self.tooth / self.across as f64
    }

    fn index(&self, frame: usize, up: usize, across: usize) -> usize {
        (frame * self.up + up) * self.across + across
    }

    /// The frame of the drive's phase at the simulation's time (the floor's motion; frame 0
    /// for a fixed floor).
    pub fn frame(&self, sim: &Simulation) -> usize {
        let Some(m) = sim.config.floor.filter(|m| !m.is_fixed()) else {
            return 0;
        };
        let cycles = m.frequency * sim.time + m.phase / (2.0 * std::f64::consts::PI);
        // A sample taken at a frame's first phase is in that frame, not the one before: the
        // product `f t` of a sample at `k / (6 f)` can fall a rounding error short of `k / 6`.
        let phase = (cycles.rem_euclid(1.0) * self.frames as f64 + 1e-9).floor() as usize;
        phase % self.frames
    }

    /// Adds the grains at the simulation's time.
    pub fn add(&mut self, sim: &Simulation) {
        let frame = self.frame(sim);
        let base = sim.config.floor.map_or(0.0, |m| m.displacement(sim.time));
        let side = self.side();
        for i in 0..sim.len() {
            let (r, v) = sim.state(i);
            let z = r.y - base;
            if z < 0.0 {
                continue;
            }
            let up = (z / side) as usize;
            if up >= self.up {
                continue;
            }
            let across = ((r.x.rem_euclid(self.tooth) / side) as usize).min(self.across - 1);
            let k = self.index(frame, up, across);
            let m = sim.mass[i];
            self.mass[k] += m;
            self.px[k] += m * v.x;
            self.pz[k] += m * v.y;
        }
        self.samples[frame] += 1;
    }

    /// Per box of `frame`: `(x, z, mass per area, p_x per area, p_z per area)` at the box's
    /// centre, averaged over the frame's samples (kg/m^2 and kg/(m s)); empty for a frame
    /// without samples.
    pub fn rows(&self, frame: usize) -> Vec<[f64; 5]> {
        let n = self.samples[frame];
        if n == 0 {
            return Vec::new();
        }
        let side = self.side();
        // A box holds the grains of every tooth's box at once: its area counts once per tooth.
        let norm = n as f64 * side * side * self.teeth;
        let mut rows = Vec::with_capacity(self.up * self.across);
        for up in 0..self.up {
            for across in 0..self.across {
                let k = self.index(frame, up, across);
                rows.push([
                    (across as f64 + 0.5) * side,
                    (up as f64 + 0.5) * side,
                    self.mass[k] / norm,
                    self.px[k] / norm,
                    self.pz[k] / norm,
                ]);
            }
        }
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boxes_and_frames_cover_one_tooth() {
        let f = PhaseField::new(0.006, 0.06, 0.0125);
        assert_eq!(f.teeth, 10.0);
        assert_eq!(f.side(), 0.001);
        assert_eq!(f.up, 13);
        assert_eq!(f.mass.len(), 6 * 13 * 6);
        assert_eq!(f.index(1, 0, 0), 13 * 6);
        assert_eq!(f.index(0, 1, 2), 8);
        // No samples, no rows.
        assert!(f.rows(0).is_empty());
    }
}
