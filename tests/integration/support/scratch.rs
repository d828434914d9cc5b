//! Scratch folders: each test writes its files into a folder of its own, which goes away when the
//! test is done (passed or failed), so tests running in parallel never see each other's files.

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh, empty folder `pointshade-<process id>-<n>-<name>` in the system's temporary folder,
/// removed with everything in it on drop. `n` counts the folders made in this process, so two
/// tests (or two calls of one helper) that pass the same name still get different folders.
///
/// It dereferences to the folder's path, so `scratch.join(…)` and `&scratch` as a `&Path` work.
pub struct Scratch {
    dir: PathBuf,
}

impl Scratch {
    /// Makes the folder; `name` says what it is for (it shows in the path when a test fails).
    pub fn new(name: &str) -> Self {
        static MADE: AtomicUsize = AtomicUsize::new(0);
        let n = MADE.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("pointshade-{}-{n}-{name}", std::process::id()));
        // A folder of a killed earlier process that had the same id.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        Scratch { dir }
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// `name` in the folder (not created).
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Writes `text` to `name` in the folder; returns its path.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.path(name);
        std::fs::write(&path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        path
    }
}

impl Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.dir
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.dir
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
