//! The event queue: one predicted event per particle, kept in an indexed binary min-heap of
//! exactly the particle count. Rescheduling a particle moves its one entry up or down in
//! place, so the heap never holds stale entries (the "one event per particle" queue of
//! Rapaport's and DynamO's EDMD, here a plain heap with a position index). Ties in time go
//! to the lower particle index, so runs are deterministic.

/// The queue of the particles' next events.
#[derive(Clone, Debug, Default)]
pub struct Queue {
    /// The heap: `(time, particle)`, the earliest event at the root.
    heap: Vec<(f64, usize)>,
    /// Each particle's place in `heap`, or `usize::MAX` when it is not in it.
    place: Vec<usize>,
}

impl Queue {
    /// A queue for `n` particles, all unscheduled.
    pub fn new(n: usize) -> Self {
        Queue {
            heap: Vec::with_capacity(n),
            place: vec![usize::MAX; n],
        }
    }

    /// Whether event `a` comes before `b` (earlier time, then lower index).
    #[inline]
    fn before(a: (f64, usize), b: (f64, usize)) -> bool {
        match a.0.total_cmp(&b.0) {
            std::cmp::Ordering::Less => true,
            std::cmp::Ordering::Greater => false,
            std::cmp::Ordering::Equal => a.1 < b.1,
        }
    }

    #[inline]
    fn put(&mut self, k: usize, e: (f64, usize)) {
        self.heap[k] = e;
        self.place[e.1] = k;
    }

    fn sift_up(&mut self, mut k: usize) {
        let i = self.heap[k];
        while k > 0 {
            let parent = (k - 1) / 2;
            let p = self.heap[parent];
            if !Self::before(i, p) {
                break;
            }
            self.put(k, p);
            k = parent;
        }
        self.put(k, i);
    }

    fn sift_down(&mut self, mut k: usize) {
        let i = self.heap[k];
        let n = self.heap.len();
        loop {
            let left = 2 * k + 1;
            if left >= n {
                break;
            }
            let right = left + 1;
            let child = if right < n && Self::before(self.heap[right], self.heap[left]) {
                right
            } else {
                left
            };
            let c = self.heap[child];
            if !Self::before(c, i) {
                break;
            }
            self.put(k, c);
            k = child;
        }
        self.put(k, i);
    }

    /// Schedules particle `i` at `time`, replacing its earlier entry.
    pub fn schedule(&mut self, i: usize, time: f64) {
        match self.place[i] {
            usize::MAX => {
                self.heap.push((time, i));
                let k = self.heap.len() - 1;
                self.place[i] = k;
                self.sift_up(k);
            }
            k => {
                let old = self.heap[k].0;
                self.heap[k].0 = time;
                if time.total_cmp(&old).is_lt() {
                    self.sift_up(k);
                } else {
                    self.sift_down(k);
                }
            }
        }
    }

    /// Removes particle `i`'s entry, if any.
    pub fn cancel(&mut self, i: usize) {
        let k = self.place[i];
        if k == usize::MAX {
            return;
        }
        let last = self.heap.pop().expect("a placed particle is in the heap");
        self.place[i] = usize::MAX;
        if last.1 != i {
            self.put(k, last);
            self.sift_up(k);
            let k = self.place[last.1];
            self.sift_down(k);
        }
    }

    /// Particle `i`'s scheduled time, if it is scheduled.
    pub fn time_of(&self, i: usize) -> Option<f64> {
        let k = self.place[i];
        (k != usize::MAX).then(|| self.heap[k].0)
    }

    /// The earliest entry: `(time, particle)`, without removing it.
    pub fn peek(&self) -> Option<(f64, usize)> {
        self.heap.first().copied()
    }

    /// Removes the earliest entry.
    pub fn pop(&mut self) -> Option<(f64, usize)> {
        let top = self.peek()?;
        self.cancel(top.1);
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn the_earliest_event_comes_first_and_rescheduling_replaces_the_old_one() {
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

    proptest! {
        /// Against a plain reference: after any sequence of schedules and cancels, the queue
        /// pops every scheduled particle once, in (time, index) order, with its last time.
        #[test]
        fn pops_follow_the_last_schedule_of_each_particle(
            ops in proptest::collection::vec((0usize..20, 0u32..50, proptest::bool::weighted(0.1)), 0..200)
        ) {
            let mut q = Queue::new(20);
            let mut reference: Vec<Option<f64>> = vec![None; 20];
            for (i, t, cancel) in ops {
                if cancel {
                    q.cancel(i);
                    reference[i] = None;
                } else {
                    q.schedule(i, t as f64);
                    reference[i] = Some(t as f64);
                }
            }
            let mut want: Vec<(f64, usize)> =
                reference.iter().enumerate().filter_map(|(i, t)| t.map(|t| (t, i))).collect();
            want.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut got = Vec::new();
            while let Some(e) = q.pop() {
                got.push(e);
            }
            prop_assert_eq!(got, want);
        }
    }
}
