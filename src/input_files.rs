//! Reading the files a command is given or a scene refers to: regular files only, of bounded
//! size, each read recorded while a front end asks for it.
//!
//! Every loader (scene files, OBJ and MTL, glTF and its URIs, textures, normal images, EXR
//! inputs) reads through [`read`], so that:
//! - a FIFO, a device (`/dev/zero`, `/dev/urandom`) or a directory is refused before it is
//!   opened (opening a FIFO blocks until a writer comes; a device reads until memory runs out);
//! - no file larger than [`MAX_INPUT_BYTES`] is read;
//! - a command can refuse to write its output over one of the files it read
//!   ([`record_reads`], [`crate::output::refuse_overwriting_inputs`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The largest input file read: 4 GiB, above any mesh, image or EXR the renderer can hold
/// within the film and pixel limits, and below what a 2-core machine's memory takes.
pub const MAX_INPUT_BYTES: u64 = 4 << 30;

/// The files read since [`record_reads`], when it was called.
static READS: Mutex<Option<Vec<PathBuf>>> = Mutex::new(None);

/// From now on, records every file [`read`] reads (the command line calls it; the Python module
/// does not, since its calls run in parallel threads).
pub fn record_reads() {
    *READS.lock().unwrap_or_else(|p| p.into_inner()) = Some(Vec::new());
}

/// The files read since [`record_reads`] (empty if it was not called).
pub fn reads() -> Vec<PathBuf> {
    READS
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .clone()
        .unwrap_or_default()
}

/// Why `path` may not be read, if it may not: it is missing, not a regular file, or too large.
/// The message is the problem alone (callers name the file).
pub fn check(path: &Path) -> Result<(), String> {
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => "file not found".to_string(),
        _ => format!("cannot read: {e}"),
    })?;
    if !meta.is_file() {
        return Err(format!("cannot read: it is {}, not a regular file", kind_of(&meta)));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(format!(
            "cannot read: {} bytes is more than an input may have ({MAX_INPUT_BYTES})",
            meta.len()
        ));
    }
    Ok(())
}

/// Reads `path` whole after [`check`]ing it; the message is the problem alone.
pub fn read(path: &Path) -> Result<Vec<u8>, String> {
    use std::io::Read;
    check(path)?;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    let mut bytes = Vec::new();
    // One byte past the limit tells a file that grew after the check.
    file.take(MAX_INPUT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(format!("cannot read: more than {MAX_INPUT_BYTES} bytes"));
    }
    if let Some(reads) = READS.lock().unwrap_or_else(|p| p.into_inner()).as_mut() {
        reads.push(path.to_path_buf());
    }
    Ok(bytes)
}

/// [`read`] as UTF-8 text.
pub fn read_to_string(path: &Path) -> Result<String, String> {
    String::from_utf8(read(path)?).map_err(|e| format!("not UTF-8 text: {e}"))
}

/// What a file that is not a regular file is, for messages.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "something else"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_fifos_are_refused_before_they_are_opened() {
        assert_eq!(
            read(Path::new("/dev/zero")).unwrap_err(),
            "cannot read: it is a device, not a regular file"
        );
        assert!(read(Path::new("/dev/urandom")).unwrap_err().contains("a device"));
        assert!(read(Path::new("/tmp")).unwrap_err().contains("a directory"));
        assert_eq!(read(Path::new("/no/such/file")).unwrap_err(), "file not found");
        let fifo = std::env::temp_dir().join(format!("pointshade-fifo-{}", std::process::id()));
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        // Opening it would block forever: the check must come first.
        assert!(read(&fifo).unwrap_err().contains("a FIFO"));
        std::fs::remove_file(&fifo).unwrap();
    }
}
