//! glTF textures and emission in the Mitsuba export: what the `pointshade` plugin needs to look
//! a material's textures up as pointshade does (validation/pointshade_textures.py).
//!
//! - Each image is exported as the texels pointshade decoded (`{prefix}.image{k}.rgba`: raw RGBA,
//!   8 bits per channel, row 0 at the top), so both renderers start from the same texels whatever
//!   JPEG or PNG decoder Mitsuba would have used.
//! - A texture slot becomes plugin properties `{slot}_file`, `_width`, `_height`, `_set`
//!   (texture-coordinate set), `_wrap` ("u v"), `_filter` and, with `KHR_texture_transform`,
//!   `_transform` (the six numbers of [`crate::texture::UvTransform::m`]).
//! - The parts of a textured material carry the texture coordinates and tangents the plugin
//!   interpolates ([`super::ply::VertexAttributes`]).
//! - An emissive material's surfaces get an `area` emitter whose radiance is the plugin's
//!   `pointshade_emission` texture (emissive factor × texture).

use std::fmt::Write as _;

use super::ply::VertexAttributes;
use crate::material::{BrdfModel, Material};
use crate::scene::mesh::TriangleMesh;
use crate::texture::{Filter, TextureImage, TextureRef, Wrap};

/// The file name of image `k` of an export whose files start with `prefix`.
pub fn image_file(prefix: &str, k: usize) -> String {
    format!("{prefix}.image{k}.rgba")
}

/// The file name of image `k` as an 8-bit RGB PNG (what Mitsuba's `bitmap` texture reads).
pub fn png_file_name(prefix: &str, k: usize) -> String {
    format!("{prefix}.image{k}.png")
}

/// Image `k` of `images` as an 8-bit RGB PNG of the texels pointshade decoded (alpha dropped:
/// an albedo texture reads RGB), with its file name.
pub fn png_file(images: &[TextureImage], k: usize, prefix: &str) -> (String, Vec<u8>) {
    let image = &images[k];
    let rgb: Vec<u8> = image.texels.iter().flat_map(|t| [t[0], t[1], t[2]]).collect();
    let mut bytes = Vec::new();
    image::RgbImage::from_raw(image.width, image.height, rgb)
        .expect("a decoded image holds width × height texels")
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .expect("PNG encoding into memory does not fail");
    (png_file_name(prefix, k), bytes)
}

/// Every image of the scene (the decoded ones are exactly those its rendered materials read) as
/// (file name, raw RGBA texels).
pub fn image_files(images: &[TextureImage], prefix: &str) -> Vec<(String, Vec<u8>)> {
    images
        .iter()
        .enumerate()
        .map(|(k, image)| (image_file(prefix, k), image.texels.concat()))
        .collect()
}

/// The attributes the parts of material `m` need: the texture-coordinate sets its textures read,
/// and tangents when it has a normal texture and the mesh has tangents.
pub fn vertex_attributes(m: &Material, mesh: &TriangleMesh) -> VertexAttributes {
    let mut t = m.textures;
    let mut out = VertexAttributes::default();
    for r in t.refs_mut() {
        out.uv[usize::from(r.tex_coord.min(1))] = true;
    }
    out.tangent = t.normal.is_some() && mesh.tangents.is_some();
    out
}

/// The plugin properties of the texture `r` in `slot` (the names pointshade_textures.py reads).
fn slot_properties(slot: &str, r: &TextureRef, images: &[TextureImage], prefix: &str) -> String {
    let image = &images[r.image as usize];
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => "repeat",
        Wrap::MirroredRepeat => "mirrored-repeat",
        Wrap::ClampToEdge => "clamp",
    };
    let filter = match r.filter {
        Filter::Nearest => "nearest",
        Filter::Bilinear => "bilinear",
    };
    let transform = r.transform.map_or_else(String::new, |t| {
        let m = t.m.map(|v| v.to_string()).join(" ");
        format!("<string name=\"{slot}_transform\" value=\"{m}\"/>")
    });
    format!(
        "<string name=\"{slot}_file\" value=\"{}\"/><integer name=\"{slot}_width\" value=\"{}\"/><integer name=\"{slot}_height\" value=\"{}\"/><integer name=\"{slot}_set\" value=\"{}\"/><string name=\"{slot}_wrap\" value=\"{} {}\"/><string name=\"{slot}_filter\" value=\"{filter}\"/>{transform}",
        super::xml::xml_escape(&image_file(prefix, r.image as usize)),
        image.width,
        image.height,
        r.tex_coord,
        wrap(r.wrap_u),
        wrap(r.wrap_v),
    )
}

/// The plugin properties of a material's BRDF textures: a glTF material's base colour,
/// metallic-roughness and normal (with its scale), another model's albedo texture.
pub fn brdf_texture_properties(m: &Material, images: &[TextureImage], prefix: &str) -> String {
    let t = &m.textures;
    let mut p = String::new();
    if let Some(r) = &t.base_color {
        // The plugin's albedo slot multiplies k_d·albedo; its base colour slot, glTF's factor.
        let slot = if matches!(m.model, BrdfModel::GltfPbr(_)) {
            "base_color"
        } else {
            "albedo"
        };
        p.push_str(&slot_properties(slot, r, images, prefix));
    }
    if let Some(r) = &t.metallic_roughness {
        p.push_str(&slot_properties("metallic_roughness", r, images, prefix));
    }
    if let Some(n) = &t.normal {
        p.push_str(&slot_properties("normal", &n.texture, images, prefix));
        let _ = write!(p, "<float name=\"normal_scale\" value=\"{}\"/>", n.scale);
    }
    p
}

/// Whether the plugin, not Mitsuba's `twosided`, must handle the sides of `m`: with a normal
/// texture pointshade turns the mapped normal towards the viewer, `twosided` the interpolated one.
pub fn plugin_handles_sides(m: &Material) -> bool {
    m.textures.normal.is_some()
}

/// The `area` emitter of an emissive material: its radiance is the emissive factor times the
/// emissive texture; `None` for materials that do not emit.
pub fn area_emitter(m: &Material, images: &[TextureImage], prefix: &str) -> Option<String> {
    let BrdfModel::GltfPbr(p) = &m.model else {
        return None;
    };
    if !m.emits() {
        return None;
    }
    let texture = m
        .textures
        .emissive
        .map_or_else(String::new, |r| slot_properties("emissive", &r, images, prefix));
    Some(format!(
        "<emitter type=\"area\"><texture name=\"radiance\" type=\"pointshade_emission\">{}{texture}</texture></emitter>",
        super::xml::rgb("factor", p.emissive)
    ))
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::material::{MaterialTextures, NormalTexture};
    use crate::texture::UvTransform;

    fn reference(image: u32, tex_coord: u8) -> TextureRef {
        TextureRef {
            image,
            tex_coord,
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::MirroredRepeat,
            filter: Filter::Bilinear,
            transform: None,
        }
    }

    fn textured() -> Material {
        let mut m = Material::gltf_pbr("t", [1.0; 3], 1.0, 1.0);
        if let BrdfModel::GltfPbr(p) = &mut m.model {
            p.emissive = [0.5, 1.0, 2.0];
            m.textures = MaterialTextures {
                base_color: Some(reference(0, 0)),
                metallic_roughness: None,
                normal: Some(NormalTexture {
                    texture: TextureRef {
                        transform: Some(UvTransform::new([0.5, 0.0], 0.0, [1.0, 1.0])),
                        ..reference(1, 1)
                    },
                    scale: 0.5,
                }),
                emissive: Some(reference(1, 0)),
                ..MaterialTextures::default()
            };
        }
        m
    }

    fn images() -> Vec<TextureImage> {
        (0..2)
            .map(|k| TextureImage {
                label: format!("image {k}"),
                width: 2 + k,
                height: 1,
                texels: (0..2 + k).map(|i| [i as u8, 10, 20, 255]).collect(),
            })
            .collect()
    }

    #[test]
    fn images_are_written_as_their_decoded_texels() {
        let files = image_files(&images(), "s");
        assert_eq!(files[1].0, "s.image1.rgba");
        assert_eq!(files[1].1, [0, 10, 20, 255, 1, 10, 20, 255, 2, 10, 20, 255]);
    }

    #[test]
    fn a_material_asks_for_the_sets_its_textures_read_and_tangents_for_its_normal_texture() {
        let mut mesh = TriangleMesh {
            uvs: Some(vec![Vec2::ZERO]),
            ..TriangleMesh::default()
        };
        let m = textured();
        assert_eq!(
            vertex_attributes(&m, &mesh),
            VertexAttributes {
                uv: [true, true],
                tangent: false
            },
            "no tangents in the mesh"
        );
        mesh.tangents = Some(vec![glam::Vec4::X]);
        assert!(vertex_attributes(&m, &mesh).tangent);
        let plain = Material::gltf_pbr("plain", [1.0; 3], 0.0, 0.5);
        assert_eq!(vertex_attributes(&plain, &mesh), VertexAttributes::default());
        assert!(plugin_handles_sides(&m) && !plugin_handles_sides(&plain));
    }

    #[test]
    fn texture_slots_and_emission_become_plugin_properties() {
        let m = textured();
        let p = brdf_texture_properties(&m, &images(), "s");
        assert!(p.contains("<string name=\"base_color_file\" value=\"s.image0.rgba\"/><integer name=\"base_color_width\" value=\"2\"/>"), "{p}");
        assert!(p.contains("<string name=\"normal_wrap\" value=\"repeat mirrored-repeat\"/>"));
        assert!(p.contains("<integer name=\"normal_set\" value=\"1\"/>"));
        assert!(p.contains("<float name=\"normal_scale\" value=\"0.5\"/>"));
        assert!(
            p.contains("<string name=\"normal_transform\" value=\"1 0 0.5 -0 1 0\"/>"),
            "{p}"
        );
        assert!(!p.contains("metallic_roughness") && !p.contains("emissive"), "{p}");
        let e = area_emitter(&m, &images(), "s").unwrap();
        assert!(e.starts_with("<emitter type=\"area\"><texture name=\"radiance\" type=\"pointshade_emission\"><rgb name=\"factor\" value=\"0.5, 1, 2\"/>"), "{e}");
        assert!(e.contains("<integer name=\"emissive_width\" value=\"3\"/>"));
        assert!(area_emitter(&Material::gltf_pbr("dark", [1.0; 3], 0.0, 0.5), &images(), "s").is_none());
    }
}
