//! The dot products every BRDF term is a function of.

use super::Real;

/// n·ω_i, n·ω_o, n·ω_h and ω_i·ω_h for one pair of directions at one surface point.
///
/// Built from vectors by [`LocalDots::from_unit_vectors`], or field by field by callers that
/// follow other conventions (the normal-map `tp` preset clamps each product itself).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalDots<R> {
    /// Cosine between the shading normal and the direction to the light.
    pub n_dot_i: R,
    /// Cosine between the shading normal and the direction to the viewer.
    pub n_dot_o: R,
    /// Cosine between the shading normal and the half vector.
    pub n_dot_h: R,
    /// Cosine between the direction to the light and the half vector (= ω_o·ω_h).
    pub i_dot_h: R,
}

#[inline(always)]
fn dot<R: Real>(a: [R; 3], b: [R; 3]) -> R {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl<R: Real> LocalDots<R> {
    /// The dot products of unit vectors `n`, `wi` (towards the light) and `wo` (towards the
    /// viewer), or `None` when ω_i = −ω_o, where the half vector is undefined.
    ///
    /// ω_i + ω_o is formed once and its length taken directly, rather than as √(2 + 2 ω_i·ω_o):
    /// that form cancels catastrophically as ω_i → −ω_o, this one keeps full relative precision.
    /// i·h is clamped to [0, 1] against rounding (it is |ω_i + ω_o|/2 ≥ 0 in exact arithmetic).
    #[inline(always)]
    pub fn from_unit_vectors(n: [R; 3], wi: [R; 3], wo: [R; 3]) -> Option<Self> {
        let sum = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
        let len = dot(sum, sum).sqrt();
        // len = 0 (exactly opposite directions) or NaN (invalid input): no half vector.
        if !(len > R::zero()) {
            return None;
        }
        let inv = len.recip();
        Some(Self {
            n_dot_i: dot(n, wi),
            n_dot_o: dot(n, wo),
            n_dot_h: dot(n, sum) * inv,
            i_dot_h: (dot(wi, sum) * inv).max(R::zero()).min(R::one()),
        })
    }

    /// The same products in another precision.
    pub fn cast<S: Real>(&self) -> LocalDots<S> {
        LocalDots {
            n_dot_i: S::lit(self.n_dot_i.as_f64()),
            n_dot_o: S::lit(self.n_dot_o.as_f64()),
            n_dot_h: S::lit(self.n_dot_h.as_f64()),
            i_dot_h: S::lit(self.i_dot_h.as_f64()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_vector_products_match_the_explicit_half_vector() {
        let n = [0.0, 0.0, 1.0f64];
        let wi = [0.6, 0.0, 0.8];
        let wo = [0.0, 0.28, 0.96];
        let d = LocalDots::from_unit_vectors(n, wi, wo).unwrap();
        let h = [0.6, 0.28, 1.76f64];
        let len = dot(h, h).sqrt();
        assert!((d.n_dot_h - 1.76 / len).abs() < 1e-15);
        assert!((d.i_dot_h - dot(wi, h) / len).abs() < 1e-15);
        assert_eq!((d.n_dot_i, d.n_dot_o), (0.8, 0.96));
    }

    #[test]
    fn opposite_directions_have_no_half_vector() {
        let n = [0.0, 0.0, 1.0f32];
        assert!(LocalDots::from_unit_vectors(n, [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).is_none());
        assert!(LocalDots::from_unit_vectors(n, [f32::NAN, 0.0, 0.0], [0.0, 0.0, 1.0]).is_none());
    }

    #[test]
    fn nearly_opposite_grazing_directions_keep_relative_precision_in_f32() {
        // ω_i and ω_o almost opposite, both just above the horizon: |ω_i + ω_o| ≈ 2e-4.
        let e = 1e-4f64;
        let wi = [(1.0 - e * e).sqrt(), 0.0, e];
        let wo = [-(1.0 - e * e).sqrt(), 0.0, e];
        let n = [0.0, 0.0, 1.0];
        let d64 = LocalDots::from_unit_vectors(n, wi, wo).unwrap();
        let d32 =
            LocalDots::from_unit_vectors(n.map(|v| v as f32), wi.map(|v| v as f32), wo.map(|v| v as f32)).unwrap();
        assert!((d64.n_dot_h - 1.0).abs() < 1e-12, "h is the normal: {}", d64.n_dot_h);
        assert!(
            (d32.n_dot_h as f64 - d64.n_dot_h).abs() < 1e-6,
            "{} vs {}",
            d32.n_dot_h,
            d64.n_dot_h
        );
        assert!((d32.i_dot_h as f64 - d64.i_dot_h).abs() <= 1e-4 * d64.i_dot_h);
    }
}
