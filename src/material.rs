//! Materials: a Lambert diffuse part plus an optional specular lobe, composed from the BRDF
//! module's terms.
//!
//! f_r(ω_i, ω_o) = k_d·albedo/π + f_s(ω_i, ω_o), as in the assignment; `kd = 0` gives a purely
//! specular material. The glTF metallic-roughness model (`gltf-pbr`) is the exception: its
//! diffuse part is weighted by 1 − F, so it replaces the sum (see [`GltfPbr`]). This is the only
//! place the terms are combined, for every mode.

use glam::{Vec2, Vec3};

use crate::brdf::{
    blinn_phong, fresnel_conductor_rgb, fresnel_schlick, fresnel_schlick_sg, ggx_d, lambert, schlick_f0_dielectric,
    FresnelTerm, LocalDots, MaskingShadowing, MicrofacetDistribution,
};

use crate::lanes::{map3, Mask, Real};
use crate::texture::{ColorSpace, TextureImage, TextureRef};

/// Blinn-Phong specular lobe: f_s = ks · color · (n·ω_h)^shininess.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlinnPhong {
    /// Specular weight k_s.
    pub ks: f32,
    /// Exponent s.
    pub shininess: f32,
    /// Specular tint (white in the assignment).
    pub color: [f32; 3],
}

/// Cook-Torrance microfacet lobe: f_s = D·F·G / (4 (n·ω_i)(n·ω_o)), terms chosen by name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CookTorrance {
    /// Roughness α, used directly (no roughness² remapping).
    pub alpha: f32,
    /// Normal distribution D.
    pub d: MicrofacetDistribution,
    /// Masking-shadowing G.
    pub g: MaskingShadowing,
    /// Fresnel F.
    pub f: FresnelTerm,
    /// Conductor: Schlick's F0 is the specular colour; dielectric: F0 from `ior`.
    pub metallic: bool,
    /// F0 of metals (Schlick), tint of the conductor Fresnel, and F of `constant`.
    pub specular_color: [f32; 3],
    /// Index of refraction of a dielectric (Schlick's F0 when not metallic).
    pub ior: f32,
    /// Real part of the complex index, per channel (conductor Fresnel).
    pub eta: [f32; 3],
    /// Imaginary part (extinction) of the complex index, per channel (conductor Fresnel).
    pub k: [f32; 3],
}

impl CookTorrance {
    /// The `tp` preset's model and parameters, the assignment's: GGX, Schlick–Smith, Schlick; α = 0.7, metallic,
    /// specular colour [0.98, 0.82, 0.76], n = 5. η and κ default to Mitsuba's "none" (F ≡ 1).
    pub const TP_PRESET: CookTorrance = CookTorrance {
        alpha: 0.7,
        d: MicrofacetDistribution::Ggx,
        g: MaskingShadowing::SchlickSmith,
        f: FresnelTerm::Schlick,
        metallic: true,
        specular_color: [0.98, 0.82, 0.76],
        ior: 5.0,
        eta: [0.0; 3],
        k: [1.0; 3],
    };
}

impl Default for CookTorrance {
    /// [`CookTorrance::TP_PRESET`].
    fn default() -> Self {
        Self::TP_PRESET
    }
}

/// A glTF normal texture: tangent-space normals (+X along +u, +Y "up" = against +v, +Z out of
/// the surface), whose X and Y are multiplied by `scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalTexture {
    /// The texture (linear).
    pub texture: TextureRef,
    /// glTF's `normalTexture.scale`.
    pub scale: f32,
}

/// The textures of a glTF metallic-roughness material; each is optional.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PbrTextures {
    /// sRGB base colour; RGB multiplies the base colour factor (`Material::albedo`).
    pub base_color: Option<TextureRef>,
    /// Linear; blue multiplies the metallic factor, green the roughness factor.
    pub metallic_roughness: Option<TextureRef>,
    /// Tangent-space normals; applied by the surface stage (`surface::normal_texture`).
    pub normal: Option<NormalTexture>,
    /// sRGB; multiplies the emissive factor.
    pub emissive: Option<TextureRef>,
}

impl PbrTextures {
    /// Whether any texture changes the BRDF parameters (base colour or metallic-roughness).
    pub fn varies_brdf(&self) -> bool {
        self.base_color.is_some() || self.metallic_roughness.is_some()
    }

    /// Every texture reference, for renumbering images.
    pub fn refs_mut(&mut self) -> impl Iterator<Item = &mut TextureRef> {
        [
            self.base_color.as_mut(),
            self.metallic_roughness.as_mut(),
            self.normal.as_mut().map(|n| &mut n.texture),
            self.emissive.as_mut(),
        ]
        .into_iter()
        .flatten()
    }
}

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
    /// Textures that modulate the factors.
    pub textures: PbrTextures,
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

/// The BRDF parameters of a `gltf-pbr` material at one surface point, textures applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrPoint {
    /// Linear base colour.
    pub base_color: [f32; 3],
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// Microfacet roughness α = roughness².
    pub alpha: f32,
}

/// A material's BRDF model: Lambert alone, Lambert plus a specular lobe (Blinn-Phong,
/// Cook-Torrance), or glTF's metallic-roughness BRDF, which holds its own diffuse part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BrdfModel {
    /// k_d·albedo/π alone: no specular lobe.
    Lambert,
    /// Blinn-Phong.
    BlinnPhong(BlinnPhong),
    /// Cook-Torrance.
    CookTorrance(CookTorrance),
    /// glTF metallic-roughness: the whole BRDF, diffuse included (k_d is not used).
    GltfPbr(GltfPbr),
}

/// A surface's reflectance: k_d·albedo/π plus a specular lobe.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name, for messages and `--explain`.
    pub name: String,
    /// Diffuse colour.
    pub albedo: [f32; 3],
    /// Diffuse weight.
    pub kd: f32,
    /// Reflect on both sides (normals turned towards the viewer) or only on the front.
    pub two_sided: bool,
    /// The BRDF model and its parameters.
    pub model: BrdfModel,
    /// An sRGB texture whose RGB multiplies `albedo` per point (MTL `map_Kd`), for the Lambert,
    /// Blinn-Phong and Cook-Torrance models; a `gltf-pbr` material's base colour texture is in
    /// its [`PbrTextures`].
    pub albedo_texture: Option<TextureRef>,
}

impl Material {
    /// A two-sided Lambert material with k_d = 1.
    pub fn lambert(name: &str, albedo: [f32; 3]) -> Self {
        Self {
            name: name.to_string(),
            albedo,
            kd: 1.0,
            two_sided: true,
            model: BrdfModel::Lambert,
            albedo_texture: None,
        }
    }

    /// Whether the material has a specular lobe (the plan skips specular work otherwise).
    pub fn has_specular(&self) -> bool {
        !matches!(self.model, BrdfModel::Lambert)
    }

    /// The model's name as written in scene files.
    pub fn model_name(&self) -> &'static str {
        match self.model {
            BrdfModel::Lambert => "lambert",
            BrdfModel::BlinnPhong(_) => "blinn-phong",
            BrdfModel::CookTorrance(_) => "cook-torrance",
            BrdfModel::GltfPbr(_) => "gltf-pbr",
        }
    }

    /// A two-sided glTF metallic-roughness material with constant parameters.
    pub fn gltf_pbr(name: &str, base_color: [f32; 3], metallic: f32, roughness: f32) -> Self {
        Self {
            model: BrdfModel::GltfPbr(GltfPbr {
                metallic,
                roughness,
                emissive: [0.0; 3],
                textures: PbrTextures::default(),
                cutout: None,
            }),
            ..Self::lambert(name, base_color)
        }
    }

    /// The glTF textures of this material, if it is a `gltf-pbr` one.
    pub fn pbr_textures(&self) -> Option<&PbrTextures> {
        match &self.model {
            BrdfModel::GltfPbr(p) => Some(&p.textures),
            _ => None,
        }
    }

    /// Mutable access to the glTF textures (to renumber images when scenes are assembled).
    pub fn pbr_textures_mut(&mut self) -> Option<&mut PbrTextures> {
        match &mut self.model {
            BrdfModel::GltfPbr(p) => Some(&mut p.textures),
            _ => None,
        }
    }

    /// Every texture reference of the material, for renumbering and dropping images.
    pub fn texture_refs_mut(&mut self) -> impl Iterator<Item = &mut TextureRef> {
        let pbr = match &mut self.model {
            BrdfModel::GltfPbr(p) => Some(&mut p.textures),
            _ => None,
        };
        pbr.into_iter()
            .flat_map(|t| t.refs_mut())
            .chain(self.albedo_texture.as_mut())
    }

    /// Drops every texture reference (a material no triangle uses decodes no image).
    pub fn clear_textures(&mut self) {
        if let Some(t) = self.pbr_textures_mut() {
            *t = PbrTextures::default();
        }
        self.albedo_texture = None;
    }

    /// Whether the BRDF's parameters vary over the surface with a texture: the albedo texture,
    /// or a `gltf-pbr` base colour or metallic-roughness texture.
    pub fn varies_brdf(&self) -> bool {
        self.albedo_texture.is_some() || self.pbr_textures().is_some_and(PbrTextures::varies_brdf)
    }

    /// The albedo at texture coordinates `uvs` (sets 0 and 1): `albedo` times the albedo texture.
    #[inline]
    pub fn albedo_at(&self, uvs: [Vec2; 2], images: &[TextureImage]) -> [f32; 3] {
        let mut albedo = Vec3::from(self.albedo);
        if let Some(t) = self.albedo_texture {
            albedo *= t.sample(images, uvs[t.tex_coord as usize], ColorSpace::Srgb).truncate();
        }
        albedo.to_array()
    }

    /// Whether the material emits light (a `gltf-pbr` material with a non-zero emissive factor).
    pub fn emits(&self) -> bool {
        matches!(&self.model, BrdfModel::GltfPbr(p) if p.emissive.iter().any(|&e| e > 0.0))
    }

    /// The cut-out of an `alphaMode` MASK material and the base colour texture whose alpha
    /// multiplies its factor; `None` for a surface that is there everywhere.
    pub fn cutout(&self) -> Option<(Cutout, Option<TextureRef>)> {
        match &self.model {
            BrdfModel::GltfPbr(p) => p.cutout.map(|c| (c, p.textures.base_color)),
            _ => None,
        }
    }

    /// Emitted radiance at texture coordinates `uvs` (sets 0 and 1): the emissive factor times
    /// the emissive texture when `images` are given (the plan samples textures), else the factor.
    #[inline]
    pub fn emission(&self, uvs: [Vec2; 2], images: Option<&[TextureImage]>) -> Vec3 {
        let BrdfModel::GltfPbr(p) = &self.model else {
            return Vec3::ZERO;
        };
        let factor = Vec3::from(p.emissive);
        match (p.textures.emissive, images) {
            (Some(t), Some(images)) => {
                factor * t.sample(images, uvs[t.tex_coord as usize], ColorSpace::Srgb).truncate()
            }
            _ => factor,
        }
    }

    /// The diffuse part k_d·albedo/π, per channel.
    #[inline(always)]
    pub fn diffuse<R: Real>(&self) -> [R; 3] {
        self.diffuse_of(self.albedo)
    }

    /// k_d·albedo/π, per channel, for the given albedo.
    #[inline(always)]
    fn diffuse_of<R: Real>(&self, albedo: [f32; 3]) -> [R; 3] {
        let kd = R::of(self.kd);
        map3(albedo, |a| lambert(kd, R::of(a)))
    }

    /// f_r = diffuse + specular, per channel, for the given dot products. Finite and ≥ 0 for any
    /// finite input (each term guarantees it). Sidedness (n·ω_i > 0, n·ω_o > 0) is the shader's
    /// business; the Cook-Torrance lobe is 0 where either cosine is ≤ 0.
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        self.eval_with_albedo(self.albedo, dots)
    }

    /// [`Material::eval`] with `albedo` in place of the material's (its value at a point of an
    /// albedo texture, [`Material::albedo_at`]).
    #[inline(always)]
    pub fn eval_with_albedo<R: Real>(&self, albedo: [f32; 3], dots: &LocalDots<R>) -> [R; 3] {
        let d = self.diffuse_of::<R>(albedo);
        match &self.model {
            BrdfModel::Lambert => d,
            BrdfModel::BlinnPhong(bp) => {
                let s = blinn_phong(R::of(bp.ks), dots.n_dot_h, dots.sin2_h, R::of(bp.shininess));
                map3([0, 1, 2], |c| d[c] + s * R::of(bp.color[c]))
            }
            BrdfModel::CookTorrance(ct) => {
                let s = ct.eval(dots);
                map3([0, 1, 2], |c| d[c] + s[c])
            }
            BrdfModel::GltfPbr(p) => p.constant_point(albedo).eval(dots),
        }
    }

    /// Range checks on every parameter, with messages naming the key.
    pub fn validate(&self) -> Result<(), String> {
        check_color("albedo", self.albedo)?;
        check_non_negative("kd", self.kd)?;
        match &self.model {
            BrdfModel::Lambert => {}
            BrdfModel::BlinnPhong(bp) => {
                check_non_negative("ks", bp.ks)?;
                check_non_negative("shininess", bp.shininess)?;
                check_color("specular_color", bp.color)?;
            }
            BrdfModel::CookTorrance(ct) => {
                if !(0.0..=1.0).contains(&ct.alpha) {
                    return Err(format!("roughness must be in [0, 1], got {}", ct.alpha));
                }
                check_color("specular_color", ct.specular_color)?;
                if !(ct.ior > 0.0 && ct.ior.is_finite()) {
                    return Err(format!("ior must be a finite number > 0, got {}", ct.ior));
                }
                check_color("eta", ct.eta)?;
                check_color("k", ct.k)?;
            }
            BrdfModel::GltfPbr(p) => {
                // glTF keeps baseColorFactor in [0, 1]; above 1 the diffuse weight 1 − F turns
                // negative (a metal's F0 is the base colour) and base · (1 − F) can overflow to −∞.
                if !self.albedo.iter().all(|v| (0.0..=1.0).contains(v)) {
                    return Err(format!("base colour factor must be in [0, 1], got {:?}", self.albedo));
                }
                check_unit("metallic", p.metallic)?;
                check_unit("roughness", p.roughness)?;
                check_color("emissive", p.emissive)?;
                if let Some(c) = &p.cutout {
                    check_unit("base colour alpha", c.alpha)?;
                    if !(c.cutoff >= 0.0 && c.cutoff.is_finite()) {
                        return Err(format!("alphaCutoff must be a finite number ≥ 0, got {}", c.cutoff));
                    }
                }
                if let Some(n) = &p.textures.normal {
                    if !n.scale.is_finite() {
                        return Err(format!("normal texture scale must be finite, got {}", n.scale));
                    }
                }
            }
        }
        Ok(())
    }
}

impl GltfPbr {
    /// The parameters where no texture applies: the factors.
    #[inline]
    pub fn constant_point(&self, base_color: [f32; 3]) -> PbrPoint {
        PbrPoint {
            base_color,
            metallic: self.metallic,
            alpha: self.roughness * self.roughness,
        }
    }

    /// The parameters at texture coordinates `uvs` (sets 0 and 1): base colour factor × sRGB
    /// texture, metallic factor × blue, roughness factor × green of the metallic-roughness
    /// texture. Texture values lie in [0, 1], so the products stay in the factors' ranges.
    #[inline]
    pub fn point_at(&self, base_color: [f32; 3], uvs: [Vec2; 2], images: &[TextureImage]) -> PbrPoint {
        let mut base = Vec3::from(base_color);
        if let Some(t) = self.textures.base_color {
            base *= t.sample(images, uvs[t.tex_coord as usize], ColorSpace::Srgb).truncate();
        }
        let (mut metallic, mut roughness) = (self.metallic, self.roughness);
        if let Some(t) = self.textures.metallic_roughness {
            let mr = t.sample(images, uvs[t.tex_coord as usize], ColorSpace::Linear);
            metallic *= mr.z;
            roughness *= mr.y;
        }
        PbrPoint {
            base_color: base.to_array(),
            metallic,
            alpha: roughness * roughness,
        }
    }
}

impl PbrPoint {
    /// f_r per channel (see [`GltfPbr`]): (1 − F)·lambert(1 − metallic, base) + F·D·V.
    /// D and V clamp α to `MIN_ALPHA`, so α = 0 (roughness 0) gives a finite spike; V is 0 where
    /// n·ω_i ≤ 0 or n·ω_o ≤ 0, which leaves the diffuse part to the shader's sidedness test.
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        let alpha = R::of(self.alpha);
        let v = MaskingShadowing::SmithGgxCorrelated.visibility(dots.n_dot_i, dots.n_dot_o, alpha);
        // D is finite (capped at its peak), so D·V is 0 where V is: D is skipped there.
        let dv = R::choose(v.eq(R::zero()), R::zero, || ggx_d(dots.n_dot_h, dots.sin2_h, alpha) * v);
        let metallic = R::of(self.metallic);
        // Dielectric F0 of glTF: ior 1.5 → ((1.5 − 1)/(1.5 + 1))² = 0.04.
        let f0_dielectric = schlick_f0_dielectric(R::lit(1.5));
        map3(self.base_color, |b| {
            let base = R::of(b);
            let f0 = f0_dielectric + (base - f0_dielectric) * metallic;
            let f = fresnel_schlick(f0, dots.i_dot_h);
            (R::one() - f) * lambert(R::one() - metallic, base) + f * dv
        })
    }
}

impl CookTorrance {
    /// Schlick's F0 per channel: the specular colour for metals, ((ior − 1)/(ior + 1))² otherwise.
    #[inline(always)]
    pub fn f0<R: Real>(&self) -> [R; 3] {
        if self.metallic {
            map3(self.specular_color, R::of)
        } else {
            [schlick_f0_dielectric(R::of(self.ior)); 3]
        }
    }

    /// F(ω_i·ω_h) per channel.
    #[inline(always)]
    pub fn fresnel<R: Real>(&self, i_dot_h: R) -> [R; 3] {
        match self.f {
            FresnelTerm::Schlick => map3(self.f0::<R>(), |f0| fresnel_schlick(f0, i_dot_h)),
            FresnelTerm::SchlickSg => map3(self.f0::<R>(), |f0| fresnel_schlick_sg(f0, i_dot_h)),
            FresnelTerm::Conductor => {
                let f = fresnel_conductor_rgb(i_dot_h, self.eta, self.k);
                map3([0, 1, 2], |c| f[c] * R::of(self.specular_color[c]))
            }
            FresnelTerm::Constant => map3(self.specular_color, R::of),
        }
    }

    /// f_s = D·F·V with V = G/(4 (n·ω_i)(n·ω_o)) (see `MaskingShadowing::visibility`); 0 when
    /// n·ω_i ≤ 0 or n·ω_o ≤ 0, which is where the assignment's guarded denominator gives 0 too.
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        let alpha = R::of(self.alpha);
        let v = self.g.visibility(dots.n_dot_i, dots.n_dot_o, alpha);
        let unlit = v.eq(R::zero());
        if unlit.all() {
            return [R::zero(); 3];
        }
        // D and F are finite, so where V = 0 the product is 0 as well.
        let dv = self.d.eval(dots.n_dot_h, dots.sin2_h, alpha) * v;
        map3(self.fresnel(dots.i_dot_h), |f| R::select(unlit, R::zero(), f * dv))
    }
}

fn check_non_negative(key: &str, v: f32) -> Result<(), String> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(format!("{key} must be a finite number ≥ 0, got {v}"))
    }
}

fn check_unit(key: &str, v: f32) -> Result<(), String> {
    if (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(format!("{key} must be in [0, 1], got {v}"))
    }
}

fn check_color(key: &str, c: [f32; 3]) -> Result<(), String> {
    if c.iter().all(|v| *v >= 0.0 && v.is_finite()) {
        Ok(())
    } else {
        Err(format!("{key} must have finite components ≥ 0, got {c:?}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn dots(ci: f64, co: f64, nh: f64, ih: f64) -> LocalDots<f64> {
        LocalDots::from_cosines(ci, co, nh, ih)
    }

    #[test]
    fn assignment_cook_torrance_by_hand() {
        // The report's material: α = 0.7, metallic, specular colour [0.98, 0.82, 0.76], kd = 1,
        // albedo [0.4, 0.7, 0.4]; GGX, Schlick–Smith, Schlick.
        let m = Material {
            model: BrdfModel::CookTorrance(CookTorrance::default()),
            ..Material::lambert("tp", [0.4, 0.7, 0.4])
        };
        let (ci, co, nh, ih) = (0.6f64, 0.8f64, 0.95f64, 0.9f64);
        let a2 = 0.49f64;
        let d = a2 / (PI * (1.0 + (a2 - 1.0) * nh * nh).powi(2));
        let k = 0.7 * (2.0 / PI).sqrt();
        let g = ci / (ci * (1.0 - k) + k) * co / (co * (1.0 - k) + k);
        let f = [0.98f64, 0.82, 0.76].map(|f0| f0 + (1.0 - f0) * (1.0 - ih).powi(5));
        let got = m.eval(&dots(ci, co, nh, ih));
        for c in 0..3 {
            let albedo = [0.4f64, 0.7, 0.4][c];
            let expect = albedo / PI + d * f[c] * g / (4.0 * ci * co);
            // Parameters are stored in f32: compare to f32 rounding.
            assert!(
                (got[c] - expect).abs() < 1e-6 * expect,
                "channel {c}: {} vs {expect}",
                got[c]
            );
        }
    }

    #[test]
    fn blinn_phong_material_adds_tinted_lobe_to_diffuse() {
        let m = Material {
            model: BrdfModel::BlinnPhong(BlinnPhong {
                ks: 0.5,
                shininess: 10.0,
                color: [1.0, 0.5, 0.0],
            }),
            kd: 0.5,
            ..Material::lambert("bp", [0.2, 0.4, 0.6])
        };
        let got = m.eval(&dots(0.5, 0.5, 0.9, 0.7));
        let lobe = 0.5 * 0.9f64.powi(10);
        for c in 0..3 {
            let expect = 0.5 * [0.2f64, 0.4, 0.6][c] / PI + lobe * [1.0, 0.5, 0.0][c];
            assert!((got[c] - expect).abs() < 1e-7, "{c}");
        }
    }

    #[test]
    fn pure_specular_with_kd_zero_and_lambert_without_lobe() {
        let m = Material {
            kd: 0.0,
            model: BrdfModel::CookTorrance(CookTorrance::default()),
            ..Material::lambert("m", [1.0; 3])
        };
        assert!(m.eval(&dots(0.5, 0.5, 1.0, 1.0))[0] > 0.0);
        assert_eq!(
            m.eval(&dots(0.0, 0.5, 0.7, 0.7)),
            [0.0; 3],
            "CT lobe vanishes at grazing"
        );
        let l = Material::lambert("l", [0.5; 3]);
        assert!(!l.has_specular());
        assert_eq!(l.eval(&dots(0.1, 0.9, 0.2, 0.3)), [0.5 / PI; 3]);
    }

    #[test]
    fn fresnel_modes_per_channel() {
        let ct = CookTorrance {
            specular_color: [0.5, 1.0, 0.25],
            eta: [0.0; 3],
            k: [1.0; 3],
            metallic: false,
            ior: 1.5,
            ..CookTorrance::default()
        };
        let conductor = CookTorrance {
            f: FresnelTerm::Conductor,
            ..ct
        };
        assert_eq!(
            conductor.fresnel(0.3f64).map(|v| (v * 1e6).round() / 1e6),
            [0.5, 1.0, 0.25]
        );
        let constant = CookTorrance {
            f: FresnelTerm::Constant,
            ..ct
        };
        assert_eq!(constant.fresnel(0.3f32), [0.5, 1.0, 0.25]);
        assert!((ct.fresnel(1.0f64)[1] - 0.04).abs() < 1e-12, "dielectric F0 from ior");
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

    #[test]
    fn validation_names_the_key() {
        let mut m = Material::lambert("m", [0.5, f32::NAN, 0.5]);
        assert!(m.validate().unwrap_err().contains("albedo"));
        m.albedo = [0.5; 3];
        m.model = BrdfModel::CookTorrance(CookTorrance {
            alpha: 1.5,
            ..CookTorrance::default()
        });
        assert!(m.validate().unwrap_err().contains("roughness"));
        m.model = BrdfModel::CookTorrance(CookTorrance {
            ior: 0.0,
            ..CookTorrance::default()
        });
        assert!(m.validate().unwrap_err().contains("ior"));
        m.model = BrdfModel::BlinnPhong(BlinnPhong {
            ks: -1.0,
            shininess: 1.0,
            color: [1.0; 3],
        });
        assert!(m.validate().unwrap_err().contains("ks"));
        let mut g = Material::gltf_pbr("g", [0.5; 3], 1.5, 0.5);
        assert!(g.validate().unwrap_err().contains("metallic"));
        g = Material::gltf_pbr("g", [0.5; 3], 0.5, f32::NAN);
        assert!(g.validate().unwrap_err().contains("roughness"));
    }
}
