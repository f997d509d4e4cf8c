//! Lanes: the number type the force laws are written over. `f64` is one contact (particle
//! pairs, and any contact evaluated alone); [`F64x4`] is four contacts of consecutive grains
//! with the same wall, evaluated side by side (the floor pass). Every operation is the IEEE
//! operation of each lane, in the same order, so a contact gives the same bits in either.
//!
//! Branches of a law are written as [`Lane::select`]s; work that only some lanes need sits
//! behind [`Lane::any`], so the one-contact instance branches as scalar code would.

use crate::Vec3;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub};

/// A number of one or more lanes.
pub trait Lane:
    Copy
    + std::fmt::Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + MulAssign
{
    /// One truth value per lane.
    type Mask: Copy + std::ops::BitOr<Output = Self::Mask>;
    fn splat(x: f64) -> Self;
    fn sqrt(self) -> Self;
    /// Per lane `f64::max`.
    fn max(self, other: Self) -> Self;
    /// `self <= other` per lane.
    fn le(self, other: Self) -> Self::Mask;
    /// `self < other` per lane.
    fn lt(self, other: Self) -> Self::Mask;
    /// `self == other` per lane.
    fn equal(self, other: Self) -> Self::Mask;
    /// The same truth value in every lane.
    fn mask(b: bool) -> Self::Mask;
    /// Per lane `if m { a } else { b }`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// True if some lane is true.
    fn any(m: Self::Mask) -> bool;
    /// True if every lane is true.
    fn all(m: Self::Mask) -> bool;
}

impl Lane for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn le(self, other: Self) -> bool {
        self <= other
    }
    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn equal(self, other: Self) -> bool {
        self == other
    }
    #[inline(always)]
    fn mask(b: bool) -> bool {
        b
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn any(m: bool) -> bool {
        m
    }
    #[inline(always)]
    fn all(m: bool) -> bool {
        m
    }
}

/// Four `f64` lanes: plain arrays whose element-wise loops the compiler turns into vector
/// instructions (two SSE2 registers on baseline x86-64; one AVX register in code compiled
/// for AVX2, see `forces::floor_pass`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct F64x4(pub [f64; 4]);

/// Four lane masks: all bits set for true, none for false.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct Mask4(pub [u64; 4]);

impl F64x4 {
    #[inline(always)]
    pub fn new(a: [f64; 4]) -> Self {
        Self(a)
    }
    #[inline(always)]
    pub fn to_array(self) -> [f64; 4] {
        self.0
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Self([f(self.0[0]), f(self.0[1]), f(self.0[2]), f(self.0[3])])
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Self([
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ])
    }
    #[inline(always)]
    fn compare(self, o: Self, f: impl Fn(f64, f64) -> bool) -> Mask4 {
        let m = |k: usize| 0u64.wrapping_sub(f(self.0[k], o.0[k]) as u64);
        Mask4([m(0), m(1), m(2), m(3)])
    }
}

impl Mask4 {
    /// Bit `l` set if lane `l` is true.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        (0..4).fold(0, |b, l| b | (((self.0[l] >> 63) as u32) << l))
    }
}

impl std::ops::BitOr for Mask4 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        Self([self.0[0] | o.0[0], self.0[1] | o.0[1], self.0[2] | o.0[2], self.0[3] | o.0[3]])
    }
}

macro_rules! lanewise {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for F64x4 {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl AddAssign for F64x4 {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl MulAssign for F64x4 {
    #[inline(always)]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl Lane for F64x4 {
    type Mask = Mask4;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Self([x; 4])
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        // `maxpd`'s rule (the second operand when one is NaN), which equals `f64::max`
        // whenever `other` is not NaN (the laws compare with constants).
        self.zip(other, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn le(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a <= b)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a < b)
    }
    #[inline(always)]
    fn equal(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a == b)
    }
    #[inline(always)]
    fn mask(b: bool) -> Mask4 {
        Mask4([0u64.wrapping_sub(b as u64); 4])
    }
    #[inline(always)]
    fn select(m: Mask4, a: Self, b: Self) -> Self {
        let s = |k: usize| f64::from_bits((m.0[k] & a.0[k].to_bits()) | (!m.0[k] & b.0[k].to_bits()));
        Self([s(0), s(1), s(2), s(3)])
    }
    #[inline(always)]
    fn any(m: Mask4) -> bool {
        (m.0[0] | m.0[1] | m.0[2] | m.0[3]) != 0
    }
    #[inline(always)]
    fn all(m: Mask4) -> bool {
        (m.0[0] & m.0[1] & m.0[2] & m.0[3]) != 0
    }
}

/// A vector whose components are lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct V3<L> {
    pub x: L,
    pub y: L,
    pub z: L,
}

impl<L: Lane> V3<L> {
    #[inline(always)]
    pub fn new(x: L, y: L, z: L) -> Self {
        Self { x, y, z }
    }
    #[inline(always)]
    pub fn zeros() -> Self {
        Self::splat(Vec3::zeros())
    }
    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        Self::new(L::splat(v.x), L::splat(v.y), L::splat(v.z))
    }
    #[inline(always)]
    pub fn get(&self, k: usize) -> L {
        match k {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }
    #[inline(always)]
    pub fn set(&mut self, k: usize, v: L) {
        match k {
            0 => self.x = v,
            1 => self.y = v,
            _ => self.z = v,
        }
    }
    #[inline(always)]
    pub fn scale(self, s: L) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
    /// `(x x + y y) + z z`, nalgebra's order.
    #[inline(always)]
    pub fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub fn norm_squared(self) -> L {
        self.dot(self)
    }
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    #[inline(always)]
    pub fn select(m: L::Mask, a: Self, b: Self) -> Self {
        Self::new(L::select(m, a.x, b.x), L::select(m, a.y, b.y), L::select(m, a.z, b.z))
    }
}

impl<L: Lane> Add for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<L: Lane> Sub for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<L: Lane> Neg for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl From<Vec3> for V3<f64> {
    #[inline(always)]
    fn from(v: Vec3) -> Self {
        Self::new(v.x, v.y, v.z)
    }
}

impl From<V3<f64>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f64>) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl V3<F64x4> {
    /// Lanes `k[0..4]` of `a`.
    #[inline(always)]
    pub fn gather(a: &[Vec3], k: [usize; 4]) -> Self {
        let (p, q, r, s) = (a[k[0]], a[k[1]], a[k[2]], a[k[3]]);
        Self::new(
            F64x4([p.x, q.x, r.x, s.x]),
            F64x4([p.y, q.y, r.y, s.y]),
            F64x4([p.z, q.z, r.z, s.z]),
        )
    }

    /// Lane `l` as a vector.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> Vec3 {
        Vec3::new(self.x.0[l], self.y.0[l], self.z.0[l])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_give_the_bits_of_one_number() {
        let xs = [0.3, -1.7, 2.9e-7, 5.0];
        let ys = [1.1, 0.0, -3.0, 5.0];
        let (a, b) = (F64x4::new(xs), F64x4::new(ys));
        let lanes = [
            (a + b).to_array(),
            (a - b).to_array(),
            (a * b).to_array(),
            (a / F64x4::splat(3.0)).to_array(),
            Lane::sqrt(a * a).to_array(),
            Lane::max(a, F64x4::splat(0.0)).to_array(),
            <F64x4 as Lane>::select(Lane::le(a, b), a, b).to_array(),
        ];
        for l in 0..4 {
            let (x, y) = (xs[l], ys[l]);
            let one = [x + y, x - y, x * y, x / 3.0, (x * x).sqrt(), x.max(0.0), if x <= y { x } else { y }];
            for (k, v) in one.iter().enumerate() {
                assert_eq!(lanes[k][l].to_bits(), v.to_bits(), "op {k} lane {l}");
            }
        }
        let m = Lane::lt(a, F64x4::splat(0.0));
        assert!(<F64x4 as Lane>::any(m) && !<F64x4 as Lane>::all(m));
        assert!(<F64x4 as Lane>::all(<F64x4 as Lane>::mask(true)));
    }
}
