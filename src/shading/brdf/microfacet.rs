//! Microfacet normal distributions D(ω_h).

use super::{named_terms, Real};

/// Smallest roughness α the distributions accept; smaller values are raised to it (as Mitsuba
/// does). Below it the lobe is narrower than f32 can resolve in n·ω_h anyway: at α = 1e-4 the
/// peak D = 1/(πα²) ≈ 3.2e7 is still far from overflow, and 1 − n·ω_h at half-width is ~1e-8.
pub const MIN_ALPHA: f64 = 1e-4;

/// Which microfacet distribution a Cook-Torrance material uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MicrofacetDistribution {
    /// Trowbridge–Reitz / GGX, α used directly (the assignment).
    Ggx,
    /// Beckmann–Spizzichino.
    Beckmann,
}

named_terms!(MicrofacetDistribution, "D", Ggx => "ggx", Beckmann => "beckmann");

impl MicrofacetDistribution {
    /// D(n·ω_h) for roughness `alpha`.
    #[inline(always)]
    pub fn eval<R: Real>(self, n_dot_h: R, alpha: R) -> R {
        match self {
            Self::Ggx => ggx_d(n_dot_h, alpha),
            Self::Beckmann => beckmann_d(n_dot_h, alpha),
        }
    }
}

/// 1 − c², computed as (1 − c)(1 + c): for c near 1 the subtraction 1 − c is exact (Sterbenz),
/// so the result keeps its relative precision where 1 − c·c would cancel.
#[inline(always)]
pub(crate) fn one_minus_squared<R: Real>(c: R) -> R {
    ((R::one() - c) * (R::one() + c)).max(R::zero())
}

/// GGX (Trowbridge–Reitz):
/// D = α² / (π (1 + (α² − 1)(n·ω_h)²)²),
/// evaluated as α² / (π ((1 − c²) + α² c²)²) so that the peak (c → 1) does not cancel.
/// c is clamped to [0, 1] (a half vector below the surface has no microfacets) and α to
/// [`MIN_ALPHA`], so the denominator is ≥ π·MIN_ALPHA⁴·… > 0: always finite.
#[inline(always)]
pub fn ggx_d<R: Real>(n_dot_h: R, alpha: R) -> R {
    let c = n_dot_h.max(R::zero()).min(R::one());
    let a2 = {
        let a = alpha.max(R::lit(MIN_ALPHA));
        a * a
    };
    let c2 = c * c;
    let t = one_minus_squared(c) + a2 * c2;
    // t ≥ min(1, α²)·(sin² + cos²)… > 0: at c = 1, t = α² ≥ 1e-8 (normal in f32).
    a2 / (R::PI() * t * t)
}

/// Beckmann: D = exp(−tan²θ_h / α²) / (π α² cos⁴θ_h), tan²θ_h = (1 − c²)/c².
/// Zero for c ≤ 0 (the limit: the exponential vanishes faster than cos⁴ does), and zero where the
/// exponential underflows — which happens before cos⁴ can underflow for α ≤ 1, so no 0/0 arises.
#[inline(always)]
pub fn beckmann_d<R: Real>(n_dot_h: R, alpha: R) -> R {
    let c = n_dot_h.min(R::one());
    if !(c > R::zero()) {
        return R::zero();
    }
    let a2 = {
        let a = alpha.max(R::lit(MIN_ALPHA));
        a * a
    };
    let c2 = c * c;
    let e = (-(one_minus_squared(c) / c2) / a2).exp();
    if e == R::zero() {
        return R::zero();
    }
    e / (R::PI() * a2 * c2 * c2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn ggx_matches_hand_computed_values() {
        // α = 0.5, c = 0.8: α² = 0.25, 1 + (α² − 1)c² = 1 − 0.75·0.64 = 0.52.
        let d = ggx_d(0.8f64, 0.5);
        assert!((d - 0.25 / (PI * 0.52 * 0.52)).abs() < 1e-12);
        // Peak at c = 1: 1/(π α²).
        assert!((ggx_d(1.0f64, 0.5) - 1.0 / (PI * 0.25)).abs() < 1e-12);
        // α = 1 is uniform: 1/π everywhere.
        assert!((ggx_d(0.3f64, 1.0) - 1.0 / PI).abs() < 1e-12);
        // The assignment's α = 0.7 at c = 0.9.
        let a2 = 0.49;
        let expect = a2 / (PI * (1.0f64 + (a2 - 1.0) * 0.81).powi(2));
        assert!((ggx_d(0.9f64, 0.7) - expect).abs() < 1e-12);
    }

    #[test]
    fn ggx_projected_area_integrates_to_one() {
        // ∫ D(θ) cos θ dω = 1 over the hemisphere (midpoint rule in θ).
        for alpha in [0.05f64, 0.3, 1.0] {
            let n = 200_000;
            let sum: f64 = (0..n)
                .map(|k| {
                    let t = (k as f64 + 0.5) / n as f64 * PI / 2.0;
                    ggx_d(t.cos(), alpha) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / n as f64)
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
        assert!((beckmann_d(c, a) - expect).abs() < 1e-12 * expect);
        let n = 200_000;
        let sum: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64 * PI / 2.0;
                beckmann_d(t.cos(), a) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / n as f64)
            })
            .sum();
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }

    #[test]
    fn singular_inputs_give_documented_finite_values() {
        // α = 0 is raised to MIN_ALPHA: a finite spike at the peak, 0 elsewhere in f32.
        assert!((ggx_d(1.0f32, 0.0) as f64 - 1.0 / (PI * 1e-8)).abs() < 1e-6 * 1.0 / (PI * 1e-8));
        assert!(ggx_d(0.5f32, 0.0) < 1e-7);
        // Half vector under the surface or at grazing.
        assert_eq!(beckmann_d(0.0f32, 0.5), 0.0);
        assert_eq!(beckmann_d(-0.5f32, 0.5), 0.0);
        assert!(ggx_d(-0.5f32, 0.5).is_finite());
        // Beckmann near grazing with small α underflows to 0 instead of 0/0.
        assert_eq!(beckmann_d(1e-20f32, 1e-4), 0.0);
        assert_eq!(beckmann_d(1e-30f32, 1.0), 0.0);
        // NaN roughness never reaches the output as NaN: max(NaN, MIN_ALPHA) = MIN_ALPHA.
        assert!(ggx_d(0.5f32, f32::NAN).is_finite());
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
