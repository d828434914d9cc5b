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

/// `v` as the f64 of its shortest decimal form (0.7, not 0.699999988…): it reads back as `v`.
pub(crate) fn shortest(v: f32) -> f64 {
    v.to_string().parse().unwrap_or(v as f64)
}

/// The keys of a `[material.NAME]` section that [`material_from_toml`] reads back as `material`,
/// every key that changes what it reflects written (none left to the reader's defaults): what the explorer's state and its saved scene files hold. Materials a
/// section cannot describe — glTF's metallic-roughness model, textures — are refused.
pub fn material_keys(material: &Material) -> Result<toml::Table, String> {
    if material.textures != MaterialTextures::default() {
        return Err(format!(
            "material '{}' has textures, which a material section does not hold",
            material.name
        ));
    }
    let mut keys = toml::Table::new();
    let floats = |v: [f32; 3]| toml::Value::Array(v.iter().map(|&c| shortest(c).into()).collect());
    keys.insert("model".into(), material.model_name().into());
    keys.insert("albedo".into(), floats(material.albedo));
    keys.insert("kd".into(), shortest(material.kd).into());
    keys.insert("two_sided".into(), material.two_sided.into());
    match &material.model {
        BrdfModel::Lambert => {}
        BrdfModel::BlinnPhong(bp) => {
            keys.insert("ks".into(), shortest(bp.ks).into());
            keys.insert("shininess".into(), shortest(bp.shininess).into());
            keys.insert("specular_color".into(), floats(bp.color));
        }
        BrdfModel::CookTorrance(ct) => {
            keys.insert("roughness".into(), shortest(ct.alpha).into());
            keys.insert("d".into(), ct.d.name().into());
            keys.insert("g".into(), ct.g.name().into());
            keys.insert("fresnel".into(), ct.f.name().into());
            keys.insert("specular_color".into(), floats(ct.specular_color));
            match ct.f {
                FresnelTerm::Conductor => {
                    keys.insert("eta".into(), floats(ct.eta));
                    keys.insert("k".into(), floats(ct.k));
                }
                FresnelTerm::Constant => {}
                FresnelTerm::Schlick | FresnelTerm::SchlickSg => {
                    keys.insert("metallic".into(), ct.metallic.into());
                    keys.insert("ior".into(), shortest(ct.ior).into());
                }
            }
        }
        BrdfModel::GltfPbr(_) => {
            return Err(format!(
                "material '{}' is glTF's metallic-roughness model, which a material section does not describe",
                material.name
            ))
        }
    }
    Ok(keys)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `material_keys` writes reads back as the same material, for every model and Fresnel
    /// term, under either set of defaults.
    #[test]
    fn material_keys_read_back_as_the_material() {
        let sections = [
            "model = \"lambert\"\nalbedo = [0.2, 0.3, 0.4]\ntwo_sided = false\n",
            "model = \"blinn-phong\"\nks = 0.5\nshininess = 7.5\nspecular_color = [1.0, 0.9, 0.8]\n",
            "model = \"cook-torrance\"\nroughness = 0.3\nd = \"beckmann\"\ng = \"schlick-karis\"\nior = 1.7\n",
            "model = \"cook-torrance\"\nmetallic = true\nfresnel = \"schlick-sg\"\nspecular_color = [0.9, 0.6, 0.3]\n",
            "model = \"cook-torrance\"\neta = [0.2, 0.92, 1.1]\nk = [3.9, 2.45, 2.14]\nroughness = 0.25\n",
            "model = \"cook-torrance\"\nfresnel = \"constant\"\nkd = 0.25\n",
        ];
        let tp = crate::normal_map::scene_file::Preset::Tp.material_defaults();
        for text in sections {
            for defaults in [&MaterialDefaults::SCENE, &tp] {
                let material = material_from_toml("m", text, defaults).unwrap();
                let keys = toml::to_string(&material_keys(&material).unwrap()).unwrap();
                assert_eq!(material_from_toml("m", &keys, defaults).unwrap(), material, "{text}");
            }
        }
        let mut textured = material_from_toml("m", sections[0], &MaterialDefaults::SCENE).unwrap();
        textured.textures.normal = Some(crate::material::NormalTexture {
            texture: crate::texture::TextureRef::gltf_default(0),
            scale: 1.0,
        });
        assert!(material_keys(&textured).unwrap_err().contains("textures"));
    }
}
