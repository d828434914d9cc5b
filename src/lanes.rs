//! The number types BRDF terms are generic over: f32 (rendering), f64 (reference, and the `tp`
//! preset) and [`Lanes`] of either: [`F32x8`] shades eight points per instruction, [`F32x4`] the
//! three colour channels of one point (the conductor Fresnel term), [`F64x4`] four `tp` pixels.
//!
//! The terms are written once, without data-dependent `if`: a condition is a [`Real::Mask`]
//! (a `bool` for scalars, one flag per lane for [`Lanes`]) and picks values with
//! [`Real::select`] or [`Real::choose`]. For scalars that is exactly the branchy code it
//! replaces; for lanes every lane follows its own side. Every lane operation is the scalar
//! operation of that lane (IEEE-exact division and square root, the same `max`/`min` NaN rules,
//! the same `exp`/`powf`), so a lane computes what the scalar code computes, to the bit except
//! for the sign of a zero (`max(-0.0, 0.0)` may be either). `lanes::x86` holds float64 lanes as
//! vector registers, for the kernels where the compiler's grouping of array lanes falls short.

use std::ops::{Add, Div, Mul, Neg, Sub};

mod mask;
#[cfg(target_arch = "x86_64")]
pub(crate) mod x86;

pub use mask::{LaneMask, Mask, MaskWord};

/// Which instructions the eight-lane code may be compiled for, best last. Lanes give the same
/// bits with every choice (no fused multiply-add is enabled); wider registers only take fewer
/// instructions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum LaneInstructions {
    /// The target's baseline (SSE2 on x86-64): two 128-bit operations per [`F32x8`] operation.
    Portable,
    /// AVX2 (x86-64 only): one 256-bit operation per [`F32x8`] operation.
    #[cfg(target_arch = "x86_64")]
    Avx2,
    /// AVX-512F (x86-64 only): the float64 normal-map kernel runs eight lanes to a 512-bit
    /// register; the other lane code runs its AVX2 form.
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl LaneInstructions {
    /// The best this CPU runs, detected at run time (so the binary stays portable).
    pub fn detect() -> LaneInstructions {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx2") {
            return LaneInstructions::Avx512;
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return LaneInstructions::Avx2;
        }
        LaneInstructions::Portable
    }
}

/// `[f(v[0]), f(v[1]), f(v[2])]`: `array::map` for the three channels or coordinates the shading
/// path carries, written out so it is always inlined (`array::map` on [`F32x8`] elements was
/// left as a call per element, which cost the lane shader most of its speed).
#[inline(always)]
pub fn map3<T: Copy, U>(v: [T; 3], f: impl Fn(T) -> U) -> [U; 3] {
    [f(v[0]), f(v[1]), f(v[2])]
}

/// Lane `i` of a 3-vector whose coordinates are in [`F32x8`] lanes, as a `Vec3`.
#[inline(always)]
pub fn lane_vec3(v: &[F32x8; 3], i: usize) -> glam::Vec3 {
    glam::Vec3::new(v[0].0[i], v[1].0[i], v[2].0[i])
}

/// a·b of two 3-vectors, summed x, y, z in that order (as glam's `Vec3::dot`, so lanes and the
/// f32 code agree to the bit).
#[inline(always)]
pub fn dot3<R: Real>(a: [R; 3], b: [R; 3]) -> R {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// v/‖v‖, or the zero vector where that is not finite (v = 0, or ‖v‖ overflowing): glam's
/// `normalize_or_zero` (v · (1/√(v·v)), kept where the reciprocal is finite and > 0), in any
/// [`Real`].
#[inline(always)]
pub fn normalize_or_zero<R: Real>(v: [R; 3]) -> [R; 3] {
    let rcp = dot3(v, v).sqrt().recip();
    let rcp = R::select(rcp.is_finite() & rcp.gt(R::zero()), rcp, R::zero());
    map3(v, |c| c * rcp)
}

/// A floating-point type the BRDF terms can be evaluated in.
///
/// `max`/`min` follow `f32::max`/`f32::min`: a NaN operand yields the other one, which is how
/// the terms' clamps absorb NaN inputs. Comparisons are false for NaN, as `>`/`<` are.
#[allow(non_snake_case)]
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
    + std::fmt::Debug
    + 'static
{
    /// The result of a comparison.
    type Mask: Mask;

    /// The constant `v` in this precision (rounded once), in every lane.
    fn lit(v: f64) -> Self;
    /// A material parameter stored in f32, in every lane.
    fn of(v: f32) -> Self;
    /// 0.
    #[inline(always)]
    fn zero() -> Self {
        Self::lit(0.0)
    }
    /// 1.
    #[inline(always)]
    fn one() -> Self {
        Self::lit(1.0)
    }
    /// π.
    #[inline(always)]
    fn PI() -> Self {
        Self::lit(std::f64::consts::PI)
    }
    /// 1/π.
    #[inline(always)]
    fn FRAC_1_PI() -> Self {
        Self::lit(std::f64::consts::FRAC_1_PI)
    }
    /// The smallest positive normal number of the precision.
    fn min_positive_value() -> Self;

    /// The larger of the two (the other one where either is NaN).
    fn max(self, other: Self) -> Self;
    /// The smaller of the two (the other one where either is NaN).
    fn min(self, other: Self) -> Self;
    /// `self` where it is greater than `floor`, else `floor` (also where `self` is NaN): [`Real::max`]
    /// against a bound that is never NaN, as one x86 instruction (`maxpd` is exactly this
    /// select) where `max` needs three. Unlike `max`, it gives `floor` for two equal zeros, so
    /// −0 against a floor of 0 gives +0 on every path.
    #[inline(always)]
    fn at_least(self, floor: Self) -> Self {
        Self::select(self.gt(floor), self, floor)
    }
    /// `self` where it is less than `ceiling`, else `ceiling` (also where `self` is NaN):
    /// [`Real::min`] against a bound that is never NaN, as one x86 instruction (`minpd`).
    #[inline(always)]
    fn at_most(self, ceiling: Self) -> Self {
        Self::select(self.lt(ceiling), self, ceiling)
    }
    /// `self` clamped to [`low`, `high`]: [`Real::at_least`] then [`Real::at_most`], so NaN
    /// gives `low`; neither bound may be NaN.
    #[inline(always)]
    fn clamped(self, low: Self, high: Self) -> Self {
        self.at_least(low).at_most(high)
    }
    /// √self (NaN below 0).
    fn sqrt(self) -> Self;
    /// 1/self.
    fn recip(self) -> Self;
    /// |self|.
    fn abs(self) -> Self;
    /// e^self.
    fn exp(self) -> Self;
    /// 2^self.
    fn exp2(self) -> Self;
    /// ln(1 + self), accurate near 0.
    fn ln_1p(self) -> Self;
    /// self^e.
    fn powf(self, e: Self) -> Self;
    /// arccos(self) in radians (NaN outside [−1, 1]).
    fn acos(self) -> Self;

    /// self > other.
    fn gt(self, other: Self) -> Self::Mask;
    /// self ≥ other.
    fn ge(self, other: Self) -> Self::Mask;
    /// self < other.
    fn lt(self, other: Self) -> Self::Mask;
    /// self == other.
    fn eq(self, other: Self) -> Self::Mask;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> Self::Mask;

    /// `a` where `mask`, else `b`.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// This value as a plain `f32`, when `Self` is `f32` (`None` for f64 and lanes): lets a
    /// per-channel kernel run a scalar point's three channels as the lanes of one [`F32x4`]
    /// instead of one after another. Constant after inlining, so the test costs nothing.
    #[inline(always)]
    fn as_single_f32(self) -> Option<f32> {
        None
    }

    /// `a()` where `mask`, else `b()`: like [`Real::select`], but a side no lane takes is not
    /// evaluated (scalars run one side, as an `if` does).
    #[inline(always)]
    fn choose(mask: Self::Mask, a: impl FnOnce() -> Self, b: impl FnOnce() -> Self) -> Self {
        if mask.all() {
            a()
        } else if !mask.any() {
            b()
        } else {
            Self::select(mask, a(), b())
        }
    }
}

/// A scalar [`Real`] (f32 or f64): ordered, printable, convertible to f64 — what the stability
/// checks and conversions between precisions need.
pub trait Scalar: Real<Mask = bool> + PartialOrd + std::fmt::Display {
    /// The word of a lane mask of this precision ([`MaskWord`]).
    type Word: MaskWord;
    /// This value as f64 (exact for both precisions).
    fn as_f64(self) -> f64;
}

macro_rules! scalar_real {
    ($t:ty, $word:ty $(, $extra:item)*) => {
        impl Real for $t {
            type Mask = bool;
            $($extra)*
            #[inline(always)]
            fn lit(v: f64) -> Self {
                v as $t
            }
            #[inline(always)]
            fn of(v: f32) -> Self {
                v as $t
            }
            #[inline(always)]
            fn min_positive_value() -> Self {
                <$t>::MIN_POSITIVE
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                <$t>::max(self, other)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                <$t>::min(self, other)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn recip(self) -> Self {
                <$t>::recip(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                <$t>::exp(self)
            }
            #[inline(always)]
            fn exp2(self) -> Self {
                <$t>::exp2(self)
            }
            #[inline(always)]
            fn ln_1p(self) -> Self {
                <$t>::ln_1p(self)
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                <$t>::powf(self, e)
            }
            #[inline(always)]
            fn acos(self) -> Self {
                <$t>::acos(self)
            }
            #[inline(always)]
            fn gt(self, other: Self) -> bool {
                self > other
            }
            #[inline(always)]
            fn ge(self, other: Self) -> bool {
                self >= other
            }
            #[inline(always)]
            fn lt(self, other: Self) -> bool {
                self < other
            }
            #[inline(always)]
            fn eq(self, other: Self) -> bool {
                self == other
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn select(mask: bool, a: Self, b: Self) -> Self {
                if mask {
                    a
                } else {
                    b
                }
            }
        }

        impl Scalar for $t {
            type Word = $word;
            #[inline(always)]
            fn as_f64(self) -> f64 {
                self as f64
            }
        }
    };
}

scalar_real!(
    f32,
    u32,
    #[inline(always)]
    fn as_single_f32(self) -> Option<f32> {
        Some(self)
    }
);
scalar_real!(f64, u64);

/// Lanes of [`F32x8`].
pub const LANES: usize = 8;

/// The mask of [`F32x8`].
pub type Mask8 = LaneMask<u32, LANES>;

/// A [`Real`] of several lanes of one scalar precision that a kernel fills from scalars and
/// reads back: [`Lanes`], and on x86-64 the register types of the float64 kernels.
pub trait LaneArray: Real {
    /// The precision of a lane.
    type Scalar: Scalar;
    /// Lanes.
    const WIDTH: usize;
    /// Lane `i` is `f(i)`.
    fn from_fn(f: impl Fn(usize) -> Self::Scalar) -> Self;
    /// Lane `i` into `out[i]`, for every lane (`out` holds at least [`LaneArray::WIDTH`]).
    fn write_to(self, out: &mut [Self::Scalar]);
}

impl<T: Scalar, const N: usize> LaneArray for Lanes<T, N> {
    type Scalar = T;
    const WIDTH: usize = N;
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> T) -> Self {
        Lanes::from_fn(f)
    }
    #[inline(always)]
    fn write_to(self, out: &mut [T]) {
        out[..N].copy_from_slice(&self.0);
    }
}

/// N values of one scalar precision operated on together. Plain arrays with per-lane loops: the
/// compiler turns them into SIMD instructions on any target, with no `unsafe`. Each lane
/// operation is the scalar [`Real`] operation of `T`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes<T, const N: usize>(pub [T; N]);

/// Eight f32 lanes (two SSE or one AVX register): the lane shader's points.
pub type F32x8 = Lanes<f32, LANES>;

/// Four f32 lanes (one SSE register): the three colour channels of one point, and a spare.
pub type F32x4 = Lanes<f32, 4>;

/// Four f64 lanes (one AVX register): the points of the normal-map `tp` preset, which shades
/// in float64.
pub type F64x4 = Lanes<f64, 4>;

impl<T: Scalar, const N: usize> Lanes<T, N> {
    /// Every lane `v`.
    #[inline(always)]
    pub fn splat(v: T) -> Self {
        Lanes([v; N])
    }

    /// Lane `i` is `f(i)`. (Plain loops: `array::map` and `from_fn` are not always inlined.)
    #[inline(always)]
    pub fn from_fn(f: impl Fn(usize) -> T) -> Self {
        let mut v = [T::zero(); N];
        for (i, v) in v.iter_mut().enumerate() {
            *v = f(i);
        }
        Lanes(v)
    }

    #[inline(always)]
    fn map(self, f: impl Fn(T) -> T) -> Self {
        Self::from_fn(|i| f(self.0[i]))
    }

    #[inline(always)]
    fn zip(self, other: Self, f: impl Fn(T, T) -> T) -> Self {
        Self::from_fn(|i| f(self.0[i], other.0[i]))
    }

    #[inline(always)]
    fn compare(self, other: Self, f: impl Fn(T, T) -> bool) -> LaneMask<T::Word, N> {
        LaneMask::from_fn(|i| f(self.0[i], other.0[i]))
    }
}

macro_rules! lane_ops {
    ($($op:ident $method:ident $sym:tt),+) => {$(
        impl<T: Scalar, const N: usize> $op for Lanes<T, N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                self.zip(other, |a, b| a $sym b)
            }
        }
    )+};
}
lane_ops!(Add add +, Sub sub -, Mul mul *, Div div /);

impl<T: Scalar, const N: usize> Neg for Lanes<T, N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<T: Scalar, const N: usize> Real for Lanes<T, N> {
    type Mask = LaneMask<T::Word, N>;
    #[inline(always)]
    fn lit(v: f64) -> Self {
        Self::splat(T::lit(v))
    }
    #[inline(always)]
    fn of(v: f32) -> Self {
        Self::splat(T::of(v))
    }
    #[inline(always)]
    fn min_positive_value() -> Self {
        Self::splat(T::min_positive_value())
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        self.zip(other, T::max)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        self.zip(other, T::min)
    }
    #[inline(always)]
    fn at_least(self, floor: Self) -> Self {
        self.zip(floor, T::at_least)
    }
    #[inline(always)]
    fn at_most(self, ceiling: Self) -> Self {
        self.zip(ceiling, T::at_most)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(T::sqrt)
    }
    #[inline(always)]
    fn recip(self) -> Self {
        self.map(T::recip)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(T::abs)
    }
    // The transcendental functions call the scalar ones lane by lane: the same values as the
    // scalar code (a vector approximation would differ in the last bits).
    #[inline(always)]
    fn exp(self) -> Self {
        self.map(T::exp)
    }
    #[inline(always)]
    fn exp2(self) -> Self {
        self.map(T::exp2)
    }
    #[inline(always)]
    fn ln_1p(self) -> Self {
        self.map(T::ln_1p)
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        self.zip(e, T::powf)
    }
    #[inline(always)]
    fn acos(self) -> Self {
        self.map(T::acos)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> LaneMask<T::Word, N> {
        self.compare(other, |a, b| a > b)
    }
    #[inline(always)]
    fn ge(self, other: Self) -> LaneMask<T::Word, N> {
        self.compare(other, |a, b| a >= b)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> LaneMask<T::Word, N> {
        self.compare(other, |a, b| a < b)
    }
    #[inline(always)]
    fn eq(self, other: Self) -> LaneMask<T::Word, N> {
        self.compare(other, |a, b| a == b)
    }
    #[inline(always)]
    fn is_finite(self) -> LaneMask<T::Word, N> {
        // a·0 = 0 exactly when a is finite (∞·0 and NaN·0 are NaN): a vector multiply and
        // compare. Written as a class test (`is_finite`, or |a| < ∞ next to a > 0), the
        // compiler merges it into one floating-point class query that x86 evaluates lane by lane.
        (self * Self::splat(T::zero())).eq(Self::splat(T::zero()))
    }
    #[inline(always)]
    fn select(mask: LaneMask<T::Word, N>, a: Self, b: Self) -> Self {
        // A lane of a mask is all ones or all zeros, so its sign bit decides: the form the
        // compiler turns into one blend instruction (a bitwise and/andnot/or takes three).
        Self::from_fn(|i| if mask.0[i].is_set() { a.0[i] } else { b.0[i] })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_follow_the_f32_rules_for_nan() {
        let a = Lanes([f32::NAN, 1.0, -0.0, 0.0, f32::INFINITY, -1.0, 2.0, f32::NAN]);
        let b = Lanes([1.0, f32::NAN, 0.0, -0.0, 1.0, -2.0, 2.0, f32::NAN]);
        for i in 0..LANES {
            let (x, y) = (a.0[i], b.0[i]);
            // Equal as numbers: `f32::max(-0.0, 0.0)` may return either zero, and does differ
            // between the scalar and the vector instructions.
            let same = |u: f32, v: f32| u == v || (u.is_nan() && v.is_nan());
            assert!(same(a.max(b).0[i], x.max(y)), "max lane {i}");
            assert!(same(a.min(b).0[i], x.min(y)), "min lane {i}");
            assert_eq!(a.gt(b).test(i), x > y);
            assert_eq!(a.eq(b).test(i), x == y);
            assert_eq!(a.is_finite().test(i), x.is_finite());
            assert!(same((a / b).0[i], x / y), "division lane {i}");
        }
    }

    #[test]
    fn select_and_choose_pick_per_lane_and_skip_unused_sides() {
        let m = Mask8::from_fn(|i| i % 3 == 0);
        let s = F32x8::select(m, F32x8::splat(1.0), F32x8::splat(2.0));
        assert_eq!(s.0, [1.0, 2.0, 2.0, 1.0, 2.0, 2.0, 1.0, 2.0]);
        assert!(!m.all() && m.any() && (m | !m).all() && !(m & !m).any());
        let none = Mask8::from_fn(|_| false);
        let v = F32x8::choose(none, || panic!("no lane takes this side"), || F32x8::splat(3.0));
        assert_eq!(v, F32x8::splat(3.0));
        assert_eq!(f32::choose(true, || 1.0, || panic!("not evaluated")), 1.0);
    }
}
