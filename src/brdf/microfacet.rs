//! Microfacet normal distributions D(ω_h).

use super::named_terms;
use crate::lanes::Real;

/// Smallest roughness α the distributions accept; smaller values are raised to it (as Mitsuba
/// does). Below it the lobe is narrower than f32 can resolve in n·ω_h anyway: at α = 1e-4 the
/// peak D = 1/(πα²) ≈ 3.2e7 is still far from overflow, and 1 − n·ω_h at half-width is ~1e-8.
pub const MIN_ALPHA: f64 = 1e-4;

/// Which microfacet distribution a Cook-Torrance material uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MicrofacetDistribution {
    /// Trowbridge–Reitz / GGX, α used directly (Walter et al. 2007).
    Ggx,
    /// Beckmann–Spizzichino.
    Beckmann,
}

named_terms!(MicrofacetDistribution, "D", Ggx => "ggx", Beckmann => "beckmann");

impl MicrofacetDistribution {
    /// D for a half vector with cosine `n_dot_h` and sine² `sin2_h` (see [`LocalDots`]), for
    /// roughness `alpha`.
    ///
    /// [`LocalDots`]: super::LocalDots
    #[inline(always)]
    pub fn eval<R: Real>(self, n_dot_h: R, sin2_h: R, alpha: R) -> R {
        match self {
            Self::Ggx => ggx_d(n_dot_h, sin2_h, alpha),
            Self::Beckmann => beckmann_d(n_dot_h, sin2_h, alpha),
        }
    }
}

/// 1 − c², computed as (1 − c)(1 + c): for c near 1 the subtraction 1 − c is exact (Sterbenz),
/// so the result keeps its relative precision where 1 − c·c would cancel.
#[inline(always)]
pub(crate) fn one_minus_squared<R: Real>(c: R) -> R {
    ((R::one() - c) * (R::one() + c)).at_least(R::zero())
}

/// α clamped to [`MIN_ALPHA`, 1] (materials validate α ≤ 1; the clamp keeps direct calls finite),
/// squared. NaN becomes `MIN_ALPHA` (`at_least` gives its floor for NaN).
#[inline(always)]
fn alpha_squared<R: Real>(alpha: R) -> R {
    let a = alpha.clamped(R::lit(MIN_ALPHA), R::one());
    a * a
}

/// GGX (Trowbridge–Reitz):
/// D = χ⁺(n·ω_h) α² / (π (1 + (α² − 1)(n·ω_h)²)²),
/// evaluated as α² / (π (sin²θ_h + α² cos²θ_h)²): both terms of the sum are ≥ 0, and sin²θ_h
/// comes from [`LocalDots`] with its full relative precision, so the peak (θ_h → 0) does not
/// cancel. D = 0 for n·ω_h ≤ 0 (microfacet normals lie in the upper hemisphere: χ⁺). α is
/// raised to [`MIN_ALPHA`]. For consistent inputs (sin² + cos² = 1) the denominator is
/// ≥ π·min(1, α²)² > 0; the result is also capped at the peak value 1/(πα²), which it never
/// exceeds mathematically, so inconsistent inputs (sin²θ_h = 0 with a tiny cos θ_h) cannot
/// divide by zero either.
///
/// Source: B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction
/// through Rough Surfaces", EGSR 2007, eq. 33 (Trowbridge & Reitz 1975's distribution).
///
/// [`LocalDots`]: super::LocalDots
#[inline(always)]
pub fn ggx_d<R: Real>(n_dot_h: R, sin2_h: R, alpha: R) -> R {
    let c = n_dot_h.at_most(R::one());
    let s2 = sin2_h.clamped(R::zero(), R::one());
    let a2 = alpha_squared(alpha);
    let t = s2 + a2 * c * c;
    let peak = (R::PI() * a2).recip();
    // Test the raw input: `at_most` turned a NaN into 1.
    R::select(n_dot_h.gt(R::zero()), (a2 / (R::PI() * t * t)).min(peak), R::zero())
}

/// Beckmann: D = χ⁺(n·ω_h) exp(−tan²θ_h / α²) / (π α² cos⁴θ_h), tan²θ_h = sin²θ_h / cos²θ_h,
/// evaluated as exp(−tan²θ_h/α²)·(1 + tan²θ_h)² / (π α²) (1/cos⁴ = (1 + tan²)²).
/// Zero for c ≤ 0 (the limit: the exponential vanishes faster than cos⁴ does), where cos²θ_h
/// underflows, and where the exponential underflows. When it does not, tan²θ_h < 104 α² ≤ 104,
/// so the factor (1 + tan²)² is below 1.1e4: no overflow and no 0/0 anywhere.
///
/// Source: P. Beckmann, A. Spizzichino, *The Scattering of Electromagnetic Waves from Rough
/// Surfaces*, 1963; in this form, Walter et al. 2007, eq. 25.
#[inline(always)]
pub fn beckmann_d<R: Real>(n_dot_h: R, sin2_h: R, alpha: R) -> R {
    let c = n_dot_h.at_most(R::one());
    let c2 = c * c;
    // c² > 0 also rejects n·ω_h ≤ 0 and NaN (`at_most` turns NaN into 1, hence the first test).
    let lobe = n_dot_h.gt(R::zero()) & c2.gt(R::zero());
    let c2 = R::select(lobe, c2, R::one());
    let a2 = alpha_squared(alpha);
    let tan2 = sin2_h.clamped(R::zero(), R::one()) / c2;
    let e = (-tan2 / a2).exp();
    let sec2 = R::one() + tan2;
    // e = 0 where sec⁴ may overflow: the product is 0, not 0·∞.
    R::select(lobe & e.gt(R::zero()), e * sec2 * sec2 / (R::PI() * a2), R::zero())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn sin2<R: Real>(c: R) -> R {
        one_minus_squared(c)
    }

    #[test]
    fn ggx_matches_hand_computed_values() {
        // α = 0.5, c = 0.8: α² = 0.25, 1 + (α² − 1)c² = 1 − 0.75·0.64 = 0.52.
        let d = ggx_d(0.8f64, sin2(0.8f64), 0.5);
        assert!((d - 0.25 / (PI * 0.52 * 0.52)).abs() < 1e-12);
        // Peak at c = 1: 1/(π α²).
        assert!((ggx_d(1.0f64, sin2(1.0f64), 0.5) - 1.0 / (PI * 0.25)).abs() < 1e-12);
        // α = 1 is uniform: 1/π everywhere.
        assert!((ggx_d(0.3f64, sin2(0.3f64), 1.0) - 1.0 / PI).abs() < 1e-12);
        // α = 0.7 at c = 0.9.
        let a2 = 0.49;
        let expect = a2 / (PI * (1.0f64 + (a2 - 1.0) * 0.81).powi(2));
        assert!((ggx_d(0.9f64, sin2(0.9f64), 0.7) - expect).abs() < 1e-12);
    }

    #[test]
    fn ggx_projected_area_integrates_to_one() {
        // ∫ D(θ) cos θ dω = 1 over the hemisphere (midpoint rule in θ).
        for alpha in [0.05f64, 0.3, 1.0] {
            let n = 200_000;
            let sum: f64 = (0..n)
                .map(|k| {
                    let t = (k as f64 + 0.5) / n as f64 * PI / 2.0;
                    ggx_d(t.cos(), sin2(t.cos()), alpha) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / n as f64)
                })
                .sum();
            assert!((sum - 1.0).abs() < 1e-3, "α = {alpha}: {sum}");
        }
    }

    #[test]
    fn beckmann_matches_hand_computed_values_and_integrates_to_one() {
        let (c, a) = (0.8f64, 0.3);
        let tan2 = (1.0 - c * c) / (c * c);
        let expect = (-tan2 / (a * a)).exp() / (PI * a * a * c.powi(4));
        assert!((beckmann_d(c, sin2(c), a) - expect).abs() < 1e-12 * expect);
        let n = 200_000;
        let sum: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64 * PI / 2.0;
                beckmann_d(t.cos(), sin2(t.cos()), a) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / n as f64)
            })
            .sum();
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }

    #[test]
    fn singular_inputs_give_documented_finite_values() {
        // α = 0 is raised to MIN_ALPHA: a finite spike at the peak, 0 elsewhere in f32.
        assert!((ggx_d(1.0f32, sin2(1.0f32), 0.0) as f64 - 1.0 / (PI * 1e-8)).abs() < 1e-6 * 1.0 / (PI * 1e-8));
        assert!(ggx_d(0.5f32, sin2(0.5f32), 0.0) < 1e-7);
        // Half vector under the surface or at grazing.
        assert_eq!(beckmann_d(0.0f32, sin2(0.0f32), 0.5), 0.0);
        assert_eq!(beckmann_d(-0.5f32, sin2(-0.5f32), 0.5), 0.0);
        // GGX has χ⁺(n·ω_h): no microfacet normal points below the surface.
        assert_eq!(ggx_d(-0.5f32, sin2(-0.5f32), 0.5), 0.0);
        assert_eq!(ggx_d(0.0f32, 1.0, 0.5), 0.0);
        // Beckmann near grazing with small α underflows to 0 instead of 0/0.
        assert_eq!(beckmann_d(1e-20f32, sin2(1e-20f32), 1e-4), 0.0);
        assert_eq!(beckmann_d(1e-30f32, sin2(1e-30f32), 1.0), 0.0);
        // NaN roughness never reaches the output as NaN: max(NaN, MIN_ALPHA) = MIN_ALPHA.
        assert!(ggx_d(0.5f32, sin2(0.5f32), f32::NAN).is_finite());
        assert_eq!(ggx_d(f32::NAN, 0.5, 0.5), 0.0);
        assert_eq!(beckmann_d(f32::NAN, 0.5, 0.5), 0.0);
        // Inconsistent inputs (sin²θ_h = 0 with a cosine whose square underflows): finite.
        assert_eq!(ggx_d(1e-30f32, 0.0, 0.5), 1.0 / (std::f32::consts::PI * 0.25));
        assert_eq!(beckmann_d(1e-30f32, 0.0, 0.5), 0.0);
        assert!(ggx_d(1e-30f32, f32::NAN, 1e-4).is_finite());
    }

    #[test]
    fn narrow_lobes_keep_f32_precision_near_the_peak_given_sin2() {
        // θ_h = α: 1 − cos²θ_h from the f32 cosine would have lost 3 digits at α = 0.01;
        // sin²θ_h given directly keeps D within 1e-6 of the f64 value.
        for alpha in [1e-2f64, 1e-3, 1e-4] {
            let t = alpha;
            let (c, s2) = ((t.cos() as f32), (t.sin().powi(2) as f32));
            for d in MicrofacetDistribution::ALL {
                let d32 = d.eval(c, s2, alpha as f32) as f64;
                let d64 = d.eval(c as f64, s2 as f64, alpha);
                assert!((d32 - d64).abs() <= 1e-6 * d64, "{d:?} α {alpha}: {d32} vs {d64}");
            }
        }
    }

    #[test]
    fn names_round_trip() {
        for d in MicrofacetDistribution::ALL {
            assert_eq!(d.name().parse::<MicrofacetDistribution>().unwrap(), *d);
        }
        let err = "phong".parse::<MicrofacetDistribution>().unwrap_err().to_string();
        assert!(err.contains("phong") && err.contains("ggx, beckmann"), "{err}");
    }
}
