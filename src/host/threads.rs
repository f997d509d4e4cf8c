//! How many threads a run uses when the scene says `run.threads = 0` ("choose"): no more
//! than the work per step can feed, and no more than the cores that are actually idle.
//!
//! Why: the force and drift passes fork and join several times per step. With fewer than
//! about [`GRAINS_PER_THREAD`] grains per thread the joins cost more than the work they
//! share, and on a machine where other processes hold the cores a thread that is not
//! scheduled stalls every join of the step; the issue that asked for this measured a 200-grain
//! run 1.5x-24x slower with all cores than with one, under load. One thread never waits for
//! another, so it is the safe choice whenever the extra cores are busy or the work is small.

/// Grains per thread below which another thread does not pay for its joins. At 4000 grains
/// two threads gave 1.12x one thread on an idle machine (docs/performance-history.md), so the
/// break-even lies below that; 1500 keeps 200-1000-grain scenes on one thread.
pub const GRAINS_PER_THREAD: usize = 1500;

/// How long the idle cores are sampled (`/proc/stat`, Linux).
const SAMPLE: std::time::Duration = std::time::Duration::from_millis(200);

/// The thread count for a run of `grains` grains: `requested` if it is not 0, else the
/// smallest of the cores, the idle cores, and `grains / GRAINS_PER_THREAD` (at least 1).
/// Returns the count and why, for the summary.
pub fn choose(requested: usize, grains: usize) -> (usize, String) {
    if requested > 0 {
        return (requested, "run.threads".into());
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let by_work = (grains / GRAINS_PER_THREAD).max(1);
    // Sampling the idle cores takes a moment; only worth it when more than one thread could run.
    let idle = if cores.min(by_work) > 1 { idle_cores(cores) } else { None };
    let n = cores.min(by_work).min(idle.unwrap_or(cores)).max(1);
    let idle_text = idle.map_or("unknown".to_string(), |k| k.to_string());
    (
        n,
        format!("run.threads = 0: {cores} cores, {idle_text} idle, {grains} grains allow {by_work} (one per {GRAINS_PER_THREAD} grains)"),
    )
}

/// Cores idle over a short sample of `/proc/stat`: all cores but those held by other work
/// (see [`idle_share_to_cores`]). `None` where `/proc/stat` is missing.
fn idle_cores(cores: usize) -> Option<usize> {
    let a = cpu_times()?;
    std::thread::sleep(SAMPLE);
    let b = cpu_times()?;
    let (busy, idle) = (b.0.saturating_sub(a.0), b.1.saturating_sub(a.1));
    if busy + idle == 0 {
        return None;
    }
    Some(idle_share_to_cores(idle as f64 / (busy + idle) as f64, cores))
}

/// Whole idle cores from an idle share: a core counts as held only when other work keeps it
/// more than 75% busy, so that short bursts (a shell starting the run, a pipe's reader) do
/// not cost a thread, while a busy process per core leaves none.
fn idle_share_to_cores(share: f64, cores: usize) -> usize {
    let held = ((1.0 - share) * cores as f64 + 0.25).floor() as usize;
    cores.saturating_sub(held)
}

/// `(busy, idle)` jiffies of all CPUs from the first line of `/proc/stat` (idle includes
/// iowait).
fn cpu_times() -> Option<(u64, u64)> {
    let text = std::fs::read_to_string("/proc/stat").ok()?;
    parse_cpu_line(text.lines().next()?)
}

fn parse_cpu_line(line: &str) -> Option<(u64, u64)> {
    let mut f = line.split_whitespace();
    if f.next()? != "cpu" {
        return None;
    }
    let v: Vec<u64> = f.filter_map(|x| x.parse().ok()).collect();
    if v.len() < 4 {
        return None;
    }
    // user nice system idle iowait irq softirq steal (guest times are inside user).
    let idle = v[3] + v.get(4).copied().unwrap_or(0);
    let busy = v[..3].iter().sum::<u64>() + v.iter().skip(5).take(3).sum::<u64>();
    Some((busy, idle))
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
        assert!((1..=cores).contains(&n), "{n} of {cores}: {why}");
    }

    #[test]
    fn proc_stat_lines_give_busy_and_idle_time() {
        let (busy, idle) = parse_cpu_line("cpu  100 5 50 800 20 3 2 1 0 0").unwrap();
        assert_eq!((busy, idle), (100 + 5 + 50 + 3 + 2 + 1, 820));
        assert!(parse_cpu_line("cpu0 1 2 3 4").is_none());
        assert!(parse_cpu_line("cpu 1 2").is_none());
        // Two cores, one held by another process: one idle core; both busy: none; a burst
        // of a third of a core: both idle.
        assert_eq!(idle_share_to_cores(0.5, 2), 1);
        assert_eq!(idle_share_to_cores(0.02, 2), 0);
        assert_eq!(idle_share_to_cores(0.97, 2), 2);
        assert_eq!(idle_share_to_cores(0.7, 2), 2);
        assert_eq!(idle_share_to_cores(0.3, 2), 1);
    }
}
