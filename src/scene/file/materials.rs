//! `[material.NAME]` sections: the BRDF model and its parameters, with the defaults each kind of
//! scene file gives the keys a section leaves out.

use serde::Deserialize;
use toml::Spanned;

use crate::brdf::FresnelTerm;
use crate::material::{BlinnPhong, BrdfModel, CookTorrance, Material, MaterialTextures};

use super::values::three_opt;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialSection {
    #[serde(default)]
    model: ModelName,
    #[serde(default, deserialize_with = "three_opt")]
    albedo: Option<[f32; 3]>,
    kd: Option<f32>,
    two_sided: Option<bool>,
    // Blinn-Phong
    ks: Option<f32>,
    shininess: Option<f32>,
    #[serde(default, deserialize_with = "three_opt")]
    specular_color: Option<[f32; 3]>,
    // Cook-Torrance
    roughness: Option<f32>,
    metallic: Option<bool>,
    ior: Option<f32>,
    d: Option<Spanned<String>>,
    g: Option<Spanned<String>>,
    fresnel: Option<Spanned<String>>,
    #[serde(default, deserialize_with = "three_opt")]
    eta: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "three_opt")]
    k: Option<[f32; 3]>,
}

/// A material model, as named in scene files and on the command line.
#[derive(Deserialize, Default, PartialEq, Eq, Clone, Copy, Debug)]
#[serde(rename_all = "kebab-case")]
pub enum ModelName {
    /// Lambert diffuse only.
    #[default]
    Lambert,
    /// Lambert + Blinn-Phong.
    BlinnPhong,
    /// Lambert + Cook-Torrance.
    CookTorrance,
}

impl ModelName {
    /// Every model, in documentation order.
    pub const ALL: [ModelName; 3] = [ModelName::Lambert, ModelName::BlinnPhong, ModelName::CookTorrance];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ModelName::Lambert => "lambert",
            ModelName::BlinnPhong => "blinn-phong",
            ModelName::CookTorrance => "cook-torrance",
        }
    }
}

impl std::str::FromStr for ModelName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ModelName::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("unknown BRDF '{s}' (expected lambert, blinn-phong or cook-torrance)"))
    }
}

/// What the keys a material section leaves out default to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialDefaults {
    /// Diffuse colour.
    pub albedo: [f32; 3],
    /// Diffuse weight.
    pub kd: f32,
    /// Two-sided or one-sided.
    pub two_sided: bool,
    /// The Blinn-Phong lobe of a `blinn-phong` material.
    pub blinn_phong: BlinnPhong,
    /// The Cook-Torrance lobe of a `cook-torrance` material.
    pub cook_torrance: CookTorrance,
}

impl MaterialDefaults {
    /// The defaults of mesh scene files (docs/scene-format.md, "Materials"): what someone porting
    /// a Mitsuba 3 or pbrt-v4 scene expects. Diffuse reflectance 0.5 (both renderers' default);
    /// Cook-Torrance [`CookTorrance::DEFAULT`] (Mitsuba's `roughconductor` terms at its default
    /// roughness, over a dielectric unless `eta`/`k` make it a conductor: see `material`). The
    /// normal-map `tp` preset has defaults of its own (`normal_map::scene_file`).
    pub const SCENE: MaterialDefaults = MaterialDefaults {
        albedo: [0.5; 3],
        kd: 1.0,
        two_sided: true,
        blinn_phong: BlinnPhong {
            ks: 1.0,
            shininess: 32.0,
            color: [1.0; 3],
        },
        cook_torrance: CookTorrance::DEFAULT,
    };

    /// A material of `model` with every parameter at its default.
    pub fn material(&self, name: &str, model: ModelName) -> Material {
        Material {
            name: name.to_string(),
            albedo: self.albedo,
            kd: self.kd,
            two_sided: self.two_sided,
            model: match model {
                ModelName::Lambert => BrdfModel::Lambert,
                ModelName::BlinnPhong => BrdfModel::BlinnPhong(self.blinn_phong),
                ModelName::CookTorrance => BrdfModel::CookTorrance(self.cook_torrance),
            },
            textures: MaterialTextures::default(),
        }
    }
}

/// An error with the span of the value it is about, when narrower than the section.
pub(crate) type Located = (Option<std::ops::Range<usize>>, String);

/// The material a `[material.NAME]` section describes, missing keys taken from `defaults`.
///
/// A Cook-Torrance section that writes `eta` or `k` and no `fresnel` is a conductor (the exact
/// Fresnel of that complex index), and a conductor's `kd` defaults to 0: a metal has no diffuse
/// part, as in Mitsuba's `roughconductor` and pbrt's `conductor`.
pub(crate) fn material(name: &str, m: &MaterialSection, defaults: &MaterialDefaults) -> Result<Material, Located> {
    let plain = |msg: String| (None, msg);
    let mut material = defaults.material(name, m.model);
    material.albedo = m.albedo.unwrap_or(material.albedo);
    material.kd = m.kd.unwrap_or(material.kd);
    material.two_sided = m.two_sided.unwrap_or(material.two_sided);
    let unused_for = |keys: &[(&str, bool)], model: &str| -> Result<(), Located> {
        match keys.iter().find(|(_, present)| *present) {
            Some((key, _)) => Err(plain(format!("key '{key}' does not apply to the {model} model"))),
            None => Ok(()),
        }
    };
    let ct_keys = [
        ("roughness", m.roughness.is_some()),
        ("metallic", m.metallic.is_some()),
        ("ior", m.ior.is_some()),
        ("d", m.d.is_some()),
        ("g", m.g.is_some()),
        ("fresnel", m.fresnel.is_some()),
        ("eta", m.eta.is_some()),
        ("k", m.k.is_some()),
    ];
    let bp_keys = [("ks", m.ks.is_some()), ("shininess", m.shininess.is_some())];
    match m.model {
        ModelName::Lambert => {
            unused_for(&ct_keys, "lambert")?;
            unused_for(&bp_keys, "lambert")?;
            unused_for(&[("specular_color", m.specular_color.is_some())], "lambert")?;
        }
        ModelName::BlinnPhong => {
            unused_for(&ct_keys, "blinn-phong")?;
            let d = defaults.blinn_phong;
            material.model = BrdfModel::BlinnPhong(BlinnPhong {
                ks: m.ks.unwrap_or(d.ks),
                shininess: m.shininess.unwrap_or(d.shininess),
                color: m.specular_color.unwrap_or(d.color),
            });
        }
        ModelName::CookTorrance => {
            unused_for(&bp_keys, "cook-torrance")?;
            let d = defaults.cook_torrance;
            let mut ct = CookTorrance {
                alpha: m.roughness.unwrap_or(d.alpha),
                metallic: m.metallic.unwrap_or(d.metallic),
                specular_color: m.specular_color.unwrap_or(d.specular_color),
                ior: m.ior.unwrap_or(d.ior),
                eta: m.eta.unwrap_or(d.eta),
                k: m.k.unwrap_or(d.k),
                ..d
            };
            if let Some(v) = &m.d {
                ct.d = v.get_ref().parse().map_err(|e| (Some(v.span()), format!("{e}")))?;
            }
            if let Some(v) = &m.g {
                ct.g = v.get_ref().parse().map_err(|e| (Some(v.span()), format!("{e}")))?;
            }
            if let Some(v) = &m.fresnel {
                ct.f = v.get_ref().parse().map_err(|e| (Some(v.span()), format!("{e}")))?;
            } else if m.eta.is_some() || m.k.is_some() {
                ct.f = FresnelTerm::Conductor;
            }
            if ct.f == FresnelTerm::Conductor {
                material.kd = m.kd.unwrap_or(0.0);
            } else if let Some((key, _)) = [("eta", m.eta.is_some()), ("k", m.k.is_some())]
                .into_iter()
                .find(|k| k.1)
            {
                return Err(plain(format!("key '{key}' applies only to fresnel = \"conductor\"")));
            }
            if matches!(ct.f, FresnelTerm::Conductor | FresnelTerm::Constant) {
                if let Some((key, _)) = [("ior", m.ior.is_some()), ("metallic", m.metallic.is_some())]
                    .into_iter()
                    .find(|k| k.1)
                {
                    return Err(plain(format!(
                        "key '{key}' does not apply to fresnel = \"{}\" (it chooses Schlick's F0)",
                        ct.f.name()
                    )));
                }
            }
            material.model = BrdfModel::CookTorrance(ct);
        }
    }
    material.validate().map_err(plain)?;
    Ok(material)
}

/// The material of a `[material.NAME]` section's `text` (its keys, without the header), missing
/// keys taken from `defaults`: the Python module's materials, checked as scene files' are.
pub fn material_from_toml(name: &str, text: &str, defaults: &MaterialDefaults) -> Result<Material, String> {
    let section: MaterialSection = toml::from_str(text).map_err(|e| e.message().to_string())?;
    material(name, &section, defaults).map_err(|(_, problem)| format!("material '{name}': {problem}"))
}
