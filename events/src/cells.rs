//! The cell grid: columns along x (periodic or bounded) and rows along z, each at least one
//! largest diameter wide, so that a particle can only touch particles of its own and the
//! eight neighbouring cells. The bottom row reaches down and the top row up without end (a
//! particle thrown above the grid stays in the top row).

use crate::flight::height_time;
use crate::Vec2;

/// The grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub nx: usize,
    pub nz: usize,
    pub dx: f64,
    pub dz: f64,
    pub z0: f64,
    pub periodic: bool,
    pub width: f64,
    /// For each cell, its distinct neighbouring cells (itself included), as flat indices,
    /// and how many there are: computed once, read at every prediction.
    near: Vec<([u32; 9], u8)>,
}

/// A cell crossing: the time and the cell entered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub time: f64,
    pub to: (usize, usize),
    /// The x shift of a periodic wrap (0, +width or -width).
    pub wrap: f64,
}

impl Grid {
    /// A grid over `[0, width] x [z_lo, z_hi]` with cells at least `min_size` wide. Fewer than
    /// three columns (or rows) become one, so that no cell is its own neighbour twice.
    pub fn new(width: f64, z_lo: f64, z_hi: f64, min_size: f64, periodic: bool) -> Self {
        let count = |len: f64| {
            let n = (len / min_size).floor().max(1.0) as usize;
            if n < 3 {
                1
            } else {
                n.min(1 << 16)
            }
        };
        let (nx, nz) = (count(width), count(z_hi - z_lo));
        let mut grid = Grid {
            nx,
            nz,
            dx: width / nx as f64,
            dz: (z_hi - z_lo) / nz as f64,
            z0: z_lo,
            periodic,
            width,
            near: Vec::new(),
        };
        grid.near = (0..nx * nz)
            .map(|c| {
                let (mut out, mut n) = ([0u32; 9], 0u8);
                for iz in grid.rows(c / nx) {
                    for ix in grid.columns(c % nx) {
                        out[n as usize] = grid.index((ix, iz)) as u32;
                        n += 1;
                    }
                }
                (out, n)
            })
            .collect();
        grid
    }

    /// The distinct cells next to flat cell `c` (itself included).
    #[inline]
    pub fn near(&self, c: usize) -> &[u32] {
        let (cells, n) = &self.near[c];
        &cells[..*n as usize]
    }

    /// The cell of a position.
    pub fn cell(&self, r: Vec2) -> (usize, usize) {
        let ix = ((r.x / self.dx).floor().max(0.0) as usize).min(self.nx - 1);
        let iz = (((r.y - self.z0) / self.dz).floor().max(0.0) as usize).min(self.nz - 1);
        (ix, iz)
    }

    /// Flat index of a cell.
    pub fn index(&self, c: (usize, usize)) -> usize {
        c.1 * self.nx + c.0
    }

    /// The distinct columns next to `ix` (itself included).
    pub fn columns(&self, ix: usize) -> impl Iterator<Item = usize> + '_ {
        let n = self.nx as i64;
        (-1i64..=1).filter_map(move |d| {
            if n == 1 {
                return (d == 0).then_some(0);
            }
            let j = ix as i64 + d;
            if self.periodic {
                Some(j.rem_euclid(n) as usize)
            } else {
                (0..n).contains(&j).then_some(j as usize)
            }
        })
    }

    /// The distinct rows next to `iz` (itself included).
    pub fn rows(&self, iz: usize) -> impl Iterator<Item = usize> + '_ {
        let n = self.nz as i64;
        (-1i64..=1).filter_map(move |d| {
            let j = iz as i64 + d;
            (0..n).contains(&j).then_some(j as usize)
        })
    }

    /// The first time after `t0` at which a particle at `(r, v)` in cell `c` leaves it.
    pub fn crossing(&self, c: (usize, usize), r: Vec2, v: Vec2, gravity: f64, t0: f64) -> Option<Crossing> {
        let mut best: Option<Crossing> = None;
        let mut take = |s: f64, to: (usize, usize), wrap: f64| {
            if s.is_finite() && s >= 0.0 && best.is_none_or(|b| t0 + s < b.time) {
                best = Some(Crossing { time: t0 + s, to, wrap });
            }
        };
        if self.nx > 1 {
            let (lo, hi) = (c.0 as f64 * self.dx, (c.0 + 1) as f64 * self.dx);
            if v.x > 0.0 && (c.0 + 1 < self.nx || self.periodic) {
                let (to, wrap) = if c.0 + 1 == self.nx { (0, -self.width) } else { (c.0 + 1, 0.0) };
                take(((hi - r.x) / v.x).max(0.0), (to, c.1), wrap);
            } else if v.x < 0.0 && (c.0 > 0 || self.periodic) {
                let (to, wrap) = if c.0 == 0 { (self.nx - 1, self.width) } else { (c.0 - 1, 0.0) };
                take(((lo - r.x) / v.x).max(0.0), (to, c.1), wrap);
            }
        }
        if self.nz > 1 {
            let (lo, hi) = (self.z0 + c.1 as f64 * self.dz, self.z0 + (c.1 + 1) as f64 * self.dz);
            // Rising through the top comes before falling through the bottom.
            let up = if c.1 + 1 < self.nz {
                height_time(r.y, v.y, gravity, hi, true)
            } else {
                None
            };
            if let Some(s) = up {
                take(s, (c.0, c.1 + 1), 0.0);
            } else if c.1 > 0 {
                if let Some(s) = height_time(r.y, v.y, gravity, lo, false) {
                    take(s, (c.0, c.1 - 1), 0.0);
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_are_distinct_and_wrap_when_periodic() {
        let g = Grid::new(1.0, 0.0, 1.0, 0.1, true);
        assert_eq!(g.columns(0).collect::<Vec<_>>(), vec![9, 0, 1]);
        let w = Grid::new(1.0, 0.0, 1.0, 0.1, false);
        assert_eq!(w.columns(0).collect::<Vec<_>>(), vec![0, 1]);
        assert_eq!(w.rows(9).collect::<Vec<_>>(), vec![8, 9]);
        let narrow = Grid::new(0.25, 0.0, 1.0, 0.1, true);
        assert_eq!(narrow.columns(0).collect::<Vec<_>>(), vec![0]);
    }

    #[test]
    fn a_particle_crosses_into_the_next_cell_and_wraps() {
        let g = Grid::new(1.0, 0.0, 1.0, 0.1, true);
        let c = g.crossing((9, 5), Vec2::new(0.95, 0.55), Vec2::new(1.0, 0.0), 0.0, 2.0).unwrap();
        assert!((c.time - 2.05).abs() < 1e-12 && c.to == (0, 5) && c.wrap == -1.0);
        // Falling from rest at 0.55 under g = 10: leaves row 5 at z = 0.5 after sqrt(0.01) s.
        let c = g.crossing((5, 5), Vec2::new(0.55, 0.55), Vec2::zeros(), 10.0, 0.0).unwrap();
        assert!((c.time - 0.1).abs() < 1e-12 && c.to == (5, 4));
    }
}
