//! Reading a glTF file: the JSON or binary (GLB) container, required extensions, the gltf
//! crate's validation, and the buffers.
//!
//! Every failure is an [`InputError`] on the glTF file whose message says what is wrong and, for
//! external files, which one.

use std::path::{Path, PathBuf};

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
    if !path.is_file() {
        return Err(err("file not found".into()));
    }
    let bytes = std::fs::read(path).map_err(|e| err(format!("cannot read: {e}")))?;
    let binary = crate::scene::extension(path).as_deref() == Some("glb") || bytes.starts_with(b"glTF");
    if binary {
        check_glb_header(&bytes).map_err(err)?;
    }
    let gltf = ::gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| err(describe(e)))?;
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
    check_position_accessors(&json).map_err(err)?;
    let doc = ::gltf::Document::from_json(json).map_err(|e| err(describe(e)))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let buffers = load_buffers(&doc, &dir, blob).map_err(err)?;
    Ok(GltfDocument {
        doc,
        buffers,
        dir,
        path: path.to_path_buf(),
    })
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

/// Reads a URI (relative file or `data:`) the way the gltf crate's importer does; errors name
/// the URI (file URIs: the file).
pub fn read_uri(dir: &Path, uri: &str) -> Result<Vec<u8>, String> {
    ::gltf::buffer::Data::from_source(::gltf::buffer::Source::Uri(uri), Some(dir))
        .map(|d| d.0)
        .map_err(|e| {
            let shown = if uri.starts_with("data:") {
                "an embedded data: URI".to_string()
            } else {
                format!("'{}'", dir.join(uri).display())
            };
            format!("cannot read {shown}: {e}")
        })
}

fn load_buffers(doc: &::gltf::Document, dir: &Path, mut blob: Option<Vec<u8>>) -> Result<Vec<Vec<u8>>, String> {
    let mut buffers = Vec::new();
    for buffer in doc.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            ::gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| format!("buffer {i} refers to the GLB binary chunk, which is missing"))?,
            ::gltf::buffer::Source::Uri(uri) => read_uri(dir, uri).map_err(|e| format!("buffer {i}: {e}"))?,
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
