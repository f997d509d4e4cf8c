//! On-CPU timing of one thread, for the speed measurements (`stripes bench`, `stripes
//! automaton --bench`).

use std::time::Instant;

/// A stopwatch of the time the calling thread spent on a CPU (Linux
/// `/proc/thread-self/schedstat`, nanoseconds), falling back to wall time where that file
/// is missing. On a shared machine, wall time mostly measures the neighbours' load; the
/// on-CPU time of the one worker thread is the wall time the same work takes on an idle
/// core. (With more than one worker thread, use wall time: see `tradeoff::Config::cpu_time`.)
#[derive(Clone, Copy, Debug)]
pub struct Stopwatch {
    cpu: bool,
    wall: Instant,
    start_cpu: f64,
}

fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

impl Stopwatch {
    /// Starts; `cpu` asks for on-CPU time of this thread if available.
    pub fn start(cpu: bool) -> Self {
        let start_cpu = if cpu { thread_cpu_seconds() } else { None };
        Self {
            cpu: start_cpu.is_some(),
            wall: Instant::now(),
            start_cpu: start_cpu.unwrap_or(0.0),
        }
    }

    /// Seconds since the start.
    pub fn seconds(&self) -> f64 {
        match (self.cpu, thread_cpu_seconds()) {
            // A run shorter than the kernel's accounting granularity reads 0: use wall time.
            (true, Some(now)) if now > self.start_cpu => now - self.start_cpu,
            _ => self.wall.elapsed().as_secs_f64(),
        }
    }
}
