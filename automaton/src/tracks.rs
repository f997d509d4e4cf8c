//! Grains followed one by one through the `measured` rule's moves
//! ([`crate::Automaton::measured_moves`]): which cell each grain holds and how far it has
//! gone along x (unwrapped, in cells). The lattice itself stores heights only, so a state
//! written grain by grain in the lattice's scan order renumbers the grains whenever a row's
//! count changes; written in this order instead, grain `k` is the same grain in every frame
//! and a mean square displacement measured on the frames is the grains' own.

use crate::lattice::Lattice;
use crate::measured_rule::GrainMove;

const EMPTY: u32 = u32::MAX;

/// Every grain of a submonolayer, by the index it was given at the start (scan order).
#[derive(Clone, Debug)]
pub struct Tracks {
    nx: usize,
    /// Grain in each cell `j * nx + i`, or [`EMPTY`].
    id: Vec<u32>,
    /// `(row, column)` of each grain.
    cell: Vec<(usize, usize)>,
    /// Column of each grain counted without wrapping (start column plus every move's `dx`).
    x: Vec<i64>,
    taken: Vec<u32>,
}

impl Tracks {
    /// The grains of `l`, numbered in scan order (row by row, along x); None when a cell
    /// holds more than one grain (a pile's grains cannot be told apart).
    pub fn new(l: &Lattice) -> Option<Self> {
        let (nx, ny) = (l.nx, l.ny);
        let mut id = vec![EMPTY; nx * ny];
        let (mut cell, mut x) = (Vec::new(), Vec::new());
        for j in 0..ny {
            for i in 0..nx {
                match l.height(i, j) {
                    0 => {}
                    1 => {
                        id[j * nx + i] = cell.len() as u32;
                        cell.push((j, i));
                        x.push(i as i64);
                    }
                    _ => return None,
                }
            }
        }
        Some(Self {
            nx,
            id,
            cell,
            x,
            taken: Vec::new(),
        })
    }

    /// Moves the grains of one half step's `moves` (every grain that changed cell, each
    /// from a distinct cell to a distinct cell that is empty once all have left).
    pub fn apply(&mut self, moves: &[GrainMove]) {
        let nx = self.nx;
        self.taken.clear();
        for m in moves {
            let c = m.from.0 * nx + m.from.1;
            let g = std::mem::replace(&mut self.id[c], EMPTY);
            assert!(g != EMPTY, "a move from the empty cell {:?}", m.from);
            self.taken.push(g);
        }
        for (m, &g) in moves.iter().zip(&self.taken) {
            let c = m.to.0 * nx + m.to.1;
            assert!(self.id[c] == EMPTY, "a move onto the taken cell {:?}", m.to);
            self.id[c] = g;
            self.cell[g as usize] = m.to;
            self.x[g as usize] += m.dx;
        }
    }

    /// `(row, column)` of each grain.
    pub fn cells(&self) -> &[(usize, usize)] {
        &self.cell
    }

    /// Each grain's column counted without wrapping.
    pub fn unwrapped_x(&self) -> &[i64] {
        &self.x
    }

    /// Whether the followed grains are exactly the grains of `l`.
    pub fn matches(&self, l: &Lattice) -> bool {
        (0..l.ny).all(|j| (0..l.nx).all(|i| (l.height(i, j) as u32) == (self.id[j * self.nx + i] != EMPTY) as u32))
    }
}
