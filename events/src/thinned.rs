//! A bounded, evenly thinned record of a long stream of values: what the free times between
//! collisions are kept in, so that a run of any length holds at most [`Thinned::CAP`] of
//! them. When the record is full, every other kept value is dropped and from then on only
//! every `stride`-th value of the stream is kept; the record stays an even subsample of the
//! whole stream, deterministic, with no random numbers.

/// The kept values of a stream, one in every `stride`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Thinned {
    /// The kept values, in stream order.
    pub kept: Vec<f64>,
    /// One value in `stride` is kept (a power of two, 1 until the record first fills).
    pub stride: u64,
    /// Values seen since the last one kept.
    pub skipped: u64,
}

impl Thinned {
    /// The most values kept.
    pub const CAP: usize = 1 << 20;

    pub fn new() -> Self {
        Thinned {
            kept: Vec::new(),
            stride: 1,
            skipped: 0,
        }
    }

    /// Adds the next value of the stream.
    pub fn push(&mut self, x: f64) {
        self.push_capped(x, Self::CAP);
    }

    fn push_capped(&mut self, x: f64, cap: usize) {
        self.skipped += 1;
        if self.skipped < self.stride {
            return;
        }
        self.skipped = 0;
        self.kept.push(x);
        if self.kept.len() >= cap {
            let mut k = 0u64;
            self.kept.retain(|_| {
                k += 1;
                k.is_multiple_of(2)
            });
            self.stride *= 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_stream_is_kept_evenly_and_within_the_cap() {
        let mut t = Thinned::new();
        for k in 1..=1000u64 {
            t.push_capped(k as f64, 64);
        }
        assert!(t.kept.len() < 64);
        assert_eq!(t.stride, 16);
        // Every stride-th value, evenly: the kept values are multiples of the stride.
        assert!(t.kept.iter().all(|x| (*x as u64).is_multiple_of(16)), "{:?}", t.kept);
        let gaps: Vec<f64> = t.kept.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|g| *g == 16.0), "{gaps:?}");
        assert_eq!(*t.kept.last().unwrap(), 992.0);
        // A short stream is kept whole.
        let mut short = Thinned::new();
        (0..10).for_each(|k| short.push(k as f64));
        assert_eq!(short.kept, (0..10).map(|k| k as f64).collect::<Vec<_>>());
    }
}
