//! The event queue: one predicted event per particle, kept in a binary heap the size of the
//! particle count plus stale entries. Rescheduling a particle bumps its generation; an entry
//! whose generation is old is dropped when it comes up (Smallenburg's EDMD; DynamO's queue).
//! Ties in time go to the lower particle index, so runs are deterministic.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    time: f64,
    particle: usize,
    generation: u64,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: the heap's top is the earliest event.
        other
            .time
            .total_cmp(&self.time)
            .then_with(|| other.particle.cmp(&self.particle))
            .then_with(|| other.generation.cmp(&self.generation))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The queue of the particles' next events.
#[derive(Clone, Debug, Default)]
pub struct Queue {
    heap: BinaryHeap<Entry>,
    generation: Vec<u64>,
}

impl Queue {
    /// A queue for `n` particles, all unscheduled.
    pub fn new(n: usize) -> Self {
        Queue {
            heap: BinaryHeap::with_capacity(2 * n),
            generation: vec![0; n],
        }
    }

    /// Schedules particle `i` at `time`, replacing its earlier entry.
    pub fn schedule(&mut self, i: usize, time: f64) {
        self.generation[i] += 1;
        self.heap.push(Entry {
            time,
            particle: i,
            generation: self.generation[i],
        });
        // Keep stale entries from piling up.
        if self.heap.len() > 4 * self.generation.len() + 64 {
            let live = &self.generation;
            let kept: Vec<Entry> = self.heap.drain().filter(|e| e.generation == live[e.particle]).collect();
            self.heap = kept.into();
        }
    }

    /// The earliest live entry: `(time, particle)`, without removing it.
    pub fn peek(&mut self) -> Option<(f64, usize)> {
        while let Some(e) = self.heap.peek() {
            if e.generation == self.generation[e.particle] {
                return Some((e.time, e.particle));
            }
            self.heap.pop();
        }
        None
    }

    /// Removes the earliest live entry.
    pub fn pop(&mut self) -> Option<(f64, usize)> {
        let top = self.peek()?;
        self.heap.pop();
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_earliest_live_event_comes_first_and_rescheduling_drops_the_old_one() {
        let mut q = Queue::new(3);
        q.schedule(0, 3.0);
        q.schedule(1, 1.0);
        q.schedule(2, 2.0);
        q.schedule(1, 5.0); // replaces 1.0
        assert_eq!(q.pop(), Some((2.0, 2)));
        assert_eq!(q.pop(), Some((3.0, 0)));
        assert_eq!(q.pop(), Some((5.0, 1)));
        assert_eq!(q.pop(), None);
        // Ties go to the lower index.
        q.schedule(2, 1.0);
        q.schedule(0, 1.0);
        assert_eq!(q.pop(), Some((1.0, 0)));
    }
}
