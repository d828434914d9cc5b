//! Reading a glTF file: the JSON or binary (GLB) container, required extensions, the gltf
//! crate's validation, and the buffers.
//!
//! Every failure is an [`InputError`] on the glTF file whose message says what is wrong and, for
//! external files, which one.

use std::path::{Path, PathBuf};

use glam::{DMat4, DQuat, DVec3, Mat4, Quat, Vec3};

use crate::error::{InputError, InputResult};

/// Extensions pointshade implements (everything else in `extensionsRequired` is an error).
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
];

/// A parsed, validated glTF document with its buffers loaded.
pub struct GltfDocument {
    /// The document (JSON, validated by the gltf crate: indices in range, enums known).
    pub doc: ::gltf::Document,
    /// Buffer contents, indexed like the document's buffers; each at least `byteLength` long.
    pub buffers: Vec<Vec<u8>>,
    /// Directory relative URIs are resolved against.
    pub dir: PathBuf,
    /// The file.
    pub path: PathBuf,
    /// Each node's own transform read in f64 from the JSON text (the gltf crate reads f32):
    /// glTF files in map coordinates put the large offset in a node's translation.
    pub node_transforms: Vec<DMat4>,
}

impl GltfDocument {
    /// An error about this file.
    pub fn error(&self, problem: impl std::fmt::Display) -> InputError {
        InputError::new(&self.path, problem)
    }
}

/// Reads and validates `path` (.gltf or .glb) and loads its buffers.
pub fn read_document(path: &Path) -> InputResult<GltfDocument> {
    let err = |p: String| InputError::new(path, p);
    let bytes = crate::input_files::read(path).map_err(err)?;
    let binary = crate::scene::extension(path).as_deref() == Some("glb") || bytes.starts_with(b"glTF");
    if binary {
        check_glb_header(&bytes).map_err(err)?;
    }
    let gltf = ::gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| err(describe(e)))?;
    let node_transforms = node_transforms(json_text(&bytes, binary));
    let blob = gltf.blob;
    let json = gltf.document.into_json();
    let unsupported: Vec<&str> = json
        .extensions_required
        .iter()
        .map(String::as_str)
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .collect();
    if !unsupported.is_empty() {
        return Err(err(format!(
            "requires glTF extension(s) pointshade does not implement: {}",
            unsupported.join(", ")
        )));
    }
    check_asset_version(&json.asset).map_err(err)?;
    check_position_accessors(&json).map_err(err)?;
    let doc = ::gltf::Document::from_json(json).map_err(|e| err(describe(e)))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let buffers = load_buffers(&doc, &dir, blob).map_err(err)?;
    let node_transforms = if node_transforms.len() == doc.nodes().len() {
        node_transforms
    } else {
        doc.nodes().map(|n| f32_matrix(&n).as_dmat4()).collect()
    };
    Ok(GltfDocument {
        doc,
        buffers,
        dir,
        path: path.to_path_buf(),
        node_transforms,
    })
}

/// `asset.version` (and `asset.minVersion`, if given) of the form 2.MINOR: the glTF 2.0
/// specification asks loaders to refuse an asset of another major version, whose meaning they
/// cannot know.
fn check_asset_version(asset: &::gltf::json::Asset) -> Result<(), String> {
    // The minor version of "2.MINOR", if `v` has that form.
    let minor_of_two = |v: &str| v.strip_prefix("2.").and_then(|m| m.parse::<u32>().ok());
    let shown = |v: &str| v.chars().take(20).collect::<String>();
    let Some(minor) = minor_of_two(&asset.version) else {
        return Err(format!(
            "asset.version is \"{}\": pointshade reads glTF 2.x",
            shown(&asset.version)
        ));
    };
    match &asset.min_version {
        Some(min) if minor_of_two(min).is_none_or(|m| m > minor) => Err(format!(
            "asset.minVersion is \"{}\" (version \"{}\"): pointshade reads glTF 2.x",
            shown(min),
            shown(&asset.version)
        )),
        _ => Ok(()),
    }
}

/// The JSON text of a glTF file: the whole file, or a GLB's first chunk (the header was checked).
fn json_text(bytes: &[u8], binary: bool) -> &[u8] {
    if !binary {
        return bytes;
    }
    let word = |i: usize| {
        bytes
            .get(i..i + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize)
    };
    match word(12) {
        Some(length) => bytes.get(20..20 + length).unwrap_or(&[]),
        None => &[],
    }
}

/// Each node's own transform in f64, from the JSON text; empty when the text does not parse
/// (the gltf crate has then already said why, or its f32 transforms are used).
fn node_transforms(json: &[u8]) -> Vec<DMat4> {
    let Ok(root) = serde_json::from_slice::<serde_json::Value>(json) else {
        return Vec::new();
    };
    let numbers = |v: Option<&serde_json::Value>, n: usize| -> Option<Vec<f64>> {
        let a = v?.as_array()?;
        (a.len() == n).then(|| a.iter().map(|x| x.as_f64()).collect::<Option<Vec<f64>>>())?
    };
    let Some(nodes) = root.get("nodes").and_then(|n| n.as_array()) else {
        return Vec::new();
    };
    nodes
        .iter()
        .map(|node| {
            if let Some(m) = numbers(node.get("matrix"), 16) {
                return DMat4::from_cols_slice(&m);
            }
            let t = numbers(node.get("translation"), 3).map_or(DVec3::ZERO, |v| DVec3::from_slice(&v));
            let r = numbers(node.get("rotation"), 4).map_or(DQuat::IDENTITY, |q| DQuat::from_slice(&q).normalize());
            let s = numbers(node.get("scale"), 3).map_or(DVec3::ONE, |v| DVec3::from_slice(&v));
            DMat4::from_scale_rotation_translation(s, r, t)
        })
        .collect()
}

/// The node's own transform as the gltf crate reads it (f32).
pub fn f32_matrix(node: &::gltf::Node) -> Mat4 {
    match node.transform() {
        ::gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        ::gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => Mat4::from_scale_rotation_translation(
            Vec3::from(scale),
            Quat::from_array(rotation).normalize(),
            Vec3::from(translation),
        ),
    }
}

/// Every primitive's POSITION names an existing accessor. The gltf crate's validation (1.4.1)
/// looks that accessor up before checking the index and panics on one out of range, so the
/// check comes first.
fn check_position_accessors(json: &::gltf::json::Root) -> Result<(), String> {
    use ::gltf::json::validation::Checked;
    let count = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(::gltf::json::mesh::Semantic::Positions));
            if let Some(index) = position.filter(|i| i.value() >= count) {
                return Err(format!(
                    "invalid glTF: meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does not exist (the file has {count})",
                    index.value()
                ));
            }
        }
    }
    Ok(())
}

/// The 12-byte GLB header: magic "glTF", version 2, total length = the file's length.
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if bytes.len() < 12 {
        return Err(format!(
            "truncated binary glTF: {} bytes, shorter than the 12-byte header",
            bytes.len()
        ));
    }
    if &bytes[0..4] != b"glTF" {
        return Err(format!(
            "not a binary glTF file: it starts with {:?}, not the magic \"glTF\"",
            String::from_utf8_lossy(&bytes[0..4])
        ));
    }
    let word = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    let (version, length) = (word(4), word(8) as usize);
    if version != 2 {
        return Err(format!("binary glTF version {version} is not supported (only 2)"));
    }
    if length > bytes.len() {
        return Err(format!(
            "truncated binary glTF: the header announces {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    if length < 12 + 8 {
        return Err(format!(
            "malformed binary glTF: length {length} leaves no room for a JSON chunk"
        ));
    }
    Ok(())
}

/// The gltf crate's error in words for the user.
fn describe(e: ::gltf::Error) -> String {
    use ::gltf::binary::Error as Glb;
    match e {
        ::gltf::Error::Binary(Glb::ChunkLength {
            ty,
            length,
            length_read,
        }) => format!("truncated binary glTF: the {ty:?} chunk announces {length} bytes, only {length_read} follow"),
        ::gltf::Error::Binary(b) => format!("malformed binary glTF: {b}"),
        ::gltf::Error::Deserialize(d) => format!("invalid glTF JSON: {d}"),
        ::gltf::Error::Validation(list) => {
            let shown: Vec<String> = list.iter().take(3).map(|(path, e)| format!("{path}: {e}")).collect();
            let more = if list.len() > 3 {
                format!(" (and {} more)", list.len() - 3)
            } else {
                String::new()
            };
            format!("invalid glTF: {}{more}", shown.join("; "))
        }
        other => other.to_string(),
    }
}

fn load_buffers(doc: &::gltf::Document, dir: &Path, mut blob: Option<Vec<u8>>) -> Result<Vec<Vec<u8>>, String> {
    let mut buffers = Vec::new();
    for buffer in doc.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            ::gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| format!("buffer {i} refers to the GLB binary chunk, which is missing"))?,
            ::gltf::buffer::Source::Uri(uri) => {
                crate::scene::uri::read_uri(dir, uri).map_err(|e| format!("buffer {i}: {e}"))?
            }
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "buffer {i} has {} bytes, fewer than its byteLength {}",
                data.len(),
                buffer.length()
            ));
        }
        buffers.push(data);
    }
    Ok(buffers)
}
