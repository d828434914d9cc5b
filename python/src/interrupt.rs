//! Long work without the GIL, stoppable by Ctrl-C.
//!
//! The work runs on a scoped thread while the calling thread, without the GIL, wakes every
//! [`POLL`] to let Python run its signal handlers. When a handler
//! raises (KeyboardInterrupt), the stop flag the work was given is set; a render looks at it
//! before each batch of samples (`pointshade::render::render_scene_until`), so it ends within a
//! batch per thread, and the exception is raised instead of returning anything. Signals reach
//! only the main thread: work started from other Python threads runs to its end.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::prelude::*;

/// How often the waiting thread lets Python check for signals.
const POLL: Duration = Duration::from_millis(50);

/// Runs `work` without the GIL and returns its result, or the exception a signal
/// handler raised (KeyboardInterrupt) if the user interrupted it; `work` is given the flag that
/// asks it to stop.
pub fn run_interruptible<T: Send>(py: Python<'_>, work: impl FnOnce(&AtomicBool) -> T + Send) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let mut raised = None;
    let outcome = py.detach(|| {
        let (done, result) = mpsc::channel();
        std::thread::scope(|s| {
            let stop = &stop;
            s.spawn(move || {
                // A send fails only once the waiter is gone, and it waits for this thread.
                let _ = done.send(work(stop));
            });
            loop {
                match result.recv_timeout(POLL) {
                    Ok(value) => return value,
                    Err(RecvTimeoutError::Timeout) if raised.is_none() => {
                        if let Err(e) = Python::attach(|py| py.check_signals()) {
                            raised = Some(e);
                            stop.store(true, Ordering::Relaxed);
                        }
                    }
                    Err(RecvTimeoutError::Timeout) => {}
                    // The work panicked (a bug): the scope carries the panic on when it joins the
                    // thread, and PyO3 turns it into a PanicException.
                    Err(RecvTimeoutError::Disconnected) => panic!("the work panicked"),
                }
            }
        })
    });
    match raised {
        // Interrupted (or just after the work finished): the exception wins, as in Python code.
        Some(e) => Err(e),
        None => Ok(outcome),
    }
}
