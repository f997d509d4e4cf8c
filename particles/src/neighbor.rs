//! Candidate pairs for contact detection.

use crate::Vec3;

/// Neighbour search strategy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NeighborSearch {
    /// Every pair `i < j`: O(N^2), exact, the oracle for faster searches; right for a handful
    /// of particles (the collision lab).
    AllPairs,
}

impl NeighborSearch {
    /// Calls `visit(i, j)` for every candidate pair with `i < j`, in a fixed order.
    pub fn for_each_pair(&self, pos: &[Vec3], mut visit: impl FnMut(usize, usize)) {
        match self {
            NeighborSearch::AllPairs => {
                let n = pos.len();
                for i in 0..n {
                    for j in i + 1..n {
                        visit(i, j);
                    }
                }
            }
        }
    }
}
