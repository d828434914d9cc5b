//! The scalar type BRDF terms are generic over.

use num_traits::{Float, FloatConst};

/// A floating-point type the BRDF terms can be evaluated in: f32 (rendering) or f64 (reference).
pub trait Real: Float + FloatConst + Send + Sync + std::fmt::Debug + std::fmt::Display + 'static {
    /// The constant `v` in this precision (rounded once).
    fn lit(v: f64) -> Self;
    /// Converts a material parameter stored in f32.
    fn of(v: f32) -> Self;
    /// This value as f64 (exact for both precisions).
    fn as_f64(self) -> f64;
}

impl Real for f32 {
    #[inline(always)]
    fn lit(v: f64) -> Self {
        v as f32
    }
    #[inline(always)]
    fn of(v: f32) -> Self {
        v
    }
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    #[inline(always)]
    fn lit(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn of(v: f32) -> Self {
        v as f64
    }
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self
    }
}
