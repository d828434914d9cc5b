//! The worker threads of a call, and the one check of a thread count (`--threads`, Python's
//! `threads=`).

/// Worker threads allowed per logical CPU: more only adds switching, and a thread count
/// typed with extra zeros (`--threads 100000`) would spawn threads until the process is killed.
pub const MAX_THREADS_PER_CPU: usize = 8;

/// Whether `threads` worker threads may be started: 1 ≤ threads ≤ [`MAX_THREADS_PER_CPU`] × the
/// logical CPUs; the message says which bound a refused count breaks.
pub fn check_thread_count(threads: usize) -> Result<(), String> {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    let most = MAX_THREADS_PER_CPU * cpus;
    if threads == 0 {
        return Err("must be at least 1".into());
    }
    if threads > most {
        return Err(format!(
            "{threads} is more than {most} ({MAX_THREADS_PER_CPU} per logical CPU, {cpus} here)"
        ));
    }
    Ok(())
}

/// Where a call's parallel work runs: rayon's global pool (all cores, started once and reused:
/// starting threads costs more than shading a small normal image), or a pool of a given size.
/// Everything parallel, loading included, runs inside it, so a thread count bounds the whole call.
pub enum Workers {
    /// rayon's global pool.
    Global,
    /// A pool of its own.
    Own(rayon::ThreadPool),
}

impl Workers {
    /// The global pool when `threads` is `None`, else a pool of that many threads.
    pub fn new(threads: Option<usize>) -> Result<Self, String> {
        let Some(threads) = threads else {
            return Ok(Workers::Global);
        };
        check_thread_count(threads)?;
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map(Workers::Own)
            .map_err(|e| format!("cannot start {threads} threads: {e}"))
    }

    /// Runs `work` on these workers.
    pub fn install<T: Send>(&self, work: impl FnOnce() -> T + Send) -> T {
        match self {
            Workers::Global => work(),
            Workers::Own(pool) => pool.install(work),
        }
    }
}
