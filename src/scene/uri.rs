//! Reading a glTF URI: a file relative to the glTF file, or embedded `data:`.

use std::path::Path;

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
