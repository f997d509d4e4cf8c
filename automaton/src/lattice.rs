//! The top-view lattice: cell `(i, j)` with `i` along the shaking direction x (periodic) and
//! `j` across (y), holding an integer pile height (grains stacked in that cell).
//!
//! Two storages hold the same information:
//! - [`Storage::Bits`]: a submonolayer (every height 0 or 1) with rows of at most
//!   [`crate::step::MAX_WORDS`] words (1024 cells), one bit per cell, 64 cells per `u64`
//!   word, row by row; the fast, bit-parallel update works on it ([`crate::step`]);
//! - [`Storage::Heights`]: one byte per cell, any height up to 255; the general update
//!   ([`crate::scalar`]) works on it, including the multilayer resting rule.
//!
//! [`Lattice::from_heights`] picks bits whenever every height is at most 1 and the rows fit.

use crate::bits::RowShape;
use crate::step::MAX_WORDS;

/// How the cells are stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Storage {
    /// One bit per cell, `ny` rows of `shape.words` words.
    Bits(Vec<u64>),
    /// One byte per cell, index `j * nx + i`.
    Heights(Vec<u8>),
}

/// A lattice of `nx` x `ny` cells.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lattice {
    pub nx: usize,
    pub ny: usize,
    pub(crate) shape: RowShape,
    pub(crate) storage: Storage,
}

/// Why a lattice cannot be built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LatticeError(pub String);

impl std::fmt::Display for LatticeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LatticeError {}

impl Lattice {
    /// An empty lattice (bit storage where its rows fit the bit-parallel step).
    pub fn empty(nx: usize, ny: usize) -> Self {
        assert!(nx > 0 && ny > 0, "a lattice has at least one cell");
        let shape = RowShape::new(nx);
        let storage = if shape.words <= MAX_WORDS {
            Storage::Bits(vec![0; shape.words * ny])
        } else {
            Storage::Heights(vec![0; nx * ny])
        };
        Self { nx, ny, shape, storage }
    }

    /// A lattice from heights (index `j * nx + i`); bit storage if all heights are <= 1 and
    /// the rows fit the bit-parallel step.
    pub fn from_heights(nx: usize, ny: usize, heights: &[u8]) -> Result<Self, LatticeError> {
        if heights.len() != nx * ny {
            return Err(LatticeError(format!("{} heights for {nx} x {ny} cells", heights.len())));
        }
        let mut l = Self::empty(nx, ny);
        if l.is_bit_packed() && heights.iter().all(|&h| h <= 1) {
            for j in 0..ny {
                for i in 0..nx {
                    if heights[j * nx + i] == 1 {
                        l.set_bit(i, j);
                    }
                }
            }
        } else {
            l.storage = Storage::Heights(heights.to_vec());
        }
        Ok(l)
    }

    /// The same cells in byte storage (the general update path), whatever the heights.
    pub fn into_byte_storage(self) -> Self {
        let h = self.heights();
        Self {
            storage: Storage::Heights(h),
            ..self
        }
    }

    fn set_bit(&mut self, i: usize, j: usize) {
        let w = self.shape.words;
        if let Storage::Bits(b) = &mut self.storage {
            RowShape::set(&mut b[j * w..(j + 1) * w], i, true);
        }
    }

    /// Whether the lattice is held one bit per cell.
    pub fn is_bit_packed(&self) -> bool {
        matches!(self.storage, Storage::Bits(_))
    }

    /// Height of cell `(i, j)`.
    pub fn height(&self, i: usize, j: usize) -> u8 {
        match &self.storage {
            Storage::Bits(b) => RowShape::get(&b[j * self.shape.words..], i) as u8,
            Storage::Heights(h) => h[j * self.nx + i],
        }
    }

    /// All heights, index `j * nx + i`.
    pub fn heights(&self) -> Vec<u8> {
        (0..self.ny)
            .flat_map(|j| (0..self.nx).map(move |i| (i, j)))
            .map(|(i, j)| self.height(i, j))
            .collect()
    }

    /// Number of grains.
    pub fn mass(&self) -> u64 {
        match &self.storage {
            Storage::Bits(b) => b.iter().map(|w| w.count_ones() as u64).sum(),
            Storage::Heights(h) => h.iter().map(|&x| x as u64).sum(),
        }
    }

    /// Grains as `(i, j, level)`, level 0 on the floor, row by row.
    pub fn grains(&self) -> impl Iterator<Item = (usize, usize, u8)> + '_ {
        (0..self.ny).flat_map(move |j| (0..self.nx).flat_map(move |i| (0..self.height(i, j)).map(move |z| (i, j, z))))
    }

    /// The mirror image `i -> nx - 1 - i`.
    pub fn mirrored(&self) -> Self {
        let h = self.heights();
        let mut m = vec![0u8; h.len()];
        for j in 0..self.ny {
            for i in 0..self.nx {
                m[j * self.nx + self.nx - 1 - i] = h[j * self.nx + i];
            }
        }
        let out = Self::from_heights(self.nx, self.ny, &m).expect("same size");
        if self.is_bit_packed() {
            out
        } else {
            out.into_byte_storage()
        }
    }

    /// Largest height difference between x-neighbours (periodic), the slope the resting rule
    /// bounds by 1.
    pub fn max_x_slope(&self) -> u8 {
        let mut s = 0;
        for j in 0..self.ny {
            for i in 0..self.nx {
                let (a, b) = (self.height(i, j), self.height((i + 1) % self.nx, j));
                s = s.max(a.abs_diff(b));
            }
        }
        s
    }
}
