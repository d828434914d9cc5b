//! Float64 lanes as x86 vector registers: [`F64x4Avx`] (four lanes in a 256-bit AVX register)
//! and [`F64x8Avx512`] (eight in a 512-bit AVX-512F register), each operation one instruction.
//!
//! Why not [`Lanes<f64, N>`](super::Lanes): plain arrays leave the grouping of lanes into
//! registers to the compiler, and for float64 it regroups them badly — comparisons give four
//! one-bit flags that AVX2 keeps as 32-bit words, so every select between a comparison and its
//! use packs and widens, and the optimiser then vectorises the x, y and z of a vector together
//! instead of the lanes. Here a lane operation is the instruction, written once.
//!
//! Every operation is the IEEE operation of each lane (division, square root, no fused
//! multiply-add), and `max`/`min` follow `f64::max`/`f64::min` for NaN, so a lane computes what
//! [`Lanes<f64, N>`](super::Lanes) and the scalar code compute, to the bit (up to the sign of a
//! zero from `max`/`min`). The transcendental functions run the scalar ones lane by lane.
//!
//! # Safety
//! The intrinsics need the CPU features. These types are crate-private and are only created
//! inside functions compiled with `#[target_feature(enable = "avx2")]` (for [`F64x4Avx`]) or
//! `"avx2,avx512f"` ([`F64x8Avx512`]) that are called after the feature was detected
//! ([`LaneInstructions::detect`](super::LaneInstructions::detect)). Every `unsafe` block below
//! relies on that, and nothing else.

use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use super::{LaneArray, Mask, Real};

/// Four float64 lanes in an AVX register (see the module's safety note).
#[derive(Clone, Copy, Debug)]
pub(crate) struct F64x4Avx(__m256d);

/// The mask of [`F64x4Avx`]: each lane all ones (true) or all zeros, as `vcmppd` makes it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mask64x4(__m256d);

/// Eight float64 lanes in an AVX-512 register (see the module's safety note).
#[derive(Clone, Copy, Debug)]
pub(crate) struct F64x8Avx512(__m512d);

/// The mask of [`F64x8Avx512`]: one bit per lane, as AVX-512 comparisons make it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Mask64x8(__mmask8);

impl F64x4Avx {
    /// The lanes `v`.
    #[inline(always)]
    pub(crate) fn from_array(v: [f64; 4]) -> Self {
        // SAFETY: AVX is enabled where these types exist (module note).
        F64x4Avx(unsafe { _mm256_loadu_pd(v.as_ptr()) })
    }

    /// The lanes as an array.
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f64; 4] {
        let mut v = [0.0; 4];
        // SAFETY: as above; `v` holds four f64.
        unsafe { _mm256_storeu_pd(v.as_mut_ptr(), self.0) };
        v
    }
}

impl F64x8Avx512 {
    /// The lanes `v`.
    #[inline(always)]
    pub(crate) fn from_array(v: [f64; 8]) -> Self {
        // SAFETY: AVX-512F is enabled where these types exist (module note).
        F64x8Avx512(unsafe { _mm512_loadu_pd(v.as_ptr()) })
    }

    /// The lanes as an array.
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f64; 8] {
        let mut v = [0.0; 8];
        // SAFETY: as above; `v` holds eight f64.
        unsafe { _mm512_storeu_pd(v.as_mut_ptr(), self.0) };
        v
    }
}

/// The operators and [`Real`] for one register type: `$v` the lanes, `$m` their mask, and the
/// intrinsic of each operation.
macro_rules! f64_register_lanes {
    (
        $v:ident, $m:ident, $n:literal,
        splat: $splat:ident, add: $add:ident, sub: $sub:ident, mul: $mul:ident, div: $div:ident,
        max: $max:ident, min: $min:ident, sqrt: $sqrt:ident, xor: $xor:ident, andnot: $andnot:ident,
        cmp: $cmp:ident, blend: |$mask:ident, $x:ident, $y:ident| $blend:expr,
    ) => {
        impl $v {
            #[inline(always)]
            fn splat(v: f64) -> Self {
                // SAFETY: module note.
                $v(unsafe { $splat(v) })
            }

            #[inline(always)]
            fn map(self, f: impl Fn(f64) -> f64) -> Self {
                let v = self.to_array();
                <Self as LaneArray>::from_fn(|i| f(v[i]))
            }

            /// The comparison `P` (an `_CMP_*` predicate) of each lane.
            #[inline(always)]
            fn compare<const P: i32>(self, other: Self) -> $m {
                // SAFETY: module note.
                $m(unsafe { $cmp::<P>(self.0, other.0) })
            }

            /// `x` where `mask`, else `y`.
            #[inline(always)]
            fn blend($mask: $m, $x: Self, $y: Self) -> Self {
                let ($mask, $x, $y) = ($mask.0, $x.0, $y.0);
                // SAFETY: module note.
                $v(unsafe { $blend })
            }
        }

        impl Add for $v {
            type Output = Self;
            #[inline(always)]
            fn add(self, other: Self) -> Self {
                // SAFETY: module note.
                $v(unsafe { $add(self.0, other.0) })
            }
        }

        impl Sub for $v {
            type Output = Self;
            #[inline(always)]
            fn sub(self, other: Self) -> Self {
                // SAFETY: module note.
                $v(unsafe { $sub(self.0, other.0) })
            }
        }

        impl Mul for $v {
            type Output = Self;
            #[inline(always)]
            fn mul(self, other: Self) -> Self {
                // SAFETY: module note.
                $v(unsafe { $mul(self.0, other.0) })
            }
        }

        impl Div for $v {
            type Output = Self;
            #[inline(always)]
            fn div(self, other: Self) -> Self {
                // SAFETY: module note.
                $v(unsafe { $div(self.0, other.0) })
            }
        }

        impl Neg for $v {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                // The sign bit flipped, as `-x` does (also for 0 and NaN).
                // SAFETY: module note.
                $v(unsafe { $xor(self.0, $splat(-0.0)) })
            }
        }

        impl Real for $v {
            type Mask = $m;
            #[inline(always)]
            fn lit(v: f64) -> Self {
                Self::splat(v)
            }
            #[inline(always)]
            fn of(v: f32) -> Self {
                Self::splat(v as f64)
            }
            #[inline(always)]
            fn min_positive_value() -> Self {
                Self::splat(f64::MIN_POSITIVE)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                // The instruction returns its second operand where either is NaN: `other`
                // first gives `self` there; then a NaN `self` gives `other` (f64::max).
                // SAFETY: module note.
                let m = $v(unsafe { $max(other.0, self.0) });
                Self::blend(self.compare::<_CMP_UNORD_Q>(self), other, m)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                // SAFETY: module note.
                let m = $v(unsafe { $min(other.0, self.0) });
                Self::blend(self.compare::<_CMP_UNORD_Q>(self), other, m)
            }
            #[inline(always)]
            fn at_least(self, floor: Self) -> Self {
                // `vmaxpd a, b` is `a > b ? a : b`: the trait's definition.
                // SAFETY: module note.
                $v(unsafe { $max(self.0, floor.0) })
            }
            #[inline(always)]
            fn at_most(self, ceiling: Self) -> Self {
                // `vminpd a, b` is `a < b ? a : b`.
                // SAFETY: module note.
                $v(unsafe { $min(self.0, ceiling.0) })
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // SAFETY: module note.
                $v(unsafe { $sqrt(self.0) })
            }
            #[inline(always)]
            fn recip(self) -> Self {
                Self::splat(1.0) / self
            }
            #[inline(always)]
            fn abs(self) -> Self {
                // The sign bit cleared.
                // SAFETY: module note.
                $v(unsafe { $andnot($splat(-0.0), self.0) })
            }
            #[inline(always)]
            fn exp(self) -> Self {
                self.map(f64::exp)
            }
            #[inline(always)]
            fn exp2(self) -> Self {
                self.map(f64::exp2)
            }
            #[inline(always)]
            fn ln_1p(self) -> Self {
                self.map(f64::ln_1p)
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                let (a, b) = (self.to_array(), e.to_array());
                <Self as LaneArray>::from_fn(|i| a[i].powf(b[i]))
            }
            #[inline(always)]
            fn acos(self) -> Self {
                self.map(f64::acos)
            }
            #[inline(always)]
            fn gt(self, other: Self) -> $m {
                self.compare::<_CMP_GT_OQ>(other)
            }
            #[inline(always)]
            fn ge(self, other: Self) -> $m {
                self.compare::<_CMP_GE_OQ>(other)
            }
            #[inline(always)]
            fn lt(self, other: Self) -> $m {
                self.compare::<_CMP_LT_OQ>(other)
            }
            #[inline(always)]
            fn eq(self, other: Self) -> $m {
                self.compare::<_CMP_EQ_OQ>(other)
            }
            #[inline(always)]
            fn is_finite(self) -> $m {
                // a·0 = 0 exactly when a is finite (∞·0 and NaN·0 are NaN).
                (self * Self::splat(0.0)).eq(Self::splat(0.0))
            }
            #[inline(always)]
            fn select(mask: $m, a: Self, b: Self) -> Self {
                Self::blend(mask, a, b)
            }
        }

        const _: () = assert!(std::mem::size_of::<$v>() == 8 * $n);
    };
}

f64_register_lanes!(
    F64x4Avx, Mask64x4, 4,
    splat: _mm256_set1_pd, add: _mm256_add_pd, sub: _mm256_sub_pd, mul: _mm256_mul_pd,
    div: _mm256_div_pd, max: _mm256_max_pd, min: _mm256_min_pd, sqrt: _mm256_sqrt_pd,
    xor: _mm256_xor_pd, andnot: _mm256_andnot_pd,
    cmp: _mm256_cmp_pd, blend: |mask, x, y| _mm256_blendv_pd(y, x, mask),
);

f64_register_lanes!(
    F64x8Avx512, Mask64x8, 8,
    splat: _mm512_set1_pd, add: _mm512_add_pd, sub: _mm512_sub_pd, mul: _mm512_mul_pd,
    div: _mm512_div_pd, max: _mm512_max_pd, min: _mm512_min_pd, sqrt: _mm512_sqrt_pd,
    xor: xor_512, andnot: andnot_512,
    cmp: _mm512_cmp_pd_mask, blend: |mask, x, y| _mm512_mask_blend_pd(mask, y, x),
);

impl LaneArray for F64x4Avx {
    type Scalar = f64;
    const WIDTH: usize = 4;
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> f64) -> Self {
        // A plain loop: `array::from_fn` is not always inlined.
        let mut v = [0.0; 4];
        for (i, v) in v.iter_mut().enumerate() {
            *v = f(i);
        }
        Self::from_array(v)
    }
    #[inline(always)]
    fn write_to(self, out: &mut [f64]) {
        out[..4].copy_from_slice(&self.to_array());
    }
}

impl LaneArray for F64x8Avx512 {
    type Scalar = f64;
    const WIDTH: usize = 8;
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> f64) -> Self {
        // A plain loop: `array::from_fn` is not always inlined.
        let mut v = [0.0; 8];
        for (i, v) in v.iter_mut().enumerate() {
            *v = f(i);
        }
        Self::from_array(v)
    }
    #[inline(always)]
    fn write_to(self, out: &mut [f64]) {
        out[..8].copy_from_slice(&self.to_array());
    }
}

/// a XOR b bitwise, in AVX-512F alone (`_mm512_xor_pd` needs AVX-512DQ).
#[inline(always)]
unsafe fn xor_512(a: __m512d, b: __m512d) -> __m512d {
    // SAFETY: the caller's (module note).
    unsafe { _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b))) }
}

/// (NOT a) AND b bitwise, in AVX-512F alone (`_mm512_andnot_pd` needs AVX-512DQ).
#[inline(always)]
unsafe fn andnot_512(a: __m512d, b: __m512d) -> __m512d {
    // SAFETY: the caller's (module note).
    unsafe { _mm512_castsi512_pd(_mm512_andnot_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b))) }
}

impl Mask64x4 {
    /// One bit per lane: its sign bit.
    #[inline(always)]
    fn bits(self) -> i32 {
        // SAFETY: module note.
        unsafe { _mm256_movemask_pd(self.0) }
    }
}

/// Masks are equal where every lane is (lanes are all ones or all zeros).
impl PartialEq for Mask64x4 {
    fn eq(&self, other: &Self) -> bool {
        self.bits() == other.bits()
    }
}

impl BitAnd for Mask64x4 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, other: Self) -> Self {
        // SAFETY: module note.
        Mask64x4(unsafe { _mm256_and_pd(self.0, other.0) })
    }
}

impl BitOr for Mask64x4 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, other: Self) -> Self {
        // SAFETY: module note.
        Mask64x4(unsafe { _mm256_or_pd(self.0, other.0) })
    }
}

impl Not for Mask64x4 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        // SAFETY: module note.
        Mask64x4(unsafe { _mm256_xor_pd(self.0, Mask64x4::splat(true).0) })
    }
}

impl Mask for Mask64x4 {
    #[inline(always)]
    fn splat(v: bool) -> Self {
        // SAFETY: module note.
        Mask64x4(unsafe { _mm256_castsi256_pd(_mm256_set1_epi64x(-(v as i64))) })
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.bits() == 0b1111
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.bits() != 0
    }
}

impl BitAnd for Mask64x8 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, other: Self) -> Self {
        Mask64x8(self.0 & other.0)
    }
}

impl BitOr for Mask64x8 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, other: Self) -> Self {
        Mask64x8(self.0 | other.0)
    }
}

impl Not for Mask64x8 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        Mask64x8(!self.0)
    }
}

impl Mask for Mask64x8 {
    #[inline(always)]
    fn splat(v: bool) -> Self {
        Mask64x8(if v { u8::MAX } else { 0 })
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.0 == u8::MAX
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0 != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values that exercise every rule: signed zeros, NaN, infinities, subnormals, the ends of
    /// the range and ordinary numbers.
    const VALUES: [f64; 16] = [
        0.0,
        -0.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MIN_POSITIVE / 8.0,
        f64::MIN_POSITIVE,
        f64::MAX,
        -f64::MAX,
        1.0,
        -1.0,
        0.1,
        3.0,
        -2.5,
        1e-300,
        7e15,
    ];

    /// Equal bits, or both NaN, or both zeros where `zero_sign_free` (max/min may pick either).
    fn same(a: f64, b: f64, zero_sign_free: bool) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()) || (zero_sign_free && a == 0.0 && b == 0.0)
    }

    /// An operation's name, its lanes' result and the f64 operation.
    type Unary<V> = (&'static str, V, fn(f64) -> f64);
    /// A binary operation's name, result, f64 operation, and whether a zero's sign may differ.
    type Binary<V> = (&'static str, V, fn(f64, f64) -> f64, bool);

    /// Every operation of `V` on every pair of [`VALUES`] in every lane against the f64 one.
    #[inline(always)]
    fn check<V: LaneArray<Scalar = f64>>() {
        for (k, &b) in VALUES.iter().enumerate() {
            // Lane i holds VALUES[(i + offset) % 16] against `b`, for every offset.
            for offset in 0..VALUES.len() {
                let a_of = |i: usize| VALUES[(i + offset) % VALUES.len()];
                let (a, bv) = (V::from_fn(a_of), V::lit(b));
                let unary: [Unary<V>; 5] = [
                    ("sqrt", a.sqrt(), f64::sqrt),
                    ("recip", a.recip(), f64::recip),
                    ("abs", a.abs(), f64::abs),
                    ("neg", -a, |x| -x),
                    ("exp", a.exp(), f64::exp),
                ];
                let binary: [Binary<V>; 9] = [
                    ("add", a + bv, |x, y| x + y, false),
                    ("sub", a - bv, |x, y| x - y, false),
                    ("mul", a * bv, |x, y| x * y, false),
                    ("div", a / bv, |x, y| x / y, false),
                    ("max", a.max(bv), f64::max, true),
                    ("min", a.min(bv), f64::min, true),
                    // Exact bits, zeros' signs included: the trait defines them by a select.
                    ("at_least", a.at_least(bv), |x, y| if x > y { x } else { y }, false),
                    ("at_most", a.at_most(bv), |x, y| if x < y { x } else { y }, false),
                    ("powf", a.powf(bv), f64::powf, false),
                ];
                let mut out = [0.0; 8];
                for (name, v, f) in unary {
                    v.write_to(&mut out);
                    for (i, &o) in out.iter().enumerate().take(V::WIDTH) {
                        assert!(same(o, f(a_of(i)), false), "{name}({}) lane {i}: {o}", a_of(i));
                    }
                }
                for (name, v, f, zero_sign_free) in binary {
                    v.write_to(&mut out);
                    for (i, &o) in out.iter().enumerate().take(V::WIDTH) {
                        let expected = f(a_of(i), b);
                        assert!(
                            same(o, expected, zero_sign_free),
                            "{name}({}, {b}) lane {i}: {o}",
                            a_of(i)
                        );
                    }
                }
                let masks = [
                    ("gt", a.gt(bv), (|x, y| x > y) as fn(f64, f64) -> bool),
                    ("ge", a.ge(bv), |x, y| x >= y),
                    ("lt", a.lt(bv), |x, y| x < y),
                    ("eq", a.eq(bv), |x, y| x == y),
                    ("finite", a.is_finite(), |x, _| x.is_finite()),
                ];
                for (name, m, f) in masks {
                    // A mask read back through select, all() and any().
                    V::select(m, V::lit(1.0), V::lit(0.0)).write_to(&mut out);
                    let expected: Vec<bool> = (0..V::WIDTH).map(|i| f(a_of(i), b)).collect();
                    for (i, &e) in expected.iter().enumerate() {
                        assert_eq!(out[i] == 1.0, e, "{name}({}, {b}) lane {i}", a_of(i));
                    }
                    assert_eq!(m.all(), expected.iter().all(|&e| e), "{name} all, value {k}");
                    assert_eq!(m.any(), expected.iter().any(|&e| e), "{name} any, value {k}");
                    assert_eq!((!m).any(), !expected.iter().all(|&e| e), "{name} not");
                    assert!(!(m & !m).any(), "{name} and");
                    assert!((m | !m).all(), "{name} or");
                }
            }
        }
        assert!(<V as Real>::Mask::splat(true).all() && !<V as Real>::Mask::splat(false).any());
    }

    #[target_feature(enable = "avx2")]
    fn check_avx2() {
        check::<F64x4Avx>();
    }

    #[target_feature(enable = "avx2,avx512f")]
    fn check_avx512() {
        check::<F64x8Avx512>();
    }

    #[test]
    #[cfg_attr(not(cpu_avx2), ignore = "needs a CPU with AVX2")]
    fn four_register_lanes_are_the_f64_operations() {
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 is present (asserted above).
        unsafe { check_avx2() };
    }

    #[test]
    #[cfg_attr(not(cpu_avx512), ignore = "needs a CPU with AVX-512F")]
    fn eight_register_lanes_are_the_f64_operations() {
        assert!(std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 and AVX-512F are present (asserted above).
        unsafe { check_avx512() };
    }
}
