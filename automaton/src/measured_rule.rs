//! The `measured` rule: flights, band edges and sideways steps whose numbers are all
//! measured on a DEM run by `stripes mechanism` ([`crate::measured`]), nothing fitted to a
//! pattern. It runs on the byte lattice ([`crate::scalar`] calls [`flights`] in place of its
//! own flights, knock-through and sideways moves; the resting rule follows as for every
//! rule); this is its only implementation.
//!
//! In the flight frame (flights towards higher `i`), from the unchanged copy `L`:
//! 1. *Bands.* A column is a band column when its grains (all rows and levels) fill more
//!    than `band_fill` of its cells; a band is a run of at least `band_min_cells` such
//!    columns (the DEM measure's stripe detection in lattice units). A band's *leading
//!    edge* is its last column in the flight direction.
//! 2. *Held and escaping grains.* A grain in a band is held (it rests with the tray), except
//!    on the leading edge, where it escapes with probability `edge_escape` and then flies as
//!    a free grain. Each edge leads in one half step of every period, so the per-period
//!    rate measured at the same turning point is the per-half-step chance at the leading
//!    edge: no further conversion. (A grain that escaped may queue back onto its band in the
//!    next half step, as in the DEM, whose measure counts such grains as stayed.)
//! 3. *Jumps.* Every other floor grain (height 1; piles rest) flies. In an even half step
//!    (the swing out) it draws its jump from the measured excursion distribution of its
//!    contact number, `n` = the occupied cells among its four orthogonal neighbours (a cell
//!    is one grain at the band cores' packing, so orthogonal neighbours touch and diagonal
//!    ones, sqrt 2 cells off, do not): `Q_n(u)` in metres ([`Quantiles`]), over the cell
//!    size, rounded stochastically (up with the fraction's probability, so the mean is
//!    kept). In the odd half step that follows (the swing back) a grain that flew out flies
//!    back by its drawn flight out `J1` less the period's drift: `J2 = max(0, J1 - s d)`,
//!    `s` the lab direction of the flight out, `d` drawn from the measured signed drift
//!    `excursion.drift_signed` (`dx1 + dx2` along x, [`Quantiles::signed`], in cells as the
//!    jumps); so a free grain's net move over a period is the measured drift, not the
//!    difference of two independent excursions (in
//!    the DEM a grain's swing out and back are one motion: swing 13.3 mm, drift median 0.08
//!    mm on the stripe scene). A grain that did not fly out (held, or escaped only now)
//!    draws from `Q_n` on the way back too. Grains of a row queue behind the landing of the
//!    grain ahead ([`landings`] with trains): the measured excursions are the DEM grains'
//!    own moves, made together; a queue can shorten either swing. (Both swings are drawn
//!    before their queues, so queues shorten them alike: returning the *realised* flight out,
//!    only the way back was ever shortened, and every grain drifted towards the side of the
//!    flight out, +1.1 mm per period on the stripe scene against the DEM's -0.15 mm.)
//! 4. *Sideways.* Every grain that flew draws `|dy|` from the measured sideways distribution
//!    of its contact number, in cells as the jumps, and a direction (+y or -y, even odds);
//!    it steps that many cells across while the next cell is empty (walls stop it), grains
//!    taken in order of row and column.
//!
//! Every draw is a counter-based word of the grain's row, half step and start column
//! ([`crate::rng`]), and the flights out are kept per cell: the same seed gives the same
//! lattice. Every grain's move is recorded ([`GrainMove`]), so that grains can be followed
//! one by one ([`crate::Tracks`]).

use serde::{Deserialize, Serialize};

use crate::measured::{MeasuredError, MeasuredFile, Quantiles};
use crate::neighbours::neighbour_row;
use crate::rng::{self, Stream};
use crate::swing::{packing_field, PackingScratch, SwingCurve};
use crate::transport::landings;

/// Contact numbers on the lattice: 0 to 4 orthogonal neighbours.
pub const CONTACT_CLASSES: usize = 5;

/// The DEM measure's band detection in lattice units, which the root crate works out from
/// the analysis' stripe parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BandDetection {
    /// Fraction of a column's cells whose grains make it a band column (the area-fraction
    /// threshold over one grain's area fraction of a cell).
    pub fill: f64,
    /// Least width of a band, in columns.
    pub min_cells: usize,
}

/// The rule's resolved numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeasuredRule {
    /// Cell length along x (m), which turns lengths into cells.
    pub cell_m: f64,
    /// Across the tray (m), for the sideways steps.
    pub cell_y_m: f64,
    /// `|dx|` per half period by contact number 0..=4 (the last: 4 and more).
    pub excursion: [Quantiles; CONTACT_CLASSES],
    /// `|dy|` per half period by contact number.
    pub sideways: [Quantiles; CONTACT_CLASSES],
    /// `dx1 + dx2` per period, signed along x: a grain's drift over its swing out and back.
    pub drift: Quantiles,
    /// Probability that a grain of a band's leading edge escapes in a half step.
    pub edge_escape: f64,
    pub band: BandDetection,
    /// The swing field ([`crate::swing`]), when the file holds one: the `swing` rule's numbers.
    pub swing: Option<SwingCurve>,
}

impl MeasuredRule {
    /// The rule from a checked file on cells of `cell_m` by `cell_y_m`, each covered by one
    /// grain to `grain_fraction` of its area.
    pub fn new(file: &MeasuredFile, cell_m: f64, cell_y_m: f64, band: BandDetection, grain_fraction: f64) -> Result<Self, MeasuredError> {
        file.validate()?;
        let swing = match file.swing_field {
            None => None,
            Some(_) => Some(SwingCurve::new(file.swing_field()?, file.source.mean_diameter_m, grain_fraction)),
        };
        Ok(Self {
            cell_m,
            cell_y_m,
            excursion: std::array::from_fn(|n| Quantiles::of(&file.class(n).excursion)),
            sideways: std::array::from_fn(|n| Quantiles::of(&file.class(n).sideways)),
            drift: Quantiles::signed(file.drift_signed()?),
            edge_escape: file.edge_escape()?,
            band,
            swing,
        })
    }
}

/// A uniform number in [0, 1) from a random word (its top 53 bits).
#[inline]
pub(crate) fn uniform(word: u64) -> f64 {
    (word >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A length drawn from `q`, in cells of `cell`, rounded up with the fraction's probability:
/// the words `k` and `k + 1` of `(key, stream, w)`.
#[inline]
pub(crate) fn draw_cells(q: &Quantiles, cell: f64, key: u64, stream: Stream, w: usize, k: u32) -> usize {
    let x = q.at(uniform(rng::word(key, stream, w, k))) / cell;
    let whole = x.floor();
    let up = uniform(rng::word(key, stream, w, k + 1)) < x - whole;
    whole as usize + up as usize
}

/// The `swing` rule's flight of a grain at local packing `phi`, in cells of `cell`: the swing
/// at `phi` plus a normal deviation of the measured spread (Box-Muller on the words 0 and 1
/// of `(key, Jump, w)`), at least 0, rounded up with the fraction's probability (word 2).
#[inline]
pub(crate) fn swing_cells(curve: &SwingCurve, phi: f64, cell: f64, key: u64, w: usize) -> usize {
    let (s, sd) = curve.at(phi);
    let (u1, u2) = (
        uniform(rng::word(key, Stream::Jump, w, 0)),
        uniform(rng::word(key, Stream::Jump, w, 1)),
    );
    let z = (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
    let x = ((s + sd * z) / cell).max(0.0);
    let whole = x.floor();
    whole as usize + (uniform(rng::word(key, Stream::Jump, w, 2)) < x - whole) as usize
}

/// One grain's move in a half step, in lab-frame cells: from `(row, column)` to
/// `(row, column)`, and its signed displacement along x in cells (`+` towards higher `i`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GrainMove {
    pub from: (usize, usize),
    pub to: (usize, usize),
    pub dx: i64,
}

/// Buffers of [`flights`], and the moves of the last half step.
#[derive(Default)]
pub(crate) struct MeasuredScratch {
    /// Every grain that changed cell in the last half step ([`GrainMove`]).
    pub(crate) moves: Vec<GrainMove>,
    /// Grains the resting rule moved after the flights of the last half step (0 on a
    /// submonolayer: no flight lands on a grain).
    pub(crate) rested: u64,
    counts: Vec<u32>,
    band: Vec<bool>,
    lead: Vec<bool>,
    cells: Vec<usize>,
    jumps: Vec<usize>,
    land: Vec<usize>,
    /// Grains that flew: (row, landing column, contact number, start column, drawn jump).
    movers: Vec<(usize, usize, usize, usize, usize)>,
    /// The window packing of each flight-frame cell (the `swing` rule).
    packing: PackingScratch,
    /// Per lab-frame cell `j * nx + i`: 1 + the drawn flight (cells) of the grain that flew
    /// out to it in the last outgoing half step, 0 where none did.
    out: Vec<u32>,
}

/// Marks band columns and their leading edges (the last column of each run in the flight
/// direction) from the grains per column, periodic in x unless `walls`.
fn bands(counts: &[u32], ny: usize, b: &BandDetection, walls: bool, band: &mut Vec<bool>, lead: &mut Vec<bool>) {
    let nx = counts.len();
    band.clear();
    band.extend(counts.iter().map(|&c| c as f64 > b.fill * ny as f64));
    lead.clear();
    lead.resize(nx, false);
    if walls {
        // Runs end at the row's ends; a run against the far wall leads into it.
        let mut run = 0;
        for c in 0..=nx {
            if c < nx && band[c] {
                run += 1;
                continue;
            }
            if run > 0 {
                if run >= b.min_cells.max(1) {
                    lead[c - 1] = true;
                } else {
                    band[c - run..c].iter_mut().for_each(|x| *x = false);
                }
            }
            run = 0;
        }
        return;
    }
    // A whole ring of band columns has no edge.
    let Some(gap) = band.iter().position(|&x| !x) else {
        return;
    };
    let mut run = 0;
    for s in 1..=nx {
        let c = (gap + s) % nx;
        if band[c] {
            run += 1;
            continue;
        }
        if run > 0 {
            let first = (c + nx - run) % nx;
            if run >= b.min_cells.max(1) {
                lead[(c + nx - 1) % nx] = true;
            } else {
                for k in 0..run {
                    band[(first + k) % nx] = false;
                }
            }
        }
        run = 0;
    }
}

/// The measured rule's flights and sideways steps on the flight-frame copy `lf` into `new`
/// (index `j * nx + i`), for half step `t` of the run seeded `seed`, whose flight frame is
/// the lab frame mirrored when `left` (module docs); with `swing`, the `swing` rule's
/// flights instead (no band holds a grain; every floor grain flies by the swing at its
/// local packing, [`swing_cells`]). With `walls` the rows end at end walls (x = 0 and
/// x = L) instead of wrapping round. Records every grain's move in `sc.moves`, in lab-frame
/// cells.
#[allow(clippy::too_many_arguments)]
pub(crate) fn flights(
    nx: usize,
    ny: usize,
    lf: &[u8],
    new: &mut [u8],
    m: &MeasuredRule,
    seed: u64,
    t: u64,
    left: bool,
    periodic_y: bool,
    walls: bool,
    swing: Option<&SwingCurve>,
    sc: &mut MeasuredScratch,
) {
    let lab = |i: usize| if left { nx - 1 - i } else { i };
    let sign: i64 = if left { -1 } else { 1 };
    sc.moves.clear();
    // Even half steps swing grains out, odd ones back.
    let outgoing = t.is_multiple_of(2);
    if sc.out.len() != nx * ny {
        sc.out.clear();
        sc.out.resize(nx * ny, 0);
    }
    if outgoing {
        sc.out.iter_mut().for_each(|o| *o = 0);
    }
    sc.counts.clear();
    sc.counts
        .extend((0..nx).map(|i| (0..ny).map(|j| lf[j * nx + i] as u32).sum::<u32>()));
    if let Some(curve) = swing {
        // No band holds a grain: no band detection, the window packing instead.
        packing_field(nx, ny, lf, (!walls, periodic_y), curve, (m.cell_m, m.cell_y_m), &mut sc.packing);
        sc.band.clear();
        sc.band.resize(nx, false);
        sc.lead.clear();
        sc.lead.resize(nx, false);
    } else {
        bands(&sc.counts, ny, &m.band, walls, &mut sc.band, &mut sc.lead);
    }
    let occupied = |j: usize, i: usize| lf[j * nx + i] > 0;
    // The x-neighbours of column i: round the ring, or none beyond an end wall.
    let ahead = |i: usize| if walls && i + 1 == nx { None } else { Some((i + 1) % nx) };
    let behind = |i: usize| if walls && i == 0 { None } else { Some((i + nx - 1) % nx) };
    sc.movers.clear();
    for j in 0..ny {
        let key = rng::row_key(seed, t, j);
        sc.cells.clear();
        sc.jumps.clear();
        let first_mover = sc.movers.len();
        for i in 0..nx {
            let h = lf[j * nx + i];
            if h == 0 {
                continue;
            }
            sc.cells.push(i);
            let held = h > 1 || (sc.band[i] && !(sc.lead[i] && uniform(rng::word(key, Stream::Escape, i, 0)) < m.edge_escape));
            if held {
                sc.jumps.push(0);
                continue;
            }
            let n = ahead(i).is_some_and(|c| occupied(j, c)) as usize
                + behind(i).is_some_and(|c| occupied(j, c)) as usize
                + [true, false]
                    .into_iter()
                    .filter_map(|up| neighbour_row(j, up, ny, periodic_y).filter(|&jn| jn != j))
                    .filter(|&jn| occupied(jn, i))
                    .count();
            let n = n.min(CONTACT_CLASSES - 1);
            let out = if outgoing || swing.is_some() { 0 } else { sc.out[j * nx + lab(i)] };
            let jump = if let Some(curve) = swing {
                swing_cells(curve, sc.packing.phi[j * nx + i], m.cell_m, key, i)
            } else if out > 0 {
                // Back by the drawn flight out, less the period's drift `d` (signed, + towards +x):
                // the period's net move is `s_out (J1 - J2) = d`, with `s_out = -sign` the
                // lab direction of the flight out.
                let x = m.drift.at(uniform(rng::word(key, Stream::Drift, i, 0))) / m.cell_m;
                let d = x.floor() as i64 + (uniform(rng::word(key, Stream::Drift, i, 1)) < x - x.floor()) as i64;
                (out as i64 - 1 + d * sign).max(0) as usize
            } else {
                draw_cells(&m.excursion[n], m.cell_m, key, Stream::Jump, i, 0)
            };
            sc.jumps.push(jump);
            sc.movers.push((j, i, n, i, jump));
        }
        landings(nx, &sc.cells, &sc.jumps, true, walls, &mut sc.land);
        let mut mover = first_mover;
        for (&c, &l) in sc.cells.iter().zip(&sc.land) {
            if mover < sc.movers.len() && sc.movers[mover].3 == c {
                sc.movers[mover].1 = l % nx;
                mover += 1;
            }
            if l != c {
                new[j * nx + c] -= 1;
                new[j * nx + l % nx] += 1;
            }
        }
    }
    for &(j0, c, n, i0, drawn) in &sc.movers {
        let key = rng::row_key(seed, t, j0);
        let steps = draw_cells(&m.sideways[n], m.cell_y_m, key, Stream::SideStep, i0, 0);
        let up = rng::word(key, Stream::SideStep, i0, 2) & 1 == 1;
        let mut j = j0;
        for _ in 0..steps {
            match neighbour_row(j, up, ny, periodic_y) {
                Some(jn) if jn != j && new[jn * nx + c] == 0 => {
                    new[j * nx + c] -= 1;
                    new[jn * nx + c] += 1;
                    j = jn;
                }
                _ => break,
            }
        }
        if outgoing {
            sc.out[j * nx + lab(c)] = drawn as u32 + 1;
        }
        if (j, c) != (j0, i0) {
            sc.moves.push(GrainMove {
                from: (j0, lab(i0)),
                to: (j, lab(c)),
                dx: sign * ((c + nx - i0) % nx) as i64,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measured::Spread;

    fn spread(mean: f64, q: [f64; 5]) -> Spread {
        Spread {
            samples: 1000,
            mean,
            sd: 0.0,
            q10: q[0],
            q25: q[1],
            median: q[2],
            q75: q[3],
            q90: q[4],
        }
    }

    /// Draws through the rule's own random words give back the measured quantiles (before
    /// rounding to cells) and the measured mean (after it: the rounding keeps the mean).
    #[test]
    fn draws_reproduce_the_measured_quantiles_and_mean() {
        // The stripe scene's (seed 1) excursions of grains with 2 contacts, in metres.
        let s = spread(
            0.012587854193517975,
            [
                0.008675179701961877,
                0.011122165688349811,
                0.014013540446437753,
                0.014268529115688836,
                0.01429579077890196,
            ],
        );
        let q = Quantiles::of(&s);
        let cell = 0.0007584766454585922;
        let n = 200_000;
        let (mut metres, mut cells) = (Vec::with_capacity(n), 0u64);
        for k in 0..n {
            let key = rng::row_key(7, k as u64 / 64, k % 64);
            metres.push(q.at(uniform(rng::word(key, Stream::Jump, k, 0))));
            cells += draw_cells(&q, cell, key, Stream::Jump, k, 0) as u64;
        }
        metres.sort_by(f64::total_cmp);
        let at = |p: f64| metres[(p * (n - 1) as f64).round() as usize];
        for (p, v) in [(0.1, s.q10), (0.25, s.q25), (0.5, s.median), (0.75, s.q75), (0.9, s.q90)] {
            // The fraction's own sampling spread: sqrt(p (1 - p) / n) <= 1.2e-3 of u, times
            // the steepest slope of Q (16 mm per unit of u) is 1.8e-5 m; allow 3 sigma.
            assert!((at(p) - v).abs() < 6e-5, "q{p}: {} against {v}", at(p));
        }
        let mean = cells as f64 / n as f64 * cell;
        // sd of a draw about 2.3 mm / sqrt(n): 5e-6 m; allow 4 sigma.
        assert!((mean - s.mean).abs() < 2e-5, "mean {mean} against {}", s.mean);
    }

    #[test]
    fn bands_are_runs_of_full_columns_led_by_their_last_column() {
        let b = BandDetection { fill: 0.5, min_cells: 3 };
        let (mut band, mut lead) = (Vec::new(), Vec::new());
        // ny = 4: columns with 3 or 4 grains are band columns; the run 8, 9, 0, 1 wraps the
        // seam; the run 4, 5 is too short.
        let counts = [4, 3, 0, 1, 3, 4, 0, 2, 4, 4];
        bands(&counts, 4, &b, false, &mut band, &mut lead);
        assert_eq!(band, [true, true, false, false, false, false, false, false, true, true]);
        assert_eq!(lead, [false, true, false, false, false, false, false, false, false, false]);
        bands(&[4; 6], 4, &b, false, &mut band, &mut lead);
        assert!(band.iter().all(|&x| x) && lead.iter().all(|&x| !x), "a full ring has no edge");
        // Between end walls nothing wraps: the seam's run splits into two short ones, and a
        // full row leads into the far wall.
        bands(&counts, 4, &b, true, &mut band, &mut lead);
        assert_eq!(band, [false; 10]);
        bands(&[4; 6], 4, &b, true, &mut band, &mut lead);
        assert!(band.iter().all(|&x| x) && lead == [false, false, false, false, false, true]);
    }
}
