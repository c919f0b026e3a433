//! The crowd's worker threads: started with the crowd, woken for each step, parked between.
//!
//! [`WorkerPool::run`] hands out task indices `0..tasks` to the workers and the calling
//! thread through one atomic counter, and returns when every task is done. Nothing is
//! allocated per run: the task is passed by reference, workers are woken with
//! `Thread::unpark` and the caller waits on an atomic count.

use std::cell::UnsafeCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::{self, JoinHandle};

use crate::error::{Error, Result};

/// How long a worker spins on the next run before parking (busy-wait iterations).
const SPINS_BEFORE_PARKING: u32 = 2_000;

/// Each worker thread's stack: 8 MiB, the main thread's usual size on Linux. Rust's default
/// for spawned threads (2 MiB) is too small for the gaze IK's widest lanes in an unoptimised
/// build, whose every temporary takes its own stack slot.
const WORKER_STACK_BYTES: usize = 8 << 20;

/// Pools dropped in a child forked from the process that started their threads: their
/// thread handles cannot be joined or detached there, so they are kept here, reachable and
/// never freed (leak checkers see memory still in use, not lost).
type ForkedPool = (Arc<PoolState>, Vec<JoinHandle<()>>);
static FORKED_POOLS: std::sync::Mutex<Vec<ForkedPool>> = std::sync::Mutex::new(Vec::new());

/// A task: called once for each index `0..tasks`, from any of the pool's threads.
type Task<'a> = &'a (dyn Fn(usize) + Sync);

/// The run being handed out.
#[derive(Clone, Copy)]
struct Run {
    /// The task, its lifetime erased: valid until `run` returns, which waits for every
    /// worker to finish with it.
    task: Option<Task<'static>>,
    tasks: usize,
}

/// What the pool's threads share.
struct PoolState {
    /// Bumped to start each run (and to wake workers for shutdown).
    generation: AtomicU64,
    /// Written only by `run` while no worker reads it (between runs).
    current: UnsafeCell<Run>,
    /// Next task index to hand out.
    next_task: AtomicUsize,
    /// Workers still working on the current run.
    busy_workers: AtomicUsize,
    /// Set when a task panicked in the current run.
    panicked: AtomicBool,
    shutdown: AtomicBool,
}

// SAFETY: `current` is written by `run` only while every worker is idle (before bumping
// `generation`, after `busy_workers` reached 0) and read by workers only in between; the
// generation and busy counters order those accesses (release/acquire).
unsafe impl Sync for PoolState {}

impl PoolState {
    /// Takes task indices until none is left, running each; records a panic.
    fn work(&self, run: Run) {
        let Some(task) = run.task else { return };
        let result = catch_unwind(AssertUnwindSafe(|| loop {
            let index = self.next_task.fetch_add(1, Ordering::Relaxed);
            if index >= run.tasks {
                break;
            }
            task(index);
        }));
        if result.is_err() {
            self.panicked.store(true, Ordering::Relaxed);
        }
    }
}

/// Worker threads that share the tasks of a run with the calling thread.
pub(super) struct WorkerPool {
    state: Arc<PoolState>,
    workers: Vec<JoinHandle<()>>,
    /// The process that started the workers: in a child forked from it (`fork()` copies
    /// only the calling thread) they do not exist.
    process: u32,
}

impl std::fmt::Debug for WorkerPool {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("WorkerPool")
            .field("workers", &self.workers.len())
            .finish()
    }
}

impl WorkerPool {
    /// Starts `workers` threads (the caller of `run` is one more).
    pub fn new(workers: usize) -> Result<WorkerPool> {
        let state = Arc::new(PoolState {
            generation: AtomicU64::new(0),
            current: UnsafeCell::new(Run {
                task: None,
                tasks: 0,
            }),
            next_task: AtomicUsize::new(0),
            busy_workers: AtomicUsize::new(0),
            panicked: AtomicBool::new(false),
            shutdown: AtomicBool::new(false),
        });
        let mut pool = WorkerPool {
            state,
            workers: crate::alloc::try_with_capacity(
                workers,
                &crate::alloc::Field("worker threads", workers as u64),
            )?,
            process: std::process::id(),
        };
        for index in 0..workers {
            let state = Arc::clone(&pool.state);
            let worker = thread::Builder::new()
                .name(format!("crowdgaze-{index}"))
                .stack_size(WORKER_STACK_BYTES)
                .spawn(move || worker_loop(&state))
                .map_err(|error| {
                    Error::Internal(format!("cannot start a worker thread: {error}"))
                })?;
            // On an early return, dropping `pool` stops the workers started so far.
            pool.workers.push(worker);
        }
        Ok(pool)
    }

    /// The number of worker threads (the caller of `run` is one more).
    pub fn workers(&self) -> usize {
        self.workers.len()
    }

    /// True in a child process forked after the workers started: they do not run there,
    /// and `run` would wait for them forever. Drop such a pool (it lets go of the threads
    /// without joining them) and start a new one.
    pub fn is_forked(&self) -> bool {
        std::process::id() != self.process
    }

    /// Runs `task(index)` for every index in `0..tasks`, on the workers and the calling
    /// thread, and returns when all are done. Fails with [`Error::Internal`] if a task
    /// panicked (the other tasks still ran).
    pub fn run(&self, tasks: usize, task: Task<'_>) -> Result<()> {
        let state = &*self.state;
        // SAFETY: only the lifetime is erased. Every worker is idle now (the previous run
        // waited for them) and is done with `task` before this function returns (the wait
        // below), and the slot is cleared before returning.
        let task: Task<'static> = unsafe { std::mem::transmute::<Task<'_>, Task<'static>>(task) };
        let run = Run {
            task: Some(task),
            tasks,
        };
        // SAFETY: no worker reads `current` between runs (see `PoolState`).
        unsafe { *state.current.get() = run };
        state.next_task.store(0, Ordering::Relaxed);
        state.panicked.store(false, Ordering::Relaxed);
        state
            .busy_workers
            .store(self.workers.len(), Ordering::Relaxed);
        state.generation.fetch_add(1, Ordering::Release);
        for worker in &self.workers {
            worker.thread().unpark();
        }
        state.work(run);
        while state.busy_workers.load(Ordering::Acquire) != 0 {
            std::hint::spin_loop();
            thread::yield_now();
        }
        // SAFETY: every worker is idle again.
        unsafe {
            *state.current.get() = Run {
                task: None,
                tasks: 0,
            }
        };
        if state.panicked.load(Ordering::Relaxed) {
            return Err(Error::Internal("a step task panicked".into()));
        }
        Ok(())
    }
}

/// A worker: waits for each new generation, works on its run, reports done.
fn worker_loop(state: &PoolState) {
    let mut seen = 0;
    loop {
        let mut spins = 0;
        loop {
            let generation = state.generation.load(Ordering::Acquire);
            if generation != seen {
                seen = generation;
                break;
            }
            if spins < SPINS_BEFORE_PARKING {
                spins += 1;
                std::hint::spin_loop();
            } else {
                thread::park();
            }
        }
        if state.shutdown.load(Ordering::Acquire) {
            return;
        }
        // SAFETY: `run` wrote `current` before the release bump of `generation` this thread
        // acquired, and does not write it again until this worker reports done below.
        let run = unsafe { *state.current.get() };
        state.work(run);
        state.busy_workers.fetch_sub(1, Ordering::Release);
    }
}

impl Drop for WorkerPool {
    fn drop(&mut self) {
        if self.is_forked() {
            // The threads stayed in the parent: nothing to stop or join here, and joining
            // or detaching a thread of another process is undefined. Their handles and the
            // shared state are kept, unused, for the child's lifetime.
            let orphan = (Arc::clone(&self.state), std::mem::take(&mut self.workers));
            match FORKED_POOLS.lock() {
                Ok(mut orphans) => orphans.push(orphan),
                Err(_) => std::mem::forget(orphan),
            }
            return;
        }
        self.state.shutdown.store(true, Ordering::Release);
        self.state.generation.fetch_add(1, Ordering::Release);
        for worker in self.workers.drain(..) {
            worker.thread().unpark();
            let _ = worker.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_task_runs_once_over_many_runs() {
        let pool = WorkerPool::new(3).unwrap();
        let counts: Vec<AtomicUsize> = (0..100).map(|_| AtomicUsize::new(0)).collect();
        for _ in 0..200 {
            pool.run(counts.len(), &|index| {
                counts[index].fetch_add(1, Ordering::Relaxed);
            })
            .unwrap();
        }
        assert!(counts
            .iter()
            .all(|count| count.load(Ordering::Relaxed) == 200));
    }

    #[test]
    fn a_panicking_task_is_reported_and_the_pool_still_works() {
        let pool = WorkerPool::new(2).unwrap();
        let result = pool.run(8, &|index| {
            if index == 5 {
                panic!("task 5 fails");
            }
        });
        assert!(matches!(result, Err(Error::Internal(_))));
        let done = AtomicUsize::new(0);
        pool.run(8, &|_| {
            done.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(done.load(Ordering::Relaxed), 8);
    }
}
