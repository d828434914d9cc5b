//! Fresnel terms F(ω_i·ω_h): the share of light a microfacet reflects.

use super::named_terms;
use crate::lanes::{map3, F32x4, Lanes, Real};

/// Which Fresnel term a Cook-Torrance material uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FresnelTerm {
    /// Schlick's approximation (Schlick 1994).
    Schlick,
    /// Schlick with Karis' spherical-gaussian exponent.
    SchlickSg,
    /// Exact unpolarised Fresnel of a conductor with complex index η + iκ.
    Conductor,
    /// F = specular colour at every angle.
    Constant,
}

named_terms!(
    FresnelTerm, "F",
    Schlick => "schlick",
    SchlickSg => "schlick-sg",
    Conductor => "conductor",
    Constant => "constant",
);

/// Normal-incidence reflectance of a dielectric of index `ior` in air: F0 = ((n − 1)/(n + 1))²
/// (the Fresnel equations at θ = 0).
/// Symmetric in n ↔ 1/n; 0 at n = 1. `ior` > 0 is validated with the material, so n + 1 > 1.
#[inline(always)]
pub fn schlick_f0_dielectric<R: Real>(ior: R) -> R {
    let r = (ior - R::one()) / (ior + R::one());
    r * r
}

/// Schlick: F = F0 + (1 − F0)(1 − c)⁵, c = ω_i·ω_h clamped to [0, 1] (≥ 0 where the half vector
/// is behind the microfacet, ≤ 1 against rounding, so (1 − c)⁵ stays in [0, 1]).
///
/// Source: C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer
/// Graphics Forum 13(3), 1994, eq. 24.
#[inline(always)]
pub fn fresnel_schlick<R: Real>(f0: R, i_dot_h: R) -> R {
    let m = R::one() - i_dot_h.clamped(R::zero(), R::one());
    let m2 = m * m;
    f0 + (R::one() - f0) * m2 * m2 * m
}

/// Schlick with a spherical-gaussian exponent:
/// F = F0 + (1 − F0)·2^((−5.55473 c − 6.98316) c), c = ω_i·ω_h clamped to [0, 1].
///
/// Source: B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes.
#[inline(always)]
pub fn fresnel_schlick_sg<R: Real>(f0: R, i_dot_h: R) -> R {
    let c = i_dot_h.clamped(R::zero(), R::one());
    f0 + (R::one() - f0) * ((R::lit(-5.55473) * c - R::lit(6.98316)) * c).exp2()
}

/// Largest η and κ [`fresnel_conductor`] uses: beyond it F = 1 to within 4e-8 at normal
/// incidence (F ≥ 1 − 4η/(η² + κ²)) and closer to 1 at every other angle, while every square in
/// the formula stays finite in f32.
pub const MAX_CONDUCTOR_INDEX: f64 = 1e8;

/// Exact unpolarised reflectance of a conductor with complex index m = η + iκ (relative to the
/// outside medium) at cos θ = c, as Mitsuba's `fresnel_conductor` (after Moeller, "Optics"):
/// s² = 1 − c², t1 = η² − κ² − s², A = √(t1² + 4η²κ²), a = √((A + t1)/2),
/// Rs = (A + c² − 2ca)/(A + c² + 2ca), Rp = Rs (A c² + s⁴ − 2ca s²)/(A c² + s⁴ + 2ca s²),
/// F = (Rs + Rp)/2.
///
/// Source: the Fresnel equations for an absorbing medium (M. Born, E. Wolf, *Principles of
/// Optics*, the chapter on the optics of metals), in the form Mitsuba 3's `fresnel_conductor`
/// evaluates.
///
/// Evaluated without cancellation. With w = √(m² − s²) = a + ib: A = a² + b² and ab = ηκ, so
/// - the larger of a² = (A + t1)/2 and b² = (A − t1)/2 is computed from its formula (a sum of
///   like-signed terms) and the other as ηκ divided by its root — the textbook (A + t1)/2 cancels
///   completely for weakly absorbing media (κ → 0 with t1 < 0: a dielectric seen from the
///   denser side, past the critical angle);
/// - Rs = ((c − a)² + b²)/((c + a)² + b²) and Rp = Rs ((ac − s²)² + b²c²)/((ac + s²)² + b²c²),
///   the same quotients written as sums of squares, so a near-perfect index match (F → 0)
///   keeps its relative precision too.
///
/// η and κ are clamped to [0, [`MAX_CONDUCTOR_INDEX`]] (NaN counts as 0). The first denominator
/// is 0 only when c = a = b = 0, the second only when s = 0 and a = b = 0 (c = 1): both mean
/// A = 0, i.e. η² − κ² = s² and ηκ = 0, a lossless medium matching the grazing angle, where the
/// exact reflectance tends to 1 (total reflection at the critical angle); those points return 1.
#[inline(always)]
pub fn fresnel_conductor<R: Real>(i_dot_h: R, eta: R, k: R) -> R {
    let max_index = R::lit(MAX_CONDUCTOR_INDEX);
    let (eta, k) = (eta.clamped(R::zero(), max_index), k.clamped(R::zero(), max_index));
    let c = i_dot_h.clamped(R::zero(), R::one());
    let s2 = super::microfacet::one_minus_squared(c);
    let t1 = eta * eta - k * k - s2;
    let eta_k = eta * k;
    let a_sq = (t1 * t1 + R::lit(4.0) * eta_k * eta_k).sqrt();
    // t1 ≥ 0: a = √((A + t1)/2), b = ηκ/a (a = 0 only if A = t1 = 0, which needs ηκ = 0: b = 0).
    // t1 < 0: b = √((A − t1)/2) > 0, a = ηκ/b. Both roots are √((A + |t1|)/2).
    let root = ((a_sq + t1.abs()) * R::lit(0.5)).sqrt();
    let root_positive = root.gt(R::zero());
    let quotient = R::select(
        root_positive,
        eta_k / R::select(root_positive, root, R::one()),
        R::zero(),
    );
    let t1_non_negative = t1.ge(R::zero());
    let a = R::select(t1_non_negative, root, quotient);
    let b = R::select(t1_non_negative, quotient, root);
    let b2 = b * b;
    let rs_den = (c + a) * (c + a) + b2;
    // rs_den = 0 needs c = a = b = 0: F = 1 there.
    let rs_valid = rs_den.gt(R::zero());
    let rs = ((c - a) * (c - a) + b2) / R::select(rs_valid, rs_den, R::one());
    let (ac, b2c2) = (a * c, b2 * c * c);
    let rp_den = (ac + s2) * (ac + s2) + b2c2;
    let rp_valid = rp_den.gt(R::zero());
    let rp = R::select(
        rp_valid,
        rs * ((ac - s2) * (ac - s2) + b2c2) / R::select(rp_valid, rp_den, R::one()),
        rs,
    );
    R::select(
        rs_valid,
        ((rs + rp) * R::lit(0.5)).clamped(R::zero(), R::one()),
        R::one(),
    )
}

/// [`fresnel_conductor`] of the three colour channels. For a scalar f32 point the channels run as
/// three lanes of one [`F32x4`], each lane the f32 bits of its channel (the term takes two square
/// roots and three divisions); otherwise one channel after another.
#[inline(always)]
pub fn fresnel_conductor_rgb<R: Real>(i_dot_h: R, eta: [f32; 3], k: [f32; 3]) -> [R; 3] {
    if let Some(c) = i_dot_h.as_single_f32() {
        let lanes = |v: [f32; 3]| Lanes([v[0], v[1], v[2], v[2]]);
        let f = fresnel_conductor(F32x4::splat(c), lanes(eta), lanes(k));
        return map3([0, 1, 2], |ch| R::of(f.0[ch]));
    }
    // Channels written out, not through a closure (see `CookTorrance::fresnel`).
    [
        fresnel_conductor(i_dot_h, R::of(eta[0]), R::of(k[0])),
        fresnel_conductor(i_dot_h, R::of(eta[1]), R::of(k[1])),
        fresnel_conductor(i_dot_h, R::of(eta[2]), R::of(k[2])),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schlick_matches_hand_computed_values() {
        // A dielectric with n = 5: F0 = (4/6)² = 4/9.
        let f0 = schlick_f0_dielectric(5.0f64);
        assert!((f0 - 4.0 / 9.0).abs() < 1e-15);
        assert_eq!(fresnel_schlick(f0, 1.0), f0);
        assert_eq!(fresnel_schlick(f0, 0.0), 1.0);
        let c = 0.6f64;
        assert!((fresnel_schlick(0.04, c) - (0.04 + 0.96 * 0.4f64.powi(5))).abs() < 1e-15);
        // Negative ω_i·ω_h is clamped to 0.
        assert_eq!(fresnel_schlick(0.04f64, -0.3), 1.0);
        assert_eq!(schlick_f0_dielectric(1.0f64), 0.0);
        assert!((schlick_f0_dielectric(1.0 / 1.5f64) - schlick_f0_dielectric(1.5f64)).abs() < 1e-15);
    }

    #[test]
    fn three_channels_in_lanes_give_each_channels_f32_bits() {
        // Copper, a dielectric seen from the denser side (κ = 0, η < 1), a perfect index match,
        // clamped extremes and NaN parameters, at angles from grazing to normal and beyond.
        let media: [([f32; 3], [f32; 3]); 4] = [
            ([0.200, 0.924, 1.102], [3.912, 2.452, 2.142]),
            ([0.667, 1.0, 0.0], [0.0, 0.0, 0.0]),
            ([1e9, f32::NAN, 1.0], [f32::NAN, 1e-30, 1e9]),
            ([f32::INFINITY, 0.5, 2.0], [1.0, f32::INFINITY, -1.0]),
        ];
        for (eta, k) in media {
            for step in -2..=42 {
                let c = step as f32 / 40.0;
                for i_dot_h in [c, f32::NAN, 1e-30] {
                    let lanes = fresnel_conductor_rgb(i_dot_h, eta, k);
                    for ch in 0..3 {
                        let one = fresnel_conductor(i_dot_h, eta[ch], k[ch]);
                        assert_eq!(
                            lanes[ch].to_bits(),
                            one.to_bits(),
                            "channel {ch}, η {eta:?}, κ {k:?}, cos {i_dot_h}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn schlick_sg_is_close_to_schlick() {
        for k in 0..=20 {
            let c = k as f64 / 20.0;
            let a = fresnel_schlick(0.04, c);
            let b = fresnel_schlick_sg(0.04, c);
            assert!((a - b).abs() < 0.01, "c {c}: {a} vs {b}");
        }
        assert!((fresnel_schlick_sg(0.5f64, 0.0) - 1.0).abs() < 1e-15);
        // At c = 1: 2^(−12.53789) ≈ 1.68e-4 of (1 − F0) remains.
        let expect = 0.5 + 0.5 * 2f64.powf(-5.55473 - 6.98316);
        assert!((fresnel_schlick_sg(0.5f64, 1.0) - expect).abs() < 1e-15);
    }

    /// Textbook form with complex arithmetic: r_s = (c − w)/(c + w), r_p = (m² c − w)/(m² c + w),
    /// w = √(m² − s²), m = η + iκ.
    fn conductor_complex(c: f64, eta: f64, k: f64) -> f64 {
        use num_complex::Complex64 as C;
        let m = C::new(eta, k);
        let s2 = 1.0 - c * c;
        let w = (m * m - s2).sqrt();
        let rs = (c - w) / (c + w);
        let rp = (m * m * c - w) / (m * m * c + w);
        (rs.norm_sqr() + rp.norm_sqr()) / 2.0
    }

    #[test]
    fn conductor_matches_complex_fresnel_equations() {
        // Copper-like and gold-like RGB channels, and a dielectric (κ = 0).
        for &(eta, k) in &[
            (0.200f64, 3.912f64),
            (0.924, 2.452),
            (1.102, 2.142),
            (0.143, 3.983),
            (1.5, 0.0),
        ] {
            for i in 0..=10 {
                let c = i as f64 / 10.0;
                let ours = fresnel_conductor(c, eta, k);
                let exact = conductor_complex(c.max(1e-12), eta, k);
                assert!((ours - exact).abs() < 1e-9, "η {eta} κ {k} c {c}: {ours} vs {exact}");
            }
        }
    }

    #[test]
    fn conductor_special_cases() {
        // Mitsuba's material "none": η = 0, κ = 1 gives F ≡ 1.
        for c in [0.0f32, 0.3, 1.0] {
            assert!((fresnel_conductor(c, 0.0, 1.0) - 1.0).abs() < 1e-6);
        }
        // Normal incidence: ((η − 1)² + κ²)/((η + 1)² + κ²).
        let (eta, k) = (0.2f64, 3.9f64);
        let normal = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
        assert!((fresnel_conductor(1.0, eta, k) - normal).abs() < 1e-12);
        // Grazing: 1.
        assert!((fresnel_conductor(0.0f64, eta, k) - 1.0).abs() < 1e-12);
        // η = 1, κ = 0 (no interface): A = 0 at grazing, documented value 1; 0 elsewhere.
        assert_eq!(fresnel_conductor(0.0f32, 1.0, 0.0), 1.0);
        assert!(fresnel_conductor(0.7f32, 1.0, 0.0).abs() < 1e-6);
        // Degenerate η = κ = 0 at normal incidence: the second denominator is 0 → Rp = Rs = 1.
        assert_eq!(fresnel_conductor(1.0f32, 0.0, 0.0), 1.0);
        // Extreme indices clamp to the documented limit 1; NaN counts as 0 (η = κ = 0: F = 1).
        assert!(fresnel_conductor(0.5f32, 1e30, 1e30) > 1.0 - 1e-7);
        assert!(fresnel_conductor(0.5f32, f32::NAN, f32::NAN).is_finite());
    }

    #[test]
    fn weakly_absorbing_and_matched_media_keep_f32_precision() {
        // κ → 0 past the critical angle (η < 1), and a near-perfect index match (F ≈ 2.5e-7):
        // the textbook (A + t1)/2 and A + c² − 2ca cancel in f32, the sums of squares do not.
        for &(c, eta, k) in &[
            (0.3f64, 0.5f64, 1e-3f64),
            (0.2, 0.8, 1e-5),
            (1.0, 1.001, 0.0),
            (0.9, 1.0, 1e-4),
        ] {
            let (c32, e32, k32) = (c as f32, eta as f32, k as f32);
            let exact = conductor_complex(c32 as f64, e32 as f64, k32 as f64);
            let ours64 = fresnel_conductor(c32 as f64, e32 as f64, k32 as f64);
            let ours32 = fresnel_conductor(c32, e32, k32) as f64;
            assert!(
                (ours64 - exact).abs() <= 1e-9 * exact,
                "f64 c {c} η {eta} κ {k}: {ours64} vs {exact}"
            );
            assert!(
                (ours32 - exact).abs() <= 1e-5 * exact,
                "f32 c {c} η {eta} κ {k}: {ours32} vs {exact}"
            );
        }
    }
}
