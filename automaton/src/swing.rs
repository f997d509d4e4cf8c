//! The swing field (issue 40): the numbers of the automaton's `swing` rule and the lattice's
//! local packing.
//!
//! On the DEM's stripe scene no grain is held: every grain swings out and back with the tray
//! each period, by less where the layer is denser (about 12 mm in the sparse gas, 8 mm in a
//! band core), and a grain moves with its neighbours (its move less theirs spreads by 0.5-1.1
//! mm). The `swing` rule carries exactly that ([`crate::measured_rule`]): in every half step
//! every floor grain flies by the swing measured at its cell's packing
//! ([`SwingCurve::at`]), plus a normal deviation of the measured spread.
//!
//! A cell's packing is taken as the DEM measure takes a grain's
//! (`analysis::coarse::window_packing`): the grains in a window of `local_radius_diameters`
//! mean diameters either way along x and `across_m` across (on the stripe scene the whole
//! width: the DEM's grains move together across it), each covering `grain_fraction` of a
//! cell's area, over the window's cells inside the tray.

use serde::{Deserialize, Serialize};

use crate::measured::SwingFieldFile;

/// Packing classes the curve holds at most (the DEM measure's nine).
pub const SWING_CLASSES: usize = 9;

/// Classes measured on fewer grain moves are left out of the curve.
pub const MIN_CLASS_SAMPLES: usize = 100;

/// The swing and its spread against the local packing, from a parameter file.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SwingCurve {
    /// Points used (the first `points` of each array).
    pub points: usize,
    /// The classes' mean packings, increasing.
    pub packing: [f64; SWING_CLASSES],
    /// Mean `|dx|` per half period at each (m).
    pub swing: [f64; SWING_CLASSES],
    /// Standard deviation of a grain's move about its neighbours' mean move (m).
    pub spread: [f64; SWING_CLASSES],
    /// The packing window's half-length along x and half-height across (m).
    pub reach_m: f64,
    pub across_m: f64,
    /// A grain's area over a cell's (the packing of a full cell).
    pub grain_fraction: f64,
}

impl SwingCurve {
    /// The curve of a checked file's classes holding at least [`MIN_CLASS_SAMPLES`] moves
    /// (the first [`SWING_CLASSES`]), for grains of `mean_diameter_m` on cells each
    /// `grain_fraction` covered by one grain.
    pub fn new(f: &SwingFieldFile, mean_diameter_m: f64, grain_fraction: f64) -> Self {
        let mut c = SwingCurve {
            points: 0,
            packing: [0.0; SWING_CLASSES],
            swing: [0.0; SWING_CLASSES],
            spread: [0.0; SWING_CLASSES],
            reach_m: f.local_radius_diameters * mean_diameter_m,
            across_m: f.across_m,
            grain_fraction,
        };
        for k in f
            .classes
            .iter()
            .filter(|k| k.swing.samples >= MIN_CLASS_SAMPLES)
            .take(SWING_CLASSES)
        {
            c.packing[c.points] = k.packing;
            c.swing[c.points] = k.swing.mean;
            c.spread[c.points] = k.relative.sd;
            c.points += 1;
        }
        c
    }

    /// The swing and its spread (m) at local packing `phi`: linear between the classes'
    /// mean packings, the end classes' values beyond them.
    pub fn at(&self, phi: f64) -> (f64, f64) {
        let n = self.points;
        if n == 0 {
            return (0.0, 0.0);
        }
        let p = &self.packing[..n];
        if phi <= p[0] {
            return (self.swing[0], self.spread[0]);
        }
        if phi >= p[n - 1] {
            return (self.swing[n - 1], self.spread[n - 1]);
        }
        let k = p.partition_point(|&q| q <= phi);
        let w = (phi - p[k - 1]) / (p[k] - p[k - 1]);
        let lerp = |a: &[f64; SWING_CLASSES]| a[k - 1] + w * (a[k] - a[k - 1]);
        (lerp(&self.swing), lerp(&self.spread))
    }
}

/// The packing window on cells of `dx` by `dy` (m): its half-length in columns (cell
/// centres within `curve.reach_m` along x) and half-height in rows (within `curve.across_m`).
pub(crate) fn window(curve: &SwingCurve, dx: f64, dy: f64) -> (usize, usize) {
    (
        (curve.reach_m / dx + 1e-9).floor() as usize,
        (curve.across_m / dy + 1e-9).floor() as usize,
    )
}

/// Buffers of [`packing_field`], kept between half steps; `phi` is its result.
#[derive(Default)]
pub(crate) struct PackingScratch {
    pub(crate) phi: Vec<f64>,
    spans: Vec<u32>,
    prefix: Vec<u32>,
    down: Vec<u32>,
}

/// Each cell's packing in its window ([`window`]; cells of `dx` by `dy` m) on the lattice
/// `lf` (`nx` columns, `ny` rows, index `j * nx + i`, pile heights; `periodic` in x and in y,
/// walls where not): the grains in the window's cells inside the tray, each covering
/// `grain_fraction` of a cell, over those cells; into `sc.phi`.
pub(crate) fn packing_field(
    nx: usize,
    ny: usize,
    lf: &[u8],
    (periodic_x, periodic_y): (bool, bool),
    curve: &SwingCurve,
    (dx, dy): (f64, f64),
    sc: &mut PackingScratch,
) {
    let PackingScratch {
        phi: out,
        spans,
        prefix,
        down,
    } = sc;
    let (w, h) = window(curve, dx, dy);
    // Per row and column, the grains of the span of 2w + 1 columns centred on it (round the
    // ring, or cut at the end walls), and per column the span's cells inside the tray.
    let len = 2 * w + 1;
    spans.clear();
    spans.resize(nx * ny, 0);
    let width = |i: usize| {
        if periodic_x {
            len
        } else {
            (i + w).min(nx - 1) + 1 - i.saturating_sub(w)
        }
    };
    prefix.clear();
    prefix.resize(nx + 1, 0);
    for j in 0..ny {
        let row = &lf[j * nx..(j + 1) * nx];
        for i in 0..nx {
            prefix[i + 1] = prefix[i] + row[i] as u32;
        }
        let total = prefix[nx];
        for i in 0..nx {
            spans[j * nx + i] = if periodic_x {
                let (full, rem) = ((len / nx) as u32, len % nx);
                let start = (i + nx * (w / nx + 1) - w) % nx;
                let part = if start + rem <= nx {
                    prefix[start + rem] - prefix[start]
                } else {
                    total - prefix[start] + prefix[start + rem - nx]
                };
                full * total + part
            } else {
                prefix[(i + w).min(nx - 1) + 1] - prefix[i.saturating_sub(w)]
            };
        }
    }
    // Per column, prefix sums of the spans down the rows, so that a window's rows sum in
    // O(1): rows within h of each row, inside the walls, or round the ring (each row once).
    down.clear();
    down.resize((ny + 1) * nx, 0);
    for j in 0..ny {
        for i in 0..nx {
            down[(j + 1) * nx + i] = down[j * nx + i] + spans[j * nx + i];
        }
    }
    let sum = |a: usize, b: usize, i: usize| down[b * nx + i] - down[a * nx + i];
    out.clear();
    out.resize(nx * ny, 0.0);
    for j in 0..ny {
        for i in 0..nx {
            let (grains, rows) = if periodic_y && 2 * h + 1 >= ny {
                (sum(0, ny, i), ny)
            } else if periodic_y {
                let (a, b) = (j as i64 - h as i64, j + h + 1);
                let low = if a < 0 { sum((a + ny as i64) as usize, ny, i) } else { 0 };
                let high = if b > ny { sum(0, b - ny, i) } else { 0 };
                (low + sum(a.max(0) as usize, b.min(ny), i) + high, 2 * h + 1)
            } else {
                let (a, b) = (j.saturating_sub(h), (j + h + 1).min(ny));
                (sum(a, b, i), b - a)
            };
            out[j * nx + i] = grains as f64 * curve.grain_fraction / (rows * width(i)) as f64;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measured::{Spread, SwingClassFile};

    fn spread(mean: f64, sd: f64, samples: usize) -> Spread {
        Spread {
            samples,
            mean,
            sd,
            q10: mean,
            q25: mean,
            median: mean,
            q75: mean,
            q90: mean,
        }
    }

    fn file(points: &[(f64, f64, f64, usize)]) -> SwingFieldFile {
        SwingFieldFile {
            local_radius_diameters: 2.5,
            across_m: 2.5e-3,
            classes: points
                .iter()
                .map(|&(packing, swing, sd, samples)| SwingClassFile {
                    low: 0.0,
                    high: 1.0,
                    packing,
                    swing: spread(swing, 0.0, samples),
                    relative: spread(0.0, sd, samples),
                })
                .collect(),
        }
    }

    #[test]
    fn the_curve_interpolates_between_classes_and_keeps_its_ends() {
        // The middle class holds too few moves and is left out.
        let c = SwingCurve::new(
            &file(&[(0.2, 0.012, 0.001, 500), (0.5, 0.0, 0.0, 10), (0.8, 0.008, 0.0005, 500)]),
            1e-3,
            0.77,
        );
        assert_eq!(c.points, 2);
        assert_eq!((c.reach_m, c.across_m), (2.5e-3, 2.5e-3));
        assert_eq!(c.at(0.0), (0.012, 0.001));
        assert_eq!(c.at(0.95), (0.008, 0.0005));
        let (s, sd) = c.at(0.5);
        assert!((s - 0.010).abs() < 1e-15 && (sd - 0.00075).abs() < 1e-15, "{s} {sd}");
    }

    #[test]
    fn a_full_lattice_has_the_grain_fraction_and_a_lone_grain_its_share() {
        let mut c = SwingCurve::new(&file(&[(0.5, 0.01, 0.001, 500)]), 1e-3, 0.77);
        let (nx, ny) = (40, 30);
        // 5 columns either way, 5 rows either way: 11 x 11 cells.
        assert_eq!(window(&c, 0.5e-3, 0.5e-3), (5, 5));
        let mut sc = PackingScratch::default();
        for periodic in [true, false] {
            packing_field(nx, ny, &vec![1; nx * ny], (periodic, periodic), &c, (0.5e-3, 0.5e-3), &mut sc);
            let phi = &sc.phi;
            assert!(phi.iter().all(|&p| (p - 0.77).abs() < 1e-12), "{:?}", &phi[..3]);
        }
        // One grain at (j, i) = (3, 39): seen by every cell of its window, across the seam
        // in x; beside the wall the window has 9 rows (3 below, 5 above... 0..=8).
        let mut lone = vec![0; nx * ny];
        lone[3 * nx + 39] = 1;
        packing_field(nx, ny, &lone, (true, false), &c, (0.5e-3, 0.5e-3), &mut sc);
        let phi = &sc.phi;
        assert_eq!(phi.iter().filter(|&&p| p > 0.0).count(), 11 * 9);
        assert!(phi[3 * nx + 4] > 0.0 && phi[3 * nx + 5] == 0.0, "five columns on across the seam");
        assert!(
            (phi[3 * nx + 39] - 0.77 / (9 * 11) as f64).abs() < 1e-15,
            "rows 0..=8 inside the wall"
        );
        assert!((phi[8 * nx + 39] - 0.77 / 121.0).abs() < 1e-15 && phi[9 * nx + 39] == 0.0);
        // A window across the whole width (the stripe scene's): every row sees the grain.
        c.across_m = 1.0;
        packing_field(nx, ny, &lone, (true, false), &c, (0.5e-3, 0.5e-3), &mut sc);
        let phi = &sc.phi;
        assert_eq!(phi.iter().filter(|&&p| p > 0.0).count(), 11 * ny);
        assert!(phi
            .iter()
            .filter(|&&p| p > 0.0)
            .all(|&p| (p - 0.77 / (11 * ny) as f64).abs() < 1e-15));
    }

    /// The summed windows equal a cell-by-cell count on a random lattice, for every
    /// boundary and window size (wider than the lattice too).
    #[test]
    fn the_window_sums_match_a_direct_count() {
        let (nx, ny) = (17, 9);
        let mut seed = 99u64;
        let lf: Vec<u8> = (0..nx * ny)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                seed.is_multiple_of(3) as u8
            })
            .collect();
        let mut sc = PackingScratch::default();
        for (reach, across) in [(2e-3, 1e-3), (3e-3, 4e-3), (10e-3, 10e-3)] {
            let mut c = SwingCurve::new(&file(&[(0.5, 0.01, 0.0, 500)]), 1e-3, 0.8);
            (c.reach_m, c.across_m) = (reach, across);
            let (w, h) = window(&c, 1e-3, 1e-3);
            for (px, py) in [(true, true), (true, false), (false, true), (false, false)] {
                packing_field(nx, ny, &lf, (px, py), &c, (1e-3, 1e-3), &mut sc);
                let phi = &sc.phi;
                for j in 0..ny {
                    for i in 0..nx {
                        // Periodic: the window's cells round the ring, a cell as often as the
                        // window covers it along x (the span is 2w + 1 cells wide whatever the
                        // row's length), each row once across; walls: the cells inside.
                        let axis = |k: usize, half: usize, n: usize, periodic: bool| -> Vec<usize> {
                            let all = k as i64 - half as i64..=k as i64 + half as i64;
                            if periodic {
                                all.map(|v| v.rem_euclid(n as i64) as usize).collect()
                            } else {
                                all.filter(|&v| v >= 0 && v < n as i64).map(|v| v as usize).collect()
                            }
                        };
                        let cols = axis(i, w, nx, px);
                        let rows: Vec<usize> = if py && 2 * h + 1 >= ny {
                            (0..ny).collect()
                        } else {
                            axis(j, h, ny, py)
                        };
                        let grains: u32 = rows.iter().map(|&r| cols.iter().map(|&q| lf[r * nx + q] as u32).sum::<u32>()).sum();
                        let direct = grains as f64 * 0.8 / (rows.len() * cols.len()) as f64;
                        assert!((phi[j * nx + i] - direct).abs() < 1e-12, "({px}, {py}) w {w} h {h} at ({j}, {i})");
                    }
                }
            }
        }
    }
}
