//! Masking-shadowing terms G(ω_i, ω_o), each written once, in its visibility form
//! V = G / (4 (n·ω_i)(n·ω_o)).
//!
//! Cook-Torrance divides G by 4 (n·ω_i)(n·ω_o). Every G here is a product or ratio in which
//! those cosines cancel algebraically, so each term below is the simplified quotient V: exact
//! where both cosines are positive, with no 0/0 to guard at grazing angles, and accurate in f32
//! where n·ω_i·n·ω_o would underflow. [`MaskingShadowing::g`] multiplies the cosines back in for
//! the callers that want G itself (the Python module's `eval_terms`, the stability checks).

use super::microfacet::MIN_ALPHA;
use super::named_terms;
use crate::lanes::Real;

/// Which masking-shadowing term a Cook-Torrance material uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaskingShadowing {
    /// Schlick's approximation of Smith–Beckmann, k = α·√(2/π) (Schlick 1994).
    SchlickSmith,
    /// The same approximation with k = α/2 (Karis 2013).
    SchlickKaris,
    /// Separable Smith for GGX, G1(ω_i)·G1(ω_o) (Walter et al. 2007; Mitsuba's `roughconductor`).
    SmithGgx,
    /// Height-correlated Smith for GGX (Heitz 2014; glTF 2.0 Appendix B).
    SmithGgxCorrelated,
}

named_terms!(
    MaskingShadowing, "G",
    SchlickSmith => "schlick-smith",
    SchlickKaris => "schlick-karis",
    SmithGgx => "smith-ggx",
    SmithGgxCorrelated => "smith-ggx-correlated",
);

/// k of Schlick's fit to the Smith–Beckmann masking term: k = α·√(2/π).
///
/// Source: C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer
/// Graphics Forum 13(3), 1994.
#[inline(always)]
pub fn schlick_k_beckmann<R: Real>(alpha: R) -> R {
    alpha * (R::lit(2.0) / R::PI()).sqrt()
}

/// k of Karis' Schlick–Smith term: k = α/2.
///
/// Source: B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes (there α is
/// the squared perceptual roughness; here it is the material's α as given).
#[inline(always)]
pub fn schlick_k_karis<R: Real>(alpha: R) -> R {
    alpha * R::lit(0.5)
}

/// Schlick's separable G = G1(n·ω_i)·G1(n·ω_o) with G1(c) = c / (c (1 − k) + k), as
/// V = 1/4 / ((c_i (1 − k) + k)(c_o (1 − k) + k)). For c ∈ (0, 1] and k > 0 each factor is a
/// convex combination of c and 1 weighted towards k > 0: never zero.
///
/// Source: Schlick 1994 (above), eq. 19.
#[inline(always)]
pub fn v_schlick<R: Real>(n_dot_i: R, n_dot_o: R, k: R) -> R {
    let one_minus_k = R::one() - k;
    R::lit(0.25) / ((n_dot_i * one_minus_k + k) * (n_dot_o * one_minus_k + k))
}

/// √(α² + (1 − α²) c²): the common factor of the exact GGX Smith terms (≥ α > 0).
#[inline(always)]
fn ggx_lambda_root<R: Real>(c: R, a2: R) -> R {
    (a2 + (R::one() - a2) * c * c).sqrt()
}

/// Separable Smith for GGX: G = G1(ω_i)·G1(ω_o), G1 = 2 / (1 + √(1 + α² tan²θ)), which
/// multiplied through by c is 2c / (c + √(α² + (1 − α²) c²)) (no tangent at grazing), so
/// V = 1 / ((c_i + √(α² + (1 − α²)c_i²))(c_o + √(α² + (1 − α²)c_o²))).
///
/// Source: B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction
/// through Rough Surfaces", EGSR 2007, eq. 34 (G1) and eq. 23 (the separable product).
#[inline(always)]
pub fn v_smith_ggx<R: Real>(n_dot_i: R, n_dot_o: R, alpha: R) -> R {
    let a2 = alpha * alpha;
    R::one() / ((n_dot_i + ggx_lambda_root(n_dot_i, a2)) * (n_dot_o + ggx_lambda_root(n_dot_o, a2)))
}

/// Height-correlated Smith for GGX:
/// G = 2 c_i c_o / (c_i √(α² + (1 − α²) c_o²) + c_o √(α² + (1 − α²) c_i²)), so
/// V = 1/2 / (c_i √(α² + (1 − α²) c_o²) + c_o √(α² + (1 − α²) c_i²)).
///
/// Source: E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
/// JCGT 3(2), 2014, eq. 99; the same V in the glTF 2.0 specification, Appendix B.
#[inline(always)]
pub fn v_smith_ggx_correlated<R: Real>(n_dot_i: R, n_dot_o: R, alpha: R) -> R {
    let a2 = alpha * alpha;
    R::lit(0.5) / (n_dot_i * ggx_lambda_root(n_dot_o, a2) + n_dot_o * ggx_lambda_root(n_dot_i, a2))
}

impl MaskingShadowing {
    /// V = G / (4 (n·ω_i)(n·ω_o)) with the cosines cancelled, for n·ω_i, n·ω_o ∈ (0, 1];
    /// 0 when either is ≤ 0 or NaN (G is 0 there). α is raised to [`MIN_ALPHA`], which bounds
    /// every denominator below by about α², so V is always finite.
    #[inline(always)]
    pub fn visibility<R: Real>(self, n_dot_i: R, n_dot_o: R, alpha: R) -> R {
        let lit = n_dot_i.gt(R::zero()) & n_dot_o.gt(R::zero());
        // Cosines in (0, 1]; where either is ≤ 0 or NaN, 1 stands in and the result is 0.
        let (ci, co) = (
            R::select(lit, n_dot_i.at_most(R::one()), R::one()),
            R::select(lit, n_dot_o.at_most(R::one()), R::one()),
        );
        let alpha = alpha.at_least(R::lit(MIN_ALPHA));
        let v = match self {
            Self::SchlickSmith => v_schlick(ci, co, schlick_k_beckmann(alpha)),
            Self::SchlickKaris => v_schlick(ci, co, schlick_k_karis(alpha)),
            Self::SmithGgx => v_smith_ggx(ci, co, alpha),
            Self::SmithGgxCorrelated => v_smith_ggx_correlated(ci, co, alpha),
        };
        R::select(lit, v, R::zero())
    }

    /// G(ω_i, ω_o) = 4 (n·ω_i)(n·ω_o) V for cosines in [0, 1] and roughness `alpha` (raised to
    /// [`MIN_ALPHA`]); 0 where either cosine is ≤ 0.
    #[inline(always)]
    pub fn g<R: Real>(self, n_dot_i: R, n_dot_o: R, alpha: R) -> R {
        let (ci, co) = (n_dot_i.at_most(R::one()), n_dot_o.at_most(R::one()));
        R::lit(4.0) * ci * co * self.visibility(n_dot_i, n_dot_o, alpha)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The textbook G1 of each term, written independently of the visibility forms.
    fn g1_schlick(c: f64, k: f64) -> f64 {
        c / (c * (1.0 - k) + k)
    }

    fn g1_smith_ggx_tan(c: f64, a: f64) -> f64 {
        let tan2 = (1.0 - c * c) / (c * c);
        2.0 / (1.0 + (1.0 + a * a * tan2).sqrt())
    }

    #[test]
    fn schlick_smith_matches_hand_computed_values() {
        // α = 0.7: k = 0.7·√(2/π) = 0.558519…; G1(0.6) = 0.6 / (0.6·(1 − k) + k).
        let k = 0.7 * (2.0 / PI).sqrt();
        let g = MaskingShadowing::SchlickSmith.g(0.6, 0.9, 0.7);
        assert!((g - g1_schlick(0.6, k) * g1_schlick(0.9, k)).abs() < 1e-15);
        assert!((k - 0.558_519_1).abs() < 1e-6);
        let karis = MaskingShadowing::SchlickKaris.g(0.6f64, 0.9, 0.7);
        assert!((karis - g1_schlick(0.6, 0.35) * g1_schlick(0.9, 0.35)).abs() < 1e-15);
    }

    #[test]
    fn smith_ggx_equals_the_tangent_form() {
        for &(ci, co, a) in &[(0.3f64, 0.8, 0.2f64), (0.9, 0.9, 0.7), (0.05, 0.6, 1.0)] {
            let g = MaskingShadowing::SmithGgx.g(ci, co, a);
            let tangent_form = g1_smith_ggx_tan(ci, a) * g1_smith_ggx_tan(co, a);
            assert!((g - tangent_form).abs() < 1e-14, "{ci} {co} α {a}");
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
        assert!(g >= g1_smith_ggx_tan(l, a) * g1_smith_ggx_tan(v, a));
    }

    #[test]
    fn visibility_is_the_textbook_g_over_four_cosines_for_every_term() {
        let textbook = |term: MaskingShadowing, ci: f64, co: f64, a: f64| match term {
            MaskingShadowing::SchlickSmith => {
                let k = a * (2.0 / PI).sqrt();
                g1_schlick(ci, k) * g1_schlick(co, k)
            }
            MaskingShadowing::SchlickKaris => g1_schlick(ci, a / 2.0) * g1_schlick(co, a / 2.0),
            MaskingShadowing::SmithGgx => g1_smith_ggx_tan(ci, a) * g1_smith_ggx_tan(co, a),
            MaskingShadowing::SmithGgxCorrelated => {
                let root = |c: f64| (a * a + (1.0 - a * a) * c * c).sqrt();
                2.0 * ci * co / (ci * root(co) + co * root(ci))
            }
        };
        for term in MaskingShadowing::ALL {
            for &(ci, co, a) in &[
                (0.3f64, 0.8f64, 0.25f64),
                (1.0, 1.0, 1.0),
                (0.01, 0.5, 0.05),
                (0.9, 0.2, 0.7),
            ] {
                let v = term.visibility(ci, co, a);
                let g = textbook(*term, ci, co, a);
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
