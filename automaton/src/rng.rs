//! Counter-based random bits: every draw is a pure function of (seed, half step, row, word,
//! stream), so results depend on nothing else (not on thread count, not on the order rows are
//! visited), and the bit-packed and the byte (scalar) update paths see the same numbers.
//!
//! The scheme: every probability is quantised to a multiple of 1/64 ([`quantise`]). A word
//! of 64 Bernoulli lanes is `U < p` lane by lane for six random binary digits `U` per lane,
//! bit-sliced: digit `b` of all 64 lanes is a uniformly random word `R_b` (wyhash's
//! multiply-fold of the counter, one 128-bit multiplication) XORed with digit `b` of `p`
//! (still uniform, so `P(U < p) = p / 64` exactly). From the lowest set digit of `p` upwards
//! the comparison is the carry `m = maj(m, U_b, p_b)`; with `n = m ^ p_b` this is
//! `n = (n & R_b) ^ (p_b ^ p_{b+1})`, two operations per digit ([`Split::draw`]). A
//! probability costs at most six words (`6 - trailing_zeros(p)`). Draws are made only for words that hold a cell whose draw is
//! read; a draw is the same whether made or not, so skipping changes no result. The
//! activation of a grain's flight and the holding of a lateral contact (at the floor level)
//! share one set of digit words ([`bernoulli_split`]): activation is read only on cells of
//! the row that hold a grain, holding only on empty ones, so each cell's `U` decides one
//! event and the events stay independent with their own probabilities (tested against
//! binomial tolerances in `tests/rule_invariants.rs`).
//!
//! Words are indexed in the *flight frame* (the row as seen by a grain flying in +x, see
//! [`crate::step`]), which makes the automaton exactly mirror symmetric: a mirrored lattice
//! driven with the reversed phase draws the same bits for the mirrored grains.

/// Streams of independent random words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum Stream {
    /// Per cell of a row: the activation of the grain's flight (`physical`, stochastic
    /// flights) where the row has a grain, whether a lateral contact holds at level 0
    /// ([`Stream::Hold`]) where it has none. A cell's number is so used for one event only:
    /// both share the digit words of [`bernoulli_split`].
    Activation = 1,
    /// Knock-through of the far grain of a line that was hit.
    Knock = 2,
    /// Whether a grain moves sideways.
    Side = 3,
    /// Which way (+y or -y) a sideways move goes.
    SideDirection = 4,
    /// Whether a lateral contact holds against an impact above the floor level (multilayers;
    /// at level 0 the draw comes from [`Stream::Activation`]).
    Hold = 5,
    /// Whether an occupied neighbouring cell holds a grain (frustration), one key per
    /// neighbour ([`neighbour_key`]).
    Frustration = 6,
    /// The measured rule's jump of a grain: the quantile (digit 0) and the rounding to cells
    /// (digit 1), per start column ([`crate::measured_rule`]).
    Jump = 7,
    /// Whether a grain of a band's leading edge escapes (measured rule).
    Escape = 8,
    /// The measured rule's sideways step: quantile, rounding, direction (digits 0, 1, 2).
    SideStep = 9,
    /// The measured rule's signed drift over a period, drawn on the way back: quantile and
    /// rounding (digits 0, 1).
    Drift = 10,
}

/// The row key of the draws about neighbour `d` (0..8) of each cell, from the row's key.
#[inline]
pub fn neighbour_key(row_key: u64, d: usize) -> u64 {
    mix(row_key ^ (d as u64 + 1))
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

/// The constant of [`mum`] (wyhash's second secret).
const MUM_K: u64 = 0xe703_7ed1_a0b4_28db;

/// wyhash's multiply-fold of an advanced key.
#[inline(always)]
fn mum(s: u64) -> u64 {
    let t = (s as u128).wrapping_mul((s ^ MUM_K) as u128);
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
        _ => digits(row_key.wrapping_add(counter(stream, w, 0).wrapping_mul(STEP)), p),
    }
}

/// The digit recursion of [`bernoulli`] for `0 < p < 64`, from the counter base of the word
/// (`word(row_key, stream, w, b) = mum(base + b STEP)`, see `counter`): `n = (n & R_b) ^
/// (p_b ^ p_{b+1})` from `n = p_low = 1` (see the module doc).
#[inline(always)]
fn digits(base: u64, p: u32) -> u64 {
    let low = p.trailing_zeros();
    let digit = |b: u32| if b < 6 && (p >> b) & 1 == 1 { u64::MAX } else { 0 };
    let mut n = u64::MAX;
    for b in low..6 {
        let r = mum(base.wrapping_add((b as u64).wrapping_mul(STEP)));
        n = (n & r) ^ digit(b) ^ digit(b + 1);
    }
    n
}

/// `out[k] = cand[k] & bernoulli(row_key, stream, k, p)` for every word `k` of a row, drawing
/// only for words with a candidate (`cand[k] != 0`; the others get 0), with `plain =
/// Split::plain(p)` (the digits worked out once per half step, so the digit loop has no
/// branch per digit).
#[inline(always)]
pub fn bernoulli_row(row_key: u64, stream: Stream, plain: &Split, cand: &[u64], out: &mut [u64]) {
    let base = row_key.wrapping_add(counter(stream, 0, 0).wrapping_mul(STEP));
    let out = &mut out[..cand.len()];
    match plain.low {
        0 => plain.row_plain::<0>(base, cand, out),
        1 => plain.row_plain::<1>(base, cand, out),
        2 => plain.row_plain::<2>(base, cand, out),
        3 => plain.row_plain::<3>(base, cand, out),
        4 => plain.row_plain::<4>(base, cand, out),
        5 => plain.row_plain::<5>(base, cand, out),
        _ => plain.row_plain::<6>(base, cand, out),
    }
}

/// Lanes drawn with two probabilities from the same digit words: lane `i` is 1 with
/// probability `pa / 64` if bit `i` of `a` is set and `pb / 64` otherwise (both in 0..=64).
/// Lane by lane this is exactly [`bernoulli`] with the lane's probability: a lane's bit is
/// `U < p` for the lane's six random digits `U` (bit `i` of the words `word(.., b)`), so
/// `(bernoulli_split(.., a, pa, pb) >> i) & 1` is `(bernoulli(.., pa) >> i) & 1` for a lane
/// in `a`, `(bernoulli(.., pb) >> i) & 1` otherwise; both probabilities cost the words of one.
/// (The scalar reference reads single lanes with [`bernoulli`]; this word form is the
/// definition the row draws implement and is tested against it.)
#[cfg_attr(not(test), allow(dead_code))]
pub fn bernoulli_split(row_key: u64, stream: Stream, w: usize, a: u64, pa: u32, pb: u32) -> u64 {
    Split::new(pa, pb).draw::<0>(row_key.wrapping_add(counter(stream, w, 0).wrapping_mul(STEP)), a)
}

/// The digits of the two probabilities of [`bernoulli_split`], worked out once per half step.
#[derive(Clone, Copy, Debug)]
pub struct Split {
    /// First digit word drawn (6: none).
    low: u32,
    /// Digit `b` of `pa` (`pb`) as a mask (0 for probabilities 0 and 1): the start of the
    /// recursion.
    da: [u64; 6],
    db: [u64; 6],
    /// `p_b ^ p_{b+1}` of `pa` (`pb`) as masks (digit 6 is 0), the step of the recursion at
    /// digit `b`.
    step_a: [u64; 6],
    step_b: [u64; 6],
    /// All lanes of a probability 1 (their digits are 0, so the recursion leaves them 0).
    one_a: u64,
    one_b: u64,
    /// [`STEP`] and the constant of [`mum`], held as data so that the digit loop advances
    /// the counter with one addition and keeps the constant in a register (as immediates
    /// every digit costs a 64-bit constant load and an address computation).
    step: u64,
    mum_k: u64,
}

impl Split {
    /// One probability for every lane: the draws of [`bernoulli`].
    pub fn plain(p: u32) -> Self {
        Self::new(p, p)
    }

    pub fn new(pa: u32, pb: u32) -> Self {
        let frac = |p: u32| p > 0 && p < ONE;
        let low = |p: u32| if frac(p) { p.trailing_zeros() } else { 6 };
        let digit = |p: u32, b: usize| if frac(p) && b < 6 && (p >> b) & 1 == 1 { u64::MAX } else { 0 };
        let step = |p: u32, b: usize| digit(p, b) ^ digit(p, b + 1);
        let one = |p: u32| if p >= ONE { u64::MAX } else { 0 };
        Self {
            low: low(pa).min(low(pb)),
            da: std::array::from_fn(|b| digit(pa, b)),
            db: std::array::from_fn(|b| digit(pb, b)),
            step_a: std::array::from_fn(|b| step(pa, b)),
            step_b: std::array::from_fn(|b| step(pb, b)),
            one_a: one(pa),
            one_b: one(pb),
            step: std::hint::black_box(STEP),
            mum_k: std::hint::black_box(MUM_K),
        }
    }

    /// The digit words `R_b` of one word from its counter base (see [`bernoulli_row`]),
    /// `b >= LOW`, passed to `f(b, R_b)` in order.
    #[inline(always)]
    fn words<const LOW: usize>(&self, base: u64, mut f: impl FnMut(usize, u64)) {
        let mut s = base;
        for _ in 0..LOW {
            s = s.wrapping_add(self.step);
        }
        for b in LOW..6 {
            let t = (s as u128).wrapping_mul((s ^ self.mum_k) as u128);
            f(b, (t >> 64) as u64 ^ t as u64);
            s = s.wrapping_add(self.step);
        }
    }

    /// The word from its counter base (see [`bernoulli_row`]) and the lanes of `pa`, with
    /// `LOW <= self.low` (a constant, so the digit loop unrolls): `n = (n & R_b) ^ (p_b ^
    /// p_{b+1})` from `n = p_LOW`, lane by lane (see the module doc; below a lane's lowest
    /// set digit `n` stays 0, and turns 1 at the digit below it). The two probabilities run
    /// as two recursions on the same digit words, blended at the end.
    #[inline(always)]
    fn draw<const LOW: usize>(&self, base: u64, a: u64) -> u64 {
        if LOW >= 6 {
            return (a & self.one_a) | (!a & self.one_b);
        }
        let (mut na, mut nb) = (self.da[LOW], self.db[LOW]);
        self.words::<LOW>(base, |b, r| {
            na = (na & r) ^ self.step_a[b];
            nb = (nb & r) ^ self.step_b[b];
        });
        (a & (na | self.one_a)) | (!a & (nb | self.one_b))
    }

    /// [`Self::draw`] with one probability (`a = 0`, so only `pb`).
    #[inline(always)]
    fn draw_plain<const LOW: usize>(&self, base: u64) -> u64 {
        if LOW >= 6 {
            return self.one_b;
        }
        let mut n = self.db[LOW];
        self.words::<LOW>(base, |b, r| n = (n & r) ^ self.step_b[b]);
        n | self.one_b
    }

    /// `out[k] = cand[k] & draw` for one probability.
    #[inline(always)]
    fn row_plain<const LOW: usize>(&self, mut base: u64, cand: &[u64], out: &mut [u64]) {
        for (o, &c) in out.iter_mut().zip(cand) {
            *o = if c != 0 { c & self.draw_plain::<LOW>(base) } else { 0 };
            base = base.wrapping_add(NEXT_WORD);
        }
    }

    #[inline(always)]
    fn row<const LOW: usize>(&self, mut base: u64, a: &[u64], cand: &[u64], out: &mut [u64]) {
        for ((o, &c), &a) in out.iter_mut().zip(cand).zip(a) {
            *o = if c != 0 { self.draw::<LOW>(base, a) } else { 0 };
            base = base.wrapping_add(NEXT_WORD);
        }
    }
}

/// `out[k] = bernoulli_split(row_key, stream, k, a[k], pa, pb)` for the words with `cand[k]
/// != 0`, 0 for the others, with `split = Split::new(pa, pb)`.
#[inline(always)]
pub fn bernoulli_split_row(row_key: u64, stream: Stream, a: &[u64], split: &Split, cand: &[u64], out: &mut [u64]) {
    let base = row_key.wrapping_add(counter(stream, 0, 0).wrapping_mul(STEP));
    let n = cand.len();
    let (a, out) = (&a[..n], &mut out[..n]);
    match split.low {
        0 => split.row::<0>(base, a, cand, out),
        1 => split.row::<1>(base, a, cand, out),
        2 => split.row::<2>(base, a, cand, out),
        3 => split.row::<3>(base, a, cand, out),
        4 => split.row::<4>(base, a, cand, out),
        5 => split.row::<5>(base, a, cand, out),
        _ => split.row::<6>(base, a, cand, out),
    }
}

/// Counter base step from word `w` to `w + 1`: `counter(s, w + 1, 0) = counter(s, w, 0) +
/// 256` (disjoint bit fields).
const NEXT_WORD: u64 = 256u64.wrapping_mul(STEP);

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

    #[test]
    fn row_draws_equal_word_draws() {
        let key = row_key(5, 8, 2);
        // Candidates in some words only, rows longer than a chunk.
        let cand: Vec<u64> = (0..37u64).map(|k| if k % 3 == 1 { 0 } else { mix(k) }).collect();
        for p in [0u32, 1, 6, 12, 32, 51, 52, 63, 64] {
            for stream in [Stream::Activation, Stream::Knock, Stream::Hold, Stream::Side] {
                let mut out = vec![u64::MAX; cand.len()];
                bernoulli_row(key, stream, &Split::plain(p), &cand, &mut out);
                for (k, (&o, &c)) in out.iter().zip(&cand).enumerate() {
                    assert_eq!(o, c & bernoulli(key, stream, k, p), "p {p} word {k}");
                }
            }
        }
    }

    #[test]
    fn split_draws_are_the_lane_wise_plain_draws() {
        let key = row_key(9, 4, 6);
        for w in 0..50 {
            let a = mix(w as u64 + 100);
            for (pa, pb) in [
                (51u32, 52u32),
                (51, 64),
                (64, 52),
                (0, 12),
                (12, 0),
                (1, 63),
                (32, 32),
                (0, 64),
                (64, 64),
            ] {
                let s = bernoulli_split(key, Stream::Activation, w, a, pa, pb);
                let (ba, bb) = (bernoulli(key, Stream::Activation, w, pa), bernoulli(key, Stream::Activation, w, pb));
                assert_eq!(s, (a & ba) | (!a & bb), "pa {pa} pb {pb} word {w}");
            }
        }
    }
}
