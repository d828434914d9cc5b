//! Shading conventions: how the shader turns a surface point and a light into the dot products
//! the BRDF reads. The BRDF itself ([`Material::eval`]) is the same under every convention.
//!
//! - [`ShadingConvention::Physical`] (every mesh render, the normal-map `physical` preset): unit
//!   normals, ω_i towards the light, the material's sidedness (one- or two-sided) decides where a
//!   light contributes.
//! - [`ShadingConvention::Clamped`] (used by the normal-map `tp` preset): the normal is used as
//!   given (of any length), ω_i points *from the light towards the point*, ω_o towards the
//!   viewer, and every dot product is clamped to [0, 1] instead of testing sides. With the
//!   lights' `Falloff::None` (L_i = colour × intensity) the shader then forms
//!   L_o = L_i · f(ω_i, ω_o) · (n·ω_i).
//!
//! [`Material::eval`]: crate::material::Material::eval

use crate::brdf::LocalDots;
use crate::lanes::{dot3 as dot, map3, Mask, Real};

/// Which convention the shader follows; chosen once per render by the plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadingConvention {
    /// Physical: unit normals, ω_i towards the light, sidedness from the material.
    Physical,
    /// Normals as given, ω_i from the light towards the point, every dot product clamped to
    /// [0, 1].
    Clamped,
}

impl ShadingConvention {
    /// A short description for `--explain`.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Physical => "physical: unit normals, ω_i towards the light, material sidedness",
            Self::Clamped => {
                "clamped: normals used as given, ω_i from the light towards the point, \
                 every dot product clamped to [0, 1]"
            }
        }
    }
}

/// The dot products of the clamped convention at one point for one light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClampedDots<R: Real> {
    /// n·ω_i, n·ω_o, n·ω_h, ω_i·ω_h, each clamped to [0, 1]; the last two are 0 when there is no
    /// half vector.
    pub dots: LocalDots<R>,
    /// Whether ω_h was formed: false when it was not asked for (a Lambert material reads no half
    /// vector) and when ω_i + ω_o = 0, where ω_h = (ω_i + ω_o)/‖ω_i + ω_o‖ is 0/0 — the light
    /// and the viewer lie on the same ray from the point. Without it the shader adds only the
    /// diffuse part (a specular lobe has no half vector to be evaluated at; see README.md).
    pub half_vector: R::Mask,
}

/// v/‖v‖ with each component divided by ‖v‖ = √(v_x² + v_y² + v_z²), summed in that order (as
/// `v / np.linalg.norm(v)` computes it); the zero vector where ‖v‖ is 0 or not finite, with the
/// lanes where it is defined. Division, not a product with 1/‖v‖: in float64 the directions are
/// then those of a numpy implementation to the bit, so where n·ω_o is 0 in exact arithmetic — a
/// guarded Cook-Torrance denominator is discontinuous there — it rounds to the side numpy does.
#[inline(always)]
pub fn unit_by_division<R: Real>(v: [R; 3]) -> ([R; 3], R::Mask) {
    unit_by_division_of_length(v, dot(v, v).sqrt())
}

/// [`unit_by_division`] of `v` whose length `len` = √(v · v) the caller has taken (for a second
/// use of the same root).
#[inline(always)]
pub fn unit_by_division_of_length<R: Real>(v: [R; 3], len: R) -> ([R; 3], R::Mask) {
    let defined = len.gt(R::zero()) & len.is_finite();
    let safe = R::select(defined, len, R::one());
    (map3(v, |c| R::select(defined, c / safe, R::zero())), defined)
}

/// How the clamped convention turns a vector into a direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitForm {
    /// Each component divided by the length ([`unit_by_division`]): a numpy implementation's
    /// bits, for a BRDF whose value jumps where a cosine crosses 0 (the Cook-Torrance
    /// denominator), so that an exact 0 rounds to numpy's side.
    Quotients,
    /// One reciprocal of the length and three products ([`unit_by_reciprocal_of_length`]): a
    /// third of the divisions, each component within an ulp or two of the quotient — for BRDFs
    /// continuous in the clamped cosines (Lambert, Blinn-Phong), where that moves L_o by a few
    /// ulps and no output level by more than the f32 image's own rounding can.
    Reciprocal,
}

/// [`unit_by_division_of_length`] or [`unit_by_reciprocal_of_length`], as `form` says.
#[inline(always)]
pub fn unit_of_length<R: Real>(v: [R; 3], len: R, form: UnitForm) -> ([R; 3], R::Mask) {
    match form {
        UnitForm::Quotients => unit_by_division_of_length(v, len),
        UnitForm::Reciprocal => unit_by_reciprocal_of_length(v, len),
    }
}

/// v · (1/‖v‖) for `v` of length `len` = √(v · v); the zero vector where `len` is below the
/// smallest normal f32 (1.2e-38, also in float64: no direction is taken from a vector that
/// short) or not finite, with the lanes where it is defined. Above that bound 1/`len` is finite
/// in f32 and float64, and each product at most about 1 in magnitude.
#[inline(always)]
pub fn unit_by_reciprocal_of_length<R: Real>(v: [R; 3], len: R) -> ([R; 3], R::Mask) {
    let defined = len.ge(R::lit(f32::MIN_POSITIVE as f64)) & len.is_finite();
    let inverse = R::one() / R::select(defined, len, R::one());
    (map3(v, |c| R::select(defined, c * inverse, R::zero())), defined)
}

/// The clamped convention's dot products for normal `n` (used as given, any length),
/// `wi_from_light` (unit, from the light towards the point) and `wo` (unit or zero,
/// from the point towards the viewer); the half-vector products only where `half_vector` says in
/// which form to take ω_h (`None`: no half vector, its products 0).
/// Generic over [`Real`]: the `tp` preset runs it on float64 lanes, the stability checks on f64.
///
/// ω_h = (ω_i + ω_o)/‖ω_i + ω_o‖ (in `form`), with the sum formed once and its own length
/// taken (no √(2 + 2 ω_i·ω_o), which cancels as ω_i → −ω_o); a zero (or NaN) length means no half vector
/// (in [`UnitForm::Reciprocal`], also one below 1.2e-38).
#[inline(always)]
pub fn clamped_dots<R: Real>(
    n: [R; 3],
    wi_from_light: [R; 3],
    wo: [R; 3],
    half_vector: Option<UnitForm>,
) -> ClampedDots<R> {
    let wi = wi_from_light;
    // Each cosine clamped to [0, 1]; `clamped` gives its lower bound for NaN, so a NaN product
    // (impossible for finite inputs) would become 0 rather than reach the image.
    let n_dot_i = dot(n, wi).clamped(R::zero(), R::one());
    let n_dot_o = dot(n, wo).clamped(R::zero(), R::one());
    let (wh, half_vector) = match half_vector {
        Some(form) => {
            let sum = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
            unit_of_length(sum, dot(sum, sum).sqrt(), form)
        }
        None => ([R::zero(); 3], R::Mask::splat(false)),
    };
    // Without a half vector report 0 (ω_h is the zero vector there: nothing NaN in any lane).
    let keep = |v: R| R::select(half_vector, v, R::zero());
    // sin²θ_h = (1 − c)(1 + c) from the clamped c: D is a function of that c.
    ClampedDots {
        dots: LocalDots::from_cosines(
            n_dot_i,
            n_dot_o,
            keep(dot(n, wh).clamped(R::zero(), R::one())),
            keep(dot(wi, wh).clamped(R::zero(), R::one())),
        ),
        half_vector,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_are_clamped_and_the_normal_is_not_normalised() {
        // n of length > 1 (as a min-max-scaled colour can be): n·ω_i = 1.2 is clamped to 1.
        let n = [0.0, 0.0, 1.2f64];
        let d = clamped_dots(n, [0.0, 0.0, 1.0], [0.0, 0.6, 0.8], Some(UnitForm::Quotients));
        assert!(d.half_vector);
        assert_eq!(d.dots.n_dot_i, 1.0);
        assert!((d.dots.n_dot_o - 0.96).abs() < 1e-15, "1.2 · 0.8");
        // ω_h = (0, 0.6, 1.8)/‖·‖: n·ω_h = 1.2·1.8/√3.6 = 1.138… → clamped to 1.
        assert_eq!(d.dots.n_dot_h, 1.0);
        let ih = 1.8 / 3.6f64.sqrt();
        assert!((d.dots.i_dot_h - ih).abs() < 1e-15);
        // Negative products become 0.
        let back = clamped_dots(
            [0.0, 0.0, -1.0f32],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            Some(UnitForm::Reciprocal),
        );
        assert_eq!(
            (back.dots.n_dot_i, back.dots.n_dot_o, back.dots.n_dot_h),
            (0.0, 0.0, 0.0)
        );
    }

    #[test]
    fn opposite_light_and_view_directions_have_no_half_vector() {
        let d = clamped_dots(
            [0.3, 0.4, 0.5f32],
            [0.0, 0.6, 0.8],
            [0.0, -0.6, -0.8],
            Some(UnitForm::Reciprocal),
        );
        assert!(!d.half_vector);
        assert_eq!((d.dots.n_dot_h, d.dots.i_dot_h), (0.0, 0.0));
        assert!((d.dots.n_dot_i - 0.64).abs() < 1e-6);
        assert_eq!(d.dots.n_dot_o, 0.0);
    }

    #[test]
    fn zero_normal_and_zero_view_direction_give_finite_zeros() {
        let d = clamped_dots([0.0f32; 3], [0.6, 0.0, 0.8], [0.0, 0.0, 1.0], Some(UnitForm::Quotients));
        assert_eq!(d.dots.n_dot_i, 0.0);
        assert_eq!(d.dots.n_dot_h, 0.0);
        // ω_o = 0 (the viewer at the point): ω_h = ω_i.
        let d = clamped_dots(
            [0.0, 0.0, 1.0f32],
            [0.6, 0.0, 0.8],
            [0.0; 3],
            Some(UnitForm::Reciprocal),
        );
        assert!(d.half_vector);
        assert_eq!(d.dots.n_dot_o, 0.0);
        assert!((d.dots.i_dot_h - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_reciprocal_direction_is_within_two_ulps_of_the_quotients_and_never_nan() {
        let mut random = crate::test_random::XorShift32::new(45);
        for i in 0..20_000 {
            // Lengths from 1e-30 to 1e30, signs and zeros in every component.
            let scale = 10f64.powi(i % 61 - 30);
            let v: [f64; 3] = std::array::from_fn(|c| match (i as usize + c) % 7 {
                0 => 0.0,
                _ => (random.unit() as f64 * 2.0 - 1.0 + random.unit() as f64 * 1e-7) * scale,
            });
            let len = dot(v, v).sqrt();
            let (q, q_defined) = unit_by_division_of_length(v, len);
            let (r, r_defined) = unit_by_reciprocal_of_length(v, len);
            assert_eq!(q_defined, r_defined, "{v:?}");
            for c in 0..3 {
                let ulp = f64::EPSILON * q[c].abs();
                assert!((q[c] - r[c]).abs() <= 2.0 * ulp, "{v:?}: {q:?} vs {r:?}");
            }
        }
        // Where no direction is taken: zero, subnormal, infinite and NaN lengths give the zero
        // vector, never NaN.
        for v in [
            [0.0; 3],
            [1e-300, 0.0, 0.0],
            [f64::INFINITY, 1.0, 0.0],
            [f64::NAN, 0.0, 0.0],
        ] {
            let len = dot(v, v).sqrt();
            let (r, defined) = unit_by_reciprocal_of_length(v, len);
            assert!(!defined && r == [0.0; 3], "{v:?}: {r:?}");
        }
        // In f32 too, down to the bound (1/len stays finite).
        let v = [f32::MIN_POSITIVE, 0.0, 0.0];
        assert_eq!(
            unit_by_reciprocal_of_length(v, f32::MIN_POSITIVE),
            ([1.0, 0.0, 0.0], true)
        );
    }

    #[test]
    fn lambert_asks_for_no_half_vector() {
        let d = clamped_dots([0.0, 0.0, 1.0f64], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0], None);
        assert!(!d.half_vector);
        assert!((d.dots.n_dot_i - 0.8).abs() < 1e-15);
        assert_eq!((d.dots.n_dot_h, d.dots.i_dot_h), (0.0, 0.0));
    }
}
