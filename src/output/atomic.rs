//! Writing a command's files all or nothing.
//!
//! Each file is written to a temporary `.NAME.PID.tmp` beside its destination. Only when every
//! one is written are they renamed into place; a destination that already exists is first moved
//! aside to `.NAME.PID.old`, so that when a later rename fails the earlier ones are undone and
//! the old files come back. A destination that is a directory, or one of the command's own
//! inputs, is refused before anything is written.
//!
//! Temporaries of a process that died (kill -9) are removed by the next write of the same
//! destination (their PID names no running process); a front end that catches SIGINT/SIGTERM
//! calls [`remove_pending`] to remove those of the running process before it exits.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{InputError, InputResult};

/// Temporaries (and moved-aside old files, with their destinations) of the writes in progress.
static PENDING: Mutex<Vec<Pending>> = Mutex::new(Vec::new());

enum Pending {
    /// A temporary file to remove.
    Temporary(PathBuf),
    /// An old destination moved aside: put back at `.1` if the process stops.
    MovedAside(PathBuf, PathBuf),
}

fn pending() -> std::sync::MutexGuard<'static, Vec<Pending>> {
    PENDING.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// [`PENDING`]'s lock and name, for the fork handlers of `process_fork` (taken alone: no other
/// lock is taken while it is held).
pub(crate) fn lock_for_fork() -> (&'static str, Box<dyn std::any::Any>) {
    ("PENDING", Box::new(pending()))
}

/// Removes the temporaries of the writes in progress and puts moved-aside files back: what a
/// signal handler does before the process exits, so that a stopped write leaves the old files
/// and nothing else.
pub fn remove_pending() {
    for entry in pending().drain(..) {
        match entry {
            Pending::Temporary(tmp) => {
                let _ = std::fs::remove_file(tmp);
            }
            Pending::MovedAside(old, destination) => {
                let _ = std::fs::rename(old, destination);
            }
        }
    }
}

/// Refuses any of `outputs` that is one of `inputs` (the same file after resolving links and
/// `..`): writing it would destroy what the command read.
pub fn refuse_overwriting_inputs(outputs: &[&Path], inputs: &[&Path]) -> InputResult<()> {
    let inputs: Vec<PathBuf> = inputs.iter().filter_map(|p| p.canonicalize().ok()).collect();
    for output in outputs {
        if let Some(resolved) = resolved_output(output) {
            if inputs.contains(&resolved) {
                return Err(InputError::new(
                    output,
                    "is also an input of this command: choose another output path",
                ));
            }
        }
    }
    Ok(())
}

/// `path` resolved as [`Path::canonicalize`] does, also when the file does not exist yet (then
/// its folder is resolved).
fn resolved_output(path: &Path) -> Option<PathBuf> {
    if let Ok(resolved) = path.canonicalize() {
        return Some(resolved);
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    Some(folder.canonicalize().ok()?.join(path.file_name()?))
}

/// Writes every `(path, bytes)` or none (see the module's documentation).
pub fn write_all_or_nothing(files: &[(PathBuf, Vec<u8>)]) -> InputResult<()> {
    let inputs = crate::input_files::reads();
    let outputs: Vec<&Path> = files.iter().map(|(path, _)| path.as_path()).collect();
    refuse_overwriting_inputs(&outputs, &inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>())?;
    for (i, (path, _)) in files.iter().enumerate() {
        if path.is_dir() {
            return Err(InputError::new(path, "cannot write: it is a directory"));
        }
        if files[..i].iter().any(|(earlier, _)| earlier == path) {
            return Err(InputError::new(path, "is written twice by this command"));
        }
        remove_stale_temporaries(path);
    }
    let mut temporaries: Vec<PathBuf> = Vec::new();
    let discard = |temporaries: &[PathBuf]| {
        for tmp in temporaries {
            let _ = std::fs::remove_file(tmp);
        }
        forget(temporaries);
    };
    for (path, bytes) in files {
        let tmp = sibling(path, "tmp");
        pending().push(Pending::Temporary(tmp.clone()));
        temporaries.push(tmp.clone());
        if let Err(e) = std::fs::write(&tmp, bytes) {
            discard(&temporaries);
            return Err(InputError::new(path, format!("cannot write: {e}")));
        }
    }
    // Move the existing destinations aside, then the new files in; undo all on a failure.
    let mut aside: Vec<(PathBuf, PathBuf)> = Vec::new();
    let mut placed: Vec<&Path> = Vec::new();
    let undo = |placed: &[&Path], aside: &[(PathBuf, PathBuf)]| {
        for path in placed {
            let _ = std::fs::remove_file(path);
        }
        for (old, destination) in aside {
            let _ = std::fs::rename(old, destination);
        }
    };
    let mut failure = None;
    for (path, _) in files {
        if std::fs::symlink_metadata(path).is_ok() {
            let old = sibling(path, "old");
            if let Err(e) = std::fs::rename(path, &old) {
                failure = Some(InputError::new(path, format!("cannot replace: {e}")));
                break;
            }
            pending().push(Pending::MovedAside(old.clone(), path.clone()));
            aside.push((old, path.clone()));
        }
    }
    if failure.is_none() {
        for ((path, _), tmp) in files.iter().zip(&temporaries) {
            if let Err(e) = std::fs::rename(tmp, path) {
                failure = Some(InputError::new(path, format!("cannot write: {e}")));
                break;
            }
            placed.push(path);
        }
    }
    if let Some(error) = failure {
        undo(&placed, &aside);
        discard(&temporaries);
        forget(&aside.iter().map(|(old, _)| old.clone()).collect::<Vec<_>>());
        return Err(error);
    }
    for (old, _) in &aside {
        let _ = std::fs::remove_file(old);
    }
    forget(&temporaries);
    forget(&aside.iter().map(|(old, _)| old.clone()).collect::<Vec<_>>());
    Ok(())
}

/// Drops `files` (temporaries or moved-aside files) from [`PENDING`]: other threads' writes
/// stay registered.
fn forget(files: &[PathBuf]) {
    pending().retain(|p| match p {
        Pending::Temporary(t) | Pending::MovedAside(t, _) => !files.contains(t),
    });
}

/// `.NAME.PID.EXT` beside `path`.
fn sibling(path: &Path, extension: &str) -> PathBuf {
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.{extension}", std::process::id()))
}

/// Removes `.NAME.PID.tmp` and `.NAME.PID.old` files of `path` left by processes that no
/// longer run (Linux: no `/proc/PID`). An `.old` file of a dead process is the destination it
/// had moved aside: put back when the destination is missing, otherwise removed.
fn remove_stale_temporaries(path: &Path) {
    let Some(name) = path.file_name().map(|s| s.to_string_lossy().into_owned()) else {
        return;
    };
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !Path::new("/proc/self").exists() {
        return; // no way to tell a running process from a dead one
    }
    let Ok(entries) = std::fs::read_dir(folder) else { return };
    let prefix = format!(".{name}.");
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&prefix) else {
            continue;
        };
        let Some((pid, extension)) = rest.split_once('.') else {
            continue;
        };
        if !(extension == "tmp" || extension == "old") || pid.parse::<u32>().is_err() {
            continue;
        }
        if Path::new("/proc").join(pid).exists() {
            continue;
        }
        let stale = entry.path();
        if extension == "old" && std::fs::symlink_metadata(path).is_err() {
            let _ = std::fs::rename(&stale, path);
        } else {
            let _ = std::fs::remove_file(&stale);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("pointshade-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn failed_write_leaves_no_file() {
        let dir = scratch("missing");
        let good = dir.join("a.png");
        let bad = dir.join("missing-dir").join("b.png");
        let r = write_all_or_nothing(&[(good.clone(), vec![1, 2, 3]), (bad, vec![4])]);
        assert!(r.is_err());
        assert!(!good.exists(), "first file must not appear when the second fails");
        assert!(listing(&dir).is_empty(), "no temporary left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_directory_among_the_destinations_replaces_nothing() {
        // `-o o.exr --aov normal,depth` with o.depth.exr a directory replaced o.exr and
        // o.normal.exr before failing on the third.
        let dir = scratch("directory");
        let (a, b, c) = (dir.join("o.exr"), dir.join("o.normal.exr"), dir.join("o.depth.exr"));
        std::fs::write(&a, b"old a").unwrap();
        std::fs::write(&b, b"old b").unwrap();
        std::fs::create_dir(&c).unwrap();
        let r = write_all_or_nothing(&[(a.clone(), b"new".to_vec()), (b.clone(), b"new".to_vec()), (c, vec![])]);
        assert!(r
            .unwrap_err()
            .to_string()
            .contains("o.depth.exr: cannot write: it is a directory"));
        assert_eq!(std::fs::read(&a).unwrap(), b"old a");
        assert_eq!(std::fs::read(&b).unwrap(), b"old b");
        assert_eq!(listing(&dir), ["o.depth.exr", "o.exr", "o.normal.exr"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn temporaries_of_dead_processes_are_removed_and_live_ones_kept() {
        let dir = scratch("stale");
        let out = dir.join("big.exr");
        // PID 2^22 + 1 is above Linux's largest (pid_max ≤ 2^22): no process has it.
        let dead = dir.join(format!(".big.exr.{}.tmp", (1u32 << 22) + 1));
        let live = dir.join(".big.exr.1.tmp"); // PID 1 always runs
        let other = dir.join(".other.exr.99999999.tmp");
        for f in [&dead, &live, &other] {
            std::fs::write(f, b"x").unwrap();
        }
        write_all_or_nothing(&[(out.clone(), b"frame".to_vec())]).unwrap();
        assert_eq!(listing(&dir), [".big.exr.1.tmp", ".other.exr.99999999.tmp", "big.exr"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_output_that_is_an_input_is_refused() {
        let dir = scratch("inputs");
        let input = dir.join("n.png");
        std::fs::write(&input, b"png").unwrap();
        let same = dir.join(".").join("n.png");
        let r = refuse_overwriting_inputs(&[&same], &[&input]);
        assert!(r.unwrap_err().to_string().contains("is also an input"));
        assert!(refuse_overwriting_inputs(&[&dir.join("out.png")], &[&input]).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
