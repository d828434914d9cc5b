//! Masking-shadowing terms G(ω_i, ω_o) and their visibility form V = G / (4 (n·ω_i)(n·ω_o)).
//!
//! Cook-Torrance divides G by 4 (n·ω_i)(n·ω_o). Every G here is a product or ratio in which
//! those cosines cancel algebraically, so [`MaskingShadowing::visibility`] returns the simplified
//! quotient: it is exact where both cosines are positive, needs no guard against 0/0 at grazing
//! angles, and stays accurate in f32 where n·ω_i·n·ω_o would underflow.

use super::microfacet::MIN_ALPHA;
use super::named_terms;
use crate::lanes::Real;

/// Which masking-shadowing term a Cook-Torrance material uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaskingShadowing {
    /// Schlick's approximation of Smith with k = α·√(2/π) (the assignment).
    SchlickSmith,
    /// The same with k = α/2 (Karis 2013).
    SchlickKaris,
    /// Separable exact Smith for GGX, G1(ω_i)·G1(ω_o) (Mitsuba's `roughconductor`).
    SmithGgx,
    /// Height-correlated Smith for GGX (glTF 2.0 Appendix B).
    SmithGgxCorrelated,
}

named_terms!(
    MaskingShadowing, "G",
    SchlickSmith => "schlick-smith",
    SchlickKaris => "schlick-karis",
    SmithGgx => "smith-ggx",
    SmithGgxCorrelated => "smith-ggx-correlated",
);

/// k of Schlick's fit to the Smith–Beckmann masking term: k = α·√(2/π) (the Schlick–Smith G
/// of the assignment).
#[inline(always)]
pub fn schlick_k_beckmann<R: Real>(alpha: R) -> R {
    alpha * (R::lit(2.0) / R::PI()).sqrt()
}

/// k of Karis' Schlick–Smith term: k = α/2.
#[inline(always)]
pub fn schlick_k_karis<R: Real>(alpha: R) -> R {
    alpha * R::lit(0.5)
}

/// Schlick's G1: G1(c) = c / (c (1 − k) + k). For c ∈ [0, 1] and k > 0 the denominator is a
/// convex combination of c and 1 weighted towards k > 0: never zero.
#[inline(always)]
pub fn g1_schlick<R: Real>(n_dot_w: R, k: R) -> R {
    n_dot_w / (n_dot_w * (R::one() - k) + k)
}

/// √(α² + (1 − α²) c²): the common factor of the exact GGX Smith terms (≥ α > 0).
#[inline(always)]
fn ggx_lambda_root<R: Real>(c: R, a2: R) -> R {
    (a2 + (R::one() - a2) * c * c).sqrt()
}

/// Exact Smith G1 for GGX: G1(c) = 2c / (c + √(α² + (1 − α²) c²)),
/// which is Mitsuba's 2 / (1 + √(1 + α² tan²θ)) multiplied through by c (no tan at grazing).
#[inline(always)]
pub fn g1_smith_ggx<R: Real>(n_dot_w: R, alpha: R) -> R {
    let a2 = alpha * alpha;
    R::lit(2.0) * n_dot_w / (n_dot_w + ggx_lambda_root(n_dot_w, a2))
}

/// Height-correlated Smith for GGX (glTF 2.0, Appendix B):
/// G = 2 (n·ω_i)(n·ω_o) / ((n·ω_i) √(α² + (1 − α²)(n·ω_o)²) + (n·ω_o) √(α² + (1 − α²)(n·ω_i)²)).
/// Zero when either cosine is zero (the denominator is then > 0 unless both are).
#[inline(always)]
pub fn smith_ggx_correlated<R: Real>(n_dot_i: R, n_dot_o: R, alpha: R) -> R {
    let a2 = alpha * alpha;
    let denom = n_dot_i * ggx_lambda_root(n_dot_o, a2) + n_dot_o * ggx_lambda_root(n_dot_i, a2);
    let positive = denom.gt(R::zero());
    R::select(
        positive,
        R::lit(2.0) * n_dot_i * n_dot_o / R::select(positive, denom, R::one()),
        R::zero(),
    )
}

impl MaskingShadowing {
    /// G(ω_i, ω_o) for cosines in [0, 1] and roughness `alpha` (raised to `MIN_ALPHA`).
    #[inline(always)]
    pub fn g<R: Real>(self, n_dot_i: R, n_dot_o: R, alpha: R) -> R {
        let alpha = alpha.max(R::lit(MIN_ALPHA));
        match self {
            Self::SchlickSmith => {
                let k = schlick_k_beckmann(alpha);
                g1_schlick(n_dot_i, k) * g1_schlick(n_dot_o, k)
            }
            Self::SchlickKaris => {
                let k = schlick_k_karis(alpha);
                g1_schlick(n_dot_i, k) * g1_schlick(n_dot_o, k)
            }
            Self::SmithGgx => g1_smith_ggx(n_dot_i, alpha) * g1_smith_ggx(n_dot_o, alpha),
            Self::SmithGgxCorrelated => smith_ggx_correlated(n_dot_i, n_dot_o, alpha),
        }
    }

    /// V = G / (4 (n·ω_i)(n·ω_o)) with the cosines cancelled, for n·ω_i, n·ω_o ∈ (0, 1];
    /// 0 when either is ≤ 0 (G is 0 there: the assignment's "denominator replaced by 1").
    /// α ≥ `MIN_ALPHA` bounds every denominator below by about α², so V is always finite.
    #[inline(always)]
    pub fn visibility<R: Real>(self, n_dot_i: R, n_dot_o: R, alpha: R) -> R {
        let lit = n_dot_i.gt(R::zero()) & n_dot_o.gt(R::zero());
        // Cosines in (0, 1]; where either is ≤ 0 or NaN, 1 stands in and the result is 0.
        let (ci, co) = (
            R::select(lit, n_dot_i.min(R::one()), R::one()),
            R::select(lit, n_dot_o.min(R::one()), R::one()),
        );
        let alpha = alpha.max(R::lit(MIN_ALPHA));
        let quarter = R::lit(0.25);
        let v = match self {
            // G1(c)/c = 1/(c(1 − k) + k).
            Self::SchlickSmith | Self::SchlickKaris => {
                let k = if self == Self::SchlickSmith {
                    schlick_k_beckmann(alpha)
                } else {
                    schlick_k_karis(alpha)
                };
                quarter / ((ci * (R::one() - k) + k) * (co * (R::one() - k) + k))
            }
            // G1(c)/c = 2/(c + √(α² + (1 − α²)c²)).
            Self::SmithGgx => {
                let a2 = alpha * alpha;
                R::one() / ((ci + ggx_lambda_root(ci, a2)) * (co + ggx_lambda_root(co, a2)))
            }
            // V = 1/2 / (n·ω_i Λ(ω_o) + n·ω_o Λ(ω_i)).
            Self::SmithGgxCorrelated => {
                let a2 = alpha * alpha;
                R::lit(0.5) / (ci * ggx_lambda_root(co, a2) + co * ggx_lambda_root(ci, a2))
            }
        };
        R::select(lit, v, R::zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn schlick_smith_matches_the_assignment_by_hand() {
        // α = 0.7: k = 0.7·√(2/π) = 0.558519…; G1(0.6) = 0.6 / (0.6·(1 − k) + k).
        let k = 0.7 * (2.0 / PI).sqrt();
        let g1 = |c: f64| c / (c * (1.0 - k) + k);
        let g = MaskingShadowing::SchlickSmith.g(0.6, 0.9, 0.7);
        assert!((g - g1(0.6) * g1(0.9)).abs() < 1e-15);
        assert!((k - 0.558_519_1).abs() < 1e-6);
        let karis = MaskingShadowing::SchlickKaris.g(0.6f64, 0.9, 0.7);
        let g1k = |c: f64| c / (c * 0.65 + 0.35);
        assert!((karis - g1k(0.6) * g1k(0.9)).abs() < 1e-15);
    }

    #[test]
    fn smith_ggx_equals_mitsubas_tangent_form() {
        for &(c, a) in &[(0.3f64, 0.2f64), (0.9, 0.7), (0.05, 1.0)] {
            let tan2 = (1.0 - c * c) / (c * c);
            let mitsuba = 2.0 / (1.0 + (1.0 + a * a * tan2).sqrt());
            assert!((g1_smith_ggx(c, a) - mitsuba).abs() < 1e-14, "c {c} α {a}");
        }
    }

    #[test]
    fn correlated_smith_matches_the_gltf_visibility_formula() {
        let (l, v, a) = (0.4f64, 0.7f64, 0.3f64);
        let a2 = a * a;
        let vis = 0.5 / (l * (v * v * (1.0 - a2) + a2).sqrt() + v * (l * l * (1.0 - a2) + a2).sqrt());
        let g = MaskingShadowing::SmithGgxCorrelated.g(l, v, a);
        assert!((g - vis * 4.0 * l * v).abs() < 1e-15);
        // Height correlation removes doubly counted occlusion: never darker than G1·G1.
        assert!(g >= g1_smith_ggx(l, a) * g1_smith_ggx(v, a));
    }

    #[test]
    fn visibility_is_g_over_four_cosines_for_every_term() {
        for term in MaskingShadowing::ALL {
            for &(ci, co, a) in &[
                (0.3f64, 0.8f64, 0.25f64),
                (1.0, 1.0, 1.0),
                (0.01, 0.5, 0.05),
                (0.9, 0.2, 0.7),
            ] {
                let v = term.visibility(ci, co, a);
                let g = term.g(ci, co, a);
                assert!((v - g / (4.0 * ci * co)).abs() < 1e-12 * v, "{term:?} {ci} {co} {a}");
            }
        }
    }

    #[test]
    fn grazing_and_degenerate_inputs() {
        for term in MaskingShadowing::ALL {
            // G vanishes at grazing; V is 0 there by definition (and the shader multiplies by n·ω_i).
            assert_eq!(term.g(0.0f32, 0.7, 0.5), 0.0, "{term:?}");
            assert_eq!(term.visibility(0.0f32, 0.7, 0.5), 0.0);
            assert_eq!(term.visibility(-0.2f32, 0.7, 0.5), 0.0);
            assert_eq!(term.visibility(f32::NAN, 0.7, 0.5), 0.0);
            // Tiny cosines whose product underflows in f32: V stays finite (bounded by ~1/α²).
            let v = term.visibility(1e-30f32, 1e-30, 0.0);
            assert!(v.is_finite() && v > 0.0, "{term:?}: {v}");
            // Full G is within [0, 1].
            let g = term.g(0.3f32, 0.4, 0.6);
            assert!((0.0..=1.0).contains(&g));
        }
    }
}
