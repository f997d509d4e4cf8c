//! `stripes run` is reproducible: the same seed gives the same `state_hash` with 1 and 2
//! threads, and a run killed mid-way (as `kill -9` would, via the hidden `--stop-after` hook)
//! and resumed from its last checkpoint ends bit-identical to an uninterrupted run, with the
//! same snapshot stream, without the prepared sample.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

/// A reduced thesis tray: 600 grains on a 6 cm strip at the thesis packing, 0.06 s of shaking
/// (7500 steps), a checkpoint every 0.02 s. 600 grains fill five force blocks, so two
/// threads really split the work.
const SMALL: &[&str] = &[
    "particles.count=600",
    "box.length=0.06",
    "prepare.duration=0.01",
    "run.duration=0.06",
    "run.checkpoint_interval=0.02",
    "run.dt=8e-6", // the scene's "auto" would change with the collision lab; pin the step
];

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("stripes-det-{}-{name}", std::process::id()))
}

fn run(out: &Path, samples: &Path, extra: &[&str]) -> Output {
    let mut all = vec!["--quiet"];
    all.extend_from_slice(extra);
    common::run("thesis-reference.toml", out, Some(samples), SMALL, &all)
}

use common::summary;

#[test]
fn same_seed_same_state_for_one_and_two_threads_and_after_a_kill_and_resume() {
    for d in ["samples", "no-samples", "t1", "t2", "killed"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
    let samples = tmp("samples");
    let one = summary(&run(&tmp("t1"), &samples, &["--set", "run.threads=1"]));
    let two = summary(&run(&tmp("t2"), &samples, &["--set", "run.threads=2"]));
    assert_eq!(one["steps"], 7500);
    assert_eq!(one["state_hash"], two["state_hash"], "thread count changed the result");
    assert_eq!(one["energy"], two["energy"]);

    // Killed at step 6000: the last checkpoint is at step 5000 (0.04 s).
    let dir = tmp("killed");
    let killed = run(&dir, &samples, &["--set", "run.threads=2", "--stop-after", "6000"]);
    assert!(!killed.status.success());
    assert!(dir.join("checkpoint.bin").exists());
    let data = dir.join("resumed.data");
    // The resume gets an empty sample cache: it needs no prepared sample (the checkpoint holds
    // every moving quantity) and prepares none.
    let no_samples = tmp("no-samples");
    let resumed = summary(&run(
        &dir,
        &no_samples,
        &["--set", "run.threads=1", "--resume", "--lammps-data", data.to_str().unwrap()],
    ));
    assert_eq!(resumed["state_hash"], one["state_hash"], "resume diverged");
    assert!(!no_samples.exists(), "the resume prepared a sample");
    assert_eq!(resumed["sample_cached"], false);
    // The LAMMPS data file holds the state the resumed run started from: the checkpoint.
    let data = std::fs::read_to_string(&data).unwrap();
    assert!(
        data.lines().next().unwrap().contains("t = 0.04"),
        "{}",
        data.lines().next().unwrap()
    );
    assert!(data.contains("\n600 atoms\n"));
    let atoms: Vec<Vec<f64>> = data
        .split("Atoms # sphere\n\n")
        .nth(1)
        .unwrap()
        .lines()
        .take(600)
        .map(|l| l.split(' ').map(|w| w.parse().unwrap()).collect())
        .collect();
    for a in &atoms {
        let (d, x, y, z) = (a[2], a[4], a[5], a[6]);
        assert!(
            (0.5e-3..=1e-3).contains(&d) && (0.0..0.06).contains(&x) && (0.0..0.02).contains(&y) && z > 0.0,
            "{a:?}"
        );
    }
    assert_eq!(resumed["snapshots"], one["snapshots"]);
    let a = std::fs::read(tmp("t1").join("snapshots.bin")).unwrap();
    let b = std::fs::read(dir.join("snapshots.bin")).unwrap();
    assert!(a == b, "the resumed snapshot stream differs from the uninterrupted one");

    for d in ["samples", "no-samples", "t1", "t2", "killed"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
}

/// Issue 43: a run writes its first checkpoint within a few seconds of wall time whatever
/// `run.checkpoint_interval` says (here none), so one stopped early can be resumed, bit for
/// bit; and `--resume` on a run stopped before any checkpoint says what it holds instead of
/// "nothing was written". The wall-clock deadline is the hidden `--first-checkpoint-after`
/// (3 s by default), 0 here so that the test does not depend on the machine's speed.
#[test]
fn a_first_checkpoint_comes_early_and_the_resume_message_is_true() {
    for d in ["early-samples", "early-whole", "early-killed", "early-none"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
    let samples = tmp("early-samples");
    let none = ["--set", "run.checkpoint_interval=0", "--set", "run.threads=1"];
    let whole = summary(&run(&tmp("early-whole"), &samples, &none));
    let dir = tmp("early-killed");
    let mut args = none.to_vec();
    args.extend(["--first-checkpoint-after", "0", "--stop-after", "3000"]);
    assert!(!run(&dir, &samples, &args).status.success());
    assert!(dir.join("checkpoint.bin").is_file(), "no checkpoint before the kill");
    let mut resume = none.to_vec();
    resume.push("--resume");
    let resumed = summary(&run(&dir, &samples, &resume));
    assert_eq!(
        resumed["state_hash"], whole["state_hash"],
        "the resume from the early checkpoint diverged"
    );

    let dir = tmp("early-none");
    let mut args = none.to_vec();
    args.extend(["--first-checkpoint-after", "1000", "--stop-after", "300"]);
    assert!(!run(&dir, &samples, &args).status.success());
    assert!(!dir.join("checkpoint.bin").exists());
    let refused = run(&dir, &samples, &resume);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(
        !stderr.contains("nothing was written") && stderr.contains("before a first checkpoint") && stderr.contains("MB)"),
        "{stderr}"
    );
    for d in ["early-samples", "early-whole", "early-killed", "early-none"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
}
