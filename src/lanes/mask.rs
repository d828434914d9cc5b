//! Conditions per lane: the [`Mask`] trait (a `bool` for scalars), and [`LaneMask`], the mask of
//! `Lanes`, in words as wide as the lanes' numbers ([`MaskWord`]).

use std::ops::{BitAnd, BitOr, Not};

/// A condition per lane: `bool` for scalars, `LaneMask` for lanes.
pub trait Mask:
    Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> + PartialEq + std::fmt::Debug
{
    /// `v` in every lane.
    fn splat(v: bool) -> Self;
    /// True in every lane.
    fn all(self) -> bool;
    /// True in at least one lane.
    fn any(self) -> bool;
}

impl Mask for bool {
    #[inline(always)]
    fn splat(v: bool) -> Self {
        v
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
}

/// The word of one lane of a [`LaneMask`]: as wide as the lane's number (u32 for f32, u64 for
/// f64), so a comparison's result is used as the SIMD instruction produced it, with no packing
/// or widening between the compare and the blend.
pub trait MaskWord: Copy + PartialEq + Eq + std::fmt::Debug + Send + Sync + 'static {
    /// All bits clear (false).
    const CLEAR: Self;
    /// All bits set (true).
    const SET: Self;
    /// Whether the sign bit is set: the one bit a blend instruction reads.
    fn is_set(self) -> bool;
    /// Bitwise and.
    fn and(self, other: Self) -> Self;
    /// Bitwise or.
    fn or(self, other: Self) -> Self;
    /// Bitwise not.
    fn not(self) -> Self;
}

macro_rules! mask_word {
    ($($w:ty => $signed:ty),+) => {$(
        impl MaskWord for $w {
            const CLEAR: Self = 0;
            const SET: Self = <$w>::MAX;
            #[inline(always)]
            fn is_set(self) -> bool {
                (self as $signed) < 0
            }
            #[inline(always)]
            fn and(self, other: Self) -> Self {
                self & other
            }
            #[inline(always)]
            fn or(self, other: Self) -> Self {
                self | other
            }
            #[inline(always)]
            fn not(self) -> Self {
                !self
            }
        }
    )+};
}
mask_word!(u32 => i32, u64 => i64);

/// A per-lane condition of `Lanes`: all bits set for true, clear for false (the layout SIMD
/// comparisons produce), in words as wide as the lanes' numbers ([`MaskWord`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LaneMask<W, const N: usize>(pub [W; N]);

impl<W: MaskWord, const N: usize> LaneMask<W, N> {
    /// Lane `i` is `f(i)`.
    #[inline(always)]
    pub fn from_fn(f: impl Fn(usize) -> bool) -> Self {
        let mut m = [W::CLEAR; N];
        for (i, m) in m.iter_mut().enumerate() {
            *m = if f(i) { W::SET } else { W::CLEAR };
        }
        LaneMask(m)
    }

    /// Lane `i`.
    #[inline(always)]
    pub fn test(self, i: usize) -> bool {
        self.0[i] != W::CLEAR
    }
}

macro_rules! mask_ops {
    ($($op:ident $method:ident $word:ident),+) => {$(
        impl<W: MaskWord, const N: usize> $op for LaneMask<W, N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                let mut m = self.0;
                for (m, o) in m.iter_mut().zip(other.0) {
                    *m = m.$word(o);
                }
                LaneMask(m)
            }
        }
    )+};
}
mask_ops!(BitAnd bitand and, BitOr bitor or);

impl<W: MaskWord, const N: usize> Not for LaneMask<W, N> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        let mut m = self.0;
        for m in m.iter_mut() {
            *m = m.not();
        }
        LaneMask(m)
    }
}

impl<W: MaskWord, const N: usize> Mask for LaneMask<W, N> {
    #[inline(always)]
    fn splat(v: bool) -> Self {
        LaneMask::from_fn(|_| v)
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.0.iter().fold(W::SET, |a, &m| a.and(m)) != W::CLEAR
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(W::CLEAR, |a, &m| a.or(m)) != W::CLEAR
    }
}
