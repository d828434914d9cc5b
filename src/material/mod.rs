//! Materials: a Lambert diffuse part plus an optional specular lobe, composed from the BRDF
//! module's terms.
//!
//! f_r(ω_i, ω_o) = k_d·albedo/π + f_s(ω_i, ω_o) (Cook & Torrance 1982); `kd = 0` gives a purely
//! specular material. The glTF metallic-roughness model (`gltf-pbr`) is the exception: its
//! diffuse part is weighted by 1 − F, so it replaces the sum (see [`GltfPbr`]). This is the only
//! place the terms are combined, for every mode.

use glam::{Vec2, Vec3};

use crate::brdf::{blinn_phong, lambert, LocalDots};

use crate::lanes::{map3, Real};
use crate::texture::{ColorSpace, TextureImage, TextureRef};

mod blinn_phong;
mod cook_torrance;
mod gltf_pbr;
mod textures;

pub use blinn_phong::BlinnPhong;
pub use cook_torrance::CookTorrance;
pub use gltf_pbr::{Cutout, GltfPbr};
pub use textures::{Channel, MaterialTextures, NormalTexture, ScalarTexture};

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
    /// The textures that modulate its parameters and normals, whatever the model.
    pub textures: MaterialTextures,
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
            textures: MaterialTextures::default(),
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
                cutout: None,
            }),
            ..Self::lambert(name, base_color)
        }
    }

    /// Every texture reference of the material, for renumbering and dropping images.
    pub fn texture_refs_mut(&mut self) -> impl Iterator<Item = &mut TextureRef> {
        self.textures.refs_mut()
    }

    /// Drops every texture reference (a material no triangle uses decodes no image).
    pub fn clear_textures(&mut self) {
        self.textures = MaterialTextures::default();
    }

    /// Whether the BRDF's parameters vary over the surface with a texture (then the shader
    /// evaluates [`Material::at`] at each point).
    pub fn varies_brdf(&self) -> bool {
        self.textures.varies_brdf()
    }

    /// Whether the material emits light (a `gltf-pbr` material with a non-zero emissive factor).
    pub fn emits(&self) -> bool {
        matches!(&self.model, BrdfModel::GltfPbr(p) if p.emissive.iter().any(|&e| e > 0.0))
    }

    /// The cut-out of an `alphaMode` MASK material and the base colour texture whose alpha
    /// multiplies its factor; `None` for a surface that is there everywhere.
    pub fn cutout(&self) -> Option<(Cutout, Option<TextureRef>)> {
        match &self.model {
            BrdfModel::GltfPbr(p) => p.cutout.map(|c| (c, self.textures.base_color)),
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
        match (self.textures.emissive, images) {
            (Some(t), Some(images)) => {
                factor * t.sample(images, uvs[t.tex_coord as usize], ColorSpace::Srgb).truncate()
            }
            _ => factor,
        }
    }

    /// The diffuse part k_d·albedo/π, per channel.
    #[inline(always)]
    pub fn diffuse<R: Real>(&self) -> [R; 3] {
        diffuse_of(self.kd, self.albedo)
    }

    /// f_r = diffuse + specular, per channel, for the given dot products. Finite and ≥ 0 for any
    /// finite input (each term guarantees it). Sidedness (n·ω_i > 0, n·ω_o > 0) is the shader's
    /// business; the Cook-Torrance lobe is 0 where either cosine is ≤ 0.
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        PointBrdf {
            albedo: self.albedo,
            kd: self.kd,
            model: self.model,
        }
        .eval(dots)
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
            }
        }
        if let Some(n) = &self.textures.normal {
            if !n.scale.is_finite() {
                return Err(format!("normal texture scale must be finite, got {}", n.scale));
            }
        }
        for (key, s) in [
            ("map_Ns", self.textures.shininess),
            ("map_Pr", self.textures.roughness),
            ("map_Pm", self.textures.metallic),
        ] {
            if let Some(s) = s {
                check_non_negative(key, s.factor)?;
            }
        }
        Ok(())
    }
}

/// A material's BRDF at one surface point, its textures applied: the parameters
/// [`Material::eval`] reads, as values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointBrdf {
    /// Albedo (base colour).
    pub albedo: [f32; 3],
    /// Diffuse weight.
    pub kd: f32,
    /// The model with its parameters at the point.
    pub model: BrdfModel,
}

impl PointBrdf {
    /// f_r per channel: the one place a material's terms are combined, for a material's constant
    /// parameters ([`Material::eval`]) and for its parameters at a textured point
    /// ([`Material::at`]).
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        let d = diffuse_of::<R>(self.kd, self.albedo);
        match &self.model {
            BrdfModel::Lambert => d,
            BrdfModel::BlinnPhong(bp) => {
                let s = blinn_phong(R::of(bp.ks), dots.n_dot_h, dots.sin2_h, bp.shininess);
                map3([0, 1, 2], |c| d[c] + s * R::of(bp.color[c]))
            }
            BrdfModel::CookTorrance(ct) => {
                let s = ct.eval(dots);
                map3([0, 1, 2], |c| d[c] + s[c])
            }
            BrdfModel::GltfPbr(p) => p.eval(self.albedo, dots),
        }
    }
}

impl Material {
    /// The BRDF at texture coordinates `uvs` (sets 0 and 1), every texture that modulates a
    /// parameter applied. Texture values lie in [0, 1], so a product stays within its factor's
    /// range; a metallic texture switches a Cook-Torrance point between the material's
    /// dielectric form and its metal form (k_d = 0, specular colour = albedo), as MTL's `Pm`
    /// chooses between them for the whole material.
    #[inline]
    pub fn at(&self, uvs: [Vec2; 2], images: &[TextureImage]) -> PointBrdf {
        let t = &self.textures;
        let sample = |r: TextureRef, space| r.sample(images, uvs[r.tex_coord as usize], space).truncate();
        let mut albedo = Vec3::from(self.albedo);
        if let Some(r) = t.base_color {
            albedo *= sample(r, ColorSpace::Srgb);
        }
        let albedo = albedo.to_array();
        let (mut kd, mut model) = (self.kd, self.model);
        match &mut model {
            BrdfModel::Lambert => {}
            BrdfModel::BlinnPhong(bp) => {
                if let Some(r) = t.specular {
                    bp.color = (Vec3::from(bp.color) * sample(r, ColorSpace::Srgb)).to_array();
                }
                if let Some(s) = t.shininess {
                    bp.shininess = s.at(uvs, images);
                }
            }
            BrdfModel::CookTorrance(ct) => {
                if let Some(s) = t.metallic {
                    ct.metallic = s.at(uvs, images) >= 0.5;
                    if ct.metallic {
                        (kd, ct.specular_color) = (0.0, albedo);
                    }
                }
                if let Some(r) = t.specular {
                    ct.specular_color = (Vec3::from(ct.specular_color) * sample(r, ColorSpace::Srgb)).to_array();
                }
                if let Some(s) = t.roughness {
                    let r = s.at(uvs, images);
                    ct.alpha = r * r;
                }
            }
            BrdfModel::GltfPbr(p) => {
                if let Some(r) = t.metallic_roughness {
                    let mr = sample(r, ColorSpace::Linear);
                    p.metallic *= mr.z;
                    p.roughness *= mr.y;
                }
            }
        }
        PointBrdf { albedo, kd, model }
    }
}

/// k_d·albedo/π, per channel.
#[inline(always)]
fn diffuse_of<R: Real>(kd: f32, albedo: [f32; 3]) -> [R; 3] {
    let kd = R::of(kd);
    map3(albedo, |a| lambert(kd, R::of(a)))
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
    use crate::brdf::{FresnelTerm, MaskingShadowing};
    use std::f64::consts::PI;

    fn dots(ci: f64, co: f64, nh: f64, ih: f64) -> LocalDots<f64> {
        LocalDots::from_cosines(ci, co, nh, ih)
    }

    #[test]
    fn cook_torrance_by_hand() {
        // α = 0.7, metallic, specular colour [0.98, 0.82, 0.76], kd = 1, albedo [0.4, 0.7, 0.4];
        // GGX, Schlick–Smith, Schlick.
        let m = Material {
            model: BrdfModel::CookTorrance(CookTorrance {
                alpha: 0.7,
                g: MaskingShadowing::SchlickSmith,
                metallic: true,
                specular_color: [0.98, 0.82, 0.76],
                ..CookTorrance::DEFAULT
            }),
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
