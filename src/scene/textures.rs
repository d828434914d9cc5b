//! Texture images of a scene: listed while loading, decoded once at the end, and only those a
//! rendered material uses.
//!
//! Loaders return [`PendingImage`]s and materials whose `TextureRef::image` indexes them.
//! [`decode_used_images`] then finds the materials some triangle uses, decodes (in parallel) the
//! images those materials read, renumbers the references to the decoded list, and drops every
//! other reference, so that each `TextureRef` left in the scene points at a decoded image.

use std::collections::BTreeMap;
use std::path::PathBuf;

use rayon::prelude::*;

use crate::error::{InputError, InputResult};
use crate::material::Material;
use crate::texture::TextureImage;

/// Where an image's encoded bytes are.
#[derive(Clone, Debug)]
pub enum ImageSource {
    /// A URI relative to `dir` (a file, or a `data:` URI), read only if the image is used.
    Uri { dir: PathBuf, uri: String },
    /// Bytes already in memory (a glTF buffer view).
    Bytes(Vec<u8>),
}

/// An image some material may use, not decoded yet.
#[derive(Clone, Debug)]
pub struct PendingImage {
    /// The file that references it (errors are reported on it).
    pub origin: PathBuf,
    /// How it is named in messages: "image 2 ('foo.png')".
    pub label: String,
    /// Where its bytes are.
    pub source: ImageSource,
}

/// Adds `base` to every image index of `materials` (when a file's images are appended to a
/// scene's list).
pub fn offset_images(materials: &mut [Material], base: u32) {
    for m in materials {
        for r in m.texture_refs_mut() {
            r.image += base;
        }
    }
}

/// Decodes the images that the materials used by `material_of_triangle` read, renumbers their
/// references, and removes all other references (from unused materials, and emissive textures
/// of materials whose emissive factor is zero). Returns the decoded images in first-use order.
pub fn decode_used_images(
    materials: &mut [Material],
    material_of_triangle: &[u32],
    pending: &[PendingImage],
) -> InputResult<Vec<TextureImage>> {
    let mut used = vec![false; materials.len()];
    for &m in material_of_triangle {
        used[m as usize] = true;
    }
    // Old image index → new index, in first-use order.
    let mut renumber: BTreeMap<u32, u32> = BTreeMap::new();
    let mut order = Vec::new();
    for (material, used) in materials.iter_mut().zip(used) {
        if !used {
            material.clear_textures();
            continue;
        }
        let emits = material.emits();
        if !emits {
            material.textures.emissive = None;
        }
        for r in material.texture_refs_mut() {
            let next = renumber.len() as u32;
            r.image = *renumber.entry(r.image).or_insert_with(|| {
                order.push(r.image);
                next
            });
        }
    }
    order
        .par_iter()
        .map(|&i| decode(&pending[i as usize]))
        .collect::<Vec<_>>()
        .into_iter()
        .collect()
}

/// Reads and decodes one image into 8-bit RGBA.
fn decode(p: &PendingImage) -> InputResult<TextureImage> {
    let err = |problem: String| InputError::new(&p.origin, format!("{}: {problem}", p.label));
    let read;
    let bytes: &[u8] = match &p.source {
        ImageSource::Bytes(b) => b,
        ImageSource::Uri { dir, uri } => {
            read = crate::scene::uri::read_uri(dir, uri).map_err(err)?;
            &read
        }
    };
    let image = image::load_from_memory(bytes).map_err(|e| err(format!("cannot decode: {e}")))?;
    crate::texture::check_palette_indices(bytes).map_err(err)?;
    let rgba = image.to_rgba8();
    let (width, height) = rgba.dimensions();
    if width == 0 || height == 0 {
        return Err(err("the image is empty".into()));
    }
    let texels = rgba.pixels().map(|p| p.0).collect();
    Ok(TextureImage {
        label: p.label.clone(),
        width,
        height,
        texels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{BrdfModel, MaterialTextures};
    use crate::texture::TextureRef;

    fn reference(image: u32) -> Option<TextureRef> {
        Some(TextureRef::gltf_default(image))
    }

    fn textured(name: &str, base: u32, emissive: u32, emits: bool) -> Material {
        let mut m = Material::gltf_pbr(name, [1.0; 3], 0.0, 1.0);
        if let BrdfModel::GltfPbr(p) = &mut m.model {
            m.textures = MaterialTextures {
                base_color: reference(base),
                emissive: reference(emissive),
                ..Default::default()
            };
            p.emissive = if emits { [1.0; 3] } else { [0.0; 3] };
        }
        m
    }

    /// A pending 1×1 PNG of colour `c`, or an unreadable file.
    fn pending(c: Option<u8>) -> PendingImage {
        let source = match c {
            Some(c) => {
                let mut bytes = std::io::Cursor::new(Vec::new());
                image::RgbaImage::from_pixel(1, 1, image::Rgba([c, c, c, 255]))
                    .write_to(&mut bytes, image::ImageFormat::Png)
                    .unwrap();
                ImageSource::Bytes(bytes.into_inner())
            }
            None => ImageSource::Uri {
                dir: std::env::temp_dir(),
                uri: "pointshade-no-such-image.png".into(),
            },
        };
        PendingImage {
            origin: "test.gltf".into(),
            label: format!("image {c:?}"),
            source,
        }
    }

    #[test]
    fn only_images_of_rendered_materials_are_decoded_and_references_renumbered() {
        // Material 0 (unused) reads the unreadable image 0; material 1 reads images 2 and 1
        // (emissive, and it emits); material 2 reads image 2 and an emissive image 0 it cannot
        // show (emissive factor 0).
        let mut materials = vec![
            textured("unused", 0, 0, true),
            textured("a", 2, 1, true),
            textured("b", 2, 0, false),
        ];
        let images = [pending(None), pending(Some(10)), pending(Some(20))];
        let decoded = decode_used_images(&mut materials, &[1, 2, 1], &images).unwrap();
        assert_eq!(decoded.len(), 2);
        assert_eq!(decoded[0].texels, vec![[20, 20, 20, 255]], "first use: image 2");
        assert_eq!(decoded[1].texels, vec![[10, 10, 10, 255]]);
        let refs = |m: &Material| {
            let t = &m.textures;
            (t.base_color.map(|r| r.image), t.emissive.map(|r| r.image))
        };
        assert_eq!(refs(&materials[0]), (None, None));
        assert_eq!(refs(&materials[1]), (Some(0), Some(1)));
        assert_eq!(refs(&materials[2]), (Some(0), None));
        // Used, the unreadable image is an error naming it.
        let mut used = vec![textured("c", 0, 0, false)];
        let e = decode_used_images(&mut used, &[0], &images).unwrap_err();
        assert!(e.to_string().contains("pointshade-no-such-image.png"), "{e}");
    }
}
