//! A drive schedule (`[[drive.stages]]`) through `stripes run`: a run killed in its second
//! stage and resumed ends bit-identical to an uninterrupted one, with the same snapshot
//! stream; the summary says when each stage starts; the snapshots sit at each stage's turning
//! points; and the single drive of today's scenes gives the same bits as a one-stage schedule.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("stripes-sched-{}-{name}", std::process::id()))
}

/// 300 grains on a 5 x 2 cm tray with end walls: one period at 20 Hz / 5 mm (0.05 s), then
/// 10 Hz / 4 mm to 0.1 s; 12500 steps of 8e-6 s, a checkpoint every 0.02 s.
const STAGED: &str = "[box]\nlength = 0.05\nwidth = 0.02\nx_walls = true\n\
    [drive]\n[[drive.stages]]\nfrequency = 20.0\namplitude = 0.005\nduration = 0.05\n\
    [[drive.stages]]\nfrequency = 10.0\namplitude = 0.004\nduration = 0.05\n\
    [particles]\ncount = 300\nradius_min = 0.25e-3\nradius_max = 0.5e-3\n[prepare]\nduration = 0.01\n\
    [run]\nduration = 0.1\ndt = 8e-6\nseed = 2\nsnapshots_per_period = 2\ncheckpoint_interval = 0.02\n";

fn write_scene(dir: &Path, name: &str, text: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn run(scene: &Path, out: &Path, samples: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stripes"))
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .arg("--sample-cache")
        .arg(samples)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap()
}

fn frame_times(dir: &Path) -> Vec<f64> {
    let (_, frames) = analysis::snapshot::read_snapshots(&dir.join("snapshots.bin")).unwrap();
    frames.iter().map(|f| f.time).collect()
}

#[test]
fn a_run_resumed_in_the_second_stage_is_bit_identical_and_snapshots_follow_each_stage() {
    for d in ["scenes", "samples", "whole", "killed"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
    let scene = write_scene(&tmp("scenes"), "staged.toml", STAGED);
    let samples = tmp("samples");
    let whole = common::summary(&run(&scene, &tmp("whole"), &samples, &["--set", "run.threads=1"]));
    assert_eq!(whole["steps"], 12500);
    let stages = whole["drive_stages"].as_array().unwrap();
    assert_eq!(stages.len(), 2);
    assert_eq!(stages[0]["start_s"], 0.0);
    assert_eq!(stages[1]["start_s"], 0.05);
    assert_eq!(stages[1]["frequency"], 10.0);

    // Killed at step 9000 (0.072 s): the last checkpoint is at step 7500 (0.06 s), in the
    // second stage.
    let dir = tmp("killed");
    let killed = run(&scene, &dir, &samples, &["--set", "run.threads=2", "--stop-after", "9000"]);
    assert!(!killed.status.success());
    let resumed = common::summary(&run(&scene, &dir, &samples, &["--set", "run.threads=1", "--resume"]));
    assert_eq!(resumed["state_hash"], whole["state_hash"], "resume across stages diverged");
    assert_eq!(resumed["energy"], whole["energy"]);
    let (a, b) = (
        std::fs::read(tmp("whole").join("snapshots.bin")).unwrap(),
        std::fs::read(dir.join("snapshots.bin")).unwrap(),
    );
    assert!(a == b, "the resumed run's snapshot stream differs");

    // Snapshots: frame 0 at t = 0, then two per period of each stage from its turning point:
    // 20 Hz from 0.0125 s every 0.025 s (2 before 0.05 s), then 10 Hz from 0.075 s every
    // 0.05 s (one before 0.1 s).
    let times = frame_times(&tmp("whole"));
    let expect = [0.0, 0.0125, 0.0375, 0.075];
    assert_eq!(times.len(), expect.len(), "{times:?}");
    for (t, e) in times.iter().zip(expect) {
        assert!((t - e).abs() <= 0.5 * 8e-6 + 1e-12, "{times:?}");
    }
    for d in ["scenes", "samples", "whole", "killed"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
}

#[test]
fn the_single_drive_is_a_one_stage_schedule_to_the_bit_and_shares_its_sample() {
    for d in ["one-scenes", "one-samples", "single", "one-stage"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
    let single = STAGED.replace(
        "[drive]\n[[drive.stages]]\nfrequency = 20.0\namplitude = 0.005\nduration = 0.05\n\
         [[drive.stages]]\nfrequency = 10.0\namplitude = 0.004\nduration = 0.05\n",
        "[drive]\nfrequency = 20.0\namplitude = 0.005\n",
    );
    assert_ne!(single, STAGED);
    let one_stage = STAGED
        .replace("[[drive.stages]]\nfrequency = 10.0\namplitude = 0.004\nduration = 0.05\n", "")
        .replace("duration = 0.05\n[particles]", "duration = 0.1\n[particles]");
    let dir = tmp("one-scenes");
    let samples = tmp("one-samples");
    let a = common::summary(&run(&write_scene(&dir, "single.toml", &single), &tmp("single"), &samples, &[]));
    let b = common::summary(&run(&write_scene(&dir, "one.toml", &one_stage), &tmp("one-stage"), &samples, &[]));
    assert_eq!(a["state_hash"], b["state_hash"]);
    assert_eq!(a["snapshots"], b["snapshots"]);
    // The schedule does not enter the sample: the second run found it prepared.
    assert_eq!(b["sample_cached"], true);
    assert_eq!(a["sample_key"], b["sample_key"]);
    assert_eq!(a["drive_stages"], b["drive_stages"]);
    for d in ["one-scenes", "one-samples", "single", "one-stage"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
}
