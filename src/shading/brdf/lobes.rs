//! The non-microfacet lobes: Lambert diffuse and Blinn-Phong specular.

use super::Real;

/// Lambert: f_d = k_d · albedo / π (per channel). Constant in the directions.
#[inline(always)]
pub fn lambert<R: Real>(kd: R, albedo: R) -> R {
    kd * albedo * R::FRAC_1_PI()
}

/// Blinn-Phong as the assignment defines it: f_s = k_s (n·ω_h)^s, with n·ω_h clamped to
/// [0, 1] so the power is real and bounded; 0^0 = 1 (the s = 0 limit is the constant k_s).
/// Not energy-normalised: that is the assignment's model, kept as is.
#[inline(always)]
pub fn blinn_phong<R: Real>(ks: R, n_dot_h: R, shininess: R) -> R {
    let c = n_dot_h.max(R::zero()).min(R::one());
    ks * c.powf(shininess)
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
    fn blinn_phong_matches_hand_computed_values() {
        assert!((blinn_phong(1.0f64, 0.9, 1.0) - 0.9).abs() < 1e-16);
        assert!((blinn_phong(0.5f64, 0.9, 32.0) - 0.5 * 0.9f64.powi(32)).abs() < 1e-16);
        assert_eq!(blinn_phong(0.5f32, 0.0, 0.0), 0.5);
        assert_eq!(blinn_phong(0.5f32, -0.3, 2.0), 0.0);
        assert_eq!(blinn_phong(1.0f32, 1.0, 1e6), 1.0);
        assert!(blinn_phong(1.0f32, 0.999, 1e6) < 1e-30);
    }
}
