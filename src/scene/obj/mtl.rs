//! MTL materials → the BRDF module's [`Material`]s: the model their keys choose, the textures
//! they name, and one warning for each MTL statement that nothing reads.
//!
//! | MTL | pointshade |
//! |---|---|
//! | `Kd` | albedo (Lambert; Blinn-Phong's diffuse; Cook-Torrance's, or its specular colour when metallic) |
//! | `Ks` + `Ns` (Ks not black) | Blinn-Phong: specular colour `Ks`, shininess `Ns` |
//! | `Pr`, `Pm` (the PBR extension) | Cook-Torrance, GGX + height-correlated Smith + Schlick, α = Pr², metallic when Pm ≥ 0.5 |
//! | `Ni` | a dielectric Cook-Torrance material's index of refraction |
//! | `map_Kd` | an sRGB texture multiplying the albedo |
//! | `map_Ks` | an sRGB texture multiplying the specular colour (Blinn-Phong, Cook-Torrance) |
//! | `map_Ns` | one channel multiplying Blinn-Phong's `Ns` |
//! | `map_Pr`, `map_Pm` | one channel multiplying `Pr` (α = (Pr·value)²) and `Pm` (a metal where Pm·value ≥ 0.5) |
//! | `norm`, else `map_Bump`/`bump` (`-bm s`) | a tangent-space normal map (+Y up the image), X and Y scaled by s |
//!
//! Textures are bilinear and repeated (`-clamp on`: clamped to the edge); a one-channel
//! texture reads the luminance unless `-imfchan r|g|b|m|l` says otherwise. A texture on a model
//! without the parameter it modulates, or on a mesh without texture coordinates, is an unused
//! statement. `map_Bump` is read as a normal map, as exporters write it; a greyscale height map
//! there gives meaningless normals (bump mapping is not implemented). Everything else (`Ka`,
//! `Ke`, `d`, `illum`, options such as `-s`, …) is left out with a warning naming the statement and the materials that hold it.

use std::collections::BTreeMap;
use std::path::Path;

use crate::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use crate::error::{InputError, InputResult};
use crate::material::{BlinnPhong, BrdfModel, Channel, CookTorrance, Material, NormalTexture, ScalarTexture};
use crate::scene::textures::{ImageSource, PendingImage};
use crate::texture::{TextureRef, Wrap};

/// The texture statements pointshade reads, in the order they are applied.
const TEXTURE_STATEMENTS: [&str; 7] = ["map_Kd", "map_Ks", "map_Ns", "map_Pr", "map_Pm", "norm", "map_Bump"];

/// The materials of an OBJ file's MTL libraries, converted.
pub(super) struct MtlMaterials {
    /// One per MTL material, in the file's order.
    pub materials: Vec<Material>,
    /// The images their textures name (`TextureRef::image` indexes this list).
    pub images: Vec<PendingImage>,
    /// One per unused MTL statement.
    pub warnings: Vec<String>,
}

/// Converts `materials` (read by tobj from `obj`'s libraries); texture files are looked up in
/// `dir`, the OBJ file's folder. `has_uvs`: whether the mesh has texture coordinates (without
/// them a texture cannot be looked up, and is one more unused statement).
pub(super) fn convert(
    materials: &[tobj::Material],
    dir: &Path,
    obj: &Path,
    has_uvs: bool,
) -> InputResult<MtlMaterials> {
    let mut out = MtlMaterials {
        materials: Vec::with_capacity(materials.len()),
        images: Vec::new(),
        warnings: Vec::new(),
    };
    // Statement → the materials holding it unused (ordered, so warnings come in a fixed order).
    let mut unused: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for m in materials {
        let named = |e: String| InputError::new(obj, format!("material '{}': {e}", m.name));
        let mut material = material_from_mtl(m).map_err(named)?;
        let mut leave = |statement: &str| unused.entry(statement.to_string()).or_default().push(m.name.clone());
        for statement in unused_statements(m, &material) {
            leave(statement);
        }
        let (blinn_phong, cook_torrance) = lobes(&material);
        let metal = cook_torrance.is_some_and(|ct| ct.metallic);
        for statement in TEXTURE_STATEMENTS {
            let value = match statement {
                "map_Kd" => m.diffuse_texture.as_deref(),
                "map_Ks" => m.specular_texture.as_deref(),
                "map_Ns" => m.shininess_texture.as_deref(),
                "map_Bump" => m.normal_texture.as_deref(),
                other => m.unknown_param.get(other).map(String::as_str),
            };
            let Some(value) = value else { continue };
            let texture = texture_statement(value).map_err(|e| named(format!("{statement}: {e}")))?;
            let one_channel = matches!(statement, "map_Ns" | "map_Pr" | "map_Pm");
            let normal_map = matches!(statement, "norm" | "map_Bump");
            for option in &texture.ignored_options {
                leave(&format!("{statement} option {option}"));
            }
            if texture.bump.is_some() && !normal_map {
                leave(&format!("{statement} option -bm"));
            }
            if texture.channel.is_some() && !one_channel {
                leave(&format!("{statement} option -imfchan (a colour texture reads RGB)"));
            }
            let unused = match statement {
                // k_d = 0: a metal's albedo is its specular colour, which map_Ks modulates.
                "map_Kd" if metal => Some("on a metallic material"),
                "map_Ks" if !blinn_phong && cook_torrance.is_none() => Some("the material has no specular lobe"),
                "map_Ns" if !blinn_phong => Some("the material is not Blinn-Phong"),
                "map_Pr" | "map_Pm" if cook_torrance.is_none() => Some("the material has no Pr or Pm"),
                "map_Bump" if material.textures.normal.is_some() => Some("norm gives the normal map"),
                _ if !has_uvs => Some("the mesh has no texture coordinates"),
                _ => None,
            };
            if let Some(why) = unused {
                leave(&format!("{statement} ({why})"));
                continue;
            }
            let image = out.images.len() as u32;
            out.images.push(PendingImage {
                origin: obj.to_path_buf(),
                label: format!("material '{}' {statement} ('{}')", m.name, texture.file),
                source: ImageSource::Uri {
                    dir: dir.to_path_buf(),
                    uri: texture.file.clone(),
                },
            });
            let wrap = if texture.clamp { Wrap::ClampToEdge } else { Wrap::Repeat };
            let reference = TextureRef {
                wrap_u: wrap,
                wrap_v: wrap,
                ..TextureRef::gltf_default(image)
            };
            let channel = texture.channel.unwrap_or_default();
            let scalar = |factor: f32| ScalarTexture {
                texture: reference,
                channel,
                factor,
            };
            let t = &mut material.textures;
            match statement {
                "map_Kd" => t.base_color = Some(reference),
                "map_Ks" => t.specular = Some(reference),
                // The statement's scalar, or 1 where the file gives only the texture.
                "map_Ns" => t.shininess = Some(scalar(m.shininess.map_or(1.0, |s| s as f32))),
                "map_Pr" => t.roughness = Some(scalar(param(m, "Pr").ok().flatten().unwrap_or(1.0))),
                "map_Pm" => t.metallic = Some(scalar(param(m, "Pm").ok().flatten().unwrap_or(1.0))),
                _ => {
                    t.normal = Some(NormalTexture {
                        texture: reference,
                        scale: texture.bump.unwrap_or(1.0),
                    })
                }
            }
        }
        out.materials.push(material);
    }
    out.warnings = unused
        .into_iter()
        .map(|(statement, names)| {
            let what = match statement.as_str() {
                NOT_STATEMENTS => "lines of its material library that are not MTL statements are".to_string(),
                _ => format!("MTL statement {statement} is"),
            };
            format!(
                "{}: {what} not used by pointshade (material(s) {})",
                obj.display(),
                quoted_names(&names)
            )
        })
        .collect();
    Ok(out)
}

/// Converts one MTL material to the BRDF module's [`Material`] (its textures aside).
///
/// - `Pr` (roughness) or `Pm` (metallic), or their textures, present → Cook-Torrance with the GGX + height-correlated
///   Smith + Schlick terms of the PBR workflow that extension comes from, α = Pr² (Pr is a
///   perceptual roughness there), metallic when Pm ≥ 0.5 (then Kd tints the specular colour and
///   the diffuse part is off), F0 from `Ni` (default 1.5) otherwise.
/// - `Ks` non-black and `Ns` given → Blinn-Phong with `specular_color = Ks`, `shininess = Ns`.
/// - Otherwise Lambert with `albedo = Kd`.
pub fn material_from_mtl(m: &tobj::Material) -> Result<Material, String> {
    let albedo = m.diffuse.map_or([0.8, 0.8, 0.8], single);
    let (pr, pm) = (param(m, "Pr")?, param(m, "Pm")?);
    let pbr_maps = ["map_Pr", "map_Pm"].iter().any(|k| m.unknown_param.contains_key(*k));
    let mut material = Material::lambert(&m.name, albedo);
    if pr.is_some() || pm.is_some() || pbr_maps {
        // A metallic texture chooses per point between the dielectric and the metal form
        // (`Material::at`): the material itself is then the dielectric.
        let metallic = pm.unwrap_or(0.0) >= 0.5 && !m.unknown_param.contains_key("map_Pm");
        let roughness = pr.unwrap_or(0.5);
        material.model = BrdfModel::CookTorrance(CookTorrance {
            alpha: roughness * roughness,
            d: MicrofacetDistribution::Ggx,
            g: MaskingShadowing::SmithGgxCorrelated,
            f: FresnelTerm::Schlick,
            metallic,
            specular_color: if metallic { albedo } else { [1.0; 3] },
            ior: m.optical_density.map_or(1.5, |n| n as f32),
            ..CookTorrance::default()
        });
        if metallic {
            material.kd = 0.0;
        }
    } else if let (Some(ks), Some(ns)) = (m.specular.map(single), m.shininess.map(|s| s as f32)) {
        if ks.iter().any(|&c| c > 0.0) {
            material.model = BrdfModel::BlinnPhong(BlinnPhong {
                ks: 1.0,
                shininess: ns,
                color: ks,
            });
        }
    }
    material.validate()?;
    Ok(material)
}

/// A colour of an MTL file (read in f64, as tobj reads everything with `use_f64`).
fn single(c: [f64; 3]) -> [f32; 3] {
    c.map(|v| v as f32)
}

/// A numeric statement tobj keeps as text (`Pr`, `Pm`).
fn param(m: &tobj::Material, key: &str) -> Result<Option<f32>, String> {
    m.unknown_param
        .get(key)
        .map(|v| {
            v.trim()
                .parse::<f32>()
                .map_err(|_| format!("{key} '{v}' is not a number"))
        })
        .transpose()
}

/// The statements of `m` that `material` (what [`material_from_mtl`] made of it) does not read,
/// the textures aside ([`convert`] decides about them).
fn unused_statements<'a>(m: &'a tobj::Material, material: &Material) -> Vec<&'a str> {
    let (blinn_phong, cook_torrance) = lobes(material);
    let dielectric = cook_torrance.is_some_and(|ct| !ct.metallic);
    let mut out = Vec::new();
    let mut unless = |present: bool, used: bool, statement: &'a str| {
        if present && !used {
            out.push(statement);
        }
    };
    unless(m.ambient.is_some(), false, "Ka");
    unless(m.emissive.is_some(), false, "Ke");
    unless(m.specular.is_some(), blinn_phong, "Ks");
    unless(m.shininess.is_some(), blinn_phong, "Ns");
    unless(m.optical_density.is_some(), dielectric, "Ni");
    unless(m.dissolve.is_some(), false, "d");
    unless(m.illumination_model.is_some(), false, "illum");
    unless(m.ambient_texture.is_some(), false, "map_Ka");
    unless(m.dissolve_texture.is_some(), false, "map_d");
    for key in m.unknown_param.keys() {
        // A file that is not an MTL (`mtllib /etc/passwd`) has lines whose first word tobj
        // takes for a statement: those are counted, never quoted.
        let statement = if plausible_statement(key) {
            key.as_str()
        } else {
            NOT_STATEMENTS
        };
        unless(
            true,
            matches!(key.as_str(), "Pr" | "Pm" | "map_Pr" | "map_Pm" | "norm"),
            statement,
        );
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Material names for a warning: each up to 32 characters, at most eight of them (a file that
/// is not an MTL can name thousands).
fn quoted_names(names: &[String]) -> String {
    let mut shown: Vec<String> = names.iter().take(8).map(|n| n.chars().take(32).collect()).collect();
    if names.len() > 8 {
        shown.push(format!("and {} more", names.len() - 8));
    }
    shown.join(", ")
}

/// What a warning says for the lines whose first word is not a plausible MTL statement.
const NOT_STATEMENTS: &str = "(not a statement)";

/// Whether `word` may be quoted as an MTL statement: a letter, then up to 15 letters, digits
/// or underscores (every statement of the format and its extensions has that form).
fn plausible_statement(word: &str) -> bool {
    word.len() <= 16
        && word.starts_with(|c: char| c.is_ascii_alphabetic())
        && word.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

/// Whether `material` is Blinn-Phong, and its Cook-Torrance lobe if it has one.
fn lobes(material: &Material) -> (bool, Option<CookTorrance>) {
    match material.model {
        BrdfModel::BlinnPhong(_) => (true, None),
        BrdfModel::CookTorrance(ct) => (false, Some(ct)),
        _ => (false, None),
    }
}

/// A texture statement's value: `[-option values…]… file`.
#[derive(Debug)]
struct TextureStatement {
    /// The file name (the rest of the line after the options; it may contain spaces).
    file: String,
    /// `-clamp on`.
    clamp: bool,
    /// `-imfchan`: the channel a one-channel texture reads.
    channel: Option<Channel>,
    /// `-bm`: the bump multiplier, a normal map's XY scale.
    bump: Option<f32>,
    /// Options read and not applied (`-s`, `-o`, `-mm`, …), by name.
    ignored_options: Vec<String>,
}

/// Parses a texture statement's value. Options take their documented number of values (`-o`,
/// `-s`, `-t`: one to three numbers); an option pointshade does not know is an error, since the
/// file name cannot be told from its values.
fn texture_statement(value: &str) -> Result<TextureStatement, String> {
    let mut words = value.split_whitespace().peekable();
    let mut out = TextureStatement {
        file: String::new(),
        clamp: false,
        channel: None,
        bump: None,
        ignored_options: Vec::new(),
    };
    while let Some(option) = words.next_if(|w| w.starts_with('-')) {
        let values = match option {
            "-blendu" | "-blendv" | "-bm" | "-boost" | "-cc" | "-clamp" | "-imfchan" | "-texres" | "-type" => 1,
            "-mm" => 2,
            "-o" | "-s" | "-t" => 3,
            other => return Err(format!("unknown option '{other}'")),
        };
        let mut read = Vec::new();
        for k in 0..values {
            // -o/-s/-t take one to three numbers: stop at the first word that is not one.
            let optional = k > 0 && matches!(option, "-o" | "-s" | "-t");
            match words.peek() {
                Some(w) if !optional || w.parse::<f64>().is_ok() => read.push(words.next().unwrap_or_default()),
                _ if optional => break,
                _ => return Err(format!("option {option} needs {values} value(s)")),
            }
        }
        match (option, read.as_slice()) {
            ("-clamp", ["on"]) => out.clamp = true,
            ("-clamp", ["off"]) => out.clamp = false,
            ("-clamp", v) => return Err(format!("-clamp takes on or off, not '{}'", v.join(" "))),
            ("-bm", [v]) => match v.parse::<f32>() {
                Ok(b) if b.is_finite() => out.bump = Some(b),
                _ => return Err(format!("-bm takes a finite number, not '{v}'")),
            },
            ("-imfchan", [c]) => {
                out.channel = Some(match *c {
                    "r" => Channel::R,
                    "g" => Channel::G,
                    "b" => Channel::B,
                    "m" => Channel::A,
                    "l" => Channel::Luminance,
                    other => return Err(format!("-imfchan takes r, g, b, m or l, not '{other}'")),
                })
            }
            _ => out.ignored_options.push(option.to_string()),
        }
    }
    out.file = words.collect::<Vec<_>>().join(" ");
    if out.file.is_empty() {
        return Err("no file name".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_statements_read_their_options_and_file_name() {
        let t = texture_statement("spot_texture.png").unwrap();
        assert_eq!((t.file.as_str(), t.clamp), ("spot_texture.png", false));
        let t = texture_statement("-clamp on -s 2 2 -bm 0.5 my texture.png").unwrap();
        assert_eq!((t.file.as_str(), t.clamp), ("my texture.png", true));
        assert_eq!(
            (t.ignored_options.as_slice(), t.bump),
            (&["-s".to_string()][..], Some(0.5))
        );
        assert!(texture_statement("-bm x n.png")
            .unwrap_err()
            .contains("-bm takes a finite number"));
        assert_eq!(texture_statement("-imfchan g r.png").unwrap().channel, Some(Channel::G));
        let t = texture_statement("-o 0.5 file.png").unwrap();
        assert_eq!(
            (t.file.as_str(), t.ignored_options.as_slice()),
            ("file.png", &["-o".to_string()][..])
        );
        assert!(texture_statement("-clamp on").unwrap_err().contains("no file name"));
        assert!(texture_statement("-frobnicate 1 a.png")
            .unwrap_err()
            .contains("unknown option"));
        assert!(texture_statement("-clamp maybe a.png")
            .unwrap_err()
            .contains("on or off"));
        assert!(texture_statement("-mm 1").unwrap_err().contains("needs 2"));
    }
}
