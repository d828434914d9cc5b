//! The non-microfacet lobes: Lambert diffuse and Blinn-Phong specular.

use crate::lanes::Real;

/// Lambert: f_d = k_d · albedo / π (per channel). Constant in the directions.
///
/// Source: J. H. Lambert, *Photometria*, 1760; the 1/π that makes a white surface reflect all
/// it receives, as in every physically based renderer (pbrt-v4's `DiffuseBxDF`).
#[inline(always)]
pub fn lambert<R: Real>(kd: R, albedo: R) -> R {
    kd * albedo * R::FRAC_1_PI()
}

/// The unnormalised Blinn-Phong lobe: f_s = k_s (n·ω_h)^s, with n·ω_h clamped to [0, 1] so the
/// power is real and bounded; 0^0 = 1 (the s = 0 limit is the constant k_s). Not
/// energy-normalised (no (s + 2)/2π factor): the lobe as Blinn wrote it, which the normal-map
/// `tp` preset needs as it is.
///
/// Source: J. F. Blinn, "Models of Light Reflection for Computer Synthesized Pictures",
/// SIGGRAPH 1977 (the half-vector form of Phong's cosine power).
///
/// A whole exponent from 1 to [`MAX_WHOLE_EXPONENT`] (the usual ones: 1, 8, 32, 100, …) takes
/// its power by multiplication (binary powering; s = 1 is c itself, as numpy's `c ** 1`): exp
/// and ln_1p cost more than the rest of a Lambert + Blinn-Phong evaluation together, and from
/// the rounded c such a power is within about s rounding errors of c's own (f32: 256 · 6e-8 =
/// 1.5e-5 relative at most). Any other exponent, near the peak (cos²θ_h > 1/2), is evaluated as
/// exp(s/2 · ln(1 − sin²θ_h)) with ln_1p, from the sin²θ_h of [`LocalDots`]: with s = 1e6 the
/// lobe is 1e-3 rad wide, where n·ω_h differs from 1 by 5e-7 and a power of the rounded cosine
/// would be off by several percent in f32. Elsewhere c itself is accurate and c^s is used.
///
/// The exponent is a material's constant, the same in every lane: which form is taken is decided
/// once per call, not per lane.
///
/// [`LocalDots`]: super::LocalDots
#[inline(always)]
pub fn blinn_phong<R: Real>(ks: R, n_dot_h: R, sin2_h: R, shininess: f32) -> R {
    let c = n_dot_h.clamped(R::zero(), R::one());
    ks * match whole_exponent(shininess) {
        Some(e) => whole_power(c, e),
        None => logarithmic_lobe(c, sin2_h, R::of(shininess)),
    }
}

/// The largest exponent [`blinn_phong`] takes its power of by multiplication: at most eight
/// squarings and eight products.
pub const MAX_WHOLE_EXPONENT: u32 = 256;

/// `shininess` as a whole exponent from 1 to [`MAX_WHOLE_EXPONENT`]; `None` otherwise
/// (fractions, 0, larger exponents, NaN).
#[inline(always)]
fn whole_exponent(shininess: f32) -> Option<u32> {
    // `as` saturates (NaN → 0): only a whole number in range converts back to itself.
    let e = shininess as u32;
    ((1..=MAX_WHOLE_EXPONENT).contains(&e) && e as f32 == shininess).then_some(e)
}

/// c^`exponent` by binary powering (`exponent` ≥ 1).
#[inline(always)]
fn whole_power<R: Real>(mut base: R, exponent: u32) -> R {
    let (mut power, mut e) = (R::one(), exponent);
    loop {
        if e & 1 == 1 {
            power = power * base;
        }
        e >>= 1;
        if e == 0 {
            return power;
        }
        base = base * base;
    }
}

/// c^s for any exponent s ≥ 0, through ln_1p of sin²θ_h near the peak (0^0 = 1).
#[inline(always)]
fn logarithmic_lobe<R: Real>(c: R, sin2_h: R, shininess: R) -> R {
    let s2 = sin2_h.clamped(R::zero(), R::one());
    let near_peak = s2.lt(R::lit(0.5)) & c.gt(R::zero());
    let lobe = R::choose(
        near_peak,
        || (R::lit(0.5) * shininess * (-s2).ln_1p()).exp(),
        || c.powf(shininess),
    );
    R::select(shininess.eq(R::zero()), R::one(), lobe)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn lambert_is_albedo_over_pi() {
        assert!((lambert(1.0f64, 0.7) - 0.7 / PI).abs() < 1e-16);
        assert!((lambert(0.5f32, 0.4) - 0.2 / PI as f32).abs() < 1e-8);
    }

    #[test]
    fn lambert_white_furnace_reflects_the_albedo() {
        // ∫ f_d cos θ dω over the hemisphere = k_d·albedo.
        let n = 100_000;
        let sum: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64 * PI / 2.0;
                lambert(1.0, 0.6) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / n as f64)
            })
            .sum();
        assert!((sum - 0.6).abs() < 1e-6, "{sum}");
    }

    #[test]
    fn whole_exponents_are_recognised_and_others_are_not() {
        assert_eq!(whole_exponent(1.0), Some(1));
        assert_eq!(whole_exponent(32.0), Some(32));
        assert_eq!(whole_exponent(256.0), Some(256));
        for s in [0.0, 0.5, 1.5, 31.999, 257.0, 1e6, -2.0, f32::NAN, f32::INFINITY] {
            assert_eq!(whole_exponent(s), None, "{s}");
        }
    }

    #[test]
    fn whole_powers_agree_with_the_general_lobe() {
        // Every whole exponent, cosines across [0, 1] and at the peak, both precisions: within a
        // few rounding errors per squaring of the exp/ln_1p and powf forms.
        for e in 1..=MAX_WHOLE_EXPONENT {
            for k in 0..=200 {
                let c = 1.0 - (k as f64 / 200.0).powi(3);
                let s2 = (1.0 - c) * (1.0 + c);
                let (want, got) = (logarithmic_lobe(c, s2, e as f64), whole_power(c, e));
                assert!(
                    (got - want).abs() <= 1e-13 * want.max(1e-300),
                    "f64 s = {e}, c = {c}: {got} {want}"
                );
                let (c32, s2_32) = (c as f32, s2 as f32);
                let want32 = logarithmic_lobe(c32, s2_32, e as f32) as f64;
                let got32 = whole_power(c32, e) as f64;
                let bound = 4e-7 * e as f64 * want32 + 1e-37;
                assert!(
                    (got32 - want32).abs() <= bound,
                    "f32 s = {e}, c = {c32}: {got32} {want32}"
                );
            }
            assert_eq!(blinn_phong(0.7f64, 1.0, 0.0, e as f32), 0.7, "the peak");
            assert_eq!(blinn_phong(0.7f64, -0.2, 0.96, e as f32), 0.0, "below the horizon");
        }
        assert_eq!(blinn_phong(1.0f64, 0.3, 0.91, 1.0), 0.3, "s = 1 is the cosine itself");
    }

    #[test]
    fn blinn_phong_matches_hand_computed_values() {
        let s2 = |c: f64| 1.0 - c * c;
        assert!((blinn_phong(1.0f64, 0.9, s2(0.9), 1.0) - 0.9).abs() < 1e-15);
        assert!((blinn_phong(0.5f64, 0.9, s2(0.9), 32.0) - 0.5 * 0.9f64.powi(32)).abs() < 1e-15);
        assert!((blinn_phong(0.5f64, 0.3, s2(0.3), 3.0) - 0.5 * 0.3f64.powi(3)).abs() < 1e-15);
        assert_eq!(blinn_phong(0.5f32, 0.0, 1.0, 0.0), 0.5);
        assert_eq!(blinn_phong(0.5f32, -0.3, 0.91, 2.0), 0.0);
        assert_eq!(blinn_phong(0.5f32, 0.0, 1.0, 2.0), 0.0);
        assert_eq!(blinn_phong(1.0f32, 1.0, 0.0, 1e6), 1.0);
        assert!(blinn_phong(1.0f32, 0.999, s2(0.999) as f32, 1e6) < 1e-30);
    }

    #[test]
    fn blinn_phong_huge_exponent_keeps_f32_precision_near_the_peak() {
        // s = 1e6, θ_h = 1e-3: the lobe is e^(−1/2)·… ; from the cosine alone f32 is off by ~3%.
        let t = 1e-3f64;
        let (c, s2) = (t.cos(), t.sin().powi(2));
        let exact = blinn_phong(1.0f64, c, s2, 1e6);
        let f32_value = blinn_phong(1.0f32, c as f32, s2 as f32, 1e6) as f64;
        assert!((f32_value - exact).abs() <= 1e-5 * exact, "{f32_value} vs {exact}");
        assert!((exact - c.powf(1e6)).abs() <= 1e-9 * exact);
    }
}
