//! glTF materials → `gltf-pbr` [`Material`]s, and the file's images as [`PendingImage`]s.
//!
//! Every factor and texture of `pbrMetallicRoughness` is used, plus the normal texture (with its
//! scale), the emissive factor (times `KHR_materials_emissive_strength`) and texture, each
//! texture's `KHR_texture_transform`,
//! `doubleSided`, and `alphaMode` MASK with its
//! `alphaCutoff` (cut-outs: [`Cutout`]). Not used, with a warning or a note: `alphaMode` BLEND
//! (rendered opaque: pointshade has no transparency), texture-coordinate sets above 1, and the
//! occlusion texture, which in glTF darkens indirect light only — pointshade computes direct
//! light from punctual lights only, so occlusion has nothing to act on and is not decoded.

use crate::error::InputResult;
use crate::material::{BrdfModel, Cutout, GltfPbr, Material, MaterialTextures, NormalTexture};
use crate::scene::gltf::document::GltfDocument;
use crate::scene::gltf::texture_transform::{self, SlotTransform};
use crate::scene::textures::{ImageSource, PendingImage};
use crate::texture::{Filter, TextureRef, UvTransform, Wrap};

/// The materials of a file, converted.
pub struct Materials {
    /// One per glTF material, in file order.
    pub materials: Vec<Material>,
    /// Messages for `--explain`.
    pub notes: Vec<String>,
    /// Problems worth a warning.
    pub warnings: Vec<String>,
}

/// The glTF default material (specification §3.9.6): base colour 1, metallic 1, roughness 1,
/// single-sided. Used by primitives without a material.
pub fn default_material() -> Material {
    let mut m = Material::gltf_pbr("glTF default", [1.0; 3], 1.0, 1.0);
    m.two_sided = false;
    m
}

/// Converts every material of `d`.
pub fn convert_materials(d: &GltfDocument) -> InputResult<Materials> {
    let mut out = Materials {
        materials: Vec::new(),
        notes: Vec::new(),
        warnings: Vec::new(),
    };
    let file = d.path.display();
    let mut translucent = Vec::new();
    let mut occlusion = Vec::new();
    for m in d.doc.materials() {
        let index = m.index().unwrap_or(0);
        let name = m.name().map_or_else(|| format!("material {index}"), str::to_string);
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, alpha] = pbr.base_color_factor();
        let mut tex_warning = |slot: &str, set: u32| {
            out.warnings.push(format!(
                "{file}: material '{name}': its {slot} texture uses texture coordinates {set} (only sets 0 and 1 are supported): ignored"
            ))
        };
        let transform_error = |slot: &str, e: String| {
            d.error(format!(
                "material '{name}': KHR_texture_transform of its {slot} texture: {e}"
            ))
        };
        let base_color = info_slot(pbr.base_color_texture()).map_err(|e| transform_error("base colour", e))?;
        let metallic_roughness =
            info_slot(pbr.metallic_roughness_texture()).map_err(|e| transform_error("metallic-roughness", e))?;
        let emissive = info_slot(m.emissive_texture()).map_err(|e| transform_error("emissive", e))?;
        let normal_transform = texture_transform::of_normal(&d.doc, index).map_err(|e| transform_error("normal", e))?;
        let mut reference = |slot: &str, slot_info: Option<Slot>| -> Option<TextureRef> {
            let (texture, set, transform) = slot_info?;
            let set = transform.and_then(|t| t.tex_coord).unwrap_or(set);
            if set > 1 {
                tex_warning(slot, set);
                return None;
            }
            Some(texture_ref(&texture, set as u8, transform.map(|t| t.transform)))
        };
        let textures = MaterialTextures {
            base_color: reference("base colour", base_color),
            metallic_roughness: reference("metallic-roughness", metallic_roughness),
            normal: m.normal_texture().and_then(|n| {
                let scale = n.scale();
                reference("normal", Some((n.texture(), n.tex_coord(), normal_transform)))
                    .map(|texture| NormalTexture { texture, scale })
            }),
            emissive: reference("emissive", emissive),
            ..MaterialTextures::default()
        };
        if m.occlusion_texture().is_some() {
            occlusion.push(name.clone());
        }
        let cutout = match m.alpha_mode() {
            ::gltf::material::AlphaMode::Opaque => None,
            ::gltf::material::AlphaMode::Mask => Some(Cutout {
                cutoff: m.alpha_cutoff().unwrap_or(0.5),
                alpha,
            }),
            ::gltf::material::AlphaMode::Blend => {
                translucent.push(format!("'{name}'"));
                None
            }
        };
        let material = Material {
            model: BrdfModel::GltfPbr(GltfPbr {
                metallic: pbr.metallic_factor(),
                roughness: pbr.roughness_factor(),
                // KHR_materials_emissive_strength scales the factor (HDR emission).
                emissive: m.emissive_factor().map(|e| e * m.emissive_strength().unwrap_or(1.0)),
                cutout,
            }),
            textures,
            two_sided: m.double_sided(),
            ..Material::lambert(&name, [r, g, b])
        };
        material
            .validate()
            .map_err(|e| d.error(format!("material '{name}': {e}")))?;
        out.materials.push(material);
    }
    if !translucent.is_empty() {
        out.warnings.push(format!(
            "{file}: alphaMode BLEND is not supported, rendered opaque: {}",
            translucent.join(", ")
        ));
    }
    if !occlusion.is_empty() {
        out.notes.push(format!(
            "occlusion textures not used (they scale indirect light, and pointshade computes direct light only): {}",
            occlusion.join(", ")
        ));
    }
    Ok(out)
}

/// A texture as pointshade samples it: its image, coordinate set, wrap modes and magnification
/// filter (minification filters are not used: there are no mipmaps).
fn texture_ref(texture: &::gltf::Texture, tex_coord: u8, transform: Option<UvTransform>) -> TextureRef {
    use ::gltf::texture::{MagFilter, WrappingMode};
    let sampler = texture.sampler();
    let wrap = |mode| match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    };
    TextureRef {
        image: texture.source().index() as u32,
        tex_coord,
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
        filter: match sampler.mag_filter() {
            Some(MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Bilinear,
        },
        transform,
    }
}

/// A texture slot as the file gives it: the texture, its coordinate set and its transform.
type Slot<'a> = (::gltf::Texture<'a>, u32, Option<SlotTransform>);

/// The slot of a `textureInfo`, if the material has that texture.
fn info_slot(info: Option<::gltf::texture::Info<'_>>) -> Result<Option<Slot<'_>>, String> {
    info.map(|i| Ok((i.texture(), i.tex_coord(), texture_transform::of_info(&i)?)))
        .transpose()
}

/// The file's images, not decoded: embedded ones copied out of their buffer views (checked),
/// external ones left as URIs to read if they are used.
pub fn pending_images(d: &GltfDocument) -> InputResult<Vec<PendingImage>> {
    let json = d.doc.as_json();
    let mut images = Vec::new();
    for (i, image) in json.images.iter().enumerate() {
        let named = |what: &str| match &image.name {
            Some(n) => format!("image {i} '{n}' ({what})"),
            None => format!("image {i} ({what})"),
        };
        let (label, source) = match (&image.uri, &image.buffer_view) {
            (Some(uri), _) if uri.starts_with("data:") => (
                named("data: URI"),
                ImageSource::Uri {
                    dir: d.dir.clone(),
                    uri: uri.clone(),
                },
            ),
            (Some(uri), _) => (
                format!("image {i} '{uri}'"),
                ImageSource::Uri {
                    dir: d.dir.clone(),
                    uri: uri.clone(),
                },
            ),
            (None, Some(view)) => {
                let view = d.doc.views().nth(view.value()).expect("validated index");
                let buffer = &d.buffers[view.buffer().index()];
                let bytes = view
                    .offset()
                    .checked_add(view.length())
                    .filter(|&end| end <= view.buffer().length())
                    .map(|end| buffer[view.offset()..end].to_vec())
                    .ok_or_else(|| {
                        d.error(format!(
                            "image {i}: buffer view {} lies outside buffer {}",
                            view.index(),
                            view.buffer().index()
                        ))
                    })?;
                (named("embedded"), ImageSource::Bytes(bytes))
            }
            (None, None) => return Err(d.error(format!("image {i} has neither a uri nor a bufferView"))),
        };
        images.push(PendingImage {
            origin: d.path.clone(),
            label,
            source,
        });
    }
    Ok(images)
}
