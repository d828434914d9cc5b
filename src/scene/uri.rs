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
    let mut bytes = match uri_file(dir, uri)? {
        None => data_uri_bytes(uri).map_err(|e| format!("cannot read an embedded data: URI: {e}"))?,
        Some(path) => crate::input_files::read(&path).map_err(|e| format!("'{}': {e}", path.display()))?,
    };
    bytes.resize(bytes.len().next_multiple_of(4), 0);
    Ok(bytes)
}

/// The bytes of a `data:[MEDIA TYPE];base64,DATA` URI (RFC 2397), the form glTF embeds buffers
/// and images in. DATA is base64 in the standard alphabet (RFC 4648, section 4), padded with `=`
/// or not; anything else in it is an error naming the first offending character.
fn data_uri_bytes(uri: &str) -> Result<Vec<u8>, String> {
    let Some((_, data)) = uri.split_once(";base64,") else {
        return Err("only base64 data URIs (data:...;base64,...) are supported".into());
    };
    let digits = data.trim_end_matches('=');
    if data.len() - digits.len() > 2 || digits.len() % 4 == 1 {
        return Err(format!(
            "its base64 data has an impossible length ({} characters)",
            data.len()
        ));
    }
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let mut out = Vec::with_capacity(digits.len() / 4 * 3 + 2);
    // Six bits per character, most significant first; a byte is out once eight have gathered.
    let (mut bits, mut count) = (0u32, 0u32);
    for (i, c) in digits.bytes().enumerate() {
        let v = value(c).ok_or_else(|| {
            let shown = digits[i..].chars().next().unwrap_or('?');
            format!("its base64 data has '{shown}' at character {i}")
        })?;
        bits = (bits << 6) | u32::from(v);
        count += 6;
        if count >= 8 {
            count -= 8;
            out.push((bits >> count) as u8);
            bits &= (1 << count) - 1;
        }
    }
    Ok(out)
}

/// `bytes` as a `data:MEDIA_TYPE;base64,DATA` URI, DATA in standard padded base64 (RFC 4648,
/// section 4): the form [`read_uri`] decodes (the explorer sends images in it).
pub fn data_uri(media_type: &str, bytes: &[u8]) -> String {
    const DIGITS: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = format!("data:{media_type};base64,");
    out.reserve(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(DIGITS[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
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

    #[test]
    fn data_uris_encode_as_base64_and_decode_back() {
        // RFC 4648, section 10's test vectors.
        for (input, encoded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            let uri = data_uri("text/plain", input.as_bytes());
            assert_eq!(uri, format!("data:text/plain;base64,{encoded}"), "{input}");
            assert_eq!(data_uri_bytes(&uri).unwrap(), input.as_bytes());
        }
        assert_eq!(data_uri("image/png", &[0xff, 0xfe, 0xfd]), "data:image/png;base64,//79");
        let all: Vec<u8> = (0..=255).collect();
        assert_eq!(data_uri_bytes(&data_uri("", &all)).unwrap(), all);
    }

    #[test]
    fn data_uris_decode_as_base64() {
        let bytes = |uri: &str| data_uri_bytes(uri);
        // RFC 4648, section 10's test vectors, padded and not.
        for (encoded, decoded) in [
            ("", ""),
            ("Zg==", "f"),
            ("Zm8=", "fo"),
            ("Zm9v", "foo"),
            ("Zm9vYg==", "foob"),
            ("Zm9vYmE=", "fooba"),
            ("Zm9vYmFy", "foobar"),
            ("Zm9vYg", "foob"),
        ] {
            let uri = format!("data:application/octet-stream;base64,{encoded}");
            assert_eq!(bytes(&uri).unwrap(), decoded.as_bytes(), "{encoded}");
        }
        // All 64 digits, and the bytes they stand for.
        let all = "data:;base64,ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let decoded = bytes(all).unwrap();
        assert_eq!(decoded.len(), 48);
        assert_eq!(&decoded[..3], &[0x00, 0x10, 0x83]);
        assert_eq!(&decoded[45..], &[0xf3, 0xdf, 0xbf]);
        assert!(bytes("data:;base64,Zm9v!A==")
            .unwrap_err()
            .contains("'!' at character 4"));
        assert!(bytes("data:;base64,Zm9vY").unwrap_err().contains("impossible length"));
        assert!(bytes("data:;base64,Zg===").unwrap_err().contains("impossible length"));
        assert!(bytes("data:text/plain,hello").unwrap_err().contains("only base64"));
        // read_uri pads buffers to four bytes, as files are padded.
        let padded = read_uri(Path::new("."), "data:;base64,Zm9vYmE=").unwrap();
        assert_eq!(padded, b"fooba\0\0\0");
    }
}
