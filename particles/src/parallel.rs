//! Deterministic data parallelism: work split into fixed blocks whose results come back in
//! block order, so that every result is the same for any number of threads.
//!
//! A time step has two parallel stages of about 20-80 µs each at N = 4000. On rayon's pool
//! an idle worker waits in `sched_yield` and the caller, when it has finished its own part,
//! does too; on this kind of virtual machine each call then lost 10-15 µs of its 50-60 µs to
//! the hand-over (both threads' busy time measured inside the call: 40-48 µs each). So the
//! stages run on a [`Team`]: `T - 1` threads of our own that spin on an atomic counter for
//! the next job (parking after [`SPIN`] without one), and a caller that takes the first run
//! of blocks itself and spins until the others are done. Each thread gets one contiguous run
//! of blocks, as rayon did; which thread evaluates a block changes no result. A step runs
//! its stages in one [`region`]: every thread takes its own blocks, with a [`Barrier`]
//! between the stages, so a step costs one hand-over instead of one per stage.

use rayon::prelude::*;
use std::any::Any;
use std::cell::UnsafeCell;
use std::collections::HashMap;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, OnceLock, TryLockError};
use std::time::{Duration, Instant};

/// `f` applied to every block, in block order, on `T = rayon::current_num_threads()`
/// threads: serially when `T` is 1, otherwise on the [`Team`] of `T` threads (or on the
/// rayon pool, when that team is busy with another simulation or `T` exceeds the cores).
/// The blocks are split into `T` contiguous runs, one per thread: the blocks are of equal
/// size, so finer tasks would only add hand-overs to every stage. The per-block work and the order of the results are the
/// same either way, so the results do not depend on the number of threads.
pub(crate) fn on_blocks<B: Send, T: Send>(blocks: Vec<B>, f: impl Fn(B) -> T + Sync + Send) -> Vec<T> {
    let threads = rayon::current_num_threads();
    if threads == 1 || blocks.len() < 2 {
        return blocks.into_iter().map(f).collect();
    }
    // Spinning threads need a core each: with more threads than cores, rayon's pool.
    if threads > cores() {
        return on_rayon(blocks, threads, f);
    }
    let team = Team::of(threads);
    // Another simulation (a sweep's concurrent job) or a nested call holds the team: rayon.
    // (A lease poisoned by a panic that has reached its caller is free again.)
    let _lease = match team.lease.try_lock() {
        Ok(lease) => lease,
        Err(TryLockError::Poisoned(lease)) => lease.into_inner(),
        Err(TryLockError::WouldBlock) => return on_rayon(blocks, threads, f),
    };
    team.run(blocks, f)
}

/// [`on_blocks`] on the current rayon pool.
fn on_rayon<B: Send, T: Send>(blocks: Vec<B>, threads: usize, f: impl Fn(B) -> T + Sync + Send) -> Vec<T> {
    let run = blocks.len().div_ceil(threads).max(1);
    blocks.into_par_iter().with_min_len(run).map(f).collect()
}

/// Cores available to this process.
fn cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// How long a team thread spins for its next job before it parks (the gap between the
/// stages of a step, and between steps, is a few microseconds; writing a snapshot is not).
const SPIN: Duration = Duration::from_micros(200);

/// A job: `job(t)` evaluates run `t` of the current split on the calling thread.
type Job<'a> = dyn Fn(usize) + Sync + 'a;

/// `T - 1` persistent threads that run the runs `1..T` of each [`Team::run`] while the
/// caller runs run 0.
pub(crate) struct Team {
    /// Team threads plus the caller.
    threads: usize,
    shared: Arc<Shared>,
    /// Held by the one caller using the team.
    lease: Mutex<()>,
}

struct Shared {
    /// Incremented for every job; a thread runs a job when it sees a new value.
    epoch: AtomicU64,
    /// The current job, valid while `pending > 0` (written before `epoch` is incremented).
    job: UnsafeCell<Option<*const Job<'static>>>,
    /// Team threads (not counting the caller) that have not finished the current job.
    pending: AtomicUsize,
    /// Threads parked, or about to park, waiting for a job.
    sleepers: AtomicUsize,
    park: Mutex<()>,
    wake: Condvar,
    /// The first panic of a team thread in the current job.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
}

// SAFETY: `job` is written only by the caller holding the lease while no team thread reads it
// (all have finished the previous job: `pending == 0`), and read by team threads only after
// they have seen the new `epoch` (acquire), which is incremented (release) after the write.
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

impl Team {
    /// The team for `threads` threads of this process, started on first use.
    fn of(threads: usize) -> Arc<Team> {
        static TEAMS: OnceLock<Mutex<HashMap<usize, Arc<Team>>>> = OnceLock::new();
        let mut teams = TEAMS.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
        teams.entry(threads).or_insert_with(|| Arc::new(Team::start(threads))).clone()
    }

    fn start(threads: usize) -> Team {
        let shared = Arc::new(Shared {
            epoch: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            pending: AtomicUsize::new(0),
            sleepers: AtomicUsize::new(0),
            park: Mutex::new(()),
            wake: Condvar::new(),
            panic: Mutex::new(None),
        });
        for t in 1..threads {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name(format!("stripes-team-{t}"))
                .spawn(move || shared.serve(t))
                .expect("starting a team thread");
        }
        Team {
            threads,
            shared,
            lease: Mutex::new(()),
        }
    }

    /// Runs `f` on every block; results in block order. The caller holds the lease.
    fn run<B: Send, T: Send>(&self, blocks: Vec<B>, f: impl Fn(B) -> T + Sync) -> Vec<T> {
        let n = blocks.len();
        let threads = self.threads;
        let inputs: Vec<Slot<B>> = blocks.into_iter().map(|b| Slot(UnsafeCell::new(Some(b)))).collect();
        let outputs: Vec<Slot<T>> = (0..n).map(|_| Slot(UnsafeCell::new(None))).collect();
        self.dispatch(&|t: usize| {
            for k in run_of(n, threads, t) {
                // SAFETY: block k belongs to run t alone, and each run is executed once.
                let b = unsafe { (*inputs[k].0.get()).take() }.expect("each block is taken once");
                let r = f(b);
                unsafe { *outputs[k].0.get() = Some(r) };
            }
        });
        outputs
            .into_iter()
            .map(|o| o.0.into_inner().expect("every block is evaluated"))
            .collect()
    }

    /// Runs `f(t, threads, barrier)` on every thread `t` of the team at once. The caller
    /// holds the lease.
    fn region(&self, f: impl Fn(usize, usize, &Barrier) + Sync) {
        let barrier = Barrier::new(self.threads);
        self.dispatch(&|t: usize| {
            // A panicking thread never reaches the next barrier: release the others.
            if let Err(p) = catch_unwind(AssertUnwindSafe(|| f(t, self.threads, &barrier))) {
                barrier.abort.store(true, Ordering::Release);
                resume_unwind(p);
            }
        });
    }

    /// Runs `job(t)` for `t` in `1..T` on the team threads and `job(0)` on the caller, and
    /// returns when all have finished (a panic of any of them is resumed here).
    fn dispatch(&self, job: &Job<'_>) {
        // SAFETY: the reference does not outlive this call: `Wait` below does not return (not
        // even by unwinding) before every team thread has finished with it.
        let erased: *const Job<'static> = unsafe { std::mem::transmute::<&Job<'_>, &'static Job<'static>>(job) };
        let s = &*self.shared;
        // A team thread's panic left over from a job whose caller panicked as well.
        s.panic.lock().unwrap_or_else(|e| e.into_inner()).take();
        s.pending.store(self.threads - 1, Ordering::Relaxed);
        unsafe { *s.job.get() = Some(erased) };
        s.epoch.fetch_add(1, Ordering::SeqCst);
        if s.sleepers.load(Ordering::SeqCst) > 0 {
            let _guard = s.park.lock().unwrap_or_else(|e| e.into_inner());
            s.wake.notify_all();
        }
        let wait = Wait(s);
        job(0);
        drop(wait);
        if let Some(p) = s.panic.lock().unwrap_or_else(|e| e.into_inner()).take() {
            resume_unwind(p);
        }
    }
}

/// The blocks of run `t` when `n` blocks are split into `threads` contiguous runs.
pub(crate) fn run_of(n: usize, threads: usize, t: usize) -> std::ops::Range<usize> {
    let per = n.div_ceil(threads);
    (t * per).min(n)..((t + 1) * per).min(n)
}

/// A parallel region: `f(t, threads, barrier)` on each of `T = rayon::current_num_threads()`
/// threads at once, where `barrier.wait()` returns once every thread has reached it. Each
/// thread takes its own blocks ([`run_of`]), so a step's stages run in one hand-over instead
/// of one per stage, with no block lists built by the caller. Returns false, having run
/// nothing, when the team is not available (busy with another simulation, or more threads
/// than cores): the caller then runs its stages through [`on_blocks`]. Work of fewer than
/// two `blocks` runs on the calling thread alone, as in [`on_blocks`].
pub(crate) fn region(blocks: usize, f: impl Fn(usize, usize, &Barrier) + Sync) -> bool {
    let threads = rayon::current_num_threads();
    if threads == 1 || blocks < 2 {
        f(0, 1, &Barrier::new(1));
        return true;
    }
    if threads > cores() {
        return false;
    }
    let team = Team::of(threads);
    let _lease = match team.lease.try_lock() {
        Ok(lease) => lease,
        Err(TryLockError::Poisoned(lease)) => lease.into_inner(),
        Err(TryLockError::WouldBlock) => return false,
    };
    team.region(f);
    true
}

/// A barrier among the threads of one [`region`].
pub(crate) struct Barrier {
    threads: usize,
    arrived: AtomicUsize,
    /// Incremented each time every thread has arrived.
    generation: AtomicUsize,
    /// Set when a thread of the region panicked: the barrier no longer waits.
    abort: AtomicBool,
}

impl Barrier {
    fn new(threads: usize) -> Barrier {
        Barrier {
            threads,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            abort: AtomicBool::new(false),
        }
    }

    /// Waits until every thread of the region has called `wait` as often as this one.
    /// Returns false if another thread panicked instead (the caller should return).
    pub(crate) fn wait(&self) -> bool {
        if self.threads == 1 {
            return true;
        }
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::Release);
        } else {
            let passed = || self.generation.load(Ordering::Acquire) != generation || self.abort.load(Ordering::Acquire);
            while !spin_until(passed) {
                std::thread::yield_now();
            }
        }
        !self.abort.load(Ordering::Acquire)
    }
}

/// One block's input or output, handed to exactly one thread.
struct Slot<X>(UnsafeCell<Option<X>>);
// SAFETY: each slot is accessed by the one thread whose run contains it, and by the caller
// after every run has finished.
unsafe impl<X: Send> Sync for Slot<X> {}

/// Waits, on drop, until every team thread has finished the current job.
struct Wait<'a>(&'a Shared);

impl Drop for Wait<'_> {
    fn drop(&mut self) {
        while !spin_until(|| self.0.pending.load(Ordering::Acquire) == 0) {
            std::thread::yield_now();
        }
    }
}

/// Spins until `done()` holds or [`SPIN`] has passed; returns `done()`.
fn spin_until(done: impl Fn() -> bool) -> bool {
    let start = Instant::now();
    let mut spins = 0u32;
    loop {
        if done() {
            return true;
        }
        std::hint::spin_loop();
        spins = spins.wrapping_add(1);
        if spins.is_multiple_of(1024) && start.elapsed() > SPIN {
            return done();
        }
    }
}

impl Shared {
    /// A team thread's life: run run `t` of every job.
    fn serve(&self, t: usize) {
        let mut seen = 0u64;
        loop {
            seen = self.next_epoch(seen);
            // SAFETY: see `impl Sync for Shared`.
            let job = unsafe { (*self.job.get()).expect("a job is set before its epoch") };
            if let Err(p) = catch_unwind(AssertUnwindSafe(|| unsafe { (*job)(t) })) {
                self.panic.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert(p);
            }
            self.pending.fetch_sub(1, Ordering::Release);
        }
    }

    /// Waits for an epoch other than `seen`: spins for [`SPIN`], then parks.
    fn next_epoch(&self, seen: u64) -> u64 {
        if spin_until(|| self.epoch.load(Ordering::Acquire) != seen) {
            return self.epoch.load(Ordering::Acquire);
        }
        self.sleepers.fetch_add(1, Ordering::SeqCst);
        let mut guard = self.park.lock().unwrap_or_else(|e| e.into_inner());
        let e = loop {
            let e = self.epoch.load(Ordering::SeqCst);
            if e != seen {
                break e;
            }
            guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
        };
        drop(guard);
        self.sleepers.fetch_sub(1, Ordering::SeqCst);
        // The epoch load above is SeqCst; the job's data needs acquire, which it implies.
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
    }

    #[test]
    fn every_block_once_and_results_in_block_order_for_any_split() {
        for threads in [1, 2, 3] {
            pool(threads).install(|| {
                for n in [0, 1, 2, 3, 5, 7, 64] {
                    let calls = AtomicUsize::new(0);
                    let blocks: Vec<usize> = (0..n).collect();
                    let out = on_blocks(blocks, |b| {
                        calls.fetch_add(1, Ordering::Relaxed);
                        (b * b, std::thread::current().id())
                    });
                    assert_eq!(calls.load(Ordering::Relaxed), n, "{threads} threads, {n} blocks");
                    let squares: Vec<usize> = out.iter().map(|o| o.0).collect();
                    assert_eq!(squares, (0..n).map(|b| b * b).collect::<Vec<_>>());
                    // One contiguous run per thread: the runs' threads never interleave.
                    let mut runs = out.iter().map(|o| o.1).collect::<Vec<_>>();
                    runs.dedup();
                    assert!(runs.len() <= threads, "{threads} threads, {n} blocks: {} runs", runs.len());
                }
            });
        }
    }

    #[test]
    fn blocks_may_borrow_mutable_slices_of_the_callers_data() {
        pool(2).install(|| {
            let mut data: Vec<u64> = (0..1000).collect();
            for _ in 0..200 {
                let sums = on_blocks(data.chunks_mut(64).collect(), |chunk| {
                    chunk.iter_mut().for_each(|x| *x += 1);
                    chunk.iter().sum::<u64>()
                });
                assert_eq!(sums.iter().sum::<u64>(), data.iter().sum::<u64>());
            }
            assert_eq!(data, (200..1200).collect::<Vec<u64>>());
        });
    }

    #[test]
    fn a_region_sees_every_threads_stage_after_its_barrier() {
        for threads in [1, 2] {
            pool(threads).install(|| {
                let n = 9;
                let counts: Vec<AtomicUsize> = (0..n).map(|_| AtomicUsize::new(0)).collect();
                let (mut rounds, wrong) = (0, AtomicUsize::new(0));
                let start = Instant::now();
                while rounds < 300 && start.elapsed() < Duration::from_secs(60) {
                    // Another test may hold the team: then nothing runs (the caller would use
                    // `on_blocks`), and the round is tried again.
                    let ran = region(n, |t, runs, barrier| {
                        assert_eq!(runs, threads);
                        for b in run_of(n, runs, t) {
                            counts[b].fetch_add(1, Ordering::Relaxed);
                        }
                        assert!(barrier.wait());
                        let behind = counts.iter().filter(|c| c.load(Ordering::Relaxed) != rounds + 1).count();
                        wrong.fetch_add(behind, Ordering::Relaxed);
                        // The second stage must not start before every thread has checked.
                        assert!(barrier.wait());
                    });
                    rounds += ran as usize;
                }
                assert!(rounds > 0, "{threads} threads: the region never ran");
                assert_eq!(wrong.load(Ordering::Relaxed), 0, "{threads} threads");
                assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == rounds));
            });
        }
    }

    #[test]
    fn a_panic_in_a_region_reaches_the_caller_and_releases_the_barrier() {
        let team = Team::start(2);
        for bad in [0, 1] {
            let r = catch_unwind(AssertUnwindSafe(|| {
                team.region(|t, _, barrier| {
                    if t == bad {
                        panic!("run {t}");
                    }
                    assert!(!barrier.wait(), "the barrier must not wait for a panicked thread");
                })
            }));
            let msg = r.expect_err("the panic must propagate");
            assert_eq!(
                msg.downcast_ref::<String>().map(String::as_str),
                Some(format!("run {bad}").as_str())
            );
            let sum = AtomicUsize::new(0);
            team.region(|t, _, barrier| {
                assert!(barrier.wait());
                sum.fetch_add(t + 1, Ordering::Relaxed);
            });
            assert_eq!(sum.load(Ordering::Relaxed), 3);
        }
    }

    #[test]
    fn a_panic_in_any_block_reaches_the_caller_and_the_team_still_works() {
        // A team of its own, so that no other test leases it meanwhile.
        let team = Team::start(2);
        for bad in [0, 5, 7] {
            let r = catch_unwind(AssertUnwindSafe(|| {
                team.run((0..8).collect(), |b: usize| if b == bad { panic!("block {b}") } else { b })
            }));
            let msg = r.expect_err("the panic must propagate");
            assert_eq!(
                msg.downcast_ref::<String>().map(String::as_str),
                Some(format!("block {bad}").as_str())
            );
            assert_eq!(team.run((0..8).collect(), |b: usize| b + 1), (1..9).collect::<Vec<_>>());
        }
    }

    #[test]
    fn concurrent_callers_and_nested_calls_get_correct_results() {
        // Two simulations on two threads of the same size contend for one team: one of them
        // leases it, the other falls back to rayon. A call from inside a block is nested.
        let outer = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..2)
                .map(|k| {
                    scope.spawn(move || {
                        pool(2).install(|| {
                            (0..300)
                                .map(|round| {
                                    let out = on_blocks((0..16).collect(), |b: usize| {
                                        let inner = on_blocks((0..4).collect(), |c: usize| c * b);
                                        inner.iter().sum::<usize>() + k + round
                                    });
                                    let expect: Vec<usize> = (0..16).map(|b| 6 * b + k + round).collect();
                                    (out == expect) as usize
                                })
                                .sum::<usize>()
                        })
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect::<Vec<_>>()
        });
        assert_eq!(outer, vec![300, 300]);
    }
}
