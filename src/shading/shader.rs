//! The shader: outgoing radiance of a [`SurfacePoint`] under every light, with shadow rays.
//!
//! L_o = L_e + Σ_lights f_r(ω_i, ω_o) · E_light · cos θ_i · V, summed in light order
//! (deterministic); L_e is the emitted radiance of glTF materials with an emissive factor.
//! Under the physical convention, sidedness follows the material: one-sided (Mitsuba's
//! convention) contributes only where n_s·ω_i > 0 and n_s·ω_o > 0; two-sided first turns both
//! normals towards the viewer (when the shading normal faces away from it, as Mitsuba's
//! `twosided` does). Lights behind the surface are skipped before any shadow ray is traced.
//! Under the assignment convention (the normal-map `tp` preset, see [`ShadingConvention`]) the
//! same sum is formed from clamped dot products instead. Either way f_r is [`Material::eval`]:
//! the convention changes the inputs, never the BRDF.

use glam::Vec3;

use crate::shading::brdf::LocalDots;
use crate::shading::convention::{assignment_dots, ShadingConvention};
use crate::shading::light::Light;
use crate::shading::material::{Material, Specular};
use crate::shading::shadow::{Occluder, ShadowOffset, ShadowRay};
use crate::shading::texture::TextureImage;
use crate::surface::SurfacePoint;

/// Everything shading needs besides the point itself.
pub struct Shader<'a, O: Occluder> {
    /// The scene's materials, indexed by `SurfacePoint::material`.
    pub materials: &'a [Material],
    /// The scene's lights.
    pub lights: &'a [Light],
    /// What blocks shadow rays; `None` when the plan leaves shadows out.
    pub occluder: Option<&'a O>,
    /// Length unit of the shadow-ray offset (scene size / 256).
    pub scene_unit: f32,
    /// How directions and dot products are formed (the plan decides).
    pub convention: ShadingConvention,
    /// The scene's decoded texture images when the plan samples material textures; `None`
    /// otherwise (then no texture is looked up and materials use their constant factors).
    pub textures: Option<&'a [TextureImage]>,
    /// Add emitted radiance (the plan found a rendered material that emits).
    pub emission: bool,
    /// How shadow rays leave the surface.
    pub shadow_offset: ShadowOffset,
}

impl<O: Occluder> Shader<'_, O> {
    /// Outgoing radiance towards `sp.to_viewer`; `shadow_rays` counts the rays traced.
    /// Always finite and non-negative (the BRDF module guarantees it for f_r, lights for E).
    #[inline]
    pub fn shade(&self, sp: &SurfacePoint, shadow_rays: &mut u64) -> Vec3 {
        match self.convention {
            ShadingConvention::Physical => self.shade_physical(sp, shadow_rays),
            ShadingConvention::Assignment => self.shade_assignment(sp),
        }
    }

    #[inline(always)]
    fn shade_physical(&self, sp: &SurfacePoint, shadow_rays: &mut u64) -> Vec3 {
        let material = &self.materials[sp.material as usize];
        let wo = sp.to_viewer;
        let (mut ng, mut ns) = (sp.geometric_normal, sp.shading_normal);
        // Two-sided: face the viewer, decided by the shading normal as Mitsuba's `twosided` does
        // (so silhouettes of smooth meshes never turn black).
        if material.two_sided && ns.dot(wo) < 0.0 {
            ng = -ng;
            ns = -ns;
        }
        // Emission: from both sides of a two-sided material, from the front of a one-sided one.
        let mut radiance = Vec3::ZERO;
        if self.emission && (material.two_sided || sp.geometric_normal.dot(wo) > 0.0) {
            radiance = material.emission([sp.uv, sp.uv1], self.textures);
        }
        let cos_o = ns.dot(wo);
        if cos_o <= 0.0 {
            return radiance;
        }
        // Textured glTF materials: their BRDF parameters at this point, looked up once for all
        // lights.
        let textured = match (self.textures, &material.specular) {
            (Some(images), Specular::GltfPbr(p)) if p.textures.varies_brdf() => {
                Some(p.point_at(material.albedo, [sp.uv, sp.uv1], images))
            }
            _ => None,
        };
        for light in self.lights {
            let Some(ls) = light.sample(sp.position) else { continue };
            let cos_i = ns.dot(ls.wi);
            if cos_i <= 0.0 {
                continue;
            }
            let dots = if material.has_specular() {
                // ω_i = −ω_o cannot happen here (both are on the normal's side), but stay total.
                match LocalDots::from_unit_vectors(ns.to_array(), ls.wi.to_array(), wo.to_array()) {
                    Some(d) => d,
                    None => continue,
                }
            } else {
                // Lambert reads no dot product: skip the half vector.
                LocalDots::from_cosines(cos_i, cos_o, 0.0, 0.0)
            };
            if let Some(occluder) = self.occluder {
                *shadow_rays += 1;
                let ray = ShadowRay::new(self.shadow_offset, sp.position, ng, ls.wi, ls.distance, self.scene_unit);
                if occluder.occluded(&ray) {
                    continue;
                }
            }
            let f = Vec3::from(match &textured {
                Some(point) => point.eval(&dots),
                None => material.eval(&dots),
            });
            radiance += f * ls.irradiance * cos_i;
        }
        // Every term is finite and ≥ 0; only the sum of saturated lights could reach infinity.
        radiance.min(Vec3::splat(f32::MAX))
    }

    /// The assignment's L_o = Σ L_i · f(ω_i, ω_o) · (n·ω_i) with ω_i from the light towards the
    /// point, n as given and every dot product clamped to [0, 1] ([`assignment_dots`]). No sides
    /// and no shadow rays (the plan never pairs this convention with an occluder). Where ω_i + ω_o
    /// = 0 the half vector is undefined and only the diffuse part k_d·albedo/π is added.
    #[inline(always)]
    fn shade_assignment(&self, sp: &SurfacePoint) -> Vec3 {
        let material = &self.materials[sp.material as usize];
        let n = sp.shading_normal.to_array();
        let wo = sp.to_viewer.to_array();
        let specular = material.has_specular();
        let mut radiance = Vec3::ZERO;
        for light in self.lights {
            let Some(ls) = light.sample(sp.position) else { continue };
            let a = assignment_dots(n, (-ls.wi).to_array(), wo, specular);
            let f = if a.half_vector {
                material.eval(&a.dots)
            } else {
                material.diffuse()
            };
            radiance += Vec3::from(f) * ls.irradiance * a.dots.n_dot_i;
        }
        radiance.min(Vec3::splat(f32::MAX))
    }
}
