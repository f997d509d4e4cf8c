//! How many threads a run uses when the scene says `run.threads = 0` ("choose"): no more
//! than the cores, and no more than the work per step can feed.
//!
//! Why: with fewer than about [`GRAINS_PER_THREAD`] grains per thread the hand-overs of a
//! step cost more than the work they share. The load of the machine is no longer sampled
//! here (it was: the idle cores over 0.2 s at the start): the run's pace
//! (`particles::pace`) measures the rate of every team size up to this count while the run
//! goes, steps on the fastest, and follows the load as it changes, up as well as down.

/// Grains per thread below which another thread does not pay for its joins. At 4000 grains
/// two threads gave 1.12x one thread on an idle machine (docs/performance-history.md), so the
/// break-even lies below that; 1500 keeps 200-1000-grain scenes on one thread.
pub const GRAINS_PER_THREAD: usize = 1500;

/// The thread count for a run of `grains` grains: `requested` if it is not 0, else the
/// smaller of the cores and `grains / GRAINS_PER_THREAD` (at least 1). Returns the count
/// and why, for the summary.
pub fn choose(requested: usize, grains: usize) -> (usize, String) {
    if requested > 0 {
        return (requested, "run.threads".into());
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let by_work = (grains / GRAINS_PER_THREAD).max(1);
    let n = cores.min(by_work).max(1);
    (
        n,
        format!(
            "run.threads = 0: {cores} cores, {grains} grains allow {by_work} (one per {GRAINS_PER_THREAD} grains); \
             the pace steps on fewer where fewer are faster"
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_requested_count_is_kept_and_small_scenes_get_one_thread() {
        assert_eq!(choose(3, 10).0, 3);
        assert_eq!(choose(0, 200).0, 1);
        assert_eq!(choose(0, GRAINS_PER_THREAD - 1).0, 1);
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let (n, why) = choose(0, 1_000_000);
        assert_eq!(n, cores, "{why}");
    }
}
