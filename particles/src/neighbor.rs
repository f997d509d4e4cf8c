//! Neighbour search: which pairs can touch.
//!
//! Lists are *full*: every pair appears in the lists of both particles, so the force on a
//! particle can be gathered by that particle alone. That doubles the pair arithmetic but makes
//! the force loop trivially parallel, free of write conflicts, and bit-identical for any
//! number of threads. Pair kernels are exactly antisymmetric (IEEE negation and commutative
//! addition), so `F_ji = -F_ij` bit for bit.

use crate::boundary::Boundary;
use crate::Vec3;

/// Neighbour search strategy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NeighborSearch {
    /// Every other particle is a candidate: O(N^2), exact, the oracle for the Verlet list;
    /// right for a handful of particles (the collision lab).
    AllPairs,
    /// Verlet list with a `skin` (m) built from a grid of columns in x and y (the layer is
    /// thin, so z is not binned) and rebuilt when some particle has moved more than
    /// `skin / 2` since the last build.
    VerletList { skin: f64 },
}

/// Candidate partners of every particle in compressed-row form: the partners of `i` are
/// `partners[offsets[i]..offsets[i + 1]]`, in increasing index order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NeighborList {
    pub offsets: Vec<usize>,
    pub partners: Vec<u32>,
    /// The particle whose list holds each slot: `owner[s] = i` for `s` in
    /// `offsets[i]..offsets[i + 1]`, so a loop can run over slots without nesting.
    pub owner: Vec<u32>,
    /// Positions at the last build, for the displacement criterion.
    anchor: Vec<Vec3>,
    /// Number of builds so far.
    pub builds: u64,
    // Scratch of the cell grid, kept to avoid allocation per build.
    cell_start: Vec<usize>,
    cell_items: Vec<u32>,
}

impl NeighborList {
    /// Partners of particle `i`.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.partners[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Positions at the last build.
    pub fn anchor(&self) -> &[Vec3] {
        &self.anchor
    }

    /// Square of the displacement since the last build beyond which a rebuild is due, or
    /// `None` when displacements do not matter (all pairs).
    pub fn rebuild_distance2(search: &NeighborSearch) -> Option<f64> {
        match *search {
            NeighborSearch::AllPairs => None,
            NeighborSearch::VerletList { skin } => Some(0.25 * skin * skin),
        }
    }

    /// True if the list must be rebuilt before it can be trusted for `pos`.
    pub fn needs_rebuild(&self, search: &NeighborSearch, pos: &[Vec3], boundary: &Boundary) -> bool {
        match *search {
            NeighborSearch::AllPairs => self.offsets.len() != pos.len() + 1,
            NeighborSearch::VerletList { skin } => {
                if self.anchor.len() != pos.len() {
                    return true;
                }
                let limit = 0.25 * skin * skin;
                pos.iter()
                    .zip(&self.anchor)
                    .any(|(x, a)| boundary.min_image(x - a).norm_squared() > limit)
            }
        }
    }

    /// Builds the lists for `pos` with radii `radius`.
    pub fn build(&mut self, search: &NeighborSearch, pos: &[Vec3], radius: &[f64], boundary: &Boundary) {
        let n = pos.len();
        self.offsets.clear();
        self.partners.clear();
        self.offsets.push(0);
        match *search {
            NeighborSearch::AllPairs => {
                for i in 0..n {
                    self.partners.extend((0..n as u32).filter(|&j| j as usize != i));
                    self.offsets.push(self.partners.len());
                }
            }
            NeighborSearch::VerletList { skin } => self.build_cells(skin, pos, radius, boundary),
        }
        self.owner.clear();
        for i in 0..n {
            self.owner.resize(self.offsets[i + 1], i as u32);
        }
        self.anchor.clear();
        self.anchor.extend_from_slice(pos);
        self.builds += 1;
    }

    fn build_cells(&mut self, skin: f64, pos: &[Vec3], radius: &[f64], boundary: &Boundary) {
        let n = pos.len();
        if n == 0 {
            return;
        }
        let r_max = radius.iter().cloned().fold(0.0, f64::max);
        let reach = 2.0 * r_max + skin;
        // Grid over the bounding box in x and y (or the periodic length).
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
        for k in 0..2 {
            let (origin, length) = match boundary.periodic[k] {
                Some(l) => (0.0, l),
                None => (lo[k], (hi[k] - lo[k]).max(reach)),
            };
            lo[k] = origin;
            dims[k] = ((length / reach).floor() as usize).clamp(1, 1 << 20);
            size[k] = length / dims[k] as f64;
        }
        let cell_of = |x: &Vec3| -> [usize; 2] {
            let mut c = [0usize; 2];
            for k in 0..2 {
                c[k] = (((x[k] - lo[k]) / size[k]).floor().max(0.0) as usize).min(dims[k] - 1);
            }
            c
        };
        let n_cells = dims[0] * dims[1];
        // Counting sort of particles into cells (stable: increasing index within a cell).
        self.cell_start.clear();
        self.cell_start.resize(n_cells + 1, 0);
        for x in pos {
            let c = cell_of(x);
            self.cell_start[c[1] * dims[0] + c[0] + 1] += 1;
        }
        for c in 0..n_cells {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        self.cell_items.clear();
        self.cell_items.resize(n, 0);
        let mut fill = self.cell_start.clone();
        for (i, x) in pos.iter().enumerate() {
            let c = cell_of(x);
            let slot = &mut fill[c[1] * dims[0] + c[0]];
            self.cell_items[*slot] = i as u32;
            *slot += 1;
        }
        // Neighbouring cells along each axis: distinct indices only (a periodic axis with
        // fewer than three cells must not visit a cell twice).
        let axis_cells = |k: usize, c: usize| -> Vec<usize> {
            let mut v: Vec<usize> = Vec::with_capacity(3);
            for d in [-1i64, 0, 1] {
                let j = c as i64 + d;
                let j = if boundary.periodic[k].is_some() {
                    j.rem_euclid(dims[k] as i64)
                } else if j < 0 || j >= dims[k] as i64 {
                    continue;
                } else {
                    j
                } as usize;
                if !v.contains(&j) {
                    v.push(j);
                }
            }
            v
        };
        let mut found: Vec<u32> = Vec::new();
        for (i, xi) in pos.iter().enumerate() {
            let c = cell_of(xi);
            found.clear();
            for cy in axis_cells(1, c[1]) {
                for cx in axis_cells(0, c[0]) {
                    let cell = cy * dims[0] + cx;
                    for &j in &self.cell_items[self.cell_start[cell]..self.cell_start[cell + 1]] {
                        if j as usize == i {
                            continue;
                        }
                        let cut = radius[i] + radius[j as usize] + skin;
                        if boundary.min_image(xi - pos[j as usize]).norm_squared() < cut * cut {
                            found.push(j);
                        }
                    }
                }
            }
            found.sort_unstable();
            self.partners.extend_from_slice(&found);
            self.offsets.push(self.partners.len());
        }
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

    /// Pairs within `R_i + R_j + skin` by brute force.
    fn brute(pos: &[Vec3], radius: &[f64], b: &Boundary, skin: f64) -> Vec<Vec<u32>> {
        (0..pos.len())
            .map(|i| {
                (0..pos.len() as u32)
                    .filter(|&j| {
                        let cut = radius[i] + radius[j as usize] + skin;
                        j as usize != i && b.min_image(pos[i] - pos[j as usize]).norm_squared() < cut * cut
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn verlet_list_agrees_with_all_pairs() {
        for (periodic_y, lx, ly) in [(false, 0.02, 0.01), (true, 0.02, 0.01), (true, 0.0025, 0.0015)] {
            let b = Boundary {
                periodic: [Some(lx), if periodic_y { Some(ly) } else { None }, None],
            };
            let (pos, radius) = layout(400, lx, ly, 7);
            let search = NeighborSearch::VerletList { skin: 1e-4 };
            let mut list = NeighborList::default();
            list.build(&search, &pos, &radius, &b);
            let expect = brute(&pos, &radius, &b, 1e-4);
            for (i, e) in expect.iter().enumerate() {
                assert_eq!(list.of(i), e.as_slice(), "particle {i}, box {lx} x {ly}");
                let owners = &list.owner[list.offsets[i]..list.offsets[i + 1]];
                assert!(owners.iter().all(|&o| o as usize == i), "owner of particle {i}'s slots");
            }
            assert_eq!(list.owner.len(), list.partners.len());
        }
    }

    #[test]
    fn rebuild_triggers_after_half_skin() {
        let b = Boundary::open();
        let (mut pos, radius) = layout(10, 0.01, 0.01, 3);
        let search = NeighborSearch::VerletList { skin: 1e-4 };
        let mut list = NeighborList::default();
        list.build(&search, &pos, &radius, &b);
        pos[3].x += 0.49e-4;
        assert!(!list.needs_rebuild(&search, &pos, &b));
        pos[3].x += 0.02e-4;
        assert!(list.needs_rebuild(&search, &pos, &b));
    }
}
