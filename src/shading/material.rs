//! Materials: a Lambert diffuse part plus an optional specular lobe, composed from the BRDF
//! module's terms.
//!
//! f_r(ω_i, ω_o) = k_d·albedo/π + f_s(ω_i, ω_o), as in the assignment; `kd = 0` gives a purely
//! specular material. This is the only place the terms are combined, for every mode.

use crate::shading::brdf::{
    blinn_phong, fresnel_conductor, fresnel_schlick, fresnel_schlick_sg, lambert, schlick_f0_dielectric, FresnelTerm,
    LocalDots, MaskingShadowing, MicrofacetDistribution, Real,
};

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
    /// The assignment's model and parameters: GGX, Schlick–Smith, Schlick; α = 0.7, metallic,
    /// specular colour [0.98, 0.82, 0.76], n = 5. η and κ default to Mitsuba's "none" (F ≡ 1).
    pub const ASSIGNMENT: CookTorrance = CookTorrance {
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
    /// [`CookTorrance::ASSIGNMENT`].
    fn default() -> Self {
        Self::ASSIGNMENT
    }
}

/// The specular part of a material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Specular {
    /// None: a Lambert material.
    None,
    /// Blinn-Phong.
    BlinnPhong(BlinnPhong),
    /// Cook-Torrance.
    CookTorrance(CookTorrance),
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
    /// The specular lobe.
    pub specular: Specular,
}

impl Material {
    /// A two-sided Lambert material with k_d = 1.
    pub fn lambert(name: &str, albedo: [f32; 3]) -> Self {
        Self {
            name: name.to_string(),
            albedo,
            kd: 1.0,
            two_sided: true,
            specular: Specular::None,
        }
    }

    /// Whether the material has a specular lobe (the plan skips specular work otherwise).
    pub fn has_specular(&self) -> bool {
        !matches!(self.specular, Specular::None)
    }

    /// The model's name as written in scene files.
    pub fn model_name(&self) -> &'static str {
        match self.specular {
            Specular::None => "lambert",
            Specular::BlinnPhong(_) => "blinn-phong",
            Specular::CookTorrance(_) => "cook-torrance",
        }
    }

    /// The diffuse part k_d·albedo/π, per channel.
    #[inline(always)]
    pub fn diffuse<R: Real>(&self) -> [R; 3] {
        let kd = R::of(self.kd);
        self.albedo.map(|a| lambert(kd, R::of(a)))
    }

    /// f_r = diffuse + specular, per channel, for the given dot products. Finite and ≥ 0 for any
    /// finite input (each term guarantees it). Sidedness (n·ω_i > 0, n·ω_o > 0) is the shader's
    /// business; the Cook-Torrance lobe is 0 where either cosine is ≤ 0.
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        let d = self.diffuse::<R>();
        match &self.specular {
            Specular::None => d,
            Specular::BlinnPhong(bp) => {
                let s = blinn_phong(R::of(bp.ks), dots.n_dot_h, dots.sin2_h, R::of(bp.shininess));
                [0, 1, 2].map(|c| d[c] + s * R::of(bp.color[c]))
            }
            Specular::CookTorrance(ct) => {
                let s = ct.eval(dots);
                [0, 1, 2].map(|c| d[c] + s[c])
            }
        }
    }

    /// Range checks on every parameter, with messages naming the key.
    pub fn validate(&self) -> Result<(), String> {
        check_color("albedo", self.albedo)?;
        check_non_negative("kd", self.kd)?;
        match &self.specular {
            Specular::None => {}
            Specular::BlinnPhong(bp) => {
                check_non_negative("ks", bp.ks)?;
                check_non_negative("shininess", bp.shininess)?;
                check_color("specular_color", bp.color)?;
            }
            Specular::CookTorrance(ct) => {
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
        }
        Ok(())
    }
}

impl CookTorrance {
    /// Schlick's F0 per channel: the specular colour for metals, ((ior − 1)/(ior + 1))² otherwise.
    #[inline(always)]
    pub fn f0<R: Real>(&self) -> [R; 3] {
        if self.metallic {
            self.specular_color.map(R::of)
        } else {
            [schlick_f0_dielectric(R::of(self.ior)); 3]
        }
    }

    /// F(ω_i·ω_h) per channel.
    #[inline(always)]
    pub fn fresnel<R: Real>(&self, i_dot_h: R) -> [R; 3] {
        match self.f {
            FresnelTerm::Schlick => self.f0::<R>().map(|f0| fresnel_schlick(f0, i_dot_h)),
            FresnelTerm::SchlickSg => self.f0::<R>().map(|f0| fresnel_schlick_sg(f0, i_dot_h)),
            FresnelTerm::Conductor => [0, 1, 2].map(|c| {
                fresnel_conductor(i_dot_h, R::of(self.eta[c]), R::of(self.k[c])) * R::of(self.specular_color[c])
            }),
            FresnelTerm::Constant => self.specular_color.map(R::of),
        }
    }

    /// f_s = D·F·V with V = G/(4 (n·ω_i)(n·ω_o)) (see `MaskingShadowing::visibility`); 0 when
    /// n·ω_i ≤ 0 or n·ω_o ≤ 0, which is where the assignment's guarded denominator gives 0 too.
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        let alpha = R::of(self.alpha);
        let v = self.g.visibility(dots.n_dot_i, dots.n_dot_o, alpha);
        if v == R::zero() {
            return [R::zero(); 3];
        }
        let dv = self.d.eval(dots.n_dot_h, dots.sin2_h, alpha) * v;
        self.fresnel(dots.i_dot_h).map(|f| f * dv)
    }
}

fn check_non_negative(key: &str, v: f32) -> Result<(), String> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(format!("{key} must be a finite number ≥ 0, got {v}"))
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
            specular: Specular::CookTorrance(CookTorrance::default()),
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
            specular: Specular::BlinnPhong(BlinnPhong {
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
            specular: Specular::CookTorrance(CookTorrance::default()),
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
        m.specular = Specular::CookTorrance(CookTorrance {
            alpha: 1.5,
            ..CookTorrance::default()
        });
        assert!(m.validate().unwrap_err().contains("roughness"));
        m.specular = Specular::CookTorrance(CookTorrance {
            ior: 0.0,
            ..CookTorrance::default()
        });
        assert!(m.validate().unwrap_err().contains("ior"));
        m.specular = Specular::BlinnPhong(BlinnPhong {
            ks: -1.0,
            shininess: 1.0,
            color: [1.0; 3],
        });
        assert!(m.validate().unwrap_err().contains("ks"));
    }
}
