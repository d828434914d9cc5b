//! Forks of a process that runs pointshade on several threads (Python's `multiprocessing`
//! with the `fork` start method, `os.fork`). The child gets a copy of every lock as it was at
//! the fork, but only the forking thread: a lock another thread held at that instant is held by
//! no thread in the child, and the child's first call that takes it waits forever.
//!
//! [`keep_locks_free_across_forks`] registers handlers with POSIX `pthread_atfork` that take the
//! library's process-wide locks just before a fork, in the order the library nests them (so
//! that the handler cannot deadlock against a call in progress), and release them just after it
//! in the parent and in the child. The fork waits for other threads' critical sections to end
//! (the longest, a load under a confinement, lasts as long as the load), and the child starts
//! with every lock free. The locks, in that order:
//! - `input_files`: the confinement's turn, its folder and the recorded reads;
//! - `output::atomic`: the pending files of all-or-nothing writes;
//! - `render::workers`: the idle thread pools.
//!
//! A thread that forks while it holds one of them would wait for itself. The library never
//! does: it forks nowhere, and the front ends fork (or let Python fork) only between calls.

use std::any::Any;
use std::cell::RefCell;
use std::sync::Once;

use crate::input_files;
use crate::output::atomic;
use crate::render::workers;

thread_local! {
    /// The guards the forking thread holds from the prepare handler to the parent's or the
    /// child's: the same thread runs all three, and the child's copy of this thread-local
    /// holds the child's copies of the guards.
    static HELD: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// Registers the fork handlers, once per process (a forked child inherits them). The Python
/// module calls it when it is imported; a program that never forks need not.
pub fn keep_locks_free_across_forks() {
    static REGISTERED: Once = Once::new();
    REGISTERED.call_once(|| {
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
    let mut held: Vec<Box<dyn Any>> = Vec::with_capacity(8);
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
    /// run), and takes that lock in the child. Without the handlers the child waits forever, so
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

    #[test]
    fn a_child_forked_while_another_thread_holds_a_lock_finds_it_free() {
        keep_locks_free_across_forks();
        let status = child_takes_a_lock_held_at_the_fork();
        assert!(
            libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
            "the child did not take the lock (status {status:#x}; killed by its alarm: {})",
            libc::WIFSIGNALED(status) && libc::WTERMSIG(status) == libc::SIGALRM
        );
    }
}
