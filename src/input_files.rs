//! Reading the files a command is given or a scene refers to: regular files only, of bounded
//! size, each read recorded while a front end asks for it.
//!
//! Every loader (scene files, OBJ and MTL, glTF and its URIs, textures, normal images, EXR
//! inputs) reads through [`read`], so that:
//! - a FIFO, a device (`/dev/zero`, `/dev/urandom`) or a directory is refused before it is
//!   opened (opening a FIFO blocks until a writer comes; a device reads until memory runs out);
//! - no file larger than [`MAX_INPUT_BYTES`] is read;
//! - a command can refuse to write its output over one of the files it read
//!   ([`record_reads`], [`crate::output::refuse_overwriting_inputs`]);
//! - a front end can confine every read to one folder ([`Confinement`]: `--confine DIR`, and
//!   `confine=` in Python), for files it did not write itself: a glTF rendered on a server must
//!   not read `/etc/passwd` through an image URI, a `../` or a link.

use std::any::Any;
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError, RwLock};

/// The largest input file read: 4 GiB, above any mesh, image or EXR the renderer can hold
/// within the film and pixel limits, and below what a 2-core machine's memory takes.
pub const MAX_INPUT_BYTES: u64 = 4 << 30;

/// The files read since [`record_reads`], when it was called.
static READS: Mutex<Option<Vec<PathBuf>>> = Mutex::new(None);

/// The canonical folder every [`read`] must lie in, while a [`Confinement`] runs.
static CONFINED_TO: RwLock<Option<PathBuf>> = RwLock::new(None);

/// Held while a [`Confinement`] runs: one at a time in the process.
static CONFINEMENT_RUNNING: Mutex<()> = Mutex::new(());

/// This module's locks, taken in the order [`Confinement::run`] nests them (its turn, then the
/// folder; the recorded reads are taken alone), each with its static's name, for the fork
/// handlers of `process_fork`.
pub(crate) fn locks_for_fork() -> [(&'static str, Box<dyn Any>); 3] {
    [
        (
            "CONFINEMENT_RUNNING",
            Box::new(CONFINEMENT_RUNNING.lock().unwrap_or_else(PoisonError::into_inner)),
        ),
        (
            "CONFINED_TO",
            Box::new(CONFINED_TO.write().unwrap_or_else(PoisonError::into_inner)),
        ),
        ("READS", Box::new(READS.lock().unwrap_or_else(PoisonError::into_inner))),
    ]
}

/// Where the reads of an operation may go: anywhere, or inside one folder.
///
/// A file is read under a confinement only if its path, with every link and `..` resolved,
/// lies inside the folder's (also resolved). The setting is process-wide while
/// [`Confinement::run`] runs — so that the worker threads a load spreads its reads over obey it
/// without being told — and runs take turns: an unconfined operation that runs while a
/// confined one does would otherwise be refused, and a confined one would leak through one that
/// is not. Front ends therefore run every operation that reads files through `run`, confined or
/// not; loads take milliseconds to seconds, so the turns cost little.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Confinement {
    root: Option<PathBuf>,
}

impl Confinement {
    /// No confinement: reads go wherever paths lead.
    pub const NONE: Confinement = Confinement { root: None };

    /// Reads confined to the folder `dir`, which must exist; the message is the problem alone.
    pub fn to(dir: &Path) -> Result<Confinement, String> {
        let root = std::fs::canonicalize(dir).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => "folder not found".to_string(),
            _ => format!("cannot resolve: {e}"),
        })?;
        if !root.is_dir() {
            return Err("not a folder".into());
        }
        Ok(Confinement { root: Some(root) })
    }

    /// `Some(dir)` confines to `dir`, `None` does not.
    pub fn to_optional(dir: Option<&Path>) -> Result<Confinement, String> {
        dir.map_or(Ok(Confinement::NONE), Confinement::to)
    }

    /// The canonical folder reads are confined to, if any.
    pub fn root(&self) -> Option<&Path> {
        self.root.as_deref()
    }

    /// Runs `f` with every [`read`] in the process under this confinement (after any other
    /// confinement's run has ended).
    pub fn run<T>(&self, f: impl FnOnce() -> T) -> T {
        let _turn = CONFINEMENT_RUNNING.lock().unwrap_or_else(|p| p.into_inner());
        struct Reset;
        impl Drop for Reset {
            fn drop(&mut self) {
                *CONFINED_TO.write().unwrap_or_else(|p| p.into_inner()) = None;
            }
        }
        *CONFINED_TO.write().unwrap_or_else(|p| p.into_inner()) = self.root.clone();
        let _reset = Reset;
        f()
    }
}

/// `path` as it may be read under the current confinement: unchanged when there is none, else
/// resolved (links, `..`) and inside the confinement's folder, or why not. A missing file
/// inside the folder is returned as given, for [`check`] to report; one outside is refused
/// without saying whether it exists.
fn confined_path(path: &Path) -> Result<Cow<'_, Path>, String> {
    let root = CONFINED_TO.read().unwrap_or_else(|p| p.into_inner()).clone();
    let Some(root) = root else {
        return Ok(Cow::Borrowed(path));
    };
    let outside = || format!("lies outside {}, the folder reads are confined to", root.display());
    match std::fs::canonicalize(path) {
        Ok(resolved) if resolved.starts_with(&root) => Ok(Cow::Owned(resolved)),
        Ok(_) => Err(outside()),
        Err(_) => {
            let parent = path
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            match std::fs::canonicalize(parent) {
                Ok(p) if p.starts_with(&root) => Ok(Cow::Borrowed(path)),
                _ => Err(outside()),
            }
        }
    }
}

/// Whether the current [`Confinement`] lets `path` be read; the message is the problem alone.
pub fn check_confinement(path: &Path) -> Result<(), String> {
    confined_path(path).map(|_| ())
}

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

/// Why `path` may not be read, if it may not: it is outside the current [`Confinement`],
/// missing, not a regular file, or too large. The message is the problem alone (callers name
/// the file).
pub fn check(path: &Path) -> Result<(), String> {
    check_resolved(&confined_path(path)?)
}

/// [`check`] for a path [`confined_path`] has already let through.
fn check_resolved(path: &Path) -> Result<(), String> {
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
    let original = path;
    let path = confined_path(original)?;
    check_resolved(&path)?;
    let file = std::fs::File::open(&path).map_err(|e| format!("cannot read: {e}"))?;
    let mut bytes = Vec::new();
    // One byte past the limit tells a file that grew after the check.
    file.take(MAX_INPUT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(format!("cannot read: more than {MAX_INPUT_BYTES} bytes"));
    }
    if let Some(reads) = READS.lock().unwrap_or_else(|p| p.into_inner()).as_mut() {
        reads.push(original.to_path_buf());
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
