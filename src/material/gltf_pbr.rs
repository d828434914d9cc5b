//! glTF 2.0's metallic-roughness material: its factors and cut-out, and its BRDF at a point
//! (its textures are the material's, `Material::textures`).

use crate::brdf::{fresnel_schlick, ggx_d, lambert, schlick_f0_dielectric, LocalDots, MaskingShadowing};
use crate::lanes::{map3, Real};

/// glTF 2.0 metallic-roughness material, the reference BRDF of the glTF specification
/// (Appendix B), with base colour = `Material::albedo`:
///
/// f = (1 − F)·c_diff/π + F·D·V, with c_diff = base·(1 − metallic), F0 = lerp(0.04, base,
/// metallic), F = Schlick(F0, ω_i·ω_h), D = GGX(α), V = height-correlated Smith visibility
/// G/(4 (n·ω_i)(n·ω_o)), α = roughness².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfPbr {
    /// Metallic factor in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness factor in [0, 1] (α = roughness²).
    pub roughness: f32,
    /// Emitted radiance (emissive factor), added to the reflected radiance.
    pub emissive: [f32; 3],
    /// glTF `alphaMode` MASK: where the surface is cut out (`None`: opaque everywhere).
    pub cutout: Option<Cutout>,
}

/// glTF `alphaMode` MASK: the surface is there where its alpha — the base colour factor's alpha
/// times the base colour texture's (linear) alpha — is at least `cutoff`, and absent elsewhere:
/// rays pass through the cut-out parts, camera and shadow rays alike (`accel::alpha`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutout {
    /// glTF's `alphaCutoff` (0.5 by default).
    pub cutoff: f32,
    /// The base colour factor's alpha, in [0, 1].
    pub alpha: f32,
}

impl GltfPbr {
    /// f_r per channel with base colour `base_color` (see [`GltfPbr`]): (1 − F)·lambert(1 −
    /// metallic, base) + F·D·V, α = roughness². D and V clamp α to `MIN_ALPHA`, so α = 0
    /// (roughness 0) gives a finite spike; V is 0 where n·ω_i ≤ 0 or n·ω_o ≤ 0, which leaves the
    /// diffuse part to the shader's sidedness test.
    #[inline(always)]
    pub fn eval<R: Real>(&self, base_color: [f32; 3], dots: &LocalDots<R>) -> [R; 3] {
        let alpha = R::of(self.roughness * self.roughness);
        let v = MaskingShadowing::SmithGgxCorrelated.visibility(dots.n_dot_i, dots.n_dot_o, alpha);
        // D is finite (capped at its peak), so D·V is 0 where V is: D is skipped there.
        let dv = R::choose(v.eq(R::zero()), R::zero, || ggx_d(dots.n_dot_h, dots.sin2_h, alpha) * v);
        let metallic = R::of(self.metallic);
        // Dielectric F0 of glTF: ior 1.5 → ((1.5 − 1)/(1.5 + 1))² = 0.04.
        let f0_dielectric = schlick_f0_dielectric(R::lit(1.5));
        map3(base_color, |b| {
            let base = R::of(b);
            let f0 = f0_dielectric + (base - f0_dielectric) * metallic;
            let f = fresnel_schlick(f0, dots.i_dot_h);
            (R::one() - f) * lambert(R::one() - metallic, base) + f * dv
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use std::f64::consts::PI;

    fn dots(ci: f64, co: f64, nh: f64, ih: f64) -> LocalDots<f64> {
        LocalDots::from_cosines(ci, co, nh, ih)
    }

    /// glTF 2.0 Appendix B written out independently in f64, per channel.
    fn gltf_reference(base: f64, metallic: f64, roughness: f64, d: &LocalDots<f64>) -> f64 {
        let alpha = roughness * roughness;
        let a2 = alpha * alpha;
        let (nl, nv, nh, vh) = (d.n_dot_i, d.n_dot_o, d.n_dot_h, d.i_dot_h);
        let c_diff = base * (1.0 - metallic);
        let f0 = 0.04 * (1.0 - metallic) + base * metallic;
        let f = f0 + (1.0 - f0) * (1.0 - vh).powi(5);
        let dist = a2 / (PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
        let vis = 0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt());
        (1.0 - f) * c_diff / PI + f * dist * vis
    }

    #[test]
    fn gltf_pbr_matches_the_specification_formula() {
        let base = [0.9f32, 0.5, 0.1];
        for &(metallic, roughness) in &[(0.0f32, 0.5f32), (1.0, 0.3), (0.4, 0.8), (0.0, 1.0)] {
            let m = Material::gltf_pbr("g", base, metallic, roughness);
            assert!(m.has_specular());
            for d in [
                dots(0.6, 0.8, 0.95, 0.9),
                dots(0.2, 0.9, 0.7, 0.5),
                dots(1.0, 1.0, 1.0, 1.0),
            ] {
                let got = m.eval(&d);
                for c in 0..3 {
                    let expect = gltf_reference(base[c] as f64, metallic as f64, roughness as f64, &d);
                    assert!(
                        (got[c] - expect).abs() < 1e-6 * expect.max(1e-3),
                        "metallic {metallic} roughness {roughness} channel {c}: {} vs {expect}",
                        got[c]
                    );
                }
            }
        }
    }

    #[test]
    fn gltf_pbr_extremes_stay_finite_and_metals_have_no_diffuse() {
        // Roughness 0: α is raised to MIN_ALPHA inside D and V; a finite spike at n·h = 1.
        let mirror = Material::gltf_pbr("m", [1.0; 3], 1.0, 0.0);
        let dots32 =
            |ci: f32, co: f32, nh: f32, ih: f32| dots(ci as f64, co as f64, nh as f64, ih as f64).cast::<f32>();
        let peak = mirror.eval(&dots32(0.7, 0.7, 1.0, 0.7));
        assert!(peak.iter().all(|v| v.is_finite() && *v > 1e6), "{peak:?}");
        assert!(mirror.eval(&dots32(0.7, 0.7, 0.99, 0.7))[0] < 1e-3);
        // Grazing: V = 0 → only the diffuse part, which a metal does not have.
        assert_eq!(mirror.eval(&dots32(0.0, 0.7, 0.7, 0.7)), [0.0; 3]);
        let plastic = Material::gltf_pbr("p", [0.5; 3], 0.0, 0.5);
        let g = plastic.eval(&dots(0.0f64, 0.7, 0.7, 0.7));
        let f = 0.04 + 0.96 * 0.3f64.powi(5);
        assert!((g[0] - (1.0 - f) * 0.5 / PI).abs() < 1e-7, "{g:?}");
        assert_eq!(plastic.model_name(), "gltf-pbr");
    }
}
