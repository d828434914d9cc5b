//! Reading a glTF URI: a file relative to the glTF file (percent-encoded), a `file:` URI, or
//! embedded `data:`.

use std::path::{Path, PathBuf};

/// The file a glTF URI names, resolved as the gltf crate's importer resolves it: `file://PATH`
/// and `file:PATH` are PATH; anything else without a `:` is relative to `dir`, percent-decoded.
/// `None` for `data:` URIs; an error for other schemes.
pub fn uri_file(dir: &Path, uri: &str) -> Result<Option<PathBuf>, String> {
    if uri.starts_with("data:") {
        return Ok(None);
    }
    if let Some(path) = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")) {
        return Ok(Some(PathBuf::from(path)));
    }
    if uri.contains(':') {
        let scheme = uri.split(':').next().unwrap_or_default();
        return Err(format!(
            "unsupported URI scheme '{}'",
            scheme.chars().take(16).collect::<String>()
        ));
    }
    Ok(Some(dir.join(percent_decoded(uri))))
}

/// Reads a URI (relative file, `file:` or `data:`), files through [`crate::input_files::read`];
/// errors name the URI (file URIs: the file). Buffers come back padded with zeros to a multiple
/// of four bytes, as the gltf crate pads them.
pub fn read_uri(dir: &Path, uri: &str) -> Result<Vec<u8>, String> {
    match uri_file(dir, uri)? {
        None => ::gltf::buffer::Data::from_source(::gltf::buffer::Source::Uri(uri), Some(dir))
            .map(|d| d.0)
            .map_err(|e| format!("cannot read an embedded data: URI: {e}")),
        Some(path) => {
            let mut bytes = crate::input_files::read(&path).map_err(|e| format!("'{}': {e}", path.display()))?;
            bytes.resize(bytes.len().next_multiple_of(4), 0);
            Ok(bytes)
        }
    }
}

/// `text` with each `%XX` replaced by the byte it encodes (invalid escapes stay as they are).
fn percent_decoded(text: &str) -> PathBuf {
    use std::os::unix::ffi::OsStringExt;
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    PathBuf::from(std::ffi::OsString::from_vec(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_resolve_as_the_importer_resolves_them() {
        let dir = Path::new("/scenes/helmet");
        let file = |uri| uri_file(dir, uri).unwrap().unwrap();
        assert_eq!(file("tex/a%20b.png"), PathBuf::from("/scenes/helmet/tex/a b.png"));
        assert_eq!(file("%2e%2e/x.bin"), PathBuf::from("/scenes/helmet/../x.bin"));
        assert_eq!(file("file:///etc/passwd"), PathBuf::from("/etc/passwd"));
        assert_eq!(file("100%"), PathBuf::from("/scenes/helmet/100%"));
        assert_eq!(
            uri_file(dir, "data:application/octet-stream;base64,AAAA").unwrap(),
            None
        );
        assert!(uri_file(dir, "https://example.invalid/a.bin")
            .unwrap_err()
            .contains("'https'"));
    }
}
