//! The automaton: a lattice, its parameters, the half-step counter and preallocated buffers.

use crate::lattice::{Lattice, Storage};
use crate::params::{Params, ParamsError, Resolved, Tick};
use crate::scalar::{self, ScalarScratch};
use crate::step::{self, BitScratch};

/// Direction of a flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Direction {
    /// Towards +x.
    Plus,
    /// Towards -x.
    Minus,
}

impl Direction {
    pub fn reversed(self) -> Self {
        match self {
            Direction::Plus => Direction::Minus,
            Direction::Minus => Direction::Plus,
        }
    }
}

/// A running automaton. Half step `t` flies towards `first` for even `t` and the other way
/// for odd `t` (the drive phase); one drive period is two half steps.
pub struct Automaton {
    lattice: Lattice,
    params: Params,
    resolved: Resolved,
    first: Direction,
    half_steps: u64,
    bits: BitScratch,
    bytes: ScalarScratch,
}

impl Automaton {
    /// An automaton on `lattice`, whose first flight goes towards `first`; refuses parameters
    /// out of range ([`Params::validate`]).
    pub fn new(lattice: Lattice, params: Params, first: Direction) -> Result<Self, ParamsError> {
        params.validate()?;
        let resolved = params.resolve();
        // Trains, graded transport and the measured rule have no bit-parallel step: they run
        // on bytes.
        let lattice = if resolved.trains || resolved.graded.is_some() || resolved.measured.is_some() {
            lattice.into_byte_storage()
        } else {
            lattice
        };
        let (nx, ny) = (lattice.nx, lattice.ny);
        Ok(Self {
            resolved,
            bits: BitScratch::new(lattice.shape, ny),
            bytes: ScalarScratch::new(nx, ny),
            lattice,
            params,
            first,
            half_steps: 0,
        })
    }

    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Half steps done.
    pub fn half_steps(&self) -> u64 {
        self.half_steps
    }

    /// Direction of the next flight.
    pub fn direction(&self) -> Direction {
        if self.half_steps.is_multiple_of(2) {
            self.first
        } else {
            self.first.reversed()
        }
    }

    /// Whether nothing can move (below the sliding threshold or a zero flight cap).
    pub fn frozen(&self) -> bool {
        self.resolved.frozen
    }

    /// One half period: flights, knock-through, sideways moves, resting.
    pub fn half_step(&mut self) {
        let left = self.direction() == Direction::Minus;
        let tick = Tick {
            seed: self.params.seed,
            t: self.half_steps,
            left,
        };
        let l = &mut self.lattice;
        match &mut l.storage {
            Storage::Bits(rows) => step::half_step(&l.shape, l.ny, rows, &self.resolved, tick, &mut self.bits),
            Storage::Heights(h) => scalar::half_step(l.nx, l.ny, h, &self.resolved, tick, &mut self.bytes),
        }
        self.half_steps += 1;
    }

    /// The moves of the last half step's grains, each grain followed from cell to cell: the
    /// `measured` rule's flights and sideways steps (none before the first half step). None
    /// for the other rules (their flights are not drawn per grain) and after a half step in
    /// which the resting rule moved grains (a pile came down: moves not followed).
    pub fn measured_moves(&self) -> Option<&[crate::measured_rule::GrainMove]> {
        let m = &self.bytes.measured;
        (self.resolved.measured.is_some() && m.rested == 0).then_some(m.moves.as_slice())
    }

    /// One drive period (two half steps).
    pub fn period(&mut self) {
        self.half_step();
        self.half_step();
    }
}
