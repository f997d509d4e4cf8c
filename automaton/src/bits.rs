//! Operations on bit rows: a row of `nx` cells is `ceil(nx / 64)` words, cell `i` at bit
//! `i % 64` of word `i / 64`; bits at or above `nx` in the last word are always zero. Rows
//! are periodic: all shifts are rotations modulo `nx`.
//!
//! The step ([`crate::step`]) uses the fixed-width forms (`[u64; W]`, the second `impl`). The
//! slice forms of the first `impl` state each operation for any width; outside
//! [`RowShape::window_and`] they are compiled only for the tests, which check them against
//! index formulas and the fixed-width forms against them.

// Word loops index several rows at once; explicit indices read clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

/// Geometry of a bit row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowShape {
    /// Cells.
    pub nx: usize,
    /// Words per row.
    pub words: usize,
    /// Mask of the valid bits of the last word.
    pub last: u64,
}

impl RowShape {
    pub fn new(nx: usize) -> Self {
        assert!(nx > 0, "a row has at least one cell");
        let words = nx.div_ceil(64);
        let r = nx % 64;
        Self {
            nx,
            words,
            last: if r == 0 { u64::MAX } else { (1u64 << r) - 1 },
        }
    }

    /// Clears the bits beyond `nx`.
    #[inline]
    pub fn clean(&self, row: &mut [u64]) {
        row[self.words - 1] &= self.last;
    }

    #[cfg(test)]
    /// `dst = !src` on the valid cells.
    #[inline]
    pub fn not(&self, src: &[u64], dst: &mut [u64]) {
        for (d, s) in dst.iter_mut().zip(src) {
            *d = !*s;
        }
        self.clean(dst);
    }

    #[cfg(test)]
    /// Logical shift towards higher cells by `k < nx` without wrap: `dst[i + k] = src[i]`,
    /// cells beyond `nx` dropped.
    fn shl_into(&self, src: &[u64], k: usize, dst: &mut [u64], or: bool) {
        let (wq, b) = (k / 64, (k % 64) as u32);
        for d in (0..self.words).rev() {
            let v = if d < wq {
                0
            } else {
                let hi = src[d - wq] << b;
                let lo = if b > 0 && d > wq { src[d - wq - 1] >> (64 - b) } else { 0 };
                hi | lo
            };
            if or {
                dst[d] |= v;
            } else {
                dst[d] = v;
            }
        }
        self.clean(dst);
    }

    #[cfg(test)]
    /// Logical shift towards lower cells by `k < nx` without wrap: `dst[i] = src[i + k]`.
    fn shr_or(&self, src: &[u64], k: usize, dst: &mut [u64]) {
        let (wq, b) = (k / 64, (k % 64) as u32);
        for d in 0..self.words {
            let s = d + wq;
            if s >= self.words {
                break;
            }
            let lo = src[s] >> b;
            let hi = if b > 0 && s + 1 < self.words { src[s + 1] << (64 - b) } else { 0 };
            dst[d] |= lo | hi;
        }
    }

    #[cfg(test)]
    /// Periodic rotation towards higher cells: `dst[(i + k) mod nx] = src[i]`. One pass:
    /// word `d` of the result is the 64-cell window of `src` starting at `64 d - k`.
    pub fn rotate_up(&self, src: &[u64], k: usize, dst: &mut [u64]) {
        let k = if k < self.nx { k } else { k % self.nx };
        if k == 0 {
            dst.copy_from_slice(src);
            return;
        }
        if self.words >= 2 && k == 1 {
            // By one cell: a carry from each word into the next, cell nx - 1 into cell 0.
            let n = self.words;
            let (src, dst) = (&src[..n], &mut dst[..n]);
            let top = (src[n - 1] >> ((self.nx - 1) % 64)) & 1;
            for (d, pair) in dst[1..].iter_mut().zip(src.windows(2)) {
                *d = (pair[1] << 1) | (pair[0] >> 63);
            }
            dst[0] = (src[0] << 1) | top;
            return self.clean(dst);
        }
        if self.words >= 2 && k == self.nx - 1 {
            // Down by one cell: cell 0 goes to cell nx - 1.
            let n = self.words;
            let (src, dst) = (&src[..n], &mut dst[..n]);
            for (d, pair) in dst.iter_mut().zip(src.windows(2)) {
                *d = (pair[0] >> 1) | (pair[1] << 63);
            }
            dst[n - 1] = (src[n - 1] >> 1) | ((src[0] & 1) << ((self.nx - 1) % 64));
            return self.clean(dst);
        }
        if self.nx < 128 {
            return self.rotate_up_short(src, k, dst);
        }
        if k < 64 {
            // Straight word loop; only word 0 takes cells across the seam.
            let b = k as u32;
            for d in 1..self.words {
                dst[d] = (src[d] << b) | (src[d - 1] >> (64 - b));
            }
            dst[0] = self.window(src, self.nx - k);
            return self.clean(dst);
        }
        if self.nx - k < 64 {
            // A small rotation down: only the last two words see the seam.
            let b = (self.nx - k) as u32;
            let n = self.words;
            for d in 0..n - 2 {
                dst[d] = (src[d] >> b) | (src[d + 1] << (64 - b));
            }
            for d in n - 2..n {
                dst[d] = self.window(src, (64 * d + b as usize) % self.nx);
            }
            return self.clean(dst);
        }
        let mut start = self.nx - k;
        for d in dst.iter_mut().take(self.words) {
            *d = self.window(src, start);
            start += 64;
            if start >= self.nx {
                start -= self.nx;
            }
        }
        self.clean(dst);
    }

    #[cfg(test)]
    /// The 64 cells from `start < nx` on, cyclically (rows of at least 64 cells).
    #[inline(always)]
    fn window(&self, src: &[u64], start: usize) -> u64 {
        let w = start >> 6;
        let b = (start & 63) as u32;
        let lo = src[w] >> b;
        let hi = if b > 0 && w + 1 < self.words { src[w + 1] << (64 - b) } else { 0 };
        let v = lo | hi;
        let avail = self.nx - start;
        if avail >= 64 {
            v
        } else {
            (v & ((1u64 << avail) - 1)) | (src[0] << avail)
        }
    }

    #[cfg(test)]
    /// [`Self::rotate_up`] for rows shorter than 128 cells, by two shifts.
    fn rotate_up_short(&self, src: &[u64], k: usize, dst: &mut [u64]) {
        self.shl_into(src, k, dst, false);
        if k > 0 {
            // Cells nx-k..nx move to 0..k.
            self.shr_or(src, self.nx - k, dst);
        }
    }

    #[cfg(test)]
    /// Periodic rotation towards lower cells: `dst[i] = src[(i + k) mod nx]`.
    pub fn rotate_down(&self, src: &[u64], k: usize, dst: &mut [u64]) {
        let k = if k < self.nx { k } else { k % self.nx };
        self.rotate_up(src, if k == 0 { 0 } else { self.nx - k }, dst);
    }

    #[cfg(test)]
    /// Mirror: `dst[nx - 1 - i] = src[i]`.
    pub fn reverse(&self, src: &[u64], dst: &mut [u64]) {
        let pad = self.words * 64 - self.nx; // reversed bits land `pad` too high
        let n = self.words;
        if pad == 0 {
            for d in 0..n {
                dst[d] = src[n - 1 - d].reverse_bits();
            }
            return;
        }
        let p = pad as u32;
        // Word d of the result takes reversed bits 64 d + pad .. 64 d + pad + 64: each source
        // word is reversed once and feeds two result words.
        let mut a = src[n - 1].reverse_bits();
        for d in 0..n - 1 {
            let b = src[n - 2 - d].reverse_bits();
            dst[d] = (a >> p) | (b << (64 - p));
            a = b;
        }
        dst[n - 1] = a >> p;
        self.clean(dst);
    }

    #[cfg(test)]
    /// Periodic addition with end-around carry: `dst = a + b` as `nx`-bit numbers where a
    /// carry out of cell `nx - 1` re-enters at cell 0 (one's-complement addition). With `a`
    /// the free cells and `b` single bits at the starts of free runs, the carries run along
    /// each run, across the seam if need be, and stop on the first occupied cell.
    pub fn cyclic_add(&self, a: &[u64], b: &[u64], dst: &mut [u64]) {
        let mut carry = 0u64;
        for d in 0..self.words {
            let (s1, c1) = a[d].overflowing_add(b[d]);
            let (s2, c2) = s1.overflowing_add(carry);
            dst[d] = s2;
            carry = (c1 | c2) as u64;
        }
        let mut out = self.carry_out(dst, carry);
        // At most two more rounds: the sum of two nx-bit numbers is below 2^(nx+1).
        while out {
            let mut c = 1u64;
            for w in dst.iter_mut().take(self.words) {
                let (s, o) = w.overflowing_add(c);
                *w = s;
                c = o as u64;
                if c == 0 {
                    break;
                }
            }
            out = self.carry_out(dst, c);
        }
    }

    /// Removes and returns the carry past cell `nx - 1`.
    fn carry_out(&self, dst: &mut [u64], word_carry: u64) -> bool {
        if self.last == u64::MAX {
            word_carry == 1
        } else {
            let top = &mut dst[self.words - 1];
            let out = *top & !self.last != 0;
            *top &= self.last;
            out
        }
    }

    /// Periodic window AND: `dst[a] = src[a] & src[a + 1] & ... & src[a + len - 1]` (indices
    /// mod `nx`), for `1 <= len < nx`. `ext` (at least [`Self::ext_words`] words) holds
    /// `src` followed by a second copy of it, so every window is a plain (non-periodic)
    /// range; windows of width `2s` are the AND of two of width `s` (`s` = 1, 2, 4, ...,
    /// the largest power of two `p <= len`) and the last step ANDs two overlapping windows of
    /// width `p` that start `len - p` apart: about `log2(len) + 1` shift-and-AND passes over
    /// `(nx + len) / 64` words, with no periodic rotation.
    ///
    /// Windows of at least 64 cells go through [`Self::window_and_long`] instead.
    pub fn window_and(&self, src: &[u64], len: usize, dst: &mut [u64], ext: &mut [u64]) {
        debug_assert!(len >= 1 && len < self.nx);
        if len >= 64 {
            return self.window_and_long(src, len, dst);
        }
        let w = self.words;
        let n = (self.nx + len).div_ceil(64);
        ext[..w].copy_from_slice(src);
        ext[w..n].iter_mut().for_each(|x| *x = 0);
        // The second copy starts at cell nx (`src` is clean above nx).
        let (q, b) = (self.nx / 64, (self.nx % 64) as u32);
        for d in 0..w {
            if q + d < n {
                ext[q + d] |= src[d] << b;
            }
            if b > 0 && q + d + 1 < n {
                ext[q + d + 1] |= src[d] >> (64 - b);
            }
        }
        let ext = &mut ext[..n];
        let mut s = 1;
        while 2 * s <= len {
            and_shifted_down(ext, s);
            s *= 2;
        }
        if len > s {
            and_shifted_down(ext, len - s);
        }
        dst.copy_from_slice(&ext[..w]);
        self.clean(dst);
    }

    /// [`Self::window_and`] for `64 <= len < nx` in one backward pass over the words. With
    /// `Z = !src` the blocked cells, a window of `len >= 64` cells starting at bit `b` of word
    /// `d` reaches past the word, so it is clear exactly when `Z` has no bit at or above `b`
    /// in word `d` and the next blocked cell after the word (unrolled: the row's first blocked
    /// cell plus `nx` past the seam) lies at or beyond `64 d + b + len`. Both bounds make the
    /// result a single range of bits per word.
    fn window_and_long(&self, src: &[u64], len: usize, dst: &mut [u64]) {
        let n = self.words;
        let (src, dst) = (&src[..n], &mut dst[..n]);
        let valid = |d: usize| if d + 1 == n { self.last } else { u64::MAX };
        let Some(first) = (0..n).find(|&d| !src[d] & valid(d) != 0) else {
            // Nothing blocked: every window shorter than the row is clear.
            dst.copy_from_slice(src);
            return;
        };
        let mut next = 64 * first + (!src[first] & valid(first)).trailing_zeros() as usize + self.nx;
        for d in (0..n).rev() {
            let z = !src[d] & valid(d);
            // Clear windows start at bits lo ..= hi of the word.
            let lo = 64 - z.leading_zeros() as usize; // 0 if nothing is blocked in the word
            let hi = (next - 64 * d) as isize - len as isize;
            // Bits lo ..= hi, branch-free (empty if lo = 64 or hi < 0).
            let from_lo = (u64::MAX << (lo & 63)) & ((lo < 64) as u64).wrapping_neg();
            let to_hi = (u64::MAX >> (63 - hi.clamp(0, 63) as u32)) & ((hi >= 0) as u64).wrapping_neg();
            dst[d] = from_lo & to_hi & valid(d);
            if z != 0 {
                next = 64 * d + z.trailing_zeros() as usize;
            }
        }
    }

    /// Words of the buffer [`Self::window_and`] needs.
    pub fn ext_words(&self) -> usize {
        2 * self.words
    }

    /// Whether cell `i` is set.
    #[inline]
    pub fn get(row: &[u64], i: usize) -> bool {
        (row[i / 64] >> (i % 64)) & 1 == 1
    }

    /// Sets cell `i` to `v`.
    #[inline]
    pub fn set(row: &mut [u64], i: usize, v: bool) {
        if v {
            row[i / 64] |= 1 << (i % 64);
        } else {
            row[i / 64] &= !(1 << (i % 64));
        }
    }
}

/// The row operations on fixed-width rows (`[u64; W]` with `W = words`), for the fused
/// per-row step of [`crate::step`]: with the width a constant every word loop unrolls and the
/// row stays in registers. Each equals its slice form above (tested).
impl RowShape {
    /// [`Self::rotate_up`] by one cell.
    #[inline(always)]
    pub fn rot_up1<const W: usize>(&self, s: &[u64; W]) -> [u64; W] {
        debug_assert_eq!(W, self.words);
        let top = (s[W - 1] >> ((self.nx - 1) % 64)) & 1;
        let mut d = [0; W];
        d[0] = (s[0] << 1) | top;
        for i in 1..W {
            d[i] = (s[i] << 1) | (s[i - 1] >> 63);
        }
        d[W - 1] &= self.last;
        d
    }

    /// [`Self::rotate_down`] by one cell.
    #[inline(always)]
    pub fn rot_down1<const W: usize>(&self, s: &[u64; W]) -> [u64; W] {
        debug_assert_eq!(W, self.words);
        let mut d = [0; W];
        for i in 0..W - 1 {
            d[i] = (s[i] >> 1) | (s[i + 1] << 63);
        }
        d[W - 1] = (s[W - 1] >> 1) | ((s[0] & 1) << ((self.nx - 1) % 64));
        d
    }

    /// [`Self::rotate_up`] by `k < nx` cells (rows of at most 16 words): word `d` of the result
    /// is the 64 cells from `64 d - k` of the row shifted up without wrap, ORed with those
    /// from `64 d + nx - k` (the cells that cross the seam), read from a zero-padded copy.
    #[inline(always)]
    pub fn rot_up_w<const W: usize>(&self, s: &[u64; W], k: usize) -> [u64; W] {
        const PAD: usize = 16;
        debug_assert!(W <= PAD && k < self.nx);
        let mut p = [0u64; 3 * PAD + 2];
        p[PAD..PAD + W].copy_from_slice(s);
        // The 64 cells from signed cell `start - 64 PAD` of the padded copy.
        let win = |start: usize| {
            let (q, b) = (start / 64, (start % 64) as u32);
            (p[q] >> b) | ((p[q + 1] << 1) << (63 - b))
        };
        let (lo, hi) = (64 * PAD - k, 64 * PAD + self.nx - k);
        let mut d = [0; W];
        for i in 0..W {
            d[i] = win(lo + 64 * i) | win(hi + 64 * i);
        }
        d[W - 1] &= self.last;
        d
    }

    /// `!s` on the valid cells.
    #[inline(always)]
    pub fn not_w<const W: usize>(&self, s: &[u64; W]) -> [u64; W] {
        let mut d = s.map(|x| !x);
        d[W - 1] &= self.last;
        d
    }

    /// [`Self::reverse`].
    #[inline(always)]
    pub fn reverse_w<const W: usize>(&self, s: &[u64; W]) -> [u64; W] {
        debug_assert_eq!(W, self.words);
        let pad = W * 64 - self.nx;
        let mut d = [0; W];
        if pad == 0 {
            for i in 0..W {
                d[i] = s[W - 1 - i].reverse_bits();
            }
            return d;
        }
        let p = pad as u32;
        let mut a = s[W - 1].reverse_bits();
        for i in 0..W - 1 {
            let b = s[W - 2 - i].reverse_bits();
            d[i] = (a >> p) | (b << (64 - p));
            a = b;
        }
        d[W - 1] = a >> p;
        d[W - 1] &= self.last;
        d
    }

    /// [`Self::cyclic_add`].
    #[inline(always)]
    pub fn cyclic_add_w<const W: usize>(&self, a: &[u64; W], b: &[u64; W]) -> [u64; W] {
        let mut d = [0; W];
        let mut carry = 0u64;
        for i in 0..W {
            let (s1, c1) = a[i].overflowing_add(b[i]);
            let (s2, c2) = s1.overflowing_add(carry);
            d[i] = s2;
            carry = (c1 | c2) as u64;
        }
        let mut out = self.carry_out(&mut d, carry);
        while out {
            let mut c = 1u64;
            for w in d.iter_mut() {
                let (s, o) = w.overflowing_add(c);
                *w = s;
                c = o as u64;
                if c == 0 {
                    break;
                }
            }
            out = self.carry_out(&mut d, c);
        }
        d
    }

    /// [`Self::window_and`] (`ext` as there).
    #[inline(always)]
    pub fn window_and_w<const W: usize>(&self, src: &[u64; W], len: usize, ext: &mut [u64]) -> [u64; W] {
        let mut d = [0; W];
        if len < 64 {
            self.window_and(src, len, &mut d, ext);
            return d;
        }
        debug_assert!(len < self.nx);
        let valid = |i: usize| if i + 1 == W { self.last } else { u64::MAX };
        let Some(first) = (0..W).find(|&i| !src[i] & valid(i) != 0) else {
            return *src;
        };
        let mut next = 64 * first + (!src[first] & valid(first)).trailing_zeros() as usize + self.nx;
        for i in (0..W).rev() {
            let z = !src[i] & valid(i);
            let lo = 64 - z.leading_zeros() as usize;
            let hi = (next - 64 * i) as isize - len as isize;
            let from_lo = (u64::MAX << (lo & 63)) & ((lo < 64) as u64).wrapping_neg();
            let to_hi = (u64::MAX >> (63 - hi.clamp(0, 63) as u32)) & ((hi >= 0) as u64).wrapping_neg();
            d[i] = from_lo & to_hi & valid(i);
            if z != 0 {
                next = 64 * i + z.trailing_zeros() as usize;
            }
        }
        d
    }
}

/// `x[i] &= x[i + s]` on a non-periodic bit vector (cells beyond its end read 0), in place:
/// word `d` reads only words `>= d`, which a forward pass has not changed yet.
#[inline]
fn and_shifted_down(x: &mut [u64], s: usize) {
    let n = x.len();
    let (q, b) = (s / 64, (s % 64) as u32);
    if q >= n {
        x.iter_mut().for_each(|v| *v = 0);
        return;
    }
    let m = n - q; // words with a source word
    if b == 0 {
        for d in 0..m {
            x[d] &= x[d + q];
        }
    } else {
        for d in 0..m - 1 {
            x[d] &= (x[d + q] >> b) | (x[d + q + 1] << (64 - b));
        }
        x[m - 1] &= x[n - 1] >> b;
    }
    x[m..].iter_mut().for_each(|v| *v = 0);
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn to_bits(shape: &RowShape, cells: &[bool]) -> Vec<u64> {
        let mut r = vec![0; shape.words];
        for (i, &c) in cells.iter().enumerate() {
            RowShape::set(&mut r, i, c);
        }
        r
    }

    fn from_bits(shape: &RowShape, r: &[u64]) -> Vec<bool> {
        (0..shape.nx).map(|i| RowShape::get(r, i)).collect()
    }

    /// A pseudo-random row of `shape` with about 70 % of the cells set.
    fn random_row(shape: &RowShape, seed: u64) -> Vec<u64> {
        let mut z = seed;
        let mut r: Vec<u64> = (0..shape.words)
            .map(|_| {
                z = crate::rng::mix(z);
                let a = z;
                z = crate::rng::mix(z);
                a | z
            })
            .collect();
        shape.clean(&mut r);
        r
    }

    fn fixed_width<const W: usize>(shape: &RowShape, len: usize, k: usize, seed: u64) -> Result<(), TestCaseError> {
        let a = random_row(shape, seed);
        let b = random_row(shape, seed ^ 1);
        let aw: [u64; W] = a.clone().try_into().unwrap();
        let bw: [u64; W] = b.clone().try_into().unwrap();
        let mut d = vec![0; W];
        let mut ext = vec![0; shape.ext_words()];
        shape.rotate_up(&a, 1, &mut d);
        prop_assert_eq!(&shape.rot_up1(&aw)[..], &d[..]);
        shape.rotate_down(&a, 1, &mut d);
        prop_assert_eq!(&shape.rot_down1(&aw)[..], &d[..]);
        shape.rotate_up(&a, k, &mut d);
        prop_assert_eq!(&shape.rot_up_w(&aw, k)[..], &d[..]);
        shape.reverse(&a, &mut d);
        prop_assert_eq!(&shape.reverse_w(&aw)[..], &d[..]);
        shape.not(&a, &mut d);
        prop_assert_eq!(&shape.not_w(&aw)[..], &d[..]);
        // Free cells and single run starts after occupied cells, as the step adds them.
        let free = shape.not_w(&bw);
        let mut starts = shape.rot_up1(&bw);
        for (s, f) in starts.iter_mut().zip(&free) {
            *s &= f & aw[0];
        }
        shape.cyclic_add(&free, &starts, &mut d);
        prop_assert_eq!(&shape.cyclic_add_w(&free, &starts)[..], &d[..]);
        if len < shape.nx {
            shape.window_and(&a, len, &mut d, &mut ext);
            prop_assert_eq!(&shape.window_and_w(&aw, len, &mut ext)[..], &d[..]);
        }
        Ok(())
    }

    fn fixed_width_case(nx: usize, len: usize, k: usize, seed: u64) -> Result<(), TestCaseError> {
        let s = RowShape::new(nx);
        match s.words {
            1 => fixed_width::<1>(&s, len, k, seed),
            2 => fixed_width::<2>(&s, len, k, seed),
            3 => fixed_width::<3>(&s, len, k, seed),
            4 => fixed_width::<4>(&s, len, k, seed),
            5 => fixed_width::<5>(&s, len, k, seed),
            6 => fixed_width::<6>(&s, len, k, seed),
            7 => fixed_width::<7>(&s, len, k, seed),
            8 => fixed_width::<8>(&s, len, k, seed),
            9 => fixed_width::<9>(&s, len, k, seed),
            10 => fixed_width::<10>(&s, len, k, seed),
            11 => fixed_width::<11>(&s, len, k, seed),
            12 => fixed_width::<12>(&s, len, k, seed),
            13 => fixed_width::<13>(&s, len, k, seed),
            14 => fixed_width::<14>(&s, len, k, seed),
            15 => fixed_width::<15>(&s, len, k, seed),
            16 => fixed_width::<16>(&s, len, k, seed),
            _ => unreachable!(),
        }
    }

    proptest! {
        #[test]
        fn rotations_and_reverse_match_the_index_formulas(cells in prop::collection::vec(any::<bool>(), 1..200), k in 0usize..400) {
            let s = RowShape::new(cells.len());
            let n = cells.len();
            let src = to_bits(&s, &cells);
            let mut dst = vec![0; s.words];
            s.rotate_up(&src, k, &mut dst);
            let up = from_bits(&s, &dst);
            for i in 0..n {
                prop_assert_eq!(up[(i + k) % n], cells[i]);
            }
            s.rotate_down(&src, k, &mut dst);
            let down = from_bits(&s, &dst);
            for i in 0..n {
                prop_assert_eq!(down[i], cells[(i + k) % n]);
            }
            s.reverse(&src, &mut dst);
            let rev = from_bits(&s, &dst);
            for i in 0..n {
                prop_assert_eq!(rev[n - 1 - i], cells[i]);
            }
            prop_assert_eq!(dst[s.words - 1] & !s.last, 0);
        }

        #[test]
        fn rotations_by_one_cell_match_the_index_formulas(cells in prop::collection::vec(any::<bool>(), 1..700)) {
            let s = RowShape::new(cells.len());
            let n = cells.len();
            let src = to_bits(&s, &cells);
            let mut dst = vec![0; s.words];
            s.rotate_up(&src, 1, &mut dst);
            for i in 0..n {
                prop_assert_eq!(RowShape::get(&dst, (i + 1) % n), cells[i]);
            }
            prop_assert_eq!(dst[s.words - 1] & !s.last, 0);
            s.rotate_down(&src, 1, &mut dst);
            for i in 0..n {
                prop_assert_eq!(RowShape::get(&dst, i), cells[(i + 1) % n]);
            }
            prop_assert_eq!(dst[s.words - 1] & !s.last, 0);
        }

        #[test]
        fn window_and_is_the_periodic_and_of_len_cells(cells in prop::collection::vec(prop::bool::weighted(0.9), 2..700), len in 1usize..700) {
            let s = RowShape::new(cells.len());
            let n = cells.len();
            let len = 1 + len % (n - 1);
            let mut dst = vec![0; s.words];
            let mut ext = vec![u64::MAX; s.ext_words()];
            s.window_and(&to_bits(&s, &cells), len, &mut dst, &mut ext);
            for a in 0..n {
                let all = (0..len).all(|k| cells[(a + k) % n]);
                prop_assert_eq!(RowShape::get(&dst, a), all, "cell {} len {}", a, len);
            }
            prop_assert_eq!(dst[s.words - 1] & !s.last, 0);
        }

        #[test]
        fn fixed_width_ops_equal_the_slice_ops(words in 1usize..=16, extra in 0usize..64, len in 1usize..1100, k in 0usize..1100, seed in any::<u64>()) {
            let nx = 64 * (words - 1) + 1 + extra;
            fixed_width_case(nx, 1 + len % nx.max(2).min(nx), k % nx, seed)?;
        }
        #[test]
        fn cyclic_add_fills_runs_across_the_seam(cells in prop::collection::vec(any::<bool>(), 2..200), start in 0usize..200) {
            // One run start at a free cell after an occupied cell; the carry must stop on the
            // next occupied cell (cyclically).
            let s = RowShape::new(cells.len());
            let n = cells.len();
            let mut free = cells.clone();
            let a = start % n;
            free[a] = false;
            let b0 = (a + 1) % n;
            prop_assume!(free[b0]);
            let fb = to_bits(&s, &free);
            let mut sb = vec![0; s.words];
            RowShape::set(&mut sb, b0, true);
            let mut sum = vec![0; s.words];
            s.cyclic_add(&fb, &sb, &mut sum);
            let mut end = b0;
            while free[end] {
                end = (end + 1) % n;
            }
            for i in 0..n {
                let hit = RowShape::get(&sum, i) && !free[i];
                prop_assert_eq!(hit, i == end, "cell {} end {}", i, end);
            }
        }
    }
}
