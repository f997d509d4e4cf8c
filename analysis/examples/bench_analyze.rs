//! Benchmark of the whole analysis (`analysis::report::Analyzer`), not a test: N grains x F
//! snapshots of a synthetic striped layer at the thesis packing (box length scaled with N:
//! L = 0.4 m x N / 4000, W = 0.02 m, radii uniform in [0.25, 0.5] mm, half the grains in
//! 2 cm bands every 10 cm, every grain displaced by up to +-1 mm per period). Frames are
//! generated in batches outside the timed region; only `push` and `finish` are timed.
//!
//!   RAYON_NUM_THREADS=1 cargo run --release -p analysis --example bench_analyze
//!   RAYON_NUM_THREADS=2 cargo run --release -p analysis --example bench_analyze -- 100000 1000
//!
//! Prints one JSON line: particles, frames, threads, wall and CPU seconds of the analysis, the
//! load average (the machine may be shared), and a digest of the results
//! (equal for every thread count).

use std::time::Instant;

use analysis::report::{Analyzer, Options};
use analysis::snapshot::{Frame, Header};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// CPU time of this process, all threads (s), from /proc/self/stat (utime + stime, in
/// clock ticks of 1/100 s); NaN where unavailable. The machine is shared, so wall time alone
/// overstates the cost when other jobs run.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<&str> = rest.split_whitespace().collect();
    match (
        f.get(11).and_then(|v| v.parse::<f64>().ok()),
        f.get(12).and_then(|v| v.parse::<f64>().ok()),
    ) {
        (Some(u), Some(s)) => (u + s) / 100.0,
        _ => f64::NAN,
    }
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| {
            a.parse()
                .unwrap_or_else(|_| panic!("usage: bench_analyze [PARTICLES] [FRAMES], got `{a}`"))
        })
        .collect();
    let n = args.first().copied().unwrap_or(100_000);
    let frames = args.get(1).copied().unwrap_or(1000);
    let (length, width, period) = (0.4 * n as f64 / 4000.0, 0.02, 0.05);
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let radii: Vec<f64> = (0..n).map(|_| rng.gen_range(2.5e-4..5e-4)).collect();
    let bands = (length / 0.1).round().max(1.0) as usize;
    let base: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let x = if i % 2 == 0 {
                let b = rng.gen_range(0..bands) as f64;
                (b * 0.1 + rng.gen_range(0.0..0.02)).rem_euclid(length)
            } else {
                rng.gen_range(0.0..length)
            };
            [x, rng.gen_range(radii[i]..width - radii[i]), radii[i]]
        })
        .collect();
    let header = Header { length, width, radii };
    let opts = Options::default();
    let threads = rayon::current_num_threads();
    let (start, cpu0) = (Instant::now(), cpu_seconds());
    let mut analyzer = Analyzer::new(&header, &opts, Some(period)).expect("valid synthetic header");
    let mut timed = start.elapsed().as_secs_f64();
    let mut cpu = cpu_seconds() - cpu0;
    let batch = 16;
    let mut made = 0;
    while made < frames {
        let k = batch.min(frames - made);
        let chunk: Vec<Frame> = (made..made + k)
            .map(|f| Frame {
                time: f as f64 * period,
                pos: base
                    .iter()
                    .map(|p| [(p[0] + rng.gen_range(-1e-3..1e-3)).rem_euclid(length), p[1], p[2]])
                    .collect(),
                vel: vec![[0.0; 3]; n],
            })
            .collect();
        let (t, c) = (Instant::now(), cpu_seconds());
        analyzer.push(&chunk).expect("valid synthetic frames");
        timed += t.elapsed().as_secs_f64();
        cpu += cpu_seconds() - c;
        made += k;
    }
    let (t, c) = (Instant::now(), cpu_seconds());
    let report = analyzer.finish().expect("frames were pushed");
    timed += t.elapsed().as_secs_f64();
    cpu += cpu_seconds() - c;
    let s = report.summary();
    let digest: f64 = report.density_map.iter().flatten().sum::<f64>() + report.msd.iter().map(|p| p.d).sum::<f64>();
    println!(
        "{}",
        serde_json::json!({
            "particles": n,
            "frames": frames,
            "cells": report.cells,
            "threads": threads,
            "analysis_s": timed,
            "analysis_cpu_s": cpu,
            "load_average": std::fs::read_to_string("/proc/loadavg").ok().and_then(|l| l.split_whitespace().next().map(str::to_string)),
            "ms_per_frame": 1e3 * timed / frames as f64,
            "stripe_count_final": s.stripe_count_final,
            "phase": s.phase,
            "contrast": s.contrast,
            "mobility": s.mobility,
            "digest": digest,
        })
    );
}
