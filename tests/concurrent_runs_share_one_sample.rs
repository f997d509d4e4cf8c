//! Issue 20, point 4: one sample per sweep. Two processes that start together and need the
//! same sample prepare it once: the first takes the lock file beside the sample, the other
//! waits and loads what the first wrote. Without the lock both would prepare it (both
//! summaries would say `sample_cached: false`).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stripes-sample-once-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn two_concurrent_runs_needing_one_sample_prepare_it_once() {
    let cache = tmp("cache");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/quick.toml");
    // Preparation long enough (about a second) that the two processes overlap in it.
    let start = |k: usize| {
        Command::new(env!("CARGO_BIN_EXE_stripes"))
            .arg("run")
            .arg(&scene)
            .args(["--quiet", "--out"])
            .arg(tmp(&format!("run{k}")))
            .arg("--sample-cache")
            .arg(&cache)
            .args(["--set", "particles.count=200", "--set", "box.length=0.01"])
            .args(["--set", "prepare.duration=0.1", "--set", "run.duration=0.002"])
            .args(["--set", "run.threads=1"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("stripes starts")
    };
    let runs = [start(0), start(1)];
    let summaries: Vec<serde_json::Value> = runs
        .into_iter()
        .map(|c| {
            let out = c.wait_with_output().unwrap();
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            let stdout = String::from_utf8_lossy(&out.stdout);
            serde_json::from_str(stdout.lines().last().unwrap()).unwrap()
        })
        .collect();
    let prepared = summaries.iter().filter(|s| s["sample_cached"] == false).count();
    assert_eq!(prepared, 1, "prepared {prepared} times: {summaries:?}");
    // The same sample, hence the same trajectory.
    assert_eq!(summaries[0]["state_hash"], summaries[1]["state_hash"]);
    let files: Vec<_> = std::fs::read_dir(&cache).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(files.len(), 1, "one sample file and no lock left: {files:?}");
    for d in [cache, tmp("run0"), tmp("run1")] {
        let _ = std::fs::remove_dir_all(d);
    }
}
