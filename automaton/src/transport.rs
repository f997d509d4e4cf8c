//! Graded transport: how far a grain rolls against its local packing, from the DEM's measured
//! slope `a(phi)`, and how agitation melts the crowding's hold.
//!
//! **The measurement** (`docs/results/mechanism/report.md`, section 3; `stripes mechanism`).
//! The DEM's grains roll on the shaken floor with a velocity relative to the tray
//! `u_x = a v_tray`. A free sphere rolling without slip has `a = -5/7`. With pair friction the
//! slope falls in magnitude with the area fraction `phi` of the 1 mm strip (across the tray's
//! width) a grain sits in: crowded grains rub at their contacts and follow the floor more.
//! [`SlopeTable`] holds the two measured tables of the stripe scene (seed 1): before any band
//! (1 s) and in the banded state (19 s).
//!
//! **The rule.** A grain's excursion relative to the tray per half period is `2 |a(phi)| A`,
//! so in the automaton (which lives in the tray frame and jumps a free grain the
//! single-sphere DEM's excursion, `cap` cells) a grain jumps
//! `round(cap * s(phi))` cells with `s(phi) = min(1, |a(phi)| / (5/7))`, every half period,
//! queueing behind the grain ahead of it ([`landings`]). No random draw decides who is held:
//! the hold is graded and the same for every grain of a strip, as in the DEM.
//!
//! **Melting** ([`hold_share`]). The slope's fall is pair friction braking the spin of
//! crowded grains that roll on the floor side by side. The DEM measured what agitation does
//! to it (`docs/results/automaton-pattern/mechanism-gamma/`, 0.05 m, packing 0.46,
//! A = 10 mm): at Gamma 0.64 crowded grains are held as at 0.36 (|a| 0.29-0.45 in the
//! classes above phi 0.5) and 11-47 % of the grains are off the floor; at Gamma 1.42 the
//! slope no longer falls with the packing (|a| 0.68-0.75 in every class, 0.08 of the hold
//! left), 67-80 % of the grains are off the floor and the mean pair-contact count is 16
//! against 54. The hold does not wear away at the contacts; it goes when the layer lifts
//! off the floor and its contacts open. The rule is that lift-off: the whole hold up to
//! `Gamma_c`, none above (a sharper form than the two measured points need, none gentler
//! than they allow). Well above nothing changes: crowded grains roll like free ones and no
//! band can hold (the DEM's bands melt between Gamma 1.0 and 1.45 at packing 0.46, below the
//! free sphere's rolling limit 2.45). `Gamma_c` is the rule's one fitted number; the
//! measurements bracket it between 0.64 and 1.42.

use serde::{Deserialize, Serialize};

/// The magnitude of a free rolling sphere's slope, 5/7 (thesis 3.3.1).
pub const FREE_SLOPE: f64 = 5.0 / 7.0;

/// A table of the DEM's measured slope `|a|` against the local area fraction, by class
/// (class centres; `docs/results/mechanism/by-density/mechanism_by_density_*.csv`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SlopeTable {
    /// At 1 s, before any band (`mechanism_by_density_early_s1_1s.csv`): the cause, not yet
    /// shaped by bands; no grain sat at `phi >= 0.8`.
    BeforeBands,
    /// At 19 s, three stripes (`mechanism_by_density_stripes_s1_19s.csv`): down to 0.15 in
    /// the jammed cores (`phi >= 0.8`, class centre taken as 0.85).
    InBands,
}

impl SlopeTable {
    /// Every name, as scene files write it.
    pub const NAMES: &'static [&'static str] = &["before-bands", "in-bands"];

    /// `(phi, |a|)` at the class centres, increasing in `phi`.
    pub fn points(self) -> &'static [(f64, f64)] {
        match self {
            SlopeTable::BeforeBands => &[(0.1, 0.9245), (0.275, 0.7761), (0.425, 0.6274), (0.575, 0.5549), (0.725, 0.5045)],
            SlopeTable::InBands => &[
                (0.1, 0.8285),
                (0.275, 0.8100),
                (0.425, 0.5070),
                (0.575, 0.4130),
                (0.725, 0.3075),
                (0.85, 0.1536),
            ],
        }
    }

    /// `|a(phi)|`: linear between class centres, the end values beyond them.
    pub fn slope(self, phi: f64) -> f64 {
        let p = self.points();
        let (first, last) = (p[0], p[p.len() - 1]);
        if phi.is_nan() || phi <= first.0 {
            return first.1;
        }
        if phi >= last.0 {
            return last.1;
        }
        let k = p.partition_point(|&(x, _)| x <= phi);
        let ((x0, y0), (x1, y1)) = (p[k - 1], p[k]);
        y0 + (y1 - y0) * (phi - x0) / (x1 - x0)
    }

    /// A grain's excursion relative to a free sphere's, `min(1, |a(phi)| / (5/7))`.
    pub fn relative_excursion(self, phi: f64) -> f64 {
        (self.slope(phi) / FREE_SLOPE).min(1.0)
    }
}

/// The share of the crowding's hold that agitation leaves: all of it up to the lift-off at
/// `gamma_c`, none above (module docs). `gamma` and `gamma_c` are peak tray accelerations
/// over g.
pub fn hold_share(gamma: f64, gamma_c: f64) -> f64 {
    if gamma <= gamma_c {
        1.0
    } else {
        0.0
    }
}

/// The graded-transport slot's resolved numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Graded {
    /// The measured slope table.
    pub slope: SlopeTable,
    /// The share of the crowding's hold left by agitation ([`hold_share`]), in [0, 1].
    pub hold: f64,
    /// The area fraction one grain adds to the window it sits in: its mean projected area
    /// `pi <r^2>` over the window's area (`window_cells` cells by the tray's width).
    pub grain_fraction: f64,
    /// Length of the window over which the local packing is taken, in cells (the DEM's
    /// measurement used 1 mm strips across the tray).
    pub window_cells: f64,
}

impl Graded {
    /// A grain's jump in cells at local area fraction `phi`, for a free grain's `cap`:
    /// `round(cap * (1 - (1 - s(phi)) hold))`.
    pub fn jump(&self, cap: usize, phi: f64) -> usize {
        let s = 1.0 - (1.0 - self.slope.relative_excursion(phi)) * self.hold;
        (cap as f64 * s).round().clamp(0.0, cap as f64) as usize
    }

    /// The window's weights: column offset `d` from the grain's column and the length of the
    /// window (centred on the grain's column) that falls in that column, in cells.
    pub fn window(&self) -> Vec<(isize, f64)> {
        let half = 0.5 * self.window_cells.max(1e-9);
        let reach = (half - 0.5).max(0.0).ceil() as isize;
        (-reach..=reach)
            .map(|d| {
                let (lo, hi) = (d as f64 - 0.5, d as f64 + 0.5);
                (d, (hi.min(half) - lo.max(-half)).max(0.0))
            })
            .filter(|&(_, w)| w > 0.0)
            .collect()
    }

    /// The jump of a grain in each column of a periodic row of `counts` (grains per column,
    /// all rows and levels), into `jumps`.
    pub fn jumps(&self, cap: usize, counts: &[u32], jumps: &mut [usize]) {
        let nx = counts.len();
        let window = self.window();
        for (i, jump) in jumps.iter_mut().enumerate() {
            let grains: f64 = window
                .iter()
                .map(|&(d, w)| w * counts[(i as isize + d).rem_euclid(nx as isize) as usize] as f64)
                .sum();
            *jump = self.jump(cap, self.grain_fraction * grains);
        }
    }
}

/// Where the grains of one periodic row of `nx` cells land, in the flight frame (flights go
/// to higher indices). `cells[k]` is the cell of grain `k` (strictly increasing) and
/// `jumps[k]` how far it would go alone. With `trains`, each grain stops one cell before where
/// the grain ahead of it lands (grains roll together and queue behind a slower one); without,
/// one cell before where the grain ahead of it starts (thesis 3.1 rule 1: the unchanged copy
/// L). Returns the landing cells, unwrapped (`cells[k] <= land[k] <= cells[k] + jumps[k]`,
/// strictly increasing and less than `cells[0] + nx + land[0] - cells[0]` round the ring),
/// so no two grains share a cell. With `wall` the row ends at an end wall after cell
/// `nx - 1` instead of wrapping round: the front grain stops there.
pub fn landings(nx: usize, cells: &[usize], jumps: &[usize], trains: bool, wall: bool, land: &mut Vec<usize>) {
    let n = cells.len();
    land.clear();
    land.extend(cells.iter().zip(jumps).map(|(&c, &j)| c + j));
    if n == 0 {
        return;
    }
    if wall {
        // The wall is a resting grain at cell nx: from the front grain back, each stops
        // before the next one's landing (trains) or start.
        let mut next = nx;
        for k in (0..n).rev() {
            land[k] = land[k].min(next - 1).max(cells[k]);
            next = if trains { land[k] } else { cells[k] };
        }
        return;
    }
    if !trains {
        for k in 0..n {
            let next = if k + 1 < n { cells[k + 1] } else { cells[0] + nx };
            land[k] = land[k].min(next - 1).max(cells[k]);
        }
        return;
    }
    // From upper bounds down to the largest consistent landings; every pass lowers some
    // landing or stops, and none goes below its start.
    loop {
        let mut changed = false;
        for k in (0..n).rev() {
            let next = if k + 1 < n { land[k + 1] } else { land[0] + nx };
            let l = land[k].min(next - 1).max(cells[k]);
            if l != land[k] {
                land[k] = l;
                changed = true;
            }
        }
        if !changed {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graded(hold: f64) -> Graded {
        Graded {
            slope: SlopeTable::InBands,
            hold,
            grain_fraction: 0.1,
            window_cells: 1.0,
        }
    }

    #[test]
    fn slope_tables_interpolate_the_measured_classes_and_hold_their_ends() {
        for t in [SlopeTable::BeforeBands, SlopeTable::InBands] {
            for &(phi, a) in t.points() {
                assert!((t.slope(phi) - a).abs() < 1e-12);
            }
            let p = t.points();
            assert_eq!(t.slope(0.0), p[0].1);
            assert_eq!(t.slope(2.0), p[p.len() - 1].1);
            // Crowded grains roll less: the slope never grows with the packing past the
            // dilute classes.
            let mut last = f64::INFINITY;
            for k in 0..=100 {
                let s = t.slope(k as f64 / 100.0);
                assert!(s <= last + 1e-12);
                last = s;
            }
        }
        assert!((SlopeTable::InBands.slope(0.5) - 0.5 * (0.5070 + 0.4130)).abs() < 1e-12);
        // A free grain jumps its full excursion (the dilute DEM grains roll a little more than
        // 5/7; the cap is the single sphere's excursion).
        assert_eq!(SlopeTable::BeforeBands.relative_excursion(0.2), 1.0);
        assert!((SlopeTable::InBands.relative_excursion(0.9) - 0.1536 / FREE_SLOPE).abs() < 1e-12);
    }

    #[test]
    fn lift_off_takes_the_whole_hold_above_gamma_c_and_none_below() {
        assert_eq!(hold_share(0.0, 1.35), 1.0);
        assert_eq!(hold_share(0.64, 1.35), 1.0, "the DEM holds at Gamma 0.64");
        assert_eq!(hold_share(1.35, 1.35), 1.0);
        assert_eq!(hold_share(1.42, 1.35), 0.0, "the DEM left 0.08 of it at Gamma 1.42");
        assert_eq!(hold_share(1e6, 1.35), 0.0);
        // Never rises with agitation.
        let mut last = 1.0;
        for k in 0..200 {
            let h = hold_share(k as f64 * 0.02, 1.35);
            assert!(h <= last && (h == 0.0 || h == 1.0));
            last = h;
        }
        // No hold left: every grain jumps a free grain's cap, whatever its packing; the full
        // hold gives the measured slope.
        let cap = 24;
        for phi in [0.0, 0.3, 0.6, 0.9] {
            assert_eq!(graded(0.0).jump(cap, phi), cap);
            let s = SlopeTable::InBands.relative_excursion(phi);
            assert_eq!(graded(1.0).jump(cap, phi), (cap as f64 * s).round() as usize);
        }
        assert_eq!(graded(1.0).jump(cap, 0.9), 5, "jammed: 24 * 0.1536 / (5/7) = 5.2");
    }

    #[test]
    fn the_window_covers_its_length_centred_on_the_grain() {
        for w in [0.5, 1.0, 1.67, 3.0, 4.2] {
            let g = Graded {
                window_cells: w,
                ..graded(1.0)
            };
            let win = g.window();
            let total: f64 = win.iter().map(|x| x.1).sum();
            assert!((total - w.max(1e-9)).abs() < 1e-12, "{w}: {win:?}");
            for &(d, x) in &win {
                let mirror = win.iter().find(|y| y.0 == -d).expect("symmetric");
                assert!((mirror.1 - x).abs() < 1e-12);
            }
        }
        // One grain per column everywhere: phi = grain_fraction * window length.
        let g = Graded {
            window_cells: 1.67,
            grain_fraction: 0.45 / 1.67,
            ..graded(1.0)
        };
        let mut jumps = vec![0; 20];
        g.jumps(24, &[1; 20], &mut jumps);
        assert!(jumps.iter().all(|&j| j == g.jump(24, 0.45)));
    }

    /// Landings conserve the grains, keep their order round the ring, never share a cell and
    /// never move a grain backwards or beyond its own jump.
    #[test]
    fn an_end_wall_stops_the_front_grain_and_the_row_queues_behind_it() {
        let mut land = Vec::new();
        // Trains: the front grain stops at the last cell, the others behind their landings.
        landings(10, &[5, 7, 8], &[6, 6, 6], true, true, &mut land);
        assert_eq!(land, [7, 8, 9]);
        // Without trains each stops before the next one's start.
        landings(10, &[5, 7, 8], &[6, 6, 6], false, true, &mut land);
        assert_eq!(land, [6, 7, 9]);
        // Short flights are untouched; nothing wraps round.
        landings(10, &[0, 4], &[2, 3], true, true, &mut land);
        assert_eq!(land, [2, 7]);
    }

    #[test]
    fn landings_conserve_order_and_cells() {
        let mut z = 7u64;
        let mut land = Vec::new();
        for case in 0..2000 {
            let nx = 5 + case % 40;
            let mut cells = Vec::new();
            for c in 0..nx {
                z = crate::rng::mix(z);
                if z.is_multiple_of(3) {
                    cells.push(c);
                }
            }
            let jumps: Vec<usize> = cells
                .iter()
                .map(|_| {
                    z = crate::rng::mix(z);
                    (z % 30) as usize
                })
                .collect();
            for trains in [false, true] {
                landings(nx, &cells, &jumps, trains, false, &mut land);
                let n = cells.len();
                let mut seen = vec![false; nx];
                for k in 0..n {
                    assert!(land[k] >= cells[k] && land[k] <= cells[k] + jumps[k]);
                    if k + 1 < n {
                        assert!(land[k] < land[k + 1]);
                    }
                    let c = land[k] % nx;
                    assert!(!seen[c], "two grains in cell {c}");
                    seen[c] = true;
                }
                if n > 1 {
                    assert!(land[n - 1] < land[0] + nx, "order kept round the ring");
                }
            }
        }
    }

    #[test]
    fn trains_queue_behind_a_slow_grain_and_rule_one_stops_at_the_start() {
        let mut land = Vec::new();
        // A slow grain at 10 (jump 1) and two fast ones behind it at 6 and 7 (jump 8).
        landings(40, &[6, 7, 10], &[8, 8, 1], true, false, &mut land);
        assert_eq!(land, [9, 10, 11]);
        landings(40, &[6, 7, 10], &[8, 8, 1], false, false, &mut land);
        assert_eq!(land, [6, 9, 11]);
        // A ring of grains that all fly turns rigidly (a full row stays full); without trains
        // a full row cannot move.
        landings(4, &[0, 1, 2, 3], &[3, 3, 3, 3], true, false, &mut land);
        assert_eq!(land, [3, 4, 5, 6]);
        landings(4, &[0, 1, 2, 3], &[3, 3, 3, 3], false, false, &mut land);
        assert_eq!(land, [0, 1, 2, 3]);
        // One resting grain stops the ring behind it.
        landings(6, &[0, 1, 2, 3], &[3, 3, 0, 3], true, false, &mut land);
        assert_eq!(land, [0, 1, 2, 5]);
        // Equal jumps in a touching train move the train as a whole.
        landings(40, &[3, 4, 5], &[6, 6, 6], true, false, &mut land);
        assert_eq!(land, [9, 10, 11]);
    }
}
