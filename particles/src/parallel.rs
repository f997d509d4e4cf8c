//! Deterministic data parallelism: work split into fixed blocks whose results come back in
//! block order, so that every result is the same for any number of threads.
//!
//! A time step has two parallel stages of about 20-80 µs each at N = 4000. On rayon's pool
//! an idle worker waits in `sched_yield` and the caller, when it has finished its own part,
//! does too; on this kind of virtual machine each call then lost 10-15 µs of its 50-60 µs to
//! the hand-over (both threads' busy time measured inside the call: 40-48 µs each). So the
//! stages run on a [`Team`]: `T - 1` threads of our own that spin on an atomic counter for
//! the next job, and a caller that takes the first run of blocks itself. A step runs its
//! stages in one [`region`]: every thread takes its own run of blocks, with a [`Barrier`]
//! between the stages, so a step costs one hand-over instead of one per stage; a thread that
//! has finished its run takes the blocks not yet started of the others' runs
//! ([`Crew::each`]), so a thread the system has descheduled holds the stage up by one block,
//! not by its run. Which thread evaluates a block changes no result.
//!
//! Every wait (a team thread for its next job, a thread at a barrier, the caller for the
//! team) spins for [`spin_limit`] and then sleeps on a condition variable, woken by the
//! thread that ends the wait: a waiting thread never holds a core that another thread of the
//! run, or another process, needs for longer than that (issue 41). Before, the barrier and
//! the caller yielded in a loop instead of sleeping: with one other busy process on the two
//! cores, two threads ran at half the rate of one.

use rayon::prelude::*;
use std::any::Any;
use std::cell::{Cell, UnsafeCell};
use std::collections::HashMap;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, OnceLock, TryLockError};
use std::time::{Duration, Instant};

/// `f` applied to every block, in block order, on `T = rayon::current_num_threads()`
/// threads (at most the limit of [`with_threads`]): serially when `T` is 1, otherwise on
/// the [`Team`] of `T` threads (or on the rayon pool, when that team is busy with another
/// simulation or `T` exceeds the cores). The blocks are split into `T` contiguous runs, one
/// per thread: the blocks are of equal size, so finer tasks would only add hand-overs to
/// every stage. The per-block work and the order of the results are the same either way, so
/// the results do not depend on the number of threads.
pub(crate) fn on_blocks<B: Send, T: Send>(blocks: Vec<B>, f: impl Fn(B) -> T + Sync + Send) -> Vec<T> {
    let threads = team_size();
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

thread_local! {
    /// The most threads that [`on_blocks`] and [`region`] use when called on this thread
    /// (see [`with_threads`]).
    static LIMIT: Cell<usize> = const { Cell::new(usize::MAX) };
}

/// The threads of the calls made on this thread: `rayon::current_num_threads()`, at most
/// the limit of [`with_threads`].
fn team_size() -> usize {
    rayon::current_num_threads().min(LIMIT.get()).max(1)
}

/// Runs `f` with [`on_blocks`] and [`region`] using at most `threads` threads (a step of
/// [`crate::pace::Pace`]'s size). The results are the same for any limit.
pub(crate) fn with_threads<R>(threads: usize, f: impl FnOnce() -> R) -> R {
    struct Restore(usize);
    impl Drop for Restore {
        fn drop(&mut self) {
            LIMIT.set(self.0);
        }
    }
    let _restore = Restore(LIMIT.replace(threads));
    f()
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

/// How long a waiting thread spins before it sleeps (µs), unless the environment variable
/// `STRIPES_SPIN_US` says otherwise (read once; for measurements). The gap between the
/// stages of a step, and between steps, is a few microseconds on an idle machine; a thread
/// descheduled by the system keeps the others waiting for milliseconds.
const SPIN_US: u64 = 50;

/// Where the threads of this process have waited, summed over every thread, counted only
/// when the environment variable `STRIPES_WAITS` is set (read once): for measurements of
/// the parallel step (issue 41), which `stripes run` prints at its end.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Waits {
    /// Team threads waiting for their next job: the serial parts of the caller (s).
    pub for_job_s: f64,
    /// Threads waiting at a region's barriers: imbalance between the threads' work (s).
    pub at_barrier_s: f64,
    /// The caller waiting for the team at the end of a job (s).
    pub for_team_s: f64,
    /// Waits that ended asleep rather than spinning.
    pub sleeps: u64,
    /// Blocks a thread took from another thread's run ([`Crew::each`]).
    pub taken_over: u64,
}

/// The kinds of wait of [`Waits`].
#[derive(Clone, Copy)]
enum WaitKind {
    Job = 0,
    Barrier = 1,
    Team = 2,
}

/// Nanoseconds per [`WaitKind`], then sleeps and blocks taken over.
static WAIT_COUNTS: [AtomicU64; 5] = [const { AtomicU64::new(0) }; 5];

fn counting_waits() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("STRIPES_WAITS").is_some())
}

/// The waits of this process so far ([`Waits`]), `None` unless `STRIPES_WAITS` is set.
pub fn waits() -> Option<Waits> {
    counting_waits().then(|| {
        let c = |k: usize| WAIT_COUNTS[k].load(Ordering::Relaxed);
        Waits {
            for_job_s: c(0) as f64 * 1e-9,
            at_barrier_s: c(1) as f64 * 1e-9,
            for_team_s: c(2) as f64 * 1e-9,
            sleeps: c(3),
            taken_over: c(4),
        }
    })
}

/// How long a waiting thread spins before it sleeps: [`SPIN_US`] or `STRIPES_SPIN_US`.
fn spin_limit() -> Duration {
    static SPIN: OnceLock<Duration> = OnceLock::new();
    *SPIN.get_or_init(|| {
        let us = std::env::var("STRIPES_SPIN_US")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(SPIN_US);
        Duration::from_micros(us)
    })
}

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
    /// Where team threads sleep waiting for a job.
    jobs: Sleep,
    /// Where the caller sleeps waiting for `pending` to reach 0.
    done: Sleep,
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
            jobs: Sleep::new(),
            done: Sleep::new(),
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

    /// Runs `f(crew)` on every thread of the team at once, each with its own [`Crew`] over
    /// `blocks` blocks and `stages` stages. The caller holds the lease.
    fn region(&self, blocks: usize, stages: usize, f: impl Fn(&Crew) + Sync) {
        let barrier = Barrier::new(self.threads);
        let claims = Claims::new(stages * self.threads);
        self.dispatch(&|t: usize| {
            let crew = Crew {
                t,
                threads: self.threads,
                blocks,
                barrier: &barrier,
                claims: &claims,
            };
            // A panicking thread never reaches the next barrier: release the others.
            if let Err(p) = catch_unwind(AssertUnwindSafe(|| f(&crew))) {
                barrier.abort.store(true, Ordering::SeqCst);
                barrier.sleep.wake_all();
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
        s.jobs.wake_all();
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

/// A parallel region: `f(crew)` on each of `T = rayon::current_num_threads()` threads (at
/// most the limit of [`with_threads`]) at once, where `crew.each(stage, op)` runs `op(b)`
/// on the blocks `0..blocks` shared out among the threads (each block of a stage once, on
/// one thread) and `crew.wait()` returns once every thread has reached it; `stages` bounds
/// the stage numbers. So a step's stages run in one hand-over instead of one per stage, with
/// no block lists built by the caller.
/// Returns false, having run nothing, when the team is not available (busy with another
/// simulation, or more threads than cores): the caller then runs its stages through
/// [`on_blocks`]. Work of fewer than two `blocks` runs on the calling thread alone, as in
/// [`on_blocks`].
pub(crate) fn region(blocks: usize, stages: usize, f: impl Fn(&Crew) + Sync) -> bool {
    let threads = team_size();
    if threads == 1 || blocks < 2 {
        let claims = Claims::new(stages);
        f(&Crew {
            t: 0,
            threads: 1,
            blocks,
            barrier: &Barrier::new(1),
            claims: &claims,
        });
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
    team.region(blocks, stages, f);
    true
}

/// One thread's view of a [`region`].
pub(crate) struct Crew<'a> {
    /// This thread's number, `0..threads` (0 is the caller).
    pub t: usize,
    pub threads: usize,
    blocks: usize,
    barrier: &'a Barrier,
    /// Per stage and run: how many of the run's blocks have been taken.
    claims: &'a Claims,
}

impl Crew<'_> {
    /// Runs `op(b)` for blocks `b` of stage `stage` (`< stages` of the region) until none is
    /// left: first the blocks of this thread's own run ([`run_of`]), in order from its
    /// front, then those not yet taken of the runs after it, from their backs. Every block of
    /// the stage goes to exactly one call on one thread, once every thread has called `each`
    /// for the stage. On an idle machine each thread takes its own run, as before, and a
    /// thread that finishes early takes at most the last block or two of another's run; a
    /// thread left behind (descheduled by the system) gives its remaining blocks to the
    /// others. Taking from the back leaves the owner's next blocks, and the cache line of
    /// its run's counter, to the owner until the runs meet.
    pub(crate) fn each(&self, stage: usize, mut op: impl FnMut(usize)) {
        for k in 0..self.threads {
            let r = (self.t + k) % self.threads;
            let run = run_of(self.blocks, self.threads, r);
            let taken = &self.claims.0[stage * self.threads + r].0;
            let len = run.len() as u64;
            loop {
                // Blocks taken from the front (low half) and from the back (high half).
                let cur = taken.load(Ordering::Relaxed);
                let (front, back) = (cur & 0xffff_ffff, cur >> 32);
                if front + back >= len {
                    break;
                }
                let next = if k == 0 { cur + 1 } else { cur + (1 << 32) };
                if taken
                    .compare_exchange_weak(cur, next, Ordering::Relaxed, Ordering::Relaxed)
                    .is_err()
                {
                    continue;
                }
                if k == 0 {
                    op(run.start + front as usize);
                } else {
                    if counting_waits() {
                        WAIT_COUNTS[4].fetch_add(1, Ordering::Relaxed);
                    }
                    op(run.end - 1 - back as usize);
                }
            }
        }
    }

    /// Waits until every thread of the region has called `wait` as often as this one (see
    /// [`Barrier::wait`]). Returns false if another thread panicked instead (the caller
    /// should return).
    pub(crate) fn wait(&self) -> bool {
        self.barrier.wait()
    }
}

/// Counters of the blocks taken, one per stage and run, each on a cache line of its own: the
/// blocks taken from the front of the run (by its owner) in the low 32 bits, those taken
/// from its back (by the other threads) in the high 32 bits.
struct Claims(Vec<Padded>);

#[repr(align(128))]
struct Padded(AtomicU64);

impl Claims {
    fn new(n: usize) -> Claims {
        Claims((0..n).map(|_| Padded(AtomicU64::new(0))).collect())
    }
}

/// Where threads sleep after spinning: a waiter that has spun for [`spin_limit`] registers
/// in `sleepers` and sleeps until the condition it waits for holds; whoever makes it hold
/// calls [`Sleep::wake_all`] afterwards. Both sides use sequentially consistent operations
/// on the condition and on `sleepers`, so either the waiter sees the condition before it
/// sleeps or the waker sees the sleeper and takes the lock (no lost wake-up).
struct Sleep {
    sleepers: AtomicUsize,
    lock: Mutex<()>,
    wake: Condvar,
}

impl Sleep {
    fn new() -> Sleep {
        Sleep {
            sleepers: AtomicUsize::new(0),
            lock: Mutex::new(()),
            wake: Condvar::new(),
        }
    }

    /// Returns once `done()` holds: spins for [`spin_limit`], then sleeps. `done` must read
    /// its condition with sequentially consistent loads.
    fn wait_until(&self, kind: WaitKind, done: impl Fn() -> bool) {
        let start = counting_waits().then(Instant::now);
        let slept = !spin_until(&done);
        if slept {
            self.sleepers.fetch_add(1, Ordering::SeqCst);
            let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
            while !done() {
                guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
            }
            drop(guard);
            self.sleepers.fetch_sub(1, Ordering::SeqCst);
        }
        if let Some(start) = start {
            WAIT_COUNTS[kind as usize].fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
            WAIT_COUNTS[3].fetch_add(slept as u64, Ordering::Relaxed);
        }
    }

    /// Wakes the sleepers, if any; called after the condition they wait for was made true
    /// (with a sequentially consistent store or read-modify-write).
    fn wake_all(&self) {
        if self.sleepers.load(Ordering::SeqCst) > 0 {
            let _guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
            self.wake.notify_all();
        }
    }
}

/// A barrier among the threads of one [`region`].
pub(crate) struct Barrier {
    threads: usize,
    arrived: AtomicUsize,
    /// Incremented each time every thread has arrived.
    generation: AtomicUsize,
    /// Set when a thread of the region panicked: the barrier no longer waits.
    abort: AtomicBool,
    sleep: Sleep,
}

impl Barrier {
    fn new(threads: usize) -> Barrier {
        Barrier {
            threads,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            abort: AtomicBool::new(false),
            sleep: Sleep::new(),
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
            self.generation.fetch_add(1, Ordering::SeqCst);
            self.sleep.wake_all();
        } else {
            self.sleep.wait_until(WaitKind::Barrier, || {
                self.generation.load(Ordering::SeqCst) != generation || self.abort.load(Ordering::SeqCst)
            });
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
        self.0
            .done
            .wait_until(WaitKind::Team, || self.0.pending.load(Ordering::SeqCst) == 0);
    }
}

/// Spins until `done()` holds or [`spin_limit`] has passed; returns `done()`.
fn spin_until(done: impl Fn() -> bool) -> bool {
    let limit = spin_limit();
    let start = Instant::now();
    let mut spins = 0u32;
    loop {
        if done() {
            return true;
        }
        std::hint::spin_loop();
        spins = spins.wrapping_add(1);
        if spins.is_multiple_of(256) && start.elapsed() > limit {
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
            if self.pending.fetch_sub(1, Ordering::SeqCst) == 1 {
                self.done.wake_all();
            }
        }
    }

    /// Waits for an epoch other than `seen`: spins for [`spin_limit`], then sleeps.
    fn next_epoch(&self, seen: u64) -> u64 {
        // SeqCst loads, which imply the acquire the job's data needs.
        self.jobs.wait_until(WaitKind::Job, || self.epoch.load(Ordering::SeqCst) != seen);
        self.epoch.load(Ordering::SeqCst)
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
                    let ran = region(n, 2, |crew| {
                        assert_eq!(crew.threads, threads);
                        crew.each(0, |b| {
                            counts[b].fetch_add(1, Ordering::Relaxed);
                        });
                        assert!(crew.wait());
                        let behind = counts.iter().filter(|c| c.load(Ordering::Relaxed) != 2 * rounds + 1).count();
                        wrong.fetch_add(behind, Ordering::Relaxed);
                        // The second stage must not start before every thread has checked.
                        assert!(crew.wait());
                        // Stage 1: every block once more, whichever thread takes it.
                        crew.each(1, |b| {
                            counts[b].fetch_add(1, Ordering::Relaxed);
                        });
                    });
                    rounds += ran as usize;
                }
                assert!(rounds > 0, "{threads} threads: the region never ran");
                assert_eq!(wrong.load(Ordering::Relaxed), 0, "{threads} threads");
                assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == 2 * rounds));
            });
        }
    }

    #[test]
    fn a_panic_in_a_region_reaches_the_caller_and_releases_the_barrier() {
        let team = Team::start(2);
        for bad in [0, 1] {
            let r = catch_unwind(AssertUnwindSafe(|| {
                team.region(2, 1, |crew| {
                    if crew.t == bad {
                        panic!("run {}", crew.t);
                    }
                    assert!(!crew.wait(), "the barrier must not wait for a panicked thread");
                })
            }));
            let msg = r.expect_err("the panic must propagate");
            assert_eq!(
                msg.downcast_ref::<String>().map(String::as_str),
                Some(format!("run {bad}").as_str())
            );
            let sum = AtomicUsize::new(0);
            team.region(2, 1, |crew| {
                assert!(crew.wait());
                sum.fetch_add(crew.t + 1, Ordering::Relaxed);
            });
            assert_eq!(sum.load(Ordering::Relaxed), 3);
        }
    }

    #[test]
    fn a_thread_left_behind_gives_its_blocks_to_the_others() {
        // A team of its own; thread 1 starts its stage long after thread 0 has finished its
        // own run: thread 0 takes every block, each once.
        let team = Team::start(2);
        let n = 8;
        let takers: Vec<AtomicUsize> = (0..n).map(|_| AtomicUsize::new(usize::MAX)).collect();
        let calls = AtomicUsize::new(0);
        team.region(n, 1, |crew| {
            if crew.t == 1 {
                std::thread::sleep(Duration::from_millis(300));
            }
            crew.each(0, |b| {
                calls.fetch_add(1, Ordering::Relaxed);
                takers[b].store(crew.t, Ordering::Relaxed);
            });
        });
        assert_eq!(calls.load(Ordering::Relaxed), n);
        let by: Vec<usize> = takers.iter().map(|t| t.load(Ordering::Relaxed)).collect();
        assert_eq!(by, vec![0; n], "run 1's blocks were not taken over");
    }

    /// CPU time (ns) of the calling thread so far, from `/proc/thread-self/schedstat`.
    #[cfg(target_os = "linux")]
    fn thread_cpu_ns() -> u64 {
        let stat = std::fs::read_to_string("/proc/thread-self/schedstat").expect("schedstat");
        stat.split_whitespace().next().and_then(|v| v.parse().ok()).expect("on-cpu time")
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_thread_waiting_at_a_barrier_sleeps_instead_of_holding_its_core() {
        // The caller reaches the barrier 300 ms before thread 1: it spins for `spin_limit`
        // (50 µs) and then sleeps, so it uses far less CPU than the wait lasts.
        let team = Team::start(2);
        let used = AtomicUsize::new(0);
        team.region(2, 1, |crew| {
            if crew.t == 1 {
                std::thread::sleep(Duration::from_millis(300));
                assert!(crew.wait());
            } else {
                let (cpu, start) = (thread_cpu_ns(), Instant::now());
                assert!(crew.wait());
                assert!(start.elapsed() >= Duration::from_millis(250), "the barrier did not wait");
                used.store((thread_cpu_ns() - cpu) as usize, Ordering::Relaxed);
            }
        });
        let used = Duration::from_nanos(used.load(Ordering::Relaxed) as u64);
        assert!(used < Duration::from_millis(30), "the waiting thread used {used:?} of CPU");
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
