//! Neighbour search: which pairs can touch.
//!
//! Lists are *half* lists: every pair `(i, j)` appears once, in the list of its smaller index
//! `i`, so that the force pass evaluates each contact once. The list also says, for every
//! particle, which slots hold it as the partner (`incoming`, in increasing owner order): the
//! force pass adds those pairs' reactions to it after every slot has been evaluated, each
//! particle in an order fixed by the list alone, so the forces are bit-identical for any
//! number of threads.

use crate::boundary::Boundary;
use crate::parallel::on_blocks;
use crate::Vec3;

/// Neighbour search strategy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NeighborSearch {
    /// Every other particle is a candidate: O(N^2), exact, the oracle for the Verlet list;
    /// right for a handful of particles (the collision lab).
    AllPairs,
    /// Verlet list built from a grid of columns in x and y (the layer is thin, so z is not
    /// binned) with a skin between `skin` and `max_skin` (m), rebuilt when some particle has
    /// moved more than half the skin since the last build.
    ///
    /// The skin adapts at each rebuild (see [`NeighborList::build_after`]): a layer at rest
    /// keeps the smallest, which has the fewest candidate pairs; a gas, whose lists expire
    /// within a few steps, grows it until a list lasts about [`TARGET_LIFETIME`] steps. The
    /// skin never changes a result: every contact is in the list whatever the skin, and each
    /// particle sums its contacts in partner order.
    VerletList { skin: f64, max_skin: f64 },
}

impl NeighborSearch {
    /// A Verlet list with the fixed skin `skin` (m).
    pub fn verlet(skin: f64) -> Self {
        NeighborSearch::VerletList { skin, max_skin: skin }
    }
}

/// Steps a Verlet list should last when the layer moves (see [`NeighborSearch::VerletList`]).
/// On the thesis tray's gas (`stripes run` resumed at 6 s, 625 steps, callgrind) fixed skins
/// of 0.2, 0.5, 1 and 2 R_max gave lists lasting 3, 6.6, 12.5 and 24 steps and 1.28, 0.90,
/// 0.79 and 0.85 G instructions; the same layer at rest pays 48% more per step at 1 R_max
/// than at 0.2 R_max. Timed rather than counted, 24 steps is faster: the same gas (12500
/// steps from 6 s) ran at 3.92e7 particle-steps/s against 3.68e7 with 12 (one thread; 4.9e7
/// against 4.8e7 on two), and the uncapped floor's gas at 20 Hz / 25 mm at 3.70e7 against
/// 3.32e7 (4000 grains) and 3.87e7 against 3.62e7 (400); 18 and 32 steps were between.
/// A build costs several steps' worth of work; the larger skin costs less than half the
/// builds it saves. Lists of a layer at rest or rolling last longer than either target and
/// keep the smallest skin, so those runs are unchanged (the stripe scene: 334 builds in 1 s
/// either way).
pub const TARGET_LIFETIME: f64 = 24.0;

/// Candidate pairs in compressed-row form, each pair once: the partners of `i` are the
/// larger indices `partners[offsets[i]..offsets[i + 1]]`, in increasing order (a *slot* is an
/// index into `partners`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NeighborList {
    pub offsets: Vec<usize>,
    pub partners: Vec<u32>,
    /// The particle whose list holds each slot: `owner[s] = i` for `s` in
    /// `offsets[i]..offsets[i + 1]`, so a loop can run over slots without nesting.
    pub owner: Vec<u32>,
    /// The slots whose partner is `j` are `incoming[incoming_offsets[j]..incoming_offsets[j + 1]]`,
    /// in increasing owner order (the pairs `(i, j)` with `i < j`).
    pub incoming_offsets: Vec<usize>,
    pub incoming: Vec<u32>,
    /// Positions at the last build, for the displacement criterion.
    anchor: Vec<Vec3>,
    /// Skin (m) of the last build.
    pub skin: f64,
    /// Number of builds so far.
    pub builds: u64,
    /// Particles per rigid body (`0` or `1`: none): the runs `b * body_size..(b + 1) *
    /// body_size` are clumps, whose members are never a pair of the list.
    pub body_size: u32,
    // Scratch of the cell grid, kept to avoid allocation per build.
    cell_of: Vec<u32>,
    cell_start: Vec<usize>,
    cell_fill: Vec<usize>,
    cell_items: Vec<u32>,
}

impl NeighborList {
    /// Partners of particle `i`: the candidates with a larger index.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.partners[self.offsets[i]..self.offsets[i + 1]]
    }

    /// The slots that hold particle `j` as the partner, in increasing owner order.
    #[inline]
    pub fn incoming_of(&self, j: usize) -> &[u32] {
        &self.incoming[self.incoming_offsets[j]..self.incoming_offsets[j + 1]]
    }

    /// The slot of the pair `(i, j)`, `i < j`, if it is in the list.
    pub fn slot(&self, i: usize, j: usize) -> Option<usize> {
        self.of(i).binary_search(&(j as u32)).ok().map(|k| self.offsets[i] + k)
    }

    /// Positions at the last build.
    pub fn anchor(&self) -> &[Vec3] {
        &self.anchor
    }

    /// Square of the displacement since the last build beyond which a rebuild is due, or
    /// `None` when displacements do not matter (all pairs).
    pub fn rebuild_distance2(&self, search: &NeighborSearch) -> Option<f64> {
        match *search {
            NeighborSearch::AllPairs => None,
            NeighborSearch::VerletList { .. } => Some(0.25 * self.skin * self.skin),
        }
    }

    /// True if the list must be rebuilt before it can be trusted for `pos`.
    pub fn needs_rebuild(&self, search: &NeighborSearch, pos: &[Vec3], boundary: &Boundary) -> bool {
        match *search {
            NeighborSearch::AllPairs => self.offsets.len() != pos.len() + 1,
            NeighborSearch::VerletList { .. } => {
                if self.anchor.len() != pos.len() {
                    return true;
                }
                let limit = self.rebuild_distance2(search).unwrap_or(0.0);
                pos.iter()
                    .zip(&self.anchor)
                    .any(|(x, a)| boundary.min_image(x - a).norm_squared() > limit)
            }
        }
    }

    /// Builds the lists for `pos` with radii `radius`, with the smallest skin.
    pub fn build(&mut self, search: &NeighborSearch, pos: &[Vec3], radius: &[f64], boundary: &Boundary) {
        self.build_after(search, None, pos, radius, boundary);
    }

    /// Builds the lists for `pos` with radii `radius`, the previous lists having lasted
    /// `lasted` steps (`None`: no previous lists to learn from). A Verlet list takes the skin
    /// `s' = s sqrt(TARGET_LIFETIME / lasted)`, kept within `[skin, max_skin]`: a list
    /// lasts about `s / (2 v)` steps for a relative drift `v` per step, so `s'` moves the
    /// lifetime halfway (geometrically) to [`TARGET_LIFETIME`] without overshooting.
    pub fn build_after(&mut self, search: &NeighborSearch, lasted: Option<u64>, pos: &[Vec3], radius: &[f64], boundary: &Boundary) {
        let n = pos.len();
        self.offsets.clear();
        self.partners.clear();
        self.offsets.push(0);
        match *search {
            NeighborSearch::AllPairs => {
                for i in 0..n {
                    self.partners.extend(i as u32 + 1..n as u32);
                    self.offsets.push(self.partners.len());
                }
            }
            NeighborSearch::VerletList { skin, max_skin } => {
                self.skin = match lasted {
                    Some(k) if self.skin > 0.0 => (self.skin * (TARGET_LIFETIME / k.max(1) as f64).sqrt()).clamp(skin, max_skin.max(skin)),
                    _ => skin,
                };
                self.build_cells(self.skin, pos, radius, boundary)
            }
        }
        if self.body_size > 1 {
            self.drop_pairs_within_bodies();
        }
        self.owner.clear();
        for i in 0..n {
            self.owner.resize(self.offsets[i + 1], i as u32);
        }
        // The slots by partner: a stable counting sort keeps the owners increasing.
        let (mut start, mut fill) = (std::mem::take(&mut self.incoming_offsets), std::mem::take(&mut self.cell_fill));
        counting_sort(&self.partners, n, &mut start, &mut fill, &mut self.incoming);
        (self.incoming_offsets, self.cell_fill) = (start, fill);
        self.anchor.clear();
        self.anchor.extend_from_slice(pos);
        self.builds += 1;
    }

    /// Removes the pairs of members of one body (`body_size`) from the lists.
    fn drop_pairs_within_bodies(&mut self) {
        let size = self.body_size;
        let mut kept = 0;
        let mut start = 0;
        for i in 0..self.offsets.len() - 1 {
            let end = self.offsets[i + 1];
            for s in start..end {
                let j = self.partners[s];
                if j / size != i as u32 / size {
                    self.partners[kept] = j;
                    kept += 1;
                }
            }
            start = end;
            self.offsets[i + 1] = kept;
        }
        self.partners.truncate(kept);
    }

    /// The particles in the order of the cells of the grid of the smallest skin, column by
    /// column along x and, within a column, row by row along y (stable: increasing index
    /// within a cell): `order[k]` is the particle that goes to place `k`. Grains close in
    /// space then get close indices, so a block of particles and its partners share cache
    /// lines, and two threads' runs of blocks meet only at their ends. Serial and a function
    /// of the positions and radii alone (not of the adapted skin), so the same on any number
    /// of threads and in a run resumed from a checkpoint. `None` without a grid (all pairs).
    pub fn cell_order(search: &NeighborSearch, pos: &[Vec3], radius: &[f64], boundary: &Boundary) -> Option<Vec<u32>> {
        let NeighborSearch::VerletList { skin, .. } = *search else {
            return None;
        };
        if pos.is_empty() {
            return Some(Vec::new());
        }
        let grid = Grid::new(skin, pos, radius, boundary);
        let (columns, rows) = (grid.dims[0], grid.dims[1]);
        let key = |x: &Vec3| {
            let c = grid.cell(x) as usize;
            ((c % columns) * rows + c / columns) as u32
        };
        let keys: Vec<u32> = pos.iter().map(key).collect();
        let (mut start, mut fill, mut order) = (Vec::new(), Vec::new(), Vec::new());
        counting_sort(&keys, columns * rows, &mut start, &mut fill, &mut order);
        Some(order)
    }

    fn build_cells(&mut self, skin: f64, pos: &[Vec3], radius: &[f64], boundary: &Boundary) {
        let n = pos.len();
        if n == 0 {
            return;
        }
        let grid = Grid::new(skin, pos, radius, boundary);
        // Particles sorted into cells (stable: increasing index within a cell).
        self.cell_of.clear();
        self.cell_of.extend(pos.iter().map(|x| grid.cell(x)));
        counting_sort(
            &self.cell_of,
            grid.dims[0] * grid.dims[1],
            &mut self.cell_start,
            &mut self.cell_fill,
            &mut self.cell_items,
        );
        // Each particle's candidates of larger index from its 3 x 3 cells (fewer on a short
        // or walled axis), in fixed chunks of particles, possibly in parallel: the lists do not
        // depend on the chunking or the number of threads.
        let (cells, starts, items) = (&self.cell_of, &self.cell_start, &self.cell_items);
        let chunks: Vec<std::ops::Range<usize>> = (0..n.div_ceil(BUILD_CHUNK))
            .map(|c| c * BUILD_CHUNK..((c + 1) * BUILD_CHUNK).min(n))
            .collect();
        let lists = on_blocks(chunks, |range| {
            let mut partners: Vec<u32> = Vec::with_capacity(8 * range.len());
            let mut ends: Vec<u32> = Vec::with_capacity(range.len());
            for i in range {
                let (xi, ri, c) = (pos[i], radius[i], cells[i] as usize);
                let first = partners.len();
                let (cx, cy) = (c % grid.dims[0], c / grid.dims[0]);
                let mut scan = |cells: std::ops::Range<usize>| {
                    for &j in &items[starts[cells.start]..starts[cells.end]] {
                        let cut = ri + radius[j as usize] + skin;
                        if j as usize > i && boundary.min_image(xi - pos[j as usize]).norm_squared() < cut * cut {
                            partners.push(j);
                        }
                    }
                };
                // Three neighbouring columns of a row are consecutive cells, whose grains are
                // consecutive in `items`: one loop instead of three (a loop of zero to three
                // grains mispredicts its exit, and a build visits nine cells per grain). At a
                // periodic seam or a short axis, cell by cell.
                let (columns, inner) = (grid.cols[cx].as_slice(), cx > 0 && cx + 1 < grid.dims[0]);
                for &row in grid.rows[cy].as_slice() {
                    let base = row as usize * grid.dims[0];
                    if inner {
                        scan(base + cx - 1..base + cx + 2);
                    } else {
                        for &col in columns {
                            scan(base + col as usize..base + col as usize + 1);
                        }
                    }
                }
                partners[first..].sort_unstable();
                ends.push(partners.len() as u32);
            }
            (partners, ends)
        });
        for (partners, ends) in lists {
            let base = self.partners.len();
            self.partners.extend_from_slice(&partners);
            self.offsets.extend(ends.iter().map(|&e| base + e as usize));
        }
    }
}

/// Particles per chunk of the list build.
const BUILD_CHUNK: usize = 512;

/// Up to three distinct cell indices along one axis.
#[derive(Clone, Copy, Debug)]
struct Stencil {
    cells: [u32; 3],
    len: u8,
}

impl Stencil {
    fn as_slice(&self) -> &[u32] {
        &self.cells[..self.len as usize]
    }
}

/// The grid of columns in x and y (z is not binned) of one build: cells at least
/// `2 R_max + skin` wide, over the bounding box or the periodic length, and each row's and
/// column's neighbouring indices.
struct Grid {
    lo: [f64; 2],
    size: [f64; 2],
    dims: [usize; 2],
    /// Neighbouring rows of each row, neighbouring columns of each column: distinct indices
    /// only (a periodic axis with fewer than three cells must not visit a cell twice).
    rows: Vec<Stencil>,
    cols: Vec<Stencil>,
}

impl Grid {
    fn new(skin: f64, pos: &[Vec3], radius: &[f64], boundary: &Boundary) -> Self {
        let r_max = radius.iter().cloned().fold(0.0, f64::max);
        let reach = 2.0 * r_max + skin;
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for x in pos {
            for k in 0..2 {
                lo[k] = lo[k].min(x[k]);
                hi[k] = hi[k].max(x[k]);
            }
        }
        let mut dims = [1usize; 2];
        let mut size = [1.0f64; 2];
        let mut extent = [1.0f64; 2];
        for k in 0..2 {
            let (origin, length) = match boundary.periodic[k] {
                Some(l) => (0.0, l),
                None => (lo[k], (hi[k] - lo[k]).max(reach)),
            };
            lo[k] = origin;
            extent[k] = length;
            dims[k] = ((length / reach).floor() as usize).clamp(1, 1 << 20);
        }
        // A dilute layer on a huge tray would ask for far more cells than grains (a 1000 m
        // square tray: 7e11 cells). Cells are coarsened, never refined, until there are at
        // most 8 per grain: every pair within reach is still found, and a tray of the
        // scenes' sizes (a few cells per grain) is untouched.
        let cap = 8 * pos.len() + 4096;
        while dims[0] * dims[1] > cap {
            let k = if dims[0] >= dims[1] { 0 } else { 1 };
            dims[k] = dims[k].div_ceil(2);
        }
        for k in 0..2 {
            size[k] = extent[k] / dims[k] as f64;
        }
        let stencil = |k: usize, c: usize| {
            let mut s = Stencil { cells: [0; 3], len: 0 };
            for d in [-1i64, 0, 1] {
                let j = c as i64 + d;
                let j = if boundary.periodic[k].is_some() {
                    j.rem_euclid(dims[k] as i64)
                } else if j < 0 || j >= dims[k] as i64 {
                    continue;
                } else {
                    j
                } as u32;
                if !s.as_slice().contains(&j) {
                    s.cells[s.len as usize] = j;
                    s.len += 1;
                }
            }
            s
        };
        Self {
            lo,
            size,
            dims,
            rows: (0..dims[1]).map(|c| stencil(1, c)).collect(),
            cols: (0..dims[0]).map(|c| stencil(0, c)).collect(),
        }
    }

    /// Index `row * dims[0] + column` of the cell holding `x` (clamped to the grid).
    #[inline]
    fn cell(&self, x: &Vec3) -> u32 {
        let mut c = [0usize; 2];
        for k in 0..2 {
            c[k] = (((x[k] - self.lo[k]) / self.size[k]).floor().max(0.0) as usize).min(self.dims[k] - 1);
        }
        (c[1] * self.dims[0] + c[0]) as u32
    }
}

/// Stable counting sort of the indices `0..keys.len()` by their key (each below `buckets`):
/// `items` lists the indices key by key, increasing within one key, and the indices of key
/// `k` are `items[start[k]..start[k + 1]]`. `fill` is scratch.
fn counting_sort(keys: &[u32], buckets: usize, start: &mut Vec<usize>, fill: &mut Vec<usize>, items: &mut Vec<u32>) {
    start.clear();
    start.resize(buckets + 1, 0);
    for &k in keys {
        start[k as usize + 1] += 1;
    }
    for c in 0..buckets {
        start[c + 1] += start[c];
    }
    items.clear();
    items.resize(keys.len(), 0);
    fill.clear();
    fill.extend_from_slice(start);
    for (i, &k) in keys.iter().enumerate() {
        let slot = &mut fill[k as usize];
        items[*slot] = i as u32;
        *slot += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random numbers in [0, 1) for test layouts.
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    fn layout(n: usize, lx: f64, ly: f64, seed: u64) -> (Vec<Vec3>, Vec<f64>) {
        let mut s = seed;
        let pos = (0..n)
            .map(|_| Vec3::new(lx * lcg(&mut s), ly * lcg(&mut s), 3e-4 + 1e-3 * lcg(&mut s)))
            .collect();
        let radius = (0..n).map(|_| 2.5e-4 + 2.5e-4 * lcg(&mut s)).collect();
        (pos, radius)
    }

    /// Pairs within `R_i + R_j + skin` by brute force: each particle's partners of larger
    /// index.
    fn brute(pos: &[Vec3], radius: &[f64], b: &Boundary, skin: f64) -> Vec<Vec<u32>> {
        (0..pos.len())
            .map(|i| {
                (i as u32 + 1..pos.len() as u32)
                    .filter(|&j| {
                        let cut = radius[i] + radius[j as usize] + skin;
                        b.min_image(pos[i] - pos[j as usize]).norm_squared() < cut * cut
                    })
                    .collect()
            })
            .collect()
    }

    /// Each slot is found once among the incoming slots of its partner, those of each
    /// particle in increasing owner order.
    fn assert_incoming_is_the_transpose(list: &NeighborList, n: usize) {
        let mut seen = vec![0u32; list.partners.len()];
        for j in 0..n {
            let owners: Vec<u32> = list.incoming_of(j).iter().map(|&s| list.owner[s as usize]).collect();
            assert!(
                owners.windows(2).all(|w| w[0] < w[1]),
                "owners of particle {j}'s incoming slots: {owners:?}"
            );
            for &s in list.incoming_of(j) {
                assert_eq!(list.partners[s as usize] as usize, j);
                seen[s as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }

    #[test]
    fn all_pairs_hold_each_pair_once() {
        let (pos, radius) = layout(7, 0.01, 0.01, 5);
        let mut list = NeighborList::default();
        list.build(&NeighborSearch::AllPairs, &pos, &radius, &Boundary::open());
        assert_eq!(list.partners.len(), 7 * 6 / 2);
        for i in 0..7 {
            assert_eq!(list.of(i), (i as u32 + 1..7).collect::<Vec<_>>().as_slice());
        }
        assert_incoming_is_the_transpose(&list, 7);
    }

    #[test]
    fn verlet_list_agrees_with_all_pairs() {
        for (periodic_y, lx, ly) in [(false, 0.02, 0.01), (true, 0.02, 0.01), (true, 0.0025, 0.0015)] {
            let b = Boundary {
                periodic: [Some(lx), if periodic_y { Some(ly) } else { None }, None],
            };
            let (pos, radius) = layout(400, lx, ly, 7);
            let search = NeighborSearch::verlet(1e-4);
            let mut list = NeighborList::default();
            list.build(&search, &pos, &radius, &b);
            let expect = brute(&pos, &radius, &b, 1e-4);
            for (i, e) in expect.iter().enumerate() {
                assert_eq!(list.of(i), e.as_slice(), "particle {i}, box {lx} x {ly}");
                let owners = &list.owner[list.offsets[i]..list.offsets[i + 1]];
                assert!(owners.iter().all(|&o| o as usize == i), "owner of particle {i}'s slots");
            }
            assert_eq!(list.owner.len(), list.partners.len());
            assert_incoming_is_the_transpose(&list, pos.len());
            assert!(list.partners.len() > pos.len(), "{} pairs", list.partners.len());
        }
    }

    #[test]
    fn rebuild_triggers_after_half_skin() {
        let b = Boundary::open();
        let (mut pos, radius) = layout(10, 0.01, 0.01, 3);
        let search = NeighborSearch::verlet(1e-4);
        let mut list = NeighborList::default();
        list.build(&search, &pos, &radius, &b);
        pos[3].x += 0.49e-4;
        assert!(!list.needs_rebuild(&search, &pos, &b));
        pos[3].x += 0.02e-4;
        assert!(list.needs_rebuild(&search, &pos, &b));
    }

    #[test]
    fn adapted_skin_follows_the_list_lifetime_within_its_bounds_and_lists_stay_exact() {
        let b = Boundary {
            periodic: [Some(0.02), None, None],
        };
        let (pos, radius) = layout(400, 0.02, 0.01, 11);
        let search = NeighborSearch::VerletList {
            skin: 1e-4,
            max_skin: 1e-3,
        };
        let mut list = NeighborList::default();
        list.build(&search, &pos, &radius, &b);
        assert_eq!(list.skin, 1e-4);
        // Lists that lasted a quarter of the target: the skin grows by sqrt(4) = 2, up to the
        // bound.
        let quarter = (TARGET_LIFETIME / 4.0) as u64;
        assert_eq!(quarter as f64 * 4.0, TARGET_LIFETIME);
        for expect in [2e-4, 4e-4, 8e-4, 1e-3] {
            list.build_after(&search, Some(quarter), &pos, &radius, &b);
            assert!((list.skin - expect).abs() < 1e-15, "skin {} against {expect}", list.skin);
            let brute = brute(&pos, &radius, &b, list.skin);
            for (i, e) in brute.iter().enumerate() {
                assert_eq!(list.of(i), e.as_slice(), "particle {i} at skin {}", list.skin);
            }
            assert_incoming_is_the_transpose(&list, pos.len());
        }
        // A list that lasted 100 times the target (a layer at rest): the skin shrinks tenfold,
        // back to the smallest.
        list.build_after(&search, Some((100.0 * TARGET_LIFETIME) as u64), &pos, &radius, &b);
        assert_eq!(list.skin, 1e-4);
        // A fixed skin never moves.
        let fixed = NeighborSearch::verlet(1e-4);
        list.build_after(&fixed, Some(1), &pos, &radius, &b);
        assert_eq!(list.skin, 1e-4);
    }
}
