//! The dot products every BRDF term is a function of.

use super::microfacet::one_minus_squared;
use crate::lanes::{dot3 as dot, Real, Scalar};

/// n·ω_i, n·ω_o, n·ω_h, sin²θ_h and ω_i·ω_h for one pair of directions at one surface point.
///
/// Built from vectors by [`LocalDots::from_unit_vectors`], or from the four cosines by
/// [`LocalDots::from_cosines`] for callers that follow other conventions (the normal-map `tp`
/// preset clamps each product itself).
///
/// sin²θ_h = 1 − (n·ω_h)² is carried beside n·ω_h because the narrow lobes (GGX and Beckmann with
/// small α, Blinn-Phong with a large exponent) are functions of it near their peak, where n·ω_h is
/// within a few ulps of 1: in f32, n·ω_h rounds to 1 for every θ_h below 2.4e-4 rad, so
/// 1 − (n·ω_h)² recovered from it has no correct digit there. Computed from the vectors instead
/// (as |n × ω_h|²) it keeps its relative precision down to θ_h ≈ 1e-7.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalDots<R> {
    /// Cosine between the shading normal and the direction to the light.
    pub n_dot_i: R,
    /// Cosine between the shading normal and the direction to the viewer.
    pub n_dot_o: R,
    /// Cosine between the shading normal and the half vector.
    pub n_dot_h: R,
    /// sin²θ_h = 1 − (n·ω_h)², in [0, 1], computed without cancellation.
    pub sin2_h: R,
    /// Cosine between the direction to the light and the half vector (= ω_o·ω_h).
    pub i_dot_h: R,
}

#[inline(always)]
fn cross<R: Real>(a: [R; 3], b: [R; 3]) -> [R; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl<R: Real> LocalDots<R> {
    /// The dot products of the normal `n` and unit vectors `wi` (towards the light) and `wo`
    /// (towards the viewer), or `None` when there is no shading frame: ω_i = −ω_o (the half vector
    /// is undefined), a zero or non-finite normal, or NaN directions. Such a pair reflects nothing
    /// (the shader skips the light), which is also the limit of every lobe but Lambert's as
    /// ω_i → −ω_o inside the upper hemisphere: both directions are then grazing.
    ///
    /// `n` need not be unit length: its length is not trusted (normal maps and interpolated
    /// normals are rarely exactly unit), so the products are divided by |n| and an unnormalised
    /// normal gives exactly the value of its direction.
    ///
    /// ω_i + ω_o is formed once and its length taken directly, rather than as √(2 + 2 ω_i·ω_o):
    /// that form cancels catastrophically as ω_i → −ω_o, this one keeps full relative precision.
    /// i·h is computed as |ω_i + ω_o|/2, which it equals for unit ω_i, ω_o: symmetric in the two
    /// directions by construction (so every model is exactly reciprocal), clamped to ≤ 1;
    /// n·h to [−1, 1] and sin²θ_h to [0, 1].
    #[inline(always)]
    pub fn from_unit_vectors(n: [R; 3], wi: [R; 3], wo: [R; 3]) -> Option<Self>
    where
        R: Scalar,
    {
        let (dots, frame) = Self::from_unit_vectors_masked(n, wi, wo);
        frame.then_some(dots)
    }

    /// [`LocalDots::from_unit_vectors`] for any [`Real`]: the products, and where a shading frame
    /// exists (where it does not, the products are finite placeholders that must not be used).
    #[inline(always)]
    pub fn from_unit_vectors_masked(n: [R; 3], wi: [R; 3], wo: [R; 3]) -> (Self, R::Mask) {
        let sum = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
        let len = dot(sum, sum).sqrt();
        let n_len2 = dot(n, n);
        // len = 0 (exactly opposite directions), n = 0, or NaN/infinite input: no frame. A normal
        // whose |n|² is subnormal (|n| < 1.1e-19 in f32) or overflows (|n| > 1.8e19) has lost its
        // direction's precision and counts as no normal too.
        let frame = len.gt(R::zero()) & n_len2.ge(R::min_positive_value()) & (len * n_len2).is_finite();
        // Where there is no frame, divide by 1 instead: nothing below is then NaN or infinite
        // in lanes that will be discarded (their products are replaced by 0).
        let (len, n_len2) = (R::select(frame, len, R::one()), R::select(frame, n_len2, R::one()));
        let n_len = n_len2.sqrt();
        let inv = len.recip();
        let inv_n = n_len.recip();
        let nxs = cross(n, sum);
        let sin2_h = (dot(nxs, nxs) * (inv * inv_n) * (inv * inv_n)).at_most(R::one());
        let keep = |v: R| R::select(frame, v, R::zero());
        let dots = Self {
            n_dot_i: keep(dot(n, wi) * inv_n),
            n_dot_o: keep(dot(n, wo) * inv_n),
            n_dot_h: keep((dot(n, sum) * (inv * inv_n)).clamped(-R::one(), R::one())),
            sin2_h: keep(sin2_h),
            i_dot_h: keep((len * R::lit(0.5)).at_most(R::one())),
        };
        (dots, frame)
    }

    #[inline(always)]
    pub fn from_cosines(n_dot_i: R, n_dot_o: R, n_dot_h: R, i_dot_h: R) -> Self {
        let n_dot_h = n_dot_h.clamped(-R::one(), R::one());
        Self {
            n_dot_i,
            n_dot_o,
            n_dot_h,
            sin2_h: one_minus_squared(n_dot_h),
            i_dot_h,
        }
    }

    /// The same products in another precision.
    pub fn cast<S: Scalar>(&self) -> LocalDots<S>
    where
        R: Scalar,
    {
        LocalDots {
            n_dot_i: S::lit(self.n_dot_i.as_f64()),
            n_dot_o: S::lit(self.n_dot_o.as_f64()),
            n_dot_h: S::lit(self.n_dot_h.as_f64()),
            sin2_h: S::lit(self.sin2_h.as_f64()),
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

    #[test]
    fn sin2_h_keeps_relative_precision_for_tiny_half_angles_in_f32() {
        // A mirror configuration tilted by θ_h: n·ω_h rounds to 1 in f32, sin²θ_h does not.
        for theta in [1e-2f64, 1e-3, 1e-4] {
            let t_in = 0.7f64;
            let n = [theta.sin(), 0.0, theta.cos()];
            let wi = [t_in.sin(), 0.0, t_in.cos()];
            let wo = [-t_in.sin(), 0.0, t_in.cos()];
            let (n32, wi32, wo32) = (n.map(|v| v as f32), wi.map(|v| v as f32), wo.map(|v| v as f32));
            let d32 = LocalDots::from_unit_vectors(n32, wi32, wo32).unwrap();
            let d64 =
                LocalDots::from_unit_vectors(n32.map(f64::from), wi32.map(f64::from), wo32.map(f64::from)).unwrap();
            let rel = (d32.sin2_h as f64 - d64.sin2_h).abs() / d64.sin2_h;
            // The half vector's direction is known to ~1e-7 rad in f32: relative error ~2e-7/θ.
            assert!(
                rel < 4e-7 / theta,
                "θ_h {theta}: {} vs {} (rel {rel})",
                d32.sin2_h,
                d64.sin2_h
            );
            assert!((d64.sin2_h - theta.sin().powi(2)).abs() < 1e-6 * theta * theta);
        }
    }

    #[test]
    fn unnormalised_zero_and_nan_normals() {
        let wi = [0.6, 0.0, 0.8f32];
        let wo = [0.0, 0.6, 0.8f32];
        let unit = LocalDots::from_unit_vectors([0.0, 0.0, 1.0], wi, wo).unwrap();
        // The length of n is not trusted: a scaled normal gives the same products.
        for scale in [1e-15f32, 0.5, 3.0, 1e15] {
            let d = LocalDots::from_unit_vectors([0.0, 0.0, scale], wi, wo).unwrap();
            for (a, b) in [
                (d.n_dot_i, unit.n_dot_i),
                (d.n_dot_o, unit.n_dot_o),
                (d.n_dot_h, unit.n_dot_h),
            ] {
                assert!((a - b).abs() < 1e-6, "scale {scale}: {a} vs {b}");
            }
        }
        // No direction, no frame: the light is skipped.
        assert!(LocalDots::from_unit_vectors([0.0; 3], wi, wo).is_none());
        assert!(LocalDots::from_unit_vectors([0.0, 0.0, 1e-20], wi, wo).is_none());
        assert!(LocalDots::from_unit_vectors([0.0, 0.0, 1e20], wi, wo).is_none());
        assert!(LocalDots::from_unit_vectors([f32::NAN, 0.0, 1.0], wi, wo).is_none());
        assert!(LocalDots::from_unit_vectors([f32::INFINITY, 0.0, 1.0], wi, wo).is_none());
    }

    #[test]
    fn from_cosines_matches_from_unit_vectors() {
        let (n, wi, wo) = ([0.0, 0.0, 1.0f64], [0.6, 0.0, 0.8], [0.0, 0.28, 0.96]);
        let v = LocalDots::from_unit_vectors(n, wi, wo).unwrap();
        let c = LocalDots::from_cosines(v.n_dot_i, v.n_dot_o, v.n_dot_h, v.i_dot_h);
        assert!((c.sin2_h - v.sin2_h).abs() < 1e-15);
    }
}
