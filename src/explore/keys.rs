//! The material keys the page offers, with their kinds, slider ranges and defaults (docs
//! scene-format.md, "Every material key"), and the reading of one material's keys for a plot.
//! The ranges are the sliders'; what a value may be is the scene-file reader's to say.

use serde_json::{json, Value};

use super::state::{section_text, Keys};
use crate::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use crate::material::Material;
use crate::normal_map::scene_file::Preset;
use crate::scene::file::{material_from_toml, MaterialDefaults};

const ALL: &[&str] = &["lambert", "blinn-phong", "cook-torrance"];
const SPECULAR: &[&str] = &["blinn-phong", "cook-torrance"];
const CT: &[&str] = &["cook-torrance"];
const BP: &[&str] = &["blinn-phong"];
const SCHLICK: &[&str] = &["schlick", "schlick-sg"];
const CONDUCTOR: &[&str] = &["conductor"];

/// Every material key: name, kind, slider range, the scene files' default, the models it
/// applies to and, for keys only some Fresnel terms read, those terms.
pub fn schema() -> Value {
    let number = |key: &str, min: f64, max: f64, default: f64, models: &[&str]| json!({"key": key, "kind": "number", "min": min, "max": max, "default": default, "models": models});
    let color = |key: &str, max: f64, default: [f64; 3], models: &[&str]| json!({"key": key, "kind": "color", "min": 0.0, "max": max, "default": default, "models": models});
    let choice = |key: &str, choices: Vec<&str>, default: &str| json!({"key": key, "kind": "choice", "choices": choices, "default": default, "models": CT});
    let mut keys = vec![
        json!({"key": "model", "kind": "choice", "choices": ALL, "default": "lambert", "models": ALL}),
        color("albedo", 1.0, [0.5; 3], ALL),
        number("kd", 0.0, 1.0, 1.0, ALL),
        json!({"key": "two_sided", "kind": "bool", "default": true, "models": ALL}),
        number("ks", 0.0, 2.0, 1.0, BP),
        number("shininess", 0.0, 512.0, 32.0, BP),
        color("specular_color", 1.0, [1.0; 3], SPECULAR),
        number("roughness", 0.0, 1.0, 0.1, CT),
        choice(
            "d",
            MicrofacetDistribution::ALL.iter().map(|t| t.name()).collect(),
            "ggx",
        ),
        choice(
            "g",
            MaskingShadowing::ALL.iter().map(|t| t.name()).collect(),
            "smith-ggx",
        ),
        choice(
            "fresnel",
            FresnelTerm::ALL.iter().map(|t| t.name()).collect(),
            "schlick",
        ),
    ];
    let mut only = |mut key: Value, fresnel: &[&str]| {
        key["fresnel"] = json!(fresnel);
        keys.push(key);
    };
    only(
        json!({"key": "metallic", "kind": "bool", "default": false, "models": CT}),
        SCHLICK,
    );
    only(number("ior", 1.0, 3.0, 1.5, CT), SCHLICK);
    only(color("eta", 5.0, [0.0; 3], CT), CONDUCTOR);
    only(color("k", 10.0, [1.0; 3], CT), CONDUCTOR);
    Value::Array(keys)
}

/// One material of a plot request's keys, with the defaults of `preset` (a normal image's) or of
/// scene files, checked as a scene file's section is.
pub fn material(keys: &Keys, preset: Option<&str>) -> Result<Material, String> {
    let defaults = match preset {
        Some(p) => p.parse::<Preset>()?.material_defaults(),
        None => MaterialDefaults::SCENE,
    };
    material_from_toml("material", &section_text(keys)?, &defaults)
}
