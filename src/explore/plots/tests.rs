use super::*;
use crate::scene::file::{material_from_toml, MaterialDefaults};

fn material(text: &str) -> Material {
    material_from_toml("m", text, &MaterialDefaults::SCENE).unwrap()
}

/// A Lambert material reflects k_d·albedo of what arrives at any θ_i (at 90°, the limit): the
/// quadrature must give that to within a tenth of a percent.
#[test]
fn albedo_of_lambert_is_kd_times_albedo() {
    let m = material("model = \"lambert\"\nalbedo = [0.8, 0.5, 0.2]\nkd = 0.5\n");
    let theta: Vec<f64> = (0..=18).map(|i| 5.0 * i as f64).collect();
    let a = albedo(&m, &theta);
    for (t, a) in theta.iter().zip(&a) {
        let expected = [0.4, 0.25, 0.1];
        for c in 0..3 {
            assert!((a[c] - expected[c]).abs() < 1e-3, "θ_i = {t}: {a:?}");
        }
    }
}

/// A mirror-like microfacet lobe with F ≡ 1 and no diffuse part keeps at most what arrives, and
/// nearly all of it at normal incidence (the separable Smith G loses under 1% there), however
/// narrow the lobe: the cells follow it.
#[test]
fn albedo_of_a_white_microfacet_lobe_conserves_energy() {
    for roughness in [0.005, 0.05, 0.3, 1.0] {
        let m = material(&format!(
            "model = \"cook-torrance\"\nfresnel = \"constant\"\nkd = 0.0\nroughness = {roughness}\n"
        ));
        let a = albedo(&m, &[0.0, 30.0, 60.0, 85.0]);
        for v in &a {
            assert!(v[0] <= 1.0 + 2e-3, "α = {roughness}: {a:?}");
        }
        if roughness <= 0.05 {
            assert!(a[0][0] > 0.99, "α = {roughness}: {a:?}");
        }
    }
}

#[test]
fn polar_peaks_at_the_mirror_direction_and_has_terms_for_cook_torrance_only() {
    let m = material("model = \"cook-torrance\"\nroughness = 0.1\n");
    let c = polar(&m, direction(40.0, 0.0), 181);
    assert_eq!(c.theta_o.len(), 181);
    let d = &c.terms.as_ref().unwrap().d;
    let peak = (0..181).max_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap();
    assert_eq!(c.theta_o[peak], -40.0);
    // f_r is the shader's own at each direction.
    let wo = direction(-40.0, 0.0);
    assert_eq!(c.f_r[peak], brdf_value(&m, [0.0, 0.0, 1.0], direction(40.0, 0.0), wo));
    assert!(polar(&material("model = \"lambert\"\n"), direction(0.0, 0.0), 5)
        .terms
        .is_none());
}

#[test]
fn lobe_of_lambert_is_flat() {
    let m = material("model = \"lambert\"\nalbedo = [1.0, 1.0, 1.0]\n");
    let values = lobe(&m, direction(30.0, 0.0), 4, 8);
    assert_eq!(values.len(), 5 * 8);
    let flat = 1.0 / std::f64::consts::PI;
    assert!(values.iter().all(|v| (v - flat).abs() < 1e-6), "{values:?}");
}

/// A white Lambert sphere lit from the viewer is 1 at its centre (sRGB 255), 0 outside.
#[test]
fn lit_sphere_is_white_at_the_centre_and_black_outside() {
    let m = material("model = \"lambert\"\nalbedo = [1.0, 1.0, 1.0]\n");
    let png = lit_sphere(&m, direction(0.0, 0.0), 64).unwrap();
    let image = image::load_from_memory(&png).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (64, 64));
    assert!(
        image.get_pixel(32, 32).0.iter().all(|&c| c >= 254),
        "{:?}",
        image.get_pixel(32, 32)
    );
    assert_eq!(image.get_pixel(0, 0).0, [0, 0, 0]);
}
