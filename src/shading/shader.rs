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

use crate::shading::brdf::{dot3, map3, F32x8, LocalDots, Mask, Real, LANES};
use crate::shading::convention::{assignment_dots, ShadingConvention};
use crate::shading::light::Light;
use crate::shading::material::{Material, Specular};
use crate::shading::shadow::{Occluder, ShadowOffset, ShadowRay};
use crate::shading::texture::TextureImage;
use crate::surface::{SurfaceLanes, SurfacePoint};

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
        // NaN (a normal no loader produces) counts as facing away, as in the lanes.
        if cos_o.is_nan() || cos_o <= 0.0 {
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
            if cos_i.is_nan() || cos_i <= 0.0 {
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
        let mut radiance = Vec3::ZERO;
        for light in self.lights {
            let Some(ls) = light.sample(sp.position) else { continue };
            let term = assignment_term(material, n, (-ls.wi).to_array(), wo, ls.irradiance.to_array());
            radiance += Vec3::from(term);
        }
        radiance.min(Vec3::splat(f32::MAX))
    }

    /// [`Shader::shade`] of [`LANES`] points at once: through [`Shader::shade_surface_lanes`]
    /// when they share a material and the shader has lanes for them, otherwise one by one.
    #[inline]
    pub fn shade_lanes(&self, points: &[SurfacePoint; LANES], shadow_rays: &mut u64) -> [Vec3; LANES] {
        match SurfaceLanes::from_points(points) {
            Some(lanes) if self.has_lanes() => {
                let radiance = self.shade_surface_lanes(&lanes);
                std::array::from_fn(|i| Vec3::new(radiance[0].0[i], radiance[1].0[i], radiance[2].0[i]))
            }
            _ => points.map(|p| self.shade(&p, shadow_rays)),
        }
    }

    /// Whether [`Shader::shade_surface_lanes`] serves this shader: always under the assignment
    /// convention; under the physical one when there is nothing the lanes do not carry — no
    /// shadow rays, no textures, no emission (the normal-map mode).
    pub fn has_lanes(&self) -> bool {
        match self.convention {
            ShadingConvention::Assignment => true,
            ShadingConvention::Physical => self.occluder.is_none() && self.textures.is_none() && !self.emission,
        }
    }

    /// [`Shader::shade`] of eight points of one material, per channel, on [`F32x8`] lanes — the
    /// same functions, in eight lanes, giving what the scalar path gives. Only for a shader that
    /// [`Shader::has_lanes`].
    #[inline(always)]
    pub fn shade_surface_lanes(&self, points: &SurfaceLanes) -> [F32x8; 3] {
        debug_assert!(self.has_lanes());
        match self.convention {
            ShadingConvention::Assignment => self.shade_assignment_lanes(points),
            ShadingConvention::Physical => self.shade_physical_lanes(points),
        }
    }

    /// The physical convention of [`Shader::shade`] without shadow rays, textures or emission,
    /// on lanes: a two-sided material turns the normal towards the viewer, and a light adds
    /// f·E·cos θ_i where n·ω_o > 0, n·ω_i > 0 and a shading frame exists (elsewhere the lane
    /// adds 0, which the scalar path skips).
    #[inline(always)]
    fn shade_physical_lanes(&self, points: &SurfaceLanes) -> [F32x8; 3] {
        let material = &self.materials[points.material as usize];
        let wo = points.to_viewer;
        let mut ns = points.shading_normal;
        if material.two_sided {
            let flip = dot3(ns, wo).lt(F32x8::splat(0.0));
            ns = map3(ns, |c| F32x8::select(flip, -c, c));
        }
        let cos_o = dot3(ns, wo);
        let visible = cos_o.gt(F32x8::splat(0.0));
        let mut radiance = [F32x8::splat(0.0); 3];
        if !visible.any() {
            return radiance;
        }
        for light in self.lights {
            let ls = light.sample_points(points.position);
            let cos_i = dot3(ns, ls.wi);
            let mut lit = visible & ls.lit & cos_i.gt(F32x8::splat(0.0));
            let dots = if material.has_specular() {
                let (dots, frame) = LocalDots::from_unit_vectors_masked(ns, ls.wi, wo);
                lit = lit & frame;
                dots
            } else {
                LocalDots::from_cosines(cos_i, cos_o, F32x8::splat(0.0), F32x8::splat(0.0))
            };
            if !lit.any() {
                continue;
            }
            let f = material.eval(&dots);
            for c in 0..3 {
                let term = f[c] * ls.irradiance[c] * cos_i;
                radiance[c] = radiance[c] + F32x8::select(lit, term, F32x8::splat(0.0));
            }
        }
        map3(radiance, |c| c.min(F32x8::splat(f32::MAX)))
    }

    /// The assignment convention's L_o (see [`Shader::shade`]) of eight points, per channel: the
    /// dot products, lights and BRDF run on [`F32x8`] lanes — the same functions, in eight lanes,
    /// giving what the scalar path gives. Only for a shader whose convention is
    /// [`ShadingConvention::Assignment`] (the caller's plan decides; the result ignores sides).
    #[inline(always)]
    pub fn shade_assignment_lanes(&self, points: &SurfaceLanes) -> [F32x8; 3] {
        debug_assert_eq!(self.convention, ShadingConvention::Assignment);
        let material = &self.materials[points.material as usize];
        let mut radiance = [F32x8::splat(0.0); 3];
        for light in self.lights {
            // Where the light sends nothing (a light at the point), its irradiance is 0 and its
            // direction the zero vector: the term is 0 and finite.
            let ls = light.sample_points(points.position);
            let wi_from_light = map3(ls.wi, |c| -c);
            let term = assignment_term(
                material,
                points.shading_normal,
                wi_from_light,
                points.to_viewer,
                ls.irradiance,
            );
            for c in 0..3 {
                radiance[c] = radiance[c] + term[c];
            }
        }
        map3(radiance, |c| c.min(F32x8::splat(f32::MAX)))
    }
}

/// One light's L_i · f(ω_i, ω_o) · (n·ω_i) under the assignment convention, per channel, in any
/// [`Real`] (f32 for one point, [`F32x8`] for eight).
#[inline(always)]
fn assignment_term<R: Real>(
    material: &Material,
    n: [R; 3],
    wi_from_light: [R; 3],
    wo: [R; 3],
    irradiance: [R; 3],
) -> [R; 3] {
    let a = assignment_dots(n, wi_from_light, wo, material.has_specular());
    let diffuse = material.diffuse::<R>();
    let f = if a.half_vector.any() {
        let e = material.eval(&a.dots);
        map3([0, 1, 2], |c| R::select(a.half_vector, e[c], diffuse[c]))
    } else {
        diffuse
    };
    map3([0, 1, 2], |c| f[c] * irradiance[c] * a.dots.n_dot_i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
    use crate::shading::light::{Falloff, LightKind};
    use crate::shading::material::{BlinnPhong, CookTorrance};
    use crate::shading::shadow::NoOcclusion;
    use glam::Vec2;

    /// Every model and term combination the shader can meet.
    fn materials() -> Vec<Material> {
        let mut all = vec![Material::lambert("lambert", [0.4, 0.7, 0.4])];
        let mut bp = all[0].clone();
        bp.specular = Specular::BlinnPhong(BlinnPhong {
            ks: 0.8,
            shininess: 40.0,
            color: [1.0, 0.9, 0.8],
        });
        all.push(bp);
        for d in MicrofacetDistribution::ALL {
            for g in MaskingShadowing::ALL {
                for f in FresnelTerm::ALL {
                    let mut m = all[0].clone();
                    m.specular = Specular::CookTorrance(CookTorrance {
                        d: *d,
                        g: *g,
                        f: *f,
                        alpha: 0.3,
                        ..CookTorrance::ASSIGNMENT
                    });
                    all.push(m);
                }
            }
        }
        all.push(Material::gltf_pbr("pbr", [0.8, 0.5, 0.2], 0.6, 0.4));
        all
    }

    /// Points with every kind of input: ordinary ones, n = 0, a normal longer than 1, the light
    /// at the point, the viewer at the point, and ω_i = −ω_o (no half vector).
    fn points() -> Vec<SurfacePoint> {
        let light = Vec3::new(0.0, 1.0, 1.0);
        let point = |position: Vec3, n: Vec3, to_viewer: Vec3| SurfacePoint {
            position,
            geometric_normal: Vec3::Z,
            shading_normal: n,
            uv: Vec2::ZERO,
            uv1: Vec2::ZERO,
            material: 0,
            to_viewer,
        };
        let mut v: Vec<SurfacePoint> = (0..21)
            .map(|k| {
                let t = k as f32 * 0.3;
                let n = Vec3::new(t.sin() * 0.6, t.cos() * 0.5, 0.7 + 0.1 * t);
                point(
                    Vec3::new(t, 2.0 - t, 0.1 * t),
                    n,
                    Vec3::new(0.3, t.cos(), 0.8).normalize(),
                )
            })
            .collect();
        v.push(point(Vec3::new(3.0, 1.0, 0.0), Vec3::ZERO, Vec3::Z));
        v.push(point(Vec3::new(3.0, 1.0, 0.0), Vec3::new(0.9, 1.1, 0.8), Vec3::Z));
        v.push(point(light, Vec3::Z, Vec3::Z));
        v.push(point(Vec3::ZERO, Vec3::Z, Vec3::ZERO));
        v.push(point(Vec3::new(2.0, 0.5, 0.0), Vec3::new(f32::NAN, 0.0, 1.0), Vec3::Z));
        // Normals facing away from the viewer (a two-sided material turns them around).
        v.push(point(Vec3::new(1.0, 3.0, 0.5), Vec3::new(0.1, -0.2, -0.9), Vec3::Z));
        v.push(point(
            Vec3::new(-1.0, 2.0, 0.0),
            Vec3::new(0.0, 0.6, -0.8),
            Vec3::new(0.0, 0.6, 0.8),
        ));
        // ω_i (from the light towards the point) = −ω_o.
        let p = Vec3::new(0.0, 0.0, 0.0);
        v.push(point(p, Vec3::Y, (light - p).normalize()));
        v
    }

    #[test]
    fn eight_lanes_shade_exactly_as_one_point_at_a_time() {
        let lights = [
            Light {
                kind: LightKind::Point {
                    position: Vec3::new(0.0, 1.0, 1.0),
                },
                power: Vec3::splat(0.5),
                falloff: Falloff::None,
            },
            Light {
                kind: LightKind::Spot {
                    position: Vec3::new(1.0, 4.0, 2.0),
                    direction: Vec3::new(0.0, -1.0, -0.2).normalize(),
                    cos_inner: 0.9,
                    cos_outer: 0.5,
                },
                power: Vec3::new(3.0, 2.0, 1.0),
                falloff: Falloff::InverseSquareWithin { range: 6.0 },
            },
            Light {
                kind: LightKind::Directional {
                    direction: Vec3::new(0.2, -1.0, -0.3).normalize(),
                },
                power: Vec3::ONE,
                falloff: Falloff::InverseSquare,
            },
        ];
        let points = points();
        let conventions = [ShadingConvention::Assignment, ShadingConvention::Physical];
        let sided = materials().into_iter().flat_map(|m| {
            let mut other = m.clone();
            other.two_sided = !m.two_sided;
            [m, other]
        });
        for (material, convention) in sided.flat_map(|m| conventions.map(|c| (m.clone(), c))) {
            let shader = Shader::<NoOcclusion> {
                materials: std::slice::from_ref(&material),
                lights: &lights,
                occluder: None,
                scene_unit: 1.0,
                convention,
                textures: None,
                emission: false,
                shadow_offset: Default::default(),
            };
            assert!(shader.has_lanes());
            for start in 0..points.len() - LANES {
                let group: [SurfacePoint; LANES] = std::array::from_fn(|i| points[start + i]);
                let lanes = shader.shade_lanes(&group, &mut 0);
                for (p, lane) in group.iter().zip(lanes) {
                    let one = shader.shade(p, &mut 0);
                    // Equal as numbers (the sign of a zero may differ) and never NaN.
                    assert!(
                        lane == one && lane.is_finite(),
                        "{} {convention:?} two-sided {}: {lane} vs {one} at {p:?}",
                        material.name,
                        material.two_sided
                    );
                }
            }
        }
    }
}
