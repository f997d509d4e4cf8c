//! The bit-parallel half step of a submonolayer (every height 0 or 1), both rule sets.
//!
//! Work happens in the *flight frame*: rows are mirrored when grains fly towards -x, so the
//! flight always goes to higher cell indices. For row `j`, with `L` the unchanged copy:
//! - obstacles `O = L_j` (or `L_{j-1} | L_j | L_{j+1}` with lateral contacts), free `F = !O`;
//! - flying grains `A = L_j & activation bits`;
//! - a grain at `a` with `F` set on all of `a+1 ..= a+l` (mask `FL`, built from `F` by
//!   doubling in O(log l) rotations) flies the full cap: it lands at `a + l`;
//! - every other flying grain lands just before the first obstacle `p` ahead of it:
//!   adding the run starts `S = rot_up(A & !FL, 1) & F` to `F` with end-around carry
//!   ([`RowShape::cyclic_add`]) carries along each free run and sets exactly its end `p`,
//!   `E = (F + S) & !F`, and the landing cells are `rot_down(E, 1)`;
//! - a flying grain whose cell ahead is an obstacle stays.
//!
//! The new row is `(L_j & !A) | rot_up(A & FL, l) | rot_down(E, 1) | stay`. Landing cells are
//! distinct (each lies in its grain's own free run), so the row stays 0/1 and the number of
//! grains is conserved exactly. Knock-through (a few impacts per row) and sideways moves are
//! applied afterwards in the same frame; [`crate::scalar`] is the byte-per-cell reference of
//! exactly these rules. Every buffer is allocated once, in [`BitScratch::new`].

// Word loops index several rows at once; explicit indices read clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

use crate::bits::RowShape;
use crate::params::{Lateral, Resolved, Tick};
use crate::rng::{self, Stream};

/// Buffers of the bit-parallel step (no allocation per step).
pub(crate) struct BitScratch {
    lf: Vec<u64>,
    clusters: Vec<u64>,
    new: Vec<u64>,
    active: Vec<u64>,
    impacts: Vec<u64>,
    o: Vec<u64>,
    free: Vec<u64>,
    f1: Vec<u64>,
    fl: Vec<u64>,
    pow: Vec<u64>,
    tmp: Vec<u64>,
    s2: Vec<u64>,
    sum: Vec<u64>,
    ext: Vec<u64>,
    /// The cell draws of the current row (see [`obstacles`]).
    cells: Vec<u64>,
    /// A row of zeros.
    zeros: Vec<u64>,
    /// Grains of the current row moving sideways.
    side_moving: Vec<u64>,
    /// Sideways draws of each row word for the current half step, see [`sideways_draws`].
    side_up: Vec<u64>,
    side_down: Vec<u64>,
    /// [`rng::row_key`] of each row for the current half step.
    keys: Vec<u64>,
    /// The digit masks of the draws (activation and holding, knock, sideways, frustration) and the
    /// probabilities they were worked out for.
    splits: Option<((u32, u32, u32, u32), Splits)>,
}

/// The digit masks of a half step's draws.
#[derive(Clone, Copy)]
struct Splits {
    cells: rng::Split,
    knock: rng::Split,
    side: rng::Split,
    hold: rng::Split,
}

impl BitScratch {
    /// The digit masks for `r`, worked out when its probabilities change.
    fn splits(&mut self, r: &Resolved) -> Splits {
        let probs = (r.activation, r.knock, r.sideways, r.hold);
        match self.splits {
            Some((p, s)) if p == probs => s,
            _ => {
                let s = Splits {
                    cells: rng::Split::new(r.activation, rng::ONE - r.knock),
                    knock: rng::Split::plain(r.knock),
                    side: rng::Split::plain(r.sideways),
                    hold: rng::Split::plain(r.hold),
                };
                self.splits = Some((probs, s));
                s
            }
        }
    }
}

impl BitScratch {
    pub fn new(shape: RowShape, ny: usize) -> Self {
        let w = shape.words;
        let row = || vec![0u64; w];
        Self {
            lf: vec![0; w * ny],
            clusters: vec![0; w * ny],
            new: vec![0; w * ny],
            active: row(),
            impacts: vec![0; w * ny],
            o: row(),
            free: row(),
            f1: row(),
            fl: row(),
            pow: row(),
            tmp: row(),
            s2: row(),
            sum: row(),
            ext: vec![0; shape.ext_words()],
            cells: row(),
            zeros: row(),
            side_moving: row(),
            side_up: vec![0; w * ny],
            side_down: vec![0; w * ny],
            keys: vec![0; ny],
            splits: None,
        }
    }
}

/// Row `j + dj` for `dj` in -1, 0, 1, or `None` beyond a wall.
#[inline]
pub(crate) fn offset_row(j: usize, dj: i32, ny: usize, periodic: bool) -> Option<usize> {
    if dj == 0 {
        Some(j)
    } else {
        neighbour_row(j, dj > 0, ny, periodic)
    }
}

/// Row `jn = j + d` or `None` beyond a wall.
#[inline]
pub(crate) fn neighbour_row(j: usize, up: bool, ny: usize, periodic: bool) -> Option<usize> {
    if up {
        if j + 1 < ny {
            Some(j + 1)
        } else if periodic {
            Some(0)
        } else {
            None
        }
    } else if j > 0 {
        Some(j - 1)
    } else if periodic {
        Some(ny - 1)
    } else {
        None
    }
}

/// Obstacles of row `j` in the flight-frame copy `lf`, and the row's cell draws; `clusters`
/// holds the grains that touch an x-neighbour in their row (used by [`Lateral::Clusters`]).
/// With knock-through, a lateral contact holds only with probability `1 - p_knock` (an
/// impact that knocks loose also pushes past the neighbouring rows), drawn per cell of row
/// `j`. `cells` gets [`rng::bernoulli_split`] of [`Stream::Activation`]: the activation
/// draw on the row's grains, the holding draw on its empty cells (the only cells where a
/// lateral contact is tested), in one set of digit words; words without grains or lateral
/// contacts are not drawn (the draw is the same either way).
fn obstacles(
    shape: &RowShape,
    (lf, clusters): (&[u64], &[u64]),
    (ny, j): (usize, usize),
    r: &Resolved,
    (key, split): (u64, &rng::Split),
    out: RowCells,
) {
    let RowCells { o, side_cells, cells } = out;
    let w = shape.words;
    let lrow = &lf[j * w..(j + 1) * w];
    o.copy_from_slice(lrow);
    let side = match r.lateral {
        Lateral::None => None,
        Lateral::Neighbours => Some(lf),
        Lateral::Clusters => Some(clusters),
    };
    let Some(side) = side else {
        rng::bernoulli_split_row(key, Stream::Activation, lrow, split, lrow, cells);
        return;
    };
    // A missing neighbour row (beyond a wall) is read as the own row, masked to nothing.
    let neighbour = |up: bool| match neighbour_row(j, up, ny, r.periodic_y) {
        Some(jn) => (&side[jn * w..][..w], u64::MAX),
        None => (&side[j * w..][..w], 0),
    };
    let ((below, mb), (above, ma)) = (neighbour(false), neighbour(true));
    for (k, ((s, &b), &a)) in side_cells.iter_mut().zip(below).zip(above).enumerate() {
        // Cells already blocked in the own row are not tested.
        *s = ((b & mb) | (a & ma)) & !lrow[k];
        o[k] = lrow[k] | *s;
    }
    rng::bernoulli_split_row(key, Stream::Activation, lrow, split, o, cells);
    for (o, (&s, &c)) in o.iter_mut().zip(side_cells.iter().zip(cells.iter())) {
        // A lateral contact that does not hold is no obstacle.
        *o &= !(s & !c);
    }
}

/// What [`obstacles`] writes for one row: the obstacles `o`, the lateral-contact cells
/// tested, and the row's cell draws.
struct RowCells<'a> {
    o: &'a mut [u64],
    side_cells: &'a mut [u64],
    cells: &'a mut [u64],
}

/// The occupied neighbouring cells of every cell of row `j` of the flight-frame copy `lf`, in
/// the order of [`crate::scalar::NEIGHBOURS`]: bit `a` of mask `d` is the cell at that offset
/// from `a` (no cell beyond a wall).
#[inline(always)]
fn neighbour_masks<const W: usize>(shape: &RowShape, lf: &[u64], j: usize, ny: usize, periodic: bool) -> [[u64; W]; 8] {
    crate::scalar::NEIGHBOURS.map(|(dj, di)| {
        let row = offset_row(j, dj, ny, periodic).map_or([0; W], |jn| load::<W>(lf, jn));
        match di {
            1 => shape.rot_down1(&row),
            -1 => shape.rot_up1(&row),
            _ => row,
        }
    })
}

/// Mask `d` of [`neighbour_masks`] for rows of any width, into `out`.
fn neighbour_mask(shape: &RowShape, lf: &[u64], j: usize, ny: usize, periodic: bool, d: usize, out: &mut [u64]) {
    let w = shape.words;
    let (dj, di) = crate::scalar::NEIGHBOURS[d];
    let Some(jn) = offset_row(j, dj, ny, periodic) else {
        out.iter_mut().for_each(|x| *x = 0);
        return;
    };
    let src = &lf[jn * w..(jn + 1) * w];
    match di {
        1 => shape.rotate_down(src, 1, out),
        -1 => shape.rotate_up(src, 1, out),
        _ => out.copy_from_slice(src),
    }
}

/// `clusters = L & (rot_up(L, 1) | rot_down(L, 1))` row by row.
fn cluster_cells(shape: &RowShape, ny: usize, sc: &mut BitScratch) {
    let w = shape.words;
    for j in 0..ny {
        let l = &sc.lf[j * w..(j + 1) * w];
        shape.rotate_up(l, 1, &mut sc.tmp);
        shape.rotate_down(l, 1, &mut sc.pow);
        for k in 0..w {
            sc.clusters[j * w + k] = l[k] & (sc.tmp[k] | sc.pow[k]);
        }
    }
}

/// Calls `$f::<W>($args)` for rows of `W = $w` words up to 16 (fused, fixed-width rows),
/// `$any($args)` for wider rows.
macro_rules! by_width {
    ($w:expr, $f:ident, $any:ident, $($arg:expr),*) => {
        match $w {
            1 => $f::<1>($($arg),*),
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            5 => $f::<5>($($arg),*),
            6 => $f::<6>($($arg),*),
            7 => $f::<7>($($arg),*),
            8 => $f::<8>($($arg),*),
            9 => $f::<9>($($arg),*),
            10 => $f::<10>($($arg),*),
            11 => $f::<11>($($arg),*),
            12 => $f::<12>($($arg),*),
            13 => $f::<13>($($arg),*),
            14 => $f::<14>($($arg),*),
            15 => $f::<15>($($arg),*),
            16 => $f::<16>($($arg),*),
            _ => $any($($arg),*),
        }
    };
}

/// One half step of a bit-packed submonolayer `rows` (`ny` rows of `shape.words` words).
/// `left`: grains fly towards -x in this half step; `t` numbers the half step (random bits).
///
/// On x86-64 processors with the x86-64-v3 bit instructions (`andn`, `lzcnt`, `tzcnt`,
/// `mulx`, AVX2) the same code is compiled a second time with them enabled and chosen at run
/// time; both give the same bits (integer operations only).
pub(crate) fn half_step(shape: &RowShape, ny: usize, rows: &mut [u64], r: &Resolved, tick: Tick, sc: &mut BitScratch) {
    #[cfg(target_arch = "x86_64")]
    if has_v3() {
        // SAFETY: the processor has the features `half_step_v3` is compiled for.
        return unsafe { half_step_v3(shape, ny, rows, r, tick, sc) };
    }
    half_step_body(shape, ny, rows, r, tick, sc);
}

/// Whether the processor has the features of [`half_step_v3`] (checked once, then cached by
/// the standard library).
#[cfg(target_arch = "x86_64")]
#[inline]
fn has_v3() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("bmi1")
        && std::arch::is_x86_feature_detected!("bmi2")
        && std::arch::is_x86_feature_detected!("lzcnt")
        && std::arch::is_x86_feature_detected!("popcnt")
}

/// [`half_step_body`] compiled with the x86-64-v3 bit instructions.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn half_step_v3(shape: &RowShape, ny: usize, rows: &mut [u64], r: &Resolved, tick: Tick, sc: &mut BitScratch) {
    half_step_body(shape, ny, rows, r, tick, sc);
}

/// The half step itself, inlined into both [`half_step`] and [`half_step_v3`].
#[inline(always)]
fn half_step_body(shape: &RowShape, ny: usize, rows: &mut [u64], r: &Resolved, tick: Tick, sc: &mut BitScratch) {
    let Tick { seed, t, left } = tick;
    if r.frozen {
        return;
    }
    let w = shape.words;
    let cap = r.cap.min(shape.nx);
    for (j, key) in sc.keys.iter_mut().enumerate() {
        *key = rng::row_key(seed, t, j);
    }
    // Cell draws: activation on grains, holding of lateral contacts (probability 1 without
    // knock-through) on empty cells.
    let splits = sc.splits(r);
    by_width!(w, flights, flights_any, shape, ny, rows, r, left, &splits, sc);
    if r.knock > 0 {
        by_width!(w, knock_through_w, knock_through, shape, ny, r, cap, sc);
    }
    if r.sideways > 0 {
        by_width!(w, sideways_moves, sideways_moves_any, ny, r, sc);
    }
    by_width!(w, unframe, unframe_any, shape, ny, rows, left, sc);
}

/// `rows` from the flight-frame result `sc.new`.
#[inline(always)]
fn unframe<const W: usize>(shape: &RowShape, ny: usize, rows: &mut [u64], left: bool, sc: &mut BitScratch) {
    for (dst, src) in rows.chunks_exact_mut(W).zip(sc.new.chunks_exact(W)).take(ny) {
        let src: &[u64; W] = src.try_into().expect("W words");
        dst.copy_from_slice(&if left { shape.reverse_w(src) } else { *src });
    }
}

fn unframe_any(shape: &RowShape, ny: usize, rows: &mut [u64], left: bool, sc: &mut BitScratch) {
    let w = shape.words;
    for j in 0..ny {
        let (src, dst) = (&sc.new[j * w..(j + 1) * w], &mut rows[j * w..(j + 1) * w]);
        if left {
            shape.reverse(src, dst);
        } else {
            dst.copy_from_slice(src);
        }
    }
}

/// Row `j` of `rows` (rows of `W` words) as an array.
#[inline(always)]
fn load<const W: usize>(rows: &[u64], j: usize) -> [u64; W] {
    rows[j * W..(j + 1) * W].try_into().expect("W words")
}

/// The flights of a half step for rows of `W` words: the flight frame `sc.lf` (with the
/// clusters), then per row, in one pass over fixed-width arrays, the obstacles and cell draws
/// ([`obstacles`]), the flying grains and their landing cells into `sc.new`, and the drawn
/// impacts into `sc.impacts`. The same operations as [`flights_any`], in the same order.
#[inline(always)]
fn flights<const W: usize>(shape: &RowShape, ny: usize, rows: &[u64], r: &Resolved, left: bool, splits: &Splits, sc: &mut BitScratch) {
    let (split, knock) = (&splits.cells, &splits.knock);
    let nx = shape.nx;
    let cap = r.cap.min(nx);
    let BitScratch {
        lf,
        clusters,
        new,
        impacts,
        ext,
        keys,
        ..
    } = sc;
    let with_clusters = r.lateral == Lateral::Clusters;
    for j in 0..ny {
        let src = load::<W>(rows, j);
        let l = if left { shape.reverse_w(&src) } else { src };
        lf[j * W..(j + 1) * W].copy_from_slice(&l);
        if with_clusters {
            let (u, d) = (shape.rot_up1(&l), shape.rot_down1(&l));
            for k in 0..W {
                clusters[j * W + k] = l[k] & (u[k] | d[k]);
            }
        }
    }
    let side: Option<&[u64]> = match r.lateral {
        Lateral::None => None,
        Lateral::Neighbours => Some(lf),
        Lateral::Clusters => Some(clusters),
    };
    for j in 0..ny {
        let key = keys[j];
        let l = load::<W>(lf, j);
        // Obstacles and cell draws, as in [`obstacles`].
        let mut o = l;
        let mut side_cells = [0u64; W];
        if let Some(side) = side {
            let neighbour = |up: bool| neighbour_row(j, up, ny, r.periodic_y).map_or([0; W], |jn| load::<W>(side, jn));
            let (below, above) = (neighbour(false), neighbour(true));
            for k in 0..W {
                side_cells[k] = (below[k] | above[k]) & !l[k];
                o[k] = l[k] | side_cells[k];
            }
        }
        let mut cells = [0u64; W];
        rng::bernoulli_split_row(key, Stream::Activation, &l, split, &o, &mut cells);
        for k in 0..W {
            // A lateral contact that does not hold is no obstacle.
            o[k] &= !(side_cells[k] & !cells[k]);
        }
        let free = shape.not_w(&o);
        let f1 = shape.rot_down1(&free);
        let mut act = [0u64; W];
        for k in 0..W {
            act[k] = l[k] & f1[k] & cells[k];
        }
        if r.hold > 0 {
            let masks = neighbour_masks::<W>(shape, lf, j, ny, r.periodic_y);
            let mut held = [0u64; W];
            for (d, m) in masks.iter().enumerate() {
                let mut cand = [0u64; W];
                for k in 0..W {
                    cand[k] = m[k] & act[k];
                }
                let mut h = [0u64; W];
                rng::bernoulli_row(rng::neighbour_key(key, d), Stream::Frustration, &splits.hold, &cand, &mut h);
                for k in 0..W {
                    held[k] |= cand[k] & h[k];
                }
            }
            for k in 0..W {
                act[k] &= !held[k];
            }
        }
        let fl = if cap >= nx { [0; W] } else { shape.window_and_w(&f1, cap, ext) };
        let mut stop = [0u64; W];
        for k in 0..W {
            stop[k] = act[k] & !fl[k];
        }
        let mut ends = shape.cyclic_add_w(&free, &shape.rot_up1(&stop));
        for k in 0..W {
            ends[k] &= !free[k];
        }
        if r.knock > 0 {
            rng::bernoulli_row(key, Stream::Knock, knock, &ends, &mut impacts[j * W..(j + 1) * W]);
        }
        let mut n = shape.rot_down1(&ends);
        let mut full = [0u64; W];
        let mut any = 0;
        for k in 0..W {
            n[k] |= l[k] & !act[k];
            full[k] = act[k] & fl[k];
            any |= full[k];
        }
        if cap < nx && any != 0 {
            let far = shape.rot_up_w(&full, cap);
            for k in 0..W {
                n[k] |= far[k];
            }
        }
        new[j * W..(j + 1) * W].copy_from_slice(&n);
    }
}

/// [`flights`] for rows of any width, one word loop per operation.
fn flights_any(shape: &RowShape, ny: usize, rows: &[u64], r: &Resolved, left: bool, splits: &Splits, sc: &mut BitScratch) {
    let (split, knock) = (&splits.cells, &splits.knock);
    let w = shape.words;
    // Flight frame.
    for j in 0..ny {
        let (src, dst) = (&rows[j * w..(j + 1) * w], &mut sc.lf[j * w..(j + 1) * w]);
        if left {
            shape.reverse(src, dst);
        } else {
            dst.copy_from_slice(src);
        }
    }
    let cap = r.cap.min(shape.nx);
    if r.lateral == Lateral::Clusters {
        cluster_cells(shape, ny, sc);
    }
    for j in 0..ny {
        let key = sc.keys[j];
        let out = RowCells {
            o: &mut sc.o,
            side_cells: &mut sc.tmp,
            cells: &mut sc.cells,
        };
        obstacles(shape, (&sc.lf, &sc.clusters), (ny, j), r, (key, split), out);
        shape.not(&sc.o, &mut sc.free);
        let lrow = &sc.lf[j * w..(j + 1) * w];
        shape.rotate_down(&sc.free, 1, &mut sc.f1);
        // Flying grains: those drawn active (`cells` on the row's grains) with a free cell
        // ahead (a grain with an obstacle right ahead stays whether it flies or not).
        let act = &mut sc.active[..w];
        for ((a, &l), (&f, &c)) in act.iter_mut().zip(lrow).zip(sc.f1.iter().zip(&sc.cells)) {
            *a = l & f & c;
        }
        if r.hold > 0 {
            // Each occupied neighbouring cell holds the grain with the drawn probability.
            for d in 0..8 {
                neighbour_mask(shape, &sc.lf, j, ny, r.periodic_y, d, &mut sc.s2);
                for (x, &a) in sc.s2.iter_mut().zip(act.iter()) {
                    *x &= a;
                }
                rng::bernoulli_row(rng::neighbour_key(key, d), Stream::Frustration, &splits.hold, &sc.s2, &mut sc.pow);
                for ((a, &c), &h) in act.iter_mut().zip(&sc.s2).zip(&sc.pow) {
                    *a &= !(c & h);
                }
            }
        }
        // FL[a] = F[a+1] & ... & F[a+cap]. A run of nx free cells would include the grain
        // itself: with cap >= nx nobody flies the full cap.
        if cap >= shape.nx {
            sc.fl.iter_mut().for_each(|x| *x = 0);
        } else {
            shape.window_and(&sc.f1, cap, &mut sc.fl, &mut sc.ext);
        }
        // Run starts of the grains that stop on an obstacle: s2 = rot_up(A & !FL, 1) & F,
        // where `& F` holds already (every active grain has a free cell ahead).
        for ((x, &a), &fl) in sc.tmp.iter_mut().zip(act.iter()).zip(&sc.fl) {
            *x = a & !fl;
        }
        shape.rotate_up(&sc.tmp, 1, &mut sc.s2);
        shape.cyclic_add(&sc.free, &sc.s2, &mut sc.sum);
        let new = &mut sc.new[j * w..(j + 1) * w];
        // E (ends of the runs) in sum; landing just before them.
        for (x, &f) in sc.sum.iter_mut().zip(&sc.free) {
            *x &= !f;
        }
        if r.knock > 0 {
            // Draw only where something was hit (the draw is the same either way).
            rng::bernoulli_row(key, Stream::Knock, knock, &sc.sum, &mut sc.impacts[j * w..(j + 1) * w]);
        }
        shape.rotate_down(&sc.sum, 1, new);
        let mut full = 0;
        for ((n, x), ((&l, &a), &fl)) in new.iter_mut().zip(sc.tmp.iter_mut()).zip(lrow.iter().zip(act.iter()).zip(&sc.fl)) {
            // Grains that do not fly stay (active grains all have a free cell ahead).
            *n |= l & !a;
            *x = a & fl;
            full |= *x;
        }
        if cap < shape.nx && full != 0 {
            shape.rotate_up(&sc.tmp, cap, &mut sc.pow);
            for (n, &x) in new.iter_mut().zip(&sc.pow) {
                *n |= x;
            }
        }
    }
}

/// The row of the grain that stopped a flight in row `j` at cell `p`: row `j` itself, else
/// the lower, else the upper neighbour whose obstacle grain is there.
#[inline(always)]
fn hit_row(lf: &[u64], clusters: &[u64], w: usize, ny: usize, j: usize, p: usize, r: &Resolved) -> Option<usize> {
    if RowShape::get(&lf[j * w..], p) {
        return Some(j);
    }
    let side = match r.lateral {
        Lateral::None => return None,
        Lateral::Neighbours => lf,
        Lateral::Clusters => clusters,
    };
    [false, true]
        .into_iter()
        .filter_map(|up| neighbour_row(j, up, ny, r.periodic_y))
        .find(|&jn| RowShape::get(&side[jn * w..], p))
}

/// Knock-through: after the flights, the impact's momentum runs through the line of touching
/// grains that was hit (in the hit grain's row, in the new state, from the hit grain on) and
/// the far grain of that line flies on, up to the cap, until it touches a grain of its row.
/// Impacts are handled in row order and, within a row, in flight-frame order.
#[inline(always)]
fn knock_through(shape: &RowShape, ny: usize, r: &Resolved, cap: usize, sc: &mut BitScratch) {
    let w = shape.words;
    let nx = shape.nx;
    for j in 0..ny {
        for k in 0..w {
            let mut bits = sc.impacts[j * w + k];
            while bits != 0 {
                let p = 64 * k + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let Some(h) = hit_row(&sc.lf, &sc.clusters, w, ny, j, p, r) else {
                    continue;
                };
                let new = &mut sc.new[h * w..(h + 1) * w];
                if !RowShape::get(new, p) {
                    continue; // the hit grain has flown off itself
                }
                // Cells mod nx without a division (arguments below 2 nx).
                let wrap = |i: usize| if i >= nx { i - nx } else { i };
                // Far end of the line: the cell before the first empty one after p.
                let f = match shape.next(new, p, true) {
                    Some(e) => wrap(e + nx - 1),
                    None => wrap(p + nx - 1),
                };
                // It flies until the cell before the next grain of its row, at most `cap`.
                let ahead = shape.next(new, wrap(f + 1), false).expect("the far grain itself is set");
                let dist = wrap(ahead + nx - f);
                let dist = if dist == 0 { nx } else { dist };
                let land = wrap(f + (dist - 1).min(cap));
                if land != f {
                    RowShape::set(new, f, false);
                    RowShape::set(new, land, true);
                }
            }
        }
    }
}

/// First cell at or after `from` (cyclically) of a row of `W` words that is set (`flip =
/// 0`) or clear (`flip = !0`): [`RowShape::next`] on a fixed-width row.
#[inline(always)]
fn next_w<const W: usize>(row: &[u64; W], last: u64, from: usize, flip: u64) -> Option<usize> {
    let valid = |d: usize| if d + 1 == W { last } else { u64::MAX };
    let (w0, b0) = (from / 64, from % 64);
    let x = (row[w0] ^ flip) & valid(w0) & (u64::MAX << b0);
    if x != 0 {
        return Some(64 * w0 + x.trailing_zeros() as usize);
    }
    // The words after `from`'s, wrapping round, back to `from`'s word below `from`.
    for i in 1..=W {
        let d = if w0 + i >= W { w0 + i - W } else { w0 + i };
        let mut x = (row[d] ^ flip) & valid(d);
        if i == W {
            x &= (1u64 << b0) - 1;
        }
        if x != 0 {
            return Some(64 * d + x.trailing_zeros() as usize);
        }
    }
    None
}

/// [`knock_through`] for rows of `W` words (the same operations on fixed-width rows).
#[inline(always)]
fn knock_through_w<const W: usize>(shape: &RowShape, ny: usize, r: &Resolved, cap: usize, sc: &mut BitScratch) {
    let nx = shape.nx;
    let last = shape.last;
    let BitScratch {
        lf,
        clusters,
        new,
        impacts,
        ..
    } = sc;
    let get = |row: &[u64], i: usize| (row[i / 64] >> (i % 64)) & 1 == 1;
    let side: Option<&[u64]> = match r.lateral {
        Lateral::None => None,
        Lateral::Neighbours => Some(lf),
        Lateral::Clusters => Some(clusters),
    };
    // Cells mod nx without a division (arguments below 2 nx).
    let wrap = |i: usize| if i >= nx { i - nx } else { i };
    for j in 0..ny {
        let (below, above) = (neighbour_row(j, false, ny, r.periodic_y), neighbour_row(j, true, ny, r.periodic_y));
        for k in 0..W {
            let mut bits = impacts[j * W + k];
            while bits != 0 {
                let p = 64 * k + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                // The row of the hit grain, as in [`hit_row`].
                let h = if get(&lf[j * W..], p) {
                    j
                } else {
                    let Some(side) = side else { continue };
                    match (
                        below.filter(|&jn| get(&side[jn * W..], p)),
                        above.filter(|&jn| get(&side[jn * W..], p)),
                    ) {
                        (Some(jn), _) | (None, Some(jn)) => jn,
                        (None, None) => continue,
                    }
                };
                let row: &mut [u64; W] = (&mut new[h * W..(h + 1) * W]).try_into().expect("W words");
                if !get(row, p) {
                    continue; // the hit grain has flown off itself
                }
                // Far end of the line: the cell before the first empty one after p.
                let f = match next_w(row, last, p, u64::MAX) {
                    Some(e) => wrap(e + nx - 1),
                    None => wrap(p + nx - 1),
                };
                // It flies until the cell before the next grain of its row, at most `cap`.
                let ahead = next_w(row, last, wrap(f + 1), 0).expect("the far grain itself is set");
                let dist = wrap(ahead + nx - f);
                let dist = if dist == 0 { nx } else { dist };
                let land = wrap(f + (dist - 1).min(cap));
                if land != f {
                    row[f / 64] &= !(1u64 << (f % 64));
                    row[land / 64] |= 1u64 << (land % 64);
                }
            }
        }
    }
}

/// The sideways moves of a half step: [`sideways_draws`], then [`sideways`] towards +y and
/// towards -y.
fn sideways_moves_any(ny: usize, r: &Resolved, sc: &mut BitScratch) {
    let w = sc.zeros.len();
    sideways_draws(ny, w, r, sc);
    for up in [true, false] {
        sideways(ny, w, r, up, sc);
    }
}

/// [`sideways_moves_any`] for rows of `W` words, on fixed-width arrays.
#[inline(always)]
fn sideways_moves<const W: usize>(ny: usize, r: &Resolved, sc: &mut BitScratch) {
    let side = sc.splits(r).side;
    let BitScratch {
        new,
        side_up,
        side_down,
        keys,
        ..
    } = sc;
    // Draws, as in [`sideways_draws`].
    for j in 0..ny {
        let key = keys[j];
        let row = |jn: Option<usize>| jn.filter(|&jn| jn != j).map(|jn| load::<W>(new, jn));
        let (above, up_ok) = row(neighbour_row(j, true, ny, r.periodic_y)).map_or(([0; W], 0), |x| (x, u64::MAX));
        let (below, down_ok) = row(neighbour_row(j, false, ny, r.periodic_y)).map_or(([0; W], 0), |x| (x, u64::MAX));
        let here = load::<W>(new, j);
        let mut tried = [0u64; W];
        for k in 0..W {
            let t = (here[k] & !above[k] & up_ok) | ((here[k] ^ below[k]) & down_ok);
            tried[k] = if t != 0 { u64::MAX } else { 0 };
        }
        let mut moves = [0u64; W];
        rng::bernoulli_row(key, Stream::Side, &side, &tried, &mut moves);
        for k in 0..W {
            // The direction only matters where a grain moves.
            let dir = if moves[k] != 0 {
                rng::word(key, Stream::SideDirection, k, 0)
            } else {
                0
            };
            side_up[j * W + k] = moves[k] & dir;
            side_down[j * W + k] = moves[k] & !dir;
        }
    }
    // The two passes, as in [`sideways`].
    if ny < 2 {
        return;
    }
    for up in [true, false] {
        let (first, last) = if up { (0, ny - 1) } else { (ny - 1, 0) };
        let draws: &[u64] = if up { side_up } else { side_down };
        let first_row = load::<W>(new, first);
        let mut inc = [0u64; W];
        for step in 0..ny {
            let j = if up { step } else { ny - 1 - step };
            let (next, blocked) = match neighbour_row(j, up, ny, r.periodic_y) {
                Some(_) if j == last => (first_row, 0),
                Some(jn) => (load::<W>(new, jn), 0),
                None => ([0; W], u64::MAX),
            };
            let (here, d) = (load::<W>(new, j), load::<W>(draws, j));
            let mut out = [0u64; W];
            for k in 0..W {
                let m = here[k] & !(next[k] | blocked) & d[k];
                out[k] = (here[k] & !m) | inc[k];
                inc[k] = m;
            }
            new[j * W..(j + 1) * W].copy_from_slice(&out);
        }
        if r.periodic_y {
            for k in 0..W {
                new[first * W + k] |= inc[k];
            }
        }
    }
}

/// The sideways draws of every row ([`rng::sideways_draw`]): `side_up` (move towards +y) and
/// `side_down` (towards -y), drawn once for both passes and only in words where a move can
/// be tried (the draw is the same either way): towards +y from a grain below an empty cell,
/// towards -y (after the +y pass) from a cell where rows `j` and `j - 1` differ now (a grain
/// above an empty cell stays so unless it moves up, a grain below an empty cell may move up).
fn sideways_draws(ny: usize, w: usize, r: &Resolved, sc: &mut BitScratch) {
    let side = sc.splits(r).side;
    let none = &sc.zeros[..w];
    for j in 0..ny {
        let key = sc.keys[j];
        let row = |jn: Option<usize>| jn.filter(|&jn| jn != j).map(|jn| &sc.new[jn * w..][..w]);
        let (above, below) = (
            row(neighbour_row(j, true, ny, r.periodic_y)),
            row(neighbour_row(j, false, ny, r.periodic_y)),
        );
        // Without a row above no move up is tried; without a row below, none down.
        let (above, up_ok) = above.map_or((none, 0), |x| (x, u64::MAX));
        let (below, down_ok) = below.map_or((none, 0), |x| (x, u64::MAX));
        let here = &sc.new[j * w..][..w];
        for (t, ((&h, &a), &b)) in sc.tmp.iter_mut().zip(here.iter().zip(above).zip(below)) {
            let tried = (h & !a & up_ok) | ((h ^ b) & down_ok);
            *t = if tried != 0 { u64::MAX } else { 0 };
        }
        rng::bernoulli_row(key, Stream::Side, &side, &sc.tmp, &mut sc.pow);
        let (ups, downs) = (&mut sc.side_up[j * w..][..w], &mut sc.side_down[j * w..][..w]);
        for (k, ((u, d), &moves)) in ups.iter_mut().zip(downs.iter_mut()).zip(&sc.pow[..w]).enumerate() {
            // The direction only matters where a grain moves.
            let dir = if moves != 0 {
                rng::word(key, Stream::SideDirection, k, 0)
            } else {
                0
            };
            *u = moves & dir;
            *d = moves & !dir;
        }
    }
}

/// Simultaneous sideways moves towards +y (`up`) or -y into empty cells, in one pass over the
/// rows in the direction of the move: a row is read before any grain moves into it, so every
/// move sees the state before the pass.
fn sideways(ny: usize, w: usize, r: &Resolved, up: bool, sc: &mut BitScratch) {
    if ny < 2 {
        return; // no neighbour row, or (periodic) the row itself
    }
    let (first, last) = if up { (0, ny - 1) } else { (ny - 1, 0) };
    let draws = if up { &sc.side_up } else { &sc.side_down };
    // The row that receives from the last one (periodic) is changed first: keep its state.
    sc.tmp.copy_from_slice(&sc.new[first * w..][..w]);
    sc.pow.iter_mut().for_each(|x| *x = 0); // grains moving into the current row
    for step in 0..ny {
        let j = if up { step } else { ny - 1 - step };
        // The neighbour row as it was before the pass (the first row's copy for the last);
        // beyond a wall every cell counts as occupied.
        let (next, blocked): (&[u64], u64) = match neighbour_row(j, up, ny, r.periodic_y) {
            Some(_) if j == last => (&sc.tmp, 0),
            Some(jn) => (&sc.new[jn * w..][..w], 0),
            None => (&sc.zeros[..w], u64::MAX),
        };
        let (here, draws) = (&sc.new[j * w..][..w], &draws[j * w..][..w]);
        for (((m, &h), &n), &d) in sc.side_moving.iter_mut().zip(here).zip(next).zip(draws) {
            *m = h & !(n | blocked) & d;
        }
        let (row, inc) = (&mut sc.new[j * w..][..w], &mut sc.pow[..w]);
        for ((x, i), &m) in row.iter_mut().zip(inc.iter_mut()).zip(&sc.side_moving) {
            *x = (*x & !m) | *i;
            *i = m;
        }
    }
    if r.periodic_y {
        for k in 0..w {
            sc.new[first * w + k] |= sc.pow[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{Activation, FlightCap, Frustration, Knock, Params, Physical, RuleSet, Sideways, Threshold, YBoundary};

    /// The dispatched half step (on x86-64-v3 processors the copy compiled with their bit
    /// instructions) and the plain one give the same lattice.
    #[test]
    fn dispatched_and_plain_half_steps_agree() {
        for (nx, y) in [
            (50, YBoundary::Walls),
            (533, YBoundary::Walls),
            (533, YBoundary::Periodic),
            (1100, YBoundary::Walls),
        ] {
            let ny = 6;
            let shape = RowShape::new(nx);
            let mut z = nx as u64;
            let mut rows: Vec<u64> = (0..shape.words * ny)
                .map(|_| {
                    z = rng::mix(z);
                    z & rng::mix(z ^ 1)
                })
                .collect();
            for row in rows.chunks_exact_mut(shape.words) {
                shape.clean(row);
            }
            let params = Params {
                rule: RuleSet::Physical,
                physical: Physical {
                    threshold: Threshold::None,
                    cap: FlightCap::Cells { cells: 66 },
                    activation: Activation::Bernoulli { p: 0.8 },
                    knock: Knock::Bernoulli { p: 0.2 },
                    lateral: Lateral::Clusters,
                    sideways: Sideways::Bernoulli { p: 0.1 },
                    frustration: Frustration::Bernoulli { p: 0.3 },
                    trains: false,
                },
                y,
                seed: 3,
            };
            let r = params.resolve();
            let (mut a, mut b) = (rows.clone(), rows);
            let (mut sa, mut sb) = (BitScratch::new(shape, ny), BitScratch::new(shape, ny));
            for t in 0..30 {
                let tick = Tick {
                    seed: 7,
                    t,
                    left: t % 2 == 1,
                };
                half_step(&shape, ny, &mut a, &r, tick, &mut sa);
                half_step_body(&shape, ny, &mut b, &r, tick, &mut sb);
                assert_eq!(a, b, "{nx} cells, half step {t}");
            }
        }
    }
}
