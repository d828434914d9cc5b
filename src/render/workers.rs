//! The worker threads of a call, and the one check of a thread count (`--threads`, Python's
//! `threads=`).

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Mutex, OnceLock, PoisonError};

use rayon::ThreadPool;

/// Worker threads allowed per logical CPU: more only adds switching, and a thread count
/// typed with extra zeros (`--threads 100000`) would spawn threads until the process is killed.
pub const MAX_THREADS_PER_CPU: usize = 8;

/// Whether `threads` worker threads may be started: 1 ≤ threads ≤ [`MAX_THREADS_PER_CPU`] × the
/// logical CPUs; the message says which bound a refused count breaks.
pub fn check_thread_count(threads: usize) -> Result<(), String> {
    let cpus = logical_cpus();
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

/// The logical CPUs this process may run on, asked once: the standard library reads the
/// affinity mask and the cgroup quota files each time, which cost about as much as shading a
/// small normal image (docs/performance-log.md). The count only bounds a thread count typed by
/// mistake, so one taken at the first call serves the process's life.
pub(crate) fn logical_cpus() -> usize {
    static CPUS: OnceLock<usize> = OnceLock::new();
    *CPUS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Where a call's parallel work runs: rayon's global pool (all cores, started once and reused:
/// starting threads costs more than shading a small normal image), or a pool of a given size.
/// Everything parallel, loading included, runs inside it, so a thread count bounds the whole call.
///
/// A process forked from one that used the global pool (Python's `multiprocessing` on Linux)
/// inherits that pool without its threads, and rayon cannot start it again (rayon-rs/rayon#708):
/// its calls without a thread count run on a pool of the same size of its own instead. So every
/// parallel entry of a library that may be forked (the Python module) runs inside a `Workers`.
pub struct Workers {
    /// A pool of the call's own while it runs (no other call shares its threads), or `None`:
    /// rayon's global pool. Dropped, an own pool goes back to the idle pools for the next call
    /// of its size.
    own: Option<StartedPool>,
}

/// A thread pool and the process that started its threads.
struct StartedPool {
    process: u32,
    pool: ThreadPool,
}

/// The process whose calls without a thread count use rayon's global pool: the first to ask for
/// it (0 before). A process forked from it sees another id here.
static GLOBAL_POOL_PROCESS: AtomicU32 = AtomicU32::new(0);

impl Workers {
    /// The global pool when `threads` is `None` (in a forked process, a pool of the global
    /// pool's size), else a pool of that many threads: an idle one an earlier call of the same
    /// size gave back, or a new one.
    pub fn new(threads: Option<usize>) -> Result<Self, String> {
        let process = std::process::id();
        let threads = match threads {
            Some(threads) => {
                check_thread_count(threads)?;
                threads
            }
            None if global_pool_serves(&GLOBAL_POOL_PROCESS, process) => return Ok(Workers { own: None }),
            // Outside any pool this reads the size the global pool was built with; the
            // inherited pool is not asked to run anything.
            None => rayon::current_num_threads(),
        };
        if let Some(started) = IDLE.take(process, threads) {
            return Ok(Workers { own: Some(started) });
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map(|pool| Workers {
                own: Some(StartedPool { process, pool }),
            })
            .map_err(|e| format!("cannot start {threads} threads: {e}"))
    }

    /// When another process made these workers (a Python object held across a fork), replaces
    /// them with workers of the same kind made here: the other process's threads do not run in
    /// this one. Workers of this process are kept.
    pub fn move_to_this_process(&mut self) -> Result<(), String> {
        let process = std::process::id();
        *self = match &self.own {
            Some(started) if started.process != process => Workers::new(Some(started.pool.current_num_threads()))?,
            None if !global_pool_serves(&GLOBAL_POOL_PROCESS, process) => Workers::new(None)?,
            _ => return Ok(()),
        };
        Ok(())
    }

    /// Runs `work` on these workers.
    pub fn install<T: Send>(&self, work: impl FnOnce() -> T + Send) -> T {
        match &self.own {
            Some(started) => started.pool.install(work),
            None => work(),
        }
    }
}

impl Drop for Workers {
    fn drop(&mut self) {
        if let Some(started) = self.own.take() {
            IDLE.give_back(std::process::id(), started);
        }
    }
}

/// The idle pools' lock and its static's name, for the fork handlers of `process_fork` (taken
/// alone: no other lock is taken while it is held).
pub(crate) fn lock_for_fork() -> (&'static str, Box<dyn std::any::Any>) {
    ("IDLE", Box::new(IDLE.0.lock().unwrap_or_else(PoisonError::into_inner)))
}

/// Whether rayon's global pool runs the work of `process` (this process): it does in the first
/// process to ask (recorded in `owner`), not in one forked from it.
fn global_pool_serves(owner: &AtomicU32, process: u32) -> bool {
    match owner.compare_exchange(0, process, Ordering::Relaxed, Ordering::Relaxed) {
        Ok(_) => true,
        Err(first) => first == process,
    }
}

/// The pools calls gave back. A notebook calls `shade_normal_image(…, threads=2)` again and
/// again: the next call of the same size takes the pool instead of starting its threads again.
/// Idle rayon threads sleep.
static IDLE: IdlePools = IdlePools::new();

/// Idle pools, the most recently given back last; at most [`IdlePools::MOST`] of them, so a
/// process that asks for many sizes keeps only the last few pools' threads.
///
/// A process forked from this one (Python's `multiprocessing` on Linux) inherits the list, and
/// any `Workers` it holds, but not their threads: a pool of the parent's would take its jobs and
/// never run them. The child lets those go and starts its own.
struct IdlePools(Mutex<Vec<StartedPool>>);

impl IdlePools {
    /// Idle pools kept: a few sizes in turn (a sweep over `threads=`) still find theirs.
    const MOST: usize = 4;

    const fn new() -> Self {
        IdlePools(Mutex::new(Vec::new()))
    }

    /// The most recently given back pool of `threads` threads that `process` (this process)
    /// started, taken out; the pools another process started are let go first.
    fn take(&self, process: u32, threads: usize) -> Option<StartedPool> {
        // A panic while the lock was held left the list whole: every operation on it is one
        // push, remove or drain.
        let mut idle = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let_go_of_others(&mut idle, process);
        let i = idle
            .iter()
            .rposition(|started| started.pool.current_num_threads() == threads)?;
        Some(idle.remove(i))
    }

    /// `started` kept for the next call of its size by `process` (this process); the oldest idle
    /// pool is stopped when more than [`IdlePools::MOST`] would be kept. Only this process's
    /// pools are kept or stopped: a `Workers` held across a fork gives back its parent's pool.
    fn give_back(&self, process: u32, started: StartedPool) {
        let stopped = {
            let mut idle = self.0.lock().unwrap_or_else(PoisonError::into_inner);
            idle.push(started);
            let_go_of_others(&mut idle, process);
            let over = idle.len().saturating_sub(Self::MOST);
            idle.drain(..over).collect::<Vec<_>>()
        };
        // Stopped outside the lock: dropping a pool signals its threads to end.
        drop(stopped);
    }

    #[cfg(test)]
    fn sizes(&self) -> Vec<usize> {
        let idle = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        idle.iter().map(|started| started.pool.current_num_threads()).collect()
    }
}

/// The pools of `idle` that another process started (this one's parent, before a fork), let go:
/// not dropped, which would signal threads that do not exist here through locks a parent's
/// thread may have held at the fork. A few handles leak, once per fork.
fn let_go_of_others(idle: &mut Vec<StartedPool>, process: u32) {
    if idle.iter().any(|started| started.process != process) {
        let (ours, theirs): (Vec<_>, Vec<_>) = idle.drain(..).partition(|started| started.process == process);
        *idle = ours;
        std::mem::forget(theirs);
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;
    use std::thread::ThreadId;

    use super::*;

    /// A pool of `threads` threads, as process `process` would have started it.
    fn pool(process: u32, threads: usize) -> StartedPool {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        StartedPool { process, pool }
    }

    const HERE: u32 = 7;

    #[test]
    fn a_pool_given_back_serves_the_next_call_of_its_size_and_only_that() {
        // A list of its own: the tests beside this one use the process's.
        let idle = IdlePools::new();
        idle.give_back(HERE, pool(HERE, 1));
        idle.give_back(HERE, pool(HERE, 3));
        assert!(idle.take(HERE, 2).is_none(), "no pool of 2 threads was given back");
        let one = idle.take(HERE, 1).expect("the pool of one thread");
        assert_eq!(one.pool.current_num_threads(), 1);
        assert!(
            idle.take(HERE, 1).is_none(),
            "a pool is taken out, not shared with a second call"
        );
        assert_eq!(idle.sizes(), [3]);
    }

    #[test]
    fn a_forked_process_never_takes_its_parents_pools() {
        let idle = IdlePools::new();
        let (parent, child) = (HERE, HERE + 1);
        idle.give_back(parent, pool(parent, 2));
        idle.give_back(parent, pool(parent, 1));
        assert!(
            idle.take(child, 2).is_none(),
            "the parent's pool of 2 threads has none here"
        );
        assert!(idle.sizes().is_empty(), "every pool of the parent's is let go");
        idle.give_back(child, pool(child, 2));
        let taken = idle.take(child, 2).map(|started| started.pool.current_num_threads());
        assert_eq!(taken, Some(2));
    }

    #[test]
    fn only_the_first_process_to_ask_runs_on_the_global_pool() {
        let owner = AtomicU32::new(0);
        let (parent, child) = (HERE, HERE + 1);
        assert!(global_pool_serves(&owner, parent), "the first to ask");
        assert!(global_pool_serves(&owner, parent), "and again");
        assert!(
            !global_pool_serves(&owner, child),
            "a forked process inherits no threads"
        );
        assert!(!global_pool_serves(&owner, child + 1), "nor does one forked from that");
    }

    #[test]
    fn workers_another_process_made_are_made_again_here_at_their_size() {
        let here = std::process::id();
        // What a forked child holds: a pool its parent started (whose two threads, here, leak).
        let mut inherited = Workers {
            own: Some(pool(here.wrapping_add(1), 2)),
        };
        inherited.move_to_this_process().unwrap();
        let started = inherited.own.as_ref().expect("a pool of two threads of this process");
        assert_eq!((started.process, started.pool.current_num_threads()), (here, 2));
        let mut own = Workers::new(Some(1)).unwrap();
        let thread_of = |w: &Workers| w.install(|| std::thread::current().id());
        let before = thread_of(&own);
        own.move_to_this_process().unwrap();
        assert_eq!(thread_of(&own), before, "this process's pool is kept, not made again");
    }

    #[test]
    fn at_most_four_pools_stay_idle_the_oldest_stopped() {
        let idle = IdlePools::new();
        for threads in 1..=6 {
            idle.give_back(HERE, pool(HERE, threads));
        }
        assert_eq!(idle.sizes(), [3, 4, 5, 6]);
    }

    #[test]
    fn workers_of_a_size_reuse_a_dropped_pool_and_never_share_a_held_one() {
        // Through the process's list, with a size no other test asks for (another test would
        // have to give back four pools between the drop and the next call to evict this one).
        let threads = (MAX_THREADS_PER_CPU * logical_cpus()).min(13);
        let threads_of = |w: &Workers| -> HashSet<ThreadId> {
            w.install(|| rayon::broadcast(|_| std::thread::current().id()))
                .into_iter()
                .collect()
        };
        let (first, second) = (
            Workers::new(Some(threads)).unwrap(),
            Workers::new(Some(threads)).unwrap(),
        );
        let (first_threads, second_threads) = (threads_of(&first), threads_of(&second));
        assert_eq!((first_threads.len(), second_threads.len()), (threads, threads));
        assert!(
            first_threads.is_disjoint(&second_threads),
            "two held workers share no thread"
        );
        drop(first);
        let third = Workers::new(Some(threads)).unwrap();
        assert_eq!(
            threads_of(&third),
            first_threads,
            "the dropped pool's threads serve the next call"
        );
    }
}
