//! How many of the run's threads a step uses: the team size with the best measured rate.
//!
//! A run asked for `T` threads steps on `T` only while that is faster than fewer. On a
//! machine whose cores other processes also want, a team of two can run at half the rate of
//! one thread or less (issue 41: with one busy process beside a two-thread run on two cores,
//! 0.49-0.59x of one thread), because every stage waits for the slowest thread and the
//! system deschedules one of them for milliseconds at a time. No wait strategy removes that
//! loss; choosing the team size by measurement does.
//!
//! The sizes tried are the ladder `1, 2, 4, ..., T` (and `T` itself). Steps are timed in
//! windows of about [`WINDOW`] of wall time; every so many windows one window runs at a
//! neighbouring size of the ladder (a probe, alternately the next smaller and the next
//! larger), and the run moves to it when it steps faster by more than [`MARGIN`]. A probe
//! that loses doubles the interval to the next (up to [`MAX_INTERVAL`] windows), so that a
//! clearly worse size costs at most about one window in `MAX_INTERVAL`; a window whose rate
//! has fallen by [`SLOWDOWN`] from the rate the current size was chosen at (the load has
//! changed) probes at once. A window ends after its wall time whatever its size, so a probe
//! of a size that runs ten times slower still costs `PROBE` of time, not ten times that.
//!
//! Which size runs a step changes no result: every size evaluates the same blocks and adds
//! their sums in block order (`crate::parallel`). Set the environment variable
//! `STRIPES_FIXED_TEAM` to keep every step on `T` threads (for measurements of scaling).

use std::sync::OnceLock;
use std::time::Duration;

/// The wall time of a window of steps.
pub const WINDOW: Duration = Duration::from_millis(40);
/// The wall time of a probe's window: half a window, so that a size that loses costs less.
pub const PROBE: Duration = Duration::from_millis(20);
/// The windows between two probes at first and after a change of size.
pub const FIRST_INTERVAL: u32 = 4;
/// The most windows between two probes.
pub const MAX_INTERVAL: u32 = 64;
/// A probe wins when its time per step is below the current size's by more than this
/// fraction.
pub const MARGIN: f64 = 0.03;
/// A window slower than the current size's chosen rate by this fraction probes at once.
pub const SLOWDOWN: f64 = 0.3;

/// The team size of the next step, from the times of the steps so far.
#[derive(Clone, Debug)]
pub struct Pace {
    /// The threads asked for (`T`); 0 until the first step.
    asked: usize,
    /// The ladder of sizes `1, 2, 4, ..., T`.
    sizes: Vec<usize>,
    /// Index into `sizes` of the size the run steps at.
    current: usize,
    /// Index of the size of the window in progress (`current` unless it is a probe).
    running: usize,
    /// Steps and wall time of the window in progress.
    steps: u32,
    elapsed: Duration,
    /// Seconds per step of the current size's last window.
    current_rate: Option<f64>,
    /// Seconds per step when the current size was chosen (or last confirmed by a probe).
    chosen_rate: Option<f64>,
    /// Windows since the last probe, and the windows between probes.
    since_probe: u32,
    interval: u32,
    /// Whether the next probe goes down the ladder (else up).
    down_next: bool,
    /// Whether every step runs on `T` (`STRIPES_FIXED_TEAM`).
    fixed: bool,
}

impl Default for Pace {
    fn default() -> Pace {
        Pace::new(fixed_by_environment())
    }
}

/// Whether `STRIPES_FIXED_TEAM` is set (read once).
fn fixed_by_environment() -> bool {
    static FIXED: OnceLock<bool> = OnceLock::new();
    *FIXED.get_or_init(|| std::env::var_os("STRIPES_FIXED_TEAM").is_some())
}

impl Pace {
    /// A pace that chooses the team size by measured rate, or (with `fixed`) always uses
    /// every thread asked for.
    pub fn new(fixed: bool) -> Pace {
        Pace {
            asked: 0,
            sizes: vec![1],
            current: 0,
            running: 0,
            steps: 0,
            elapsed: Duration::ZERO,
            current_rate: None,
            chosen_rate: None,
            since_probe: 0,
            interval: FIRST_INTERVAL,
            down_next: true,
            fixed,
        }
    }

    /// The team size for the next step of a run asked for `asked` threads.
    pub fn threads(&mut self, asked: usize) -> usize {
        let asked = asked.max(1);
        if self.fixed {
            self.asked = asked;
            return asked;
        }
        if asked != self.asked {
            // First step, or the run's thread count changed: start over at the full team.
            *self = Pace {
                asked,
                sizes: ladder(asked),
                ..Pace::new(false)
            };
            self.current = self.sizes.len() - 1;
            self.running = self.current;
            // The first probe right after the first window.
            self.since_probe = FIRST_INTERVAL - 1;
        }
        self.sizes[self.running]
    }

    /// Books one step that took `took` at the size [`Self::threads`] returned.
    pub fn record(&mut self, took: Duration) {
        if self.fixed || self.sizes.len() < 2 {
            return;
        }
        self.steps += 1;
        self.elapsed += took;
        let probing = self.running != self.current;
        if self.elapsed < if probing { PROBE } else { WINDOW } {
            return;
        }
        let rate = self.elapsed.as_secs_f64() / self.steps as f64;
        (self.steps, self.elapsed) = (0, Duration::ZERO);
        if probing {
            self.end_probe(rate);
        } else {
            self.end_window(rate);
        }
    }

    /// The size the run steps at now (for reports and tests): every thread asked for when
    /// fixed.
    pub fn current(&self) -> usize {
        if self.fixed {
            return self.asked.max(1);
        }
        self.sizes[self.current]
    }

    fn end_window(&mut self, rate: f64) {
        self.current_rate = Some(rate);
        let chosen = *self.chosen_rate.get_or_insert(rate);
        self.since_probe += 1;
        let slowed = rate > chosen * (1.0 + SLOWDOWN);
        if slowed {
            self.interval = FIRST_INTERVAL;
        }
        if slowed || self.since_probe >= self.interval {
            self.running = self.probe_size();
        }
    }

    fn end_probe(&mut self, rate: f64) {
        let current = self.current_rate.unwrap_or(f64::INFINITY);
        self.since_probe = 0;
        if rate < current * (1.0 - MARGIN) {
            self.current = self.running;
            self.current_rate = Some(rate);
            self.chosen_rate = Some(rate);
            self.interval = FIRST_INTERVAL;
        } else {
            self.running = self.current;
            self.chosen_rate = self.current_rate;
            self.interval = (self.interval * 2).min(MAX_INTERVAL);
        }
    }

    /// The neighbour of the current size to probe next: alternately down and up the ladder,
    /// the other way at either end.
    fn probe_size(&mut self) -> usize {
        let top = self.sizes.len() - 1;
        let down = (self.down_next && self.current > 0) || self.current == top;
        self.down_next = !down;
        if down {
            self.current - 1
        } else {
            self.current + 1
        }
    }
}

/// `1, 2, 4, ...` below `asked`, then `asked`.
fn ladder(asked: usize) -> Vec<usize> {
    let mut sizes: Vec<usize> = std::iter::successors(Some(1usize), |s| Some(s * 2))
        .take_while(|&s| s < asked)
        .collect();
    sizes.push(asked);
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `steps` steps of a machine on which a step at size `s` takes `time(s, step)`;
    /// returns the sizes used and the total time.
    fn drive(pace: &mut Pace, asked: usize, steps: usize, time: impl Fn(usize, usize) -> Duration) -> (Vec<usize>, Duration) {
        let mut used = Vec::with_capacity(steps);
        let mut total = Duration::ZERO;
        for k in 0..steps {
            let s = pace.threads(asked);
            let took = time(s, k);
            pace.record(took);
            used.push(s);
            total += took;
        }
        (used, total)
    }

    fn us(x: f64) -> Duration {
        Duration::from_secs_f64(x * 1e-6)
    }

    #[test]
    fn the_ladder_doubles_up_to_the_threads_asked() {
        assert_eq!(ladder(1), vec![1]);
        assert_eq!(ladder(2), vec![1, 2]);
        assert_eq!(ladder(6), vec![1, 2, 4, 6]);
        assert_eq!(ladder(16), vec![1, 2, 4, 8, 16]);
    }

    #[test]
    fn one_thread_asked_is_one_thread_and_a_fixed_pace_keeps_every_thread() {
        let mut pace = Pace::new(false);
        let (used, _) = drive(&mut pace, 1, 10_000, |_, _| us(100.0));
        assert!(used.iter().all(|&s| s == 1));
        let mut fixed = Pace::new(true);
        let (used, _) = drive(&mut fixed, 2, 10_000, |s, _| us(if s == 2 { 1000.0 } else { 100.0 }));
        assert!(used.iter().all(|&s| s == 2));
        assert_eq!(fixed.current(), 2);
    }

    #[test]
    fn an_idle_machine_keeps_the_faster_full_team_and_loses_little_to_probes() {
        // Two threads 1.6x one: the run starts and stays on two; the probes of one thread
        // cost under 1 % once the interval has grown.
        let mut pace = Pace::new(false);
        let time = |s: usize, _| us(if s == 2 { 100.0 } else { 160.0 });
        let (used, total) = drive(&mut pace, 2, 400_000, time);
        assert_eq!(pace.current(), 2);
        let ideal = us(100.0) * 400_000;
        let loss = total.as_secs_f64() / ideal.as_secs_f64() - 1.0;
        assert!(loss < 0.01, "probes cost {loss:.4}");
        assert!(used.iter().filter(|&&s| s == 1).count() > 0, "never probed");
    }

    #[test]
    fn a_loaded_machine_moves_to_one_thread_and_a_ten_times_slower_team_costs_little() {
        // Two threads ten times slower than one (a heavily oversubscribed machine): the run
        // moves to one thread within the first windows, and the later probes of two threads
        // (each half a window of wall time) cost a few per cent.
        let mut pace = Pace::new(false);
        let time = |s: usize, _| us(if s == 2 { 1000.0 } else { 100.0 });
        let (used, total) = drive(&mut pace, 2, 400_000, time);
        assert_eq!(pace.current(), 1);
        let first_one = used.iter().position(|&s| s == 1).unwrap();
        assert!(first_one < 100, "stayed on two threads for {first_one} steps");
        let ideal = us(100.0) * 400_000;
        let loss = total.as_secs_f64() / ideal.as_secs_f64() - 1.0;
        assert!(loss < 0.05, "the pace lost {loss:.3} against one thread");
    }

    #[test]
    fn a_change_of_load_moves_the_team_both_ways() {
        // Idle (two threads 1.6x one), then loaded (two threads 0.5x one), then idle again.
        let mut pace = Pace::new(false);
        let phase = |k: usize| (k / 200_000) % 2 == 1;
        let time = |s: usize, k: usize| {
            let loaded = phase(k);
            us(match (s, loaded) {
                (2, false) => 100.0,
                (1, false) => 160.0,
                (2, true) => 320.0,
                _ => 160.0,
            })
        };
        let (used, _) = drive(&mut pace, 2, 600_000, time);
        let share_on_two =
            |range: std::ops::Range<usize>| used[range.clone()].iter().filter(|&&s| s == 2).count() as f64 / range.len() as f64;
        assert!(share_on_two(50_000..200_000) > 0.97, "idle: {}", share_on_two(50_000..200_000));
        assert!(share_on_two(250_000..400_000) < 0.05, "loaded: {}", share_on_two(250_000..400_000));
        assert!(
            share_on_two(450_000..600_000) > 0.9,
            "idle again: {}",
            share_on_two(450_000..600_000)
        );
    }

    #[test]
    fn many_threads_climb_down_the_ladder_to_the_fastest_size() {
        // 16 threads asked; the machine's rate peaks at 4 (the other cores busy).
        let mut pace = Pace::new(false);
        let time = |s: usize, _| {
            us(match s {
                1 => 400.0,
                2 => 210.0,
                4 => 120.0,
                8 => 300.0,
                _ => 900.0,
            })
        };
        drive(&mut pace, 16, 300_000, time);
        assert_eq!(pace.current(), 4);
    }

    #[test]
    fn noise_within_the_margin_does_not_move_the_team() {
        // Two threads and one equal to within 2 %, with 1 % noise per step: the pace may
        // move, but every size it steps at is within the margin of the best.
        let mut pace = Pace::new(false);
        let time = |s: usize, k: usize| {
            let noise = 1.0 + 0.01 * (((k * 7919) % 13) as f64 / 6.0 - 1.0);
            us(if s == 2 { 100.0 } else { 102.0 } * noise)
        };
        let (_, total) = drive(&mut pace, 2, 200_000, time);
        let ideal = us(100.0) * 200_000;
        assert!(total.as_secs_f64() / ideal.as_secs_f64() < 1.03);
    }
}
