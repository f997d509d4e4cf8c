//! Counter-based random bits: every draw is a pure function of (seed, half step, row, word,
//! stream), so results depend on nothing else (not on thread count, not on the order rows are
//! visited), and the bit-packed and the byte (scalar) update paths see the same numbers.
//!
//! Words are indexed in the *flight frame* (the row as seen by a grain flying in +x, see
//! [`crate::step`]), which makes the automaton exactly mirror symmetric: a mirrored lattice
//! driven with the reversed phase draws the same bits for the mirrored grains.

/// Streams of independent random words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum Stream {
    /// Activation of a grain's flight (`physical`, stochastic flights).
    Activation = 1,
    /// Knock-through of the far grain of a line that was hit.
    Knock = 2,
    /// Whether a grain moves sideways.
    Side = 3,
    /// Which way (+y or -y) a sideways move goes.
    SideDirection = 4,
    /// Whether a lateral contact holds against an impact.
    Hold = 5,
}

/// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective 64-bit mixer.
#[inline]
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The key of one row at one half step; combine with [`word`].
#[inline]
pub fn row_key(seed: u64, half_step: u64, row: usize) -> u64 {
    mix(mix(seed ^ mix(half_step)) ^ row as u64)
}

/// Probability 1 in the units of [`bernoulli`]: probabilities are multiples of 1/64.
pub const ONE: u32 = 64;

/// A uniformly random 64-bit word: wyhash's multiply-fold of the key advanced by the
/// counter (one 128-bit multiplication).
#[inline]
pub fn word(row_key: u64, stream: Stream, w: usize, k: u32) -> u64 {
    mum(row_key.wrapping_add(counter(stream, w, k).wrapping_mul(STEP)))
}

/// Multiplier of the counter in [`word`] (wyhash's first secret).
const STEP: u64 = 0xa076_1d64_78bd_642f;

/// The counter of word `w`, digit `k` (`k < 256`) of a stream: disjoint bit fields, so
/// `counter(s, w, k) = counter(s, w, 0) + k`.
#[inline(always)]
fn counter(stream: Stream, w: usize, k: u32) -> u64 {
    ((stream as u64) << 48) ^ ((w as u64) << 8) ^ k as u64
}

/// wyhash's multiply-fold of an advanced key.
#[inline(always)]
fn mum(s: u64) -> u64 {
    let t = (s as u128).wrapping_mul((s ^ 0xe703_7ed1_a0b4_28db) as u128);
    (t >> 64) as u64 ^ t as u64
}

/// Grains that try a sideways move towards +y (`up`) or -y: a move with probability `p / 64`,
/// then an even coin for the direction, so each way has probability `p / 128`.
#[inline]
pub fn sideways(row_key: u64, w: usize, p: u32, up: bool) -> u64 {
    let (moves, dir) = sideways_draw(row_key, w, p);
    moves & if up { dir } else { !dir }
}

/// The two words [`sideways`] combines: who moves (probability `p / 64`) and which way (a
/// set bit: +y). Both directions' passes use the same pair, so it can be drawn once.
#[inline]
pub fn sideways_draw(row_key: u64, w: usize, p: u32) -> (u64, u64) {
    (bernoulli(row_key, Stream::Side, w, p), word(row_key, Stream::SideDirection, w, 0))
}

/// Probability quantised to 1/64, the resolution of [`bernoulli`].
pub fn quantise(p: f64) -> u32 {
    (p.clamp(0.0, 1.0) * ONE as f64).round() as u32
}

/// A word whose bits are independently 1 with probability `p / 64` (`p` in 0..=64), built
/// from the binary expansion of the probability: starting from the lowest set bit of `p`,
/// `m = m | r` for a 1 digit and `m = m & r` for a 0 digit, with fresh words `r` (at most
/// six random words).
#[inline]
pub fn bernoulli(row_key: u64, stream: Stream, w: usize, p: u32) -> u64 {
    match p {
        0 => 0,
        ONE.. => u64::MAX,
        _ => {
            // word(row_key, stream, w, b) for digit b, from one base (see `counter`).
            let base = row_key.wrapping_add(counter(stream, w, 0).wrapping_mul(STEP));
            let low = p.trailing_zeros();
            let mut m = mum(base.wrapping_add((low as u64).wrapping_mul(STEP)));
            // A fixed trip count lets the digits unroll; the test on `b` is the same for
            // every word of a half step.
            for b in 1..6u32 {
                if b > low {
                    let r = mum(base.wrapping_add((b as u64).wrapping_mul(STEP)));
                    // Branch-free: the digit selects `m | r` (1) or `m & r` (0).
                    let digit = (((p >> b) & 1) as u64).wrapping_neg();
                    m = (m & r) | (digit & (m | r));
                }
            }
            m
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bernoulli_words_have_the_asked_density() {
        for q in [1u32, 9, 32, 50, 63] {
            let key = row_key(7, 3, 1);
            let ones: u32 = (0..4000).map(|w| bernoulli(key, Stream::Activation, w, q).count_ones()).sum();
            let p = q as f64 / ONE as f64;
            let n = 4000.0 * 64.0;
            let sigma = (n * p * (1.0 - p)).sqrt();
            assert!((ones as f64 - n * p).abs() < 5.0 * sigma, "p = {q}/64: {ones} of {n}");
        }
        assert_eq!(bernoulli(1, Stream::Knock, 0, 0), 0);
        assert_eq!(bernoulli(1, Stream::Knock, 0, ONE), u64::MAX);
    }
}
