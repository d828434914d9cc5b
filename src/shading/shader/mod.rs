//! The shader: outgoing radiance of a [`SurfacePoint`] under every light, with shadow rays.
//!
//! L_o = L_e + Σ_lights f_r(ω_i, ω_o) · E_light · cos θ_i · V, summed in light order
//! (deterministic); L_e is the emitted radiance of glTF materials with an emissive factor.
//! Under the physical convention, sidedness follows the material: one-sided (Mitsuba's
//! convention) contributes only where n_s·ω_i > 0 and n_s·ω_o > 0; two-sided first turns both
//! normals towards the viewer (when the shading normal faces away from it, as Mitsuba's
//! `twosided` does). Lights behind the surface are skipped before any shadow ray is traced.
//! Under the clamped convention (the normal-map `tp` preset's, see [`ShadingConvention`]) the
//! same sum is formed from clamped dot products instead. Either way f_r is [`Material::eval`]:
//! the convention changes the inputs, never the BRDF.

use std::borrow::Borrow;

use glam::Vec3;

use crate::brdf::LocalDots;

use crate::accel::shadow::{Occluder, SceneExtent, ShadowRay};
use crate::lanes::{dot3, map3, Mask, Real, Scalar};
use crate::light::{Light, LightSample};
use crate::material::{BrdfModel, Material, PointBrdf};
use crate::scene::shadows::ShadowOffset;
use crate::shading::convention::{clamped_dots, ShadingConvention, UnitForm};
use crate::surface::{SurfaceLanes, SurfacePoint};
use crate::texture::TextureImage;

mod lanes;
pub mod rows;
mod terms;

pub use terms::{cook_torrance_terms, CookTorranceTerms};

/// Most points of a [`Shader::shade_batch`] whose shadow rays go to the occluder at once (the
/// samples of a pixel: as many as a BVH packet holds).
const BATCH: usize = 16;

/// What shading a point under any light needs: its material, its normals turned to the viewer's
/// side, cos θ_o, and a textured material's BRDF parameters at the point.
#[derive(Clone, Copy)]
struct Facing<'m> {
    material: &'m Material,
    ng: Vec3,
    ns: Vec3,
    cos_o: f32,
    /// A textured material's BRDF at the point, looked up once for all lights.
    textured: Option<PointBrdf>,
}

/// A light in front of a point: its sample, cos θ_i and the BRDF's dot products.
#[derive(Clone, Copy)]
struct Lit {
    ls: LightSample,
    cos_i: f32,
    dots: LocalDots<f32>,
}

/// Everything shading needs besides the point itself.
pub struct Shader<'a, O: Occluder> {
    /// The scene's materials, indexed by `SurfacePoint::material`.
    pub materials: &'a [Material],
    /// The scene's lights.
    pub lights: &'a [Light],
    /// What blocks shadow rays; `None` when the plan leaves shadows out.
    pub occluder: Option<&'a O>,
    /// The scene's size, as shadow rays need it.
    pub extent: SceneExtent,
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
            ShadingConvention::Clamped => self.shade_clamped(sp),
        }
    }

    #[inline(always)]
    fn shade_physical(&self, sp: &SurfacePoint, shadow_rays: &mut u64) -> Vec3 {
        let (radiance, facing) = self.facing(sp);
        let Some(facing) = facing else { return radiance };
        let mut radiance = radiance;
        for light in self.lights {
            let Some(lit) = self.lit(&facing, sp, light) else {
                continue;
            };
            if let Some(occluder) = self.occluder {
                *shadow_rays += 1;
                if occluder.occluded(&self.shadow_ray(&facing, sp, &lit)) {
                    continue;
                }
            }
            radiance += self.reflected(&facing, &lit);
        }
        // Every term is finite and ≥ 0; only the sum of saturated lights could reach infinity.
        radiance.min(Vec3::splat(f32::MAX))
    }

    /// [`Shader::shade`] of the points of one batch — the samples of one pixel or of a pixel
    /// block — into `out` (one entry per point): what `shade` gives each point, the same terms
    /// added in the same (light) order. What differs is that each light's shadow rays from up to
    /// `BATCH` points go to the occluder together ([`Occluder::occluded_batch`]: the BVH walks
    /// them as a packet), and that the points are shaded on lanes where they can be
    /// (`lanes.rs`), eight of one material at a time.
    pub fn shade_batch<P: Borrow<SurfacePoint>>(&self, points: &[P], out: &mut [Vec3], shadow_rays: &mut u64) {
        assert_eq!(points.len(), out.len(), "one radiance per point");
        for (points, out) in points.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
            let physical = self.convention == ShadingConvention::Physical && points.len() > 1;
            if physical && self.shade_batch_lanes(points, out, shadow_rays) {
                continue;
            }
            match self.occluder {
                Some(occluder) if physical => self.shade_batch_points(points, out, occluder, shadow_rays),
                _ => {
                    for (sp, out) in points.iter().zip(out) {
                        *out = self.shade(sp.borrow(), shadow_rays);
                    }
                }
            }
        }
    }

    /// [`Shader::shade_batch`] of at most [`BATCH`] points, one point at a time but each
    /// light's shadow rays together: bit for bit what `shade` gives each point.
    fn shade_batch_points<P: Borrow<SurfacePoint>>(
        &self,
        points: &[P],
        out: &mut [Vec3],
        occluder: &O,
        shadow_rays: &mut u64,
    ) {
        let mut facing: [Option<Facing>; BATCH] = [None; BATCH];
        for (k, sp) in points.iter().enumerate() {
            (out[k], facing[k]) = self.facing(sp.borrow());
        }
        for light in self.lights {
            let mut lit = [None; BATCH];
            // Only rays[..n] are read; the rest are placeholders.
            let mut rays = [ShadowRay {
                origin: Vec3::ZERO,
                direction: Vec3::Z,
                t_max: 0.0,
            }; BATCH];
            let mut n = 0;
            for (k, (sp, facing)) in points.iter().zip(&facing).enumerate() {
                let Some(facing) = facing else { continue };
                let sp = sp.borrow();
                let Some(l) = self.lit(facing, sp, light) else { continue };
                rays[n] = self.shadow_ray(facing, sp, &l);
                lit[n] = Some((k, l));
                n += 1;
            }
            let mut blocked = [false; BATCH];
            occluder.occluded_batch(&rays[..n], &mut blocked[..n]);
            *shadow_rays += n as u64;
            for (lit, _) in lit[..n].iter().zip(blocked).filter(|(_, blocked)| !blocked) {
                let Some((k, l)) = lit else { continue };
                if let Some(facing) = &facing[*k] {
                    out[*k] += self.reflected(facing, l);
                }
            }
        }
        for out in out.iter_mut() {
            *out = out.min(Vec3::splat(f32::MAX));
        }
    }

    /// Whether `material`'s BRDF parameters vary with its textures here (then each point
    /// looks them up: see `facing`).
    fn textured_brdf(&self, material: &Material) -> bool {
        self.textures.is_some() && material.varies_brdf()
    }

    /// Emitted radiance of `sp`, and what shading under the lights needs of it — `None` when
    /// no light can reach the viewer from it (the shading normal faces away from the viewer).
    #[inline(always)]
    fn facing<'s>(&'s self, sp: &SurfacePoint) -> (Vec3, Option<Facing<'s>>) {
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
            return (radiance, None);
        }
        // Textured materials: their BRDF at this point, looked up once for all lights.
        let textured = match self.textures {
            Some(images) if material.varies_brdf() => Some(material.at([sp.uv, sp.uv1], images)),
            _ => None,
        };
        let facing = Facing {
            material,
            ng,
            ns,
            cos_o,
            textured,
        };
        (radiance, Some(facing))
    }

    /// The light's sample at `sp` and the BRDF's dot products, when the light is in front of
    /// the shading normal (`None`: it adds nothing, and no shadow ray is needed).
    #[inline(always)]
    fn lit(&self, facing: &Facing, sp: &SurfacePoint, light: &Light) -> Option<Lit> {
        let ls = light.sample(sp.position)?;
        let cos_i = facing.ns.dot(ls.wi);
        if cos_i.is_nan() || cos_i <= 0.0 {
            return None;
        }
        let dots = if facing.material.has_specular() {
            // ω_i = −ω_o cannot happen here (both are on the normal's side), but stay total.
            LocalDots::from_unit_vectors(facing.ns.to_array(), ls.wi.to_array(), sp.to_viewer.to_array())?
        } else {
            // Lambert reads no dot product: skip the half vector.
            LocalDots::from_cosines(cos_i, facing.cos_o, 0.0, 0.0)
        };
        Some(Lit { ls, cos_i, dots })
    }

    /// The shadow ray that decides whether `lit` reaches `sp`.
    #[inline(always)]
    fn shadow_ray(&self, facing: &Facing, sp: &SurfacePoint, lit: &Lit) -> ShadowRay {
        let ls = &lit.ls;
        ShadowRay::new(
            self.shadow_offset,
            sp.position,
            front_lift(sp.shadow_lift, facing.ng, sp.geometric_normal),
            facing.ng,
            ls.wi,
            ls.distance,
            &self.extent,
        )
    }

    /// f_r · E · cos θ_i of an unoccluded light.
    #[inline(always)]
    fn reflected(&self, facing: &Facing, lit: &Lit) -> Vec3 {
        let f = match &facing.textured {
            Some(point) => point.eval(&lit.dots),
            None => facing.material.eval(&lit.dots),
        };
        Vec3::from(reflected_radiance(f, lit.ls.irradiance.to_array(), lit.cos_i))
    }

    /// The clamped convention's L_o = Σ L_i · f(ω_i, ω_o) · (n·ω_i) with ω_i from the light towards the
    /// point, n as given and every dot product clamped to [0, 1] ([`clamped_dots`]): the
    /// lane path ([`Shader::shade_clamped_lanes`]) on one point in f32. No sides and no shadow
    /// rays (the plan never pairs this convention with an occluder). Where ω_i + ω_o = 0 the half
    /// vector is undefined and only the diffuse part k_d·albedo/π is added.
    #[inline(always)]
    fn shade_clamped(&self, sp: &SurfacePoint) -> Vec3 {
        Vec3::from(self.shade_clamped_lanes(&SurfaceLanes::<f32> {
            position: sp.position.to_array(),
            shading_normal: sp.shading_normal.to_array(),
            to_viewer: sp.to_viewer.to_array(),
            material: sp.material,
        }))
    }
}

/// A point's shadow lift as its shader uses it: as is where the point is seen from the side its
/// normals face (`facing_ng`, the geometric normal as shading turned it, is `ng`), and none where
/// a two-sided material turned it round. The lift moves towards the normals' side, where the
/// smooth surface bulges; seen from behind (inside a closed mesh) it would move the origin
/// through the surface, away from the lights on the viewer's side.
#[inline(always)]
fn front_lift(lift: f32, facing_ng: Vec3, ng: Vec3) -> f32 {
    if facing_ng.dot(ng) > 0.0 {
        lift
    } else {
        0.0
    }
}

/// The form the clamped convention takes `material`'s ω_o and ω_h in, or `None` where its L_o
/// reads neither: ω_o enters only n·ω_o and the half vector, which only a specular lobe reads
/// ([`clamped_dots`]), so a Lambert material's points may come without it (the normal-map driver
/// then skips its square root and divisions). The lane shader derives it once per lane group,
/// not per light.
#[inline(always)]
pub fn clamped_to_viewer_form(material: &Material) -> Option<UnitForm> {
    material.has_specular().then(|| clamped_unit_form(material))
}

/// How the clamped convention forms `material`'s directions ([`UnitForm`]): by one reciprocal
/// where its f_r is continuous in the clamped cosines (Lambert, Blinn-Phong), by quotients
/// elsewhere (Cook-Torrance's guarded denominator jumps where n·ω_i or n·ω_o is 0).
pub fn clamped_unit_form(material: &Material) -> UnitForm {
    match material.model {
        BrdfModel::Lambert | BrdfModel::BlinnPhong(_) => UnitForm::Reciprocal,
        BrdfModel::CookTorrance(_) | BrdfModel::GltfPbr(_) => UnitForm::Quotients,
    }
}

/// One light's L_i · f(ω_i, ω_o) · (n·ω_i) under the clamped convention, per channel, in any
/// [`Real`] (one point or a lane group, f32 or float64); ω_h formed in `half_vector`, the
/// material's [`clamped_to_viewer_form`] (the caller's, derived once for every light).
#[inline(always)]
fn clamped_term<R: Real>(
    material: &Material,
    half_vector: Option<UnitForm>,
    n: [R; 3],
    wi_from_light: [R; 3],
    wo: [R; 3],
    irradiance: [R; 3],
) -> [R; 3] {
    let a = clamped_dots(n, wi_from_light, wo, half_vector);
    let diffuse = material.diffuse::<R>();
    let f = if a.half_vector.any() {
        let e = material.eval(&a.dots);
        map3([0, 1, 2], |c| R::select(a.half_vector, e[c], diffuse[c]))
    } else {
        diffuse
    };
    reflected_radiance(f, irradiance, a.dots.n_dot_i)
}

/// The dot products the physical shader evaluates an untextured `material`'s f_r of, at a
/// point whose shading normal is `n` (any length), towards unit directions `wi` (to the light)
/// and `wo` (to the viewer): a two-sided material first turns `n` to the viewer's side; where
/// ω_o or ω_i is not in front of it, or there is no shading frame, the light adds nothing and
/// there are none. (The Python module's `eval_terms` evaluates D, G and F of them.)
pub fn shading_dots<R: Scalar>(material: &Material, n: [R; 3], wi: [R; 3], wo: [R; 3]) -> Option<LocalDots<R>> {
    let (dots, lit) = shading_dots_masked(material, n, wi, wo);
    lit.then_some(dots)
}

/// [`shading_dots`] in any [`Real`]: the products, and where they exist (elsewhere they are
/// finite placeholders that must not be used).
#[inline(always)]
fn shading_dots_masked<R: Real>(material: &Material, n: [R; 3], wi: [R; 3], wo: [R; 3]) -> (LocalDots<R>, R::Mask) {
    let n = match material.two_sided {
        true => {
            let flip = dot3(n, wo).lt(R::zero());
            map3(n, |c| R::select(flip, -c, c))
        }
        false => n,
    };
    let (cos_i, cos_o) = (dot3(n, wi), dot3(n, wo));
    let lit = cos_i.gt(R::zero()) & cos_o.gt(R::zero());
    match material.has_specular() {
        true => {
            let (dots, frame) = LocalDots::from_unit_vectors_masked(n, wi, wo);
            (dots, lit & frame)
        }
        false => (LocalDots::from_cosines(cos_i, cos_o, R::zero(), R::zero()), lit),
    }
}

/// f_r(ω_i, ω_o) as the physical shader forms it: [`Material::eval`] of the [`shading_dots`]
/// `Shader::shade` gives it, 0 where there are none, so that a light of irradiance E adds
/// f_r · E · cos θ_i there. In any [`Real`]: lanes give what each lane's scalar call gives. (The
/// Python module's `eval_brdf`, through [`rows::brdf_rows`].)
#[inline(always)]
pub fn brdf_value<R: Real>(material: &Material, n: [R; 3], wi: [R; 3], wo: [R; 3]) -> [R; 3] {
    let (dots, lit) = shading_dots_masked(material, n, wi, wo);
    if !lit.any() {
        return [R::zero(); 3];
    }
    map3(material.eval(&dots), |c| R::select(lit, c, R::zero()))
}

/// What one light adds: L = f_r(ω_i, ω_o) · E · cos θ_i per channel, E the light's irradiance
/// at normal incidence. Every path of the shader (one point, lanes, either convention) combines
/// a light's terms here; the conventions differ only in how they form f_r's dot products and
/// cos θ_i.
#[inline(always)]
fn reflected_radiance<R: Real>(f: [R; 3], irradiance: [R; 3], cos_i: R) -> [R; 3] {
    map3([0, 1, 2], |c| f[c] * irradiance[c] * cos_i)
}

#[cfg(test)]
mod tests;
