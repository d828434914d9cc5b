//! Long work without the GIL, stoppable by Ctrl-C, reporting its progress.
//!
//! The work runs on a scoped thread while the calling thread, without the GIL, wakes every
//! [`POLL`] to let Python run its signal handlers and to hand the work's latest progress to a
//! Python callback. When a handler or the callback raises (KeyboardInterrupt), the stop flag the
//! work was given is set; a render looks at it before each batch of samples
//! (`pointshade::render::render_scene_until`), so it ends within a batch per thread, and the
//! exception is raised instead of returning anything. Signals reach only the main thread: work
//! started from other Python threads runs to its end. The callback always runs on the calling
//! thread, so a progress bar never sees two threads at once.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pointshade::render::progress::{Advance, Progress, ProgressUnit};
use pyo3::prelude::*;

/// How often the waiting thread lets Python check for signals.
const POLL: Duration = Duration::from_millis(50);

/// The latest advance of a render: written by its worker threads, read by the waiting thread.
#[derive(Default)]
pub struct LatestProgress {
    done: AtomicU64,
    total: AtomicU64,
    budget: AtomicBool,
    /// The `done` last handed to the callback (`u64::MAX`: none yet).
    reported: AtomicU64,
}

impl Progress for LatestProgress {
    fn advance(&self, a: Advance) {
        self.total.store(a.total, Ordering::Relaxed);
        self.budget
            .store(a.unit == ProgressUnit::BudgetMilliseconds, Ordering::Relaxed);
        self.done.fetch_max(a.done, Ordering::Relaxed);
    }
}

impl LatestProgress {
    /// A fresh record (nothing reported yet).
    pub fn new() -> Self {
        let p = Self::default();
        p.reported.store(u64::MAX, Ordering::Relaxed);
        p
    }

    /// Calls `callback(done, total, unit)` if the render came further since the last call.
    fn report(&self, py: Python<'_>, callback: &Py<PyAny>) -> PyResult<()> {
        let (done, total) = (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed));
        if total == 0 || self.reported.swap(done, Ordering::Relaxed) == done {
            return Ok(());
        }
        let unit = match self.budget.load(Ordering::Relaxed) {
            true => "ms",
            false => "tiles",
        };
        callback.call1(py, (done, total, unit)).map(drop)
    }
}

/// Runs `work` without the GIL and returns its result, or the exception a signal handler or
/// `progress`'s callback raised (KeyboardInterrupt) if the user interrupted it; `work` is given
/// the flag that asks it to stop and the record its progress goes to.
pub fn run_interruptible<T: Send>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    work: impl FnOnce(&AtomicBool, &LatestProgress) -> T + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let latest = LatestProgress::new();
    let mut raised = None;
    let tick = |py: Python<'_>| -> PyResult<()> {
        py.check_signals()?;
        match &progress {
            Some(callback) => latest.report(py, callback),
            None => Ok(()),
        }
    };
    let outcome = py.detach(|| {
        let (done, result) = mpsc::channel();
        std::thread::scope(|s| {
            let (stop, latest) = (&stop, &latest);
            s.spawn(move || {
                // A send fails only once the waiter is gone, and it waits for this thread.
                let _ = done.send(work(stop, latest));
            });
            loop {
                match result.recv_timeout(POLL) {
                    Ok(value) => return value,
                    Err(RecvTimeoutError::Timeout) if raised.is_none() => {
                        if let Err(e) = Python::attach(tick) {
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
        None => {
            // The last advance (the whole render) reaches the callback too.
            if let Some(callback) = &progress {
                latest.report(py, callback)?;
            }
            Ok(outcome)
        }
    }
}
