//! Forks of a process that runs pointshade on several threads (Python's `multiprocessing`
//! with the `fork` start method, `os.fork`). The child gets a copy of every lock as it was at
//! the fork, but only the forking thread: a lock another thread held at that instant is held by
//! no thread in the child, and the child's first call that takes it waits for ever.
//!
//! [`prepare_for_forks`] makes a process safe to fork between calls. It registers handlers with
//! POSIX `pthread_atfork` that take the library's process-wide locks just before a fork, in the
//! order the library nests them (so that the handler cannot deadlock against a call in
//! progress), and release them just after it in the parent and in the child. The fork waits
//! for other threads' critical sections to end (the longest, a load under a confinement, lasts
//! as long as the load), and the child starts with every lock free. The locks, in that order:
//! - `input_files`: the confinement's turn, its folder and the recorded reads;
//! - `output::atomic`: the pending files of all-or-nothing writes;
//! - `render::workers`: the idle thread pools.
//!
//! A thread that forks while it holds one of these locks would wait for itself. The library never
//! does: it forks nowhere, and the front ends fork (or let Python fork) only between calls.
//!
//! Values a call makes once per process (`OnceLock`s) are the same hazard: a fork while another
//! thread makes one leaves the child's copy being made for ever. The ones the Python module's
//! calls read are made when the handlers are registered instead.

use std::any::Any;
use std::cell::RefCell;
use std::sync::Once;

use crate::input_files;
use crate::output::atomic;
use crate::render::workers;

thread_local! {
    /// The guards the forking thread holds from the prepare handler to the parent's or the
    /// child's, with their statics' names: the same thread runs all three, and the child's copy
    /// of this thread-local holds the child's copies of the guards.
    static HELD: RefCell<Vec<(&'static str, Box<dyn Any>)>> = const { RefCell::new(Vec::new()) };
}

/// Makes this process safe to fork between calls, once per process (a forked child inherits
/// what it sets up): registers the fork handlers that keep the library's locks free in the
/// child, and makes the once-made values a call would otherwise make. The Python module calls
/// it when it is imported; a program that never forks need not.
pub fn prepare_for_forks() {
    static REGISTERED: Once = Once::new();
    REGISTERED.call_once(|| {
        // Made now rather than by a call, which a fork might interrupt.
        let _ = crate::texture::srgb_decode_table();
        let _ = workers::logical_cpus();
        // SAFETY: the three handlers are `extern "C"` functions without arguments that neither
        // unwind nor return anything, as `pthread_atfork` requires. Registration fails only for
        // want of memory, and then forks behave as without this module.
        #[cfg(unix)]
        unsafe {
            libc::pthread_atfork(Some(take_locks), Some(release_locks), Some(release_locks));
        }
    });
}

/// The prepare handler: every lock, in the library's nesting order.
extern "C" fn take_locks() {
    let mut held = Vec::with_capacity(8);
    held.extend(input_files::locks_for_fork());
    held.push(atomic::lock_for_fork());
    held.push(workers::lock_for_fork());
    HELD.with(|h| *h.borrow_mut() = held);
}

/// The parent's and the child's handler: the guards dropped, every lock released.
extern "C" fn release_locks() {
    HELD.with(|h| h.borrow_mut().clear());
}

#[cfg(all(test, unix))]
mod tests {
    use std::sync::mpsc;
    use std::time::Duration;

    use super::*;
    use crate::input_files::Confinement;

    /// Forks while another thread runs a confinement (whose turn is a lock held for the whole
    /// run), and takes that lock in the child. Without the handlers the child waits for ever, so
    /// an alarm ends it after 20 s and the test fails on its exit status.
    fn child_takes_a_lock_held_at_the_fork() -> i32 {
        let (locked, wait) = mpsc::channel();
        let holder = std::thread::spawn(move || {
            Confinement::NONE.run(|| {
                locked.send(()).unwrap();
                std::thread::sleep(Duration::from_millis(300));
            })
        });
        wait.recv().unwrap();
        // SAFETY: the child takes and releases one lock (no allocation) and leaves with `_exit`,
        // which runs no destructors and no handlers registered with `atexit`.
        let pid = unsafe { libc::fork() };
        assert!(pid >= 0, "fork failed");
        if pid == 0 {
            unsafe {
                libc::alarm(20);
                Confinement::NONE.run(|| ());
                libc::_exit(0);
            }
        }
        holder.join().unwrap();
        let mut status = 0;
        // SAFETY: `pid` is this process's child; `status` is a valid place to write.
        assert_eq!(unsafe { libc::waitpid(pid, &mut status, 0) }, pid);
        status
    }

    /// The `static` locks of `src/` (a `Mutex` or an `RwLock`, or one of `taken`, whose type
    /// may wrap its lock) into `found` and its `OnceLock`s into `made`, by name, from the source
    /// text.
    fn static_locks(dir: &std::path::Path, taken: &[&str], found: &mut Vec<String>, made: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                static_locks(&path, taken, found, made);
            } else if path.extension().is_some_and(|e| e == "rs") {
                for line in std::fs::read_to_string(&path).unwrap().lines() {
                    let line = line
                        .trim_start()
                        .trim_start_matches("pub(crate) ")
                        .trim_start_matches("pub ");
                    let Some((name, ty)) = line.strip_prefix("static ").and_then(|l| l.split_once(':')) else {
                        continue;
                    };
                    if ty.contains("Mutex<") || ty.contains("RwLock<") || taken.contains(&name) {
                        found.push(name.to_string());
                    } else if ty.contains("OnceLock<") {
                        made.push(name.to_string());
                    }
                }
            }
        }
    }

    /// The `OnceLock`s `prepare_for_forks` makes, and the one it need not: the
    /// convergence plot's font check is built into the CLI only, which never forks.
    const MADE_EARLY: [&str; 3] = ["CPUS", "TABLE", "FOUND"];

    #[test]
    fn every_process_wide_lock_is_taken_before_a_fork_and_every_once_made_value_made_early() {
        // What the prepare handler takes, by name (it holds every lock only for this line).
        take_locks();
        let taken: Vec<&str> = HELD.with(|h| h.borrow().iter().map(|(name, _)| *name).collect());
        release_locks();
        let (mut found, mut made) = (Vec::new(), Vec::new());
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        static_locks(&src, &taken, &mut found, &mut made);
        let sorted = |mut names: Vec<String>| {
            names.sort();
            names
        };
        assert_eq!(
            sorted(found),
            sorted(taken.iter().map(|name| name.to_string()).collect()),
            "a process-wide lock that take_locks does not take would be inherited held by a child \
             forked while another thread holds it: add it there"
        );
        assert_eq!(
            sorted(made),
            sorted(MADE_EARLY.map(String::from).to_vec()),
            "a OnceLock a forked child may find being made: make it in prepare_for_forks \
             and add it to MADE_EARLY"
        );
    }

    #[test]
    fn a_child_forked_while_another_thread_holds_a_lock_finds_it_free() {
        prepare_for_forks();
        let status = child_takes_a_lock_held_at_the_fork();
        assert!(
            libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
            "the child did not take the lock (status {status:#x}; killed by its alarm: {})",
            libc::WIFSIGNALED(status) && libc::WTERMSIG(status) == libc::SIGALRM
        );
    }
}
