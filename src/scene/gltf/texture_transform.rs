//! `KHR_texture_transform`: a texture slot's offset, rotation and scale of its texture
//! coordinates (and, optionally, another coordinate set), as a [`UvTransform`].
//!
//! The gltf crate parses the extension on `textureInfo` objects (base colour, metallic-roughness,
//! emissive) but not on the normal texture's, so that one is read from the material's JSON here,
//! with the extension's defaults (offset 0, rotation 0, scale 1).

use ::gltf::json::Value;

use crate::texture::UvTransform;

/// A slot's transform and the coordinate set it names instead of the slot's own, if any.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlotTransform {
    /// The mapping of texture coordinates.
    pub transform: UvTransform,
    /// `texCoord` of the extension, which overrides the slot's.
    pub tex_coord: Option<u32>,
}

/// The transform of a `textureInfo` (base colour, metallic-roughness, emissive), if it has one.
pub fn of_info(info: &::gltf::texture::Info) -> Result<Option<SlotTransform>, String> {
    info.texture_transform()
        .map(|t| checked(t.offset(), t.rotation(), t.scale(), t.tex_coord()))
        .transpose()
}

/// The transform of material `material`'s normal texture, read from the JSON.
pub fn of_normal(doc: &::gltf::Document, material: usize) -> Result<Option<SlotTransform>, String> {
    let Some(normal) = doc
        .as_json()
        .materials
        .get(material)
        .and_then(|m| m.normal_texture.as_ref())
    else {
        return Ok(None);
    };
    let Some(ext) = normal
        .extensions
        .as_ref()
        .and_then(|e| e.others.get("KHR_texture_transform"))
    else {
        return Ok(None);
    };
    let pair = |key: &str, default: [f32; 2]| -> Result<[f32; 2], String> {
        match ext.get(key) {
            None => Ok(default),
            Some(Value::Array(a)) if a.len() == 2 => {
                let value = |v: &Value| {
                    v.as_f64()
                        .map(|x| x as f32)
                        .ok_or(format!("{key} is not a number pair"))
                };
                Ok([value(&a[0])?, value(&a[1])?])
            }
            Some(_) => Err(format!("{key} is not a number pair")),
        }
    };
    let rotation = match ext.get("rotation") {
        None => 0.0,
        Some(v) => v.as_f64().ok_or("rotation is not a number")? as f32,
    };
    let tex_coord = match ext.get("texCoord") {
        None => None,
        Some(v) => Some(
            v.as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or("texCoord is not a set index")?,
        ),
    };
    checked(pair("offset", [0.0; 2])?, rotation, pair("scale", [1.0; 2])?, tex_coord).map(Some)
}

/// The transform, if all its numbers are finite (JSON numbers beyond f32 become infinite).
fn checked(offset: [f32; 2], rotation: f32, scale: [f32; 2], tex_coord: Option<u32>) -> Result<SlotTransform, String> {
    let transform = UvTransform::new(offset, rotation, scale);
    if transform.m.iter().all(|v| v.is_finite()) {
        Ok(SlotTransform { transform, tex_coord })
    } else {
        Err(format!(
            "offset {offset:?}, rotation {rotation} and scale {scale:?} must be finite"
        ))
    }
}
