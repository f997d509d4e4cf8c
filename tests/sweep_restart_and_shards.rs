//! Sweeps are sets of independent jobs: a sweep killed half-way and restarted redoes no
//! finished job and loses none; two shards collected equal a single run; and a tiny sweep runs
//! through GNU parallel (installed with apt-get if missing).

use std::path::{Path, PathBuf};
use std::process::Command;

/// A tiny tray (60 grains on 6 mm at the thesis packing, 0.1 s per job): 2 x 2 cells.
const TINY: &[&str] = &[
    "--set",
    "particles.count=60",
    "--set",
    "box.length=0.006",
    "--set",
    "prepare.duration=0.005",
    "--set",
    "run.duration=0.1",
    "--frequency",
    "10:20:2",
    "--amplitude",
    "0.005:0.025:2",
    "--model",
    "dem",
    "--quiet",
];

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("stripes-sweep-{}-{name}", std::process::id()))
}

fn stripes() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stripes"))
}

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thesis-reference.toml")
}

fn phase_map(out: &Path, samples: &Path, extra: &[&str]) -> serde_json::Value {
    let o = stripes()
        .arg("phase-map")
        .arg(scene())
        .args(TINY)
        .arg("--out")
        .arg(out)
        .arg("--sample-cache")
        .arg(samples)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap()
}

fn results(dir: &Path) -> Vec<(String, std::time::SystemTime, String)> {
    let mut v: Vec<_> = std::fs::read_dir(dir.join("jobs"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path().join("result.json");
            let meta = std::fs::metadata(&p).ok()?;
            Some((
                p.display().to_string(),
                meta.modified().unwrap(),
                std::fs::read_to_string(&p).unwrap(),
            ))
        })
        .collect();
    v.sort();
    v
}

#[test]
fn a_restarted_sweep_redoes_nothing_and_two_shards_equal_one_run() {
    let samples = tmp("samples");
    // "Killed half-way": only shard 0 of 2 ran.
    let dir = tmp("sharded");
    let half = phase_map(&dir, &samples, &["--shard", "0/2"]);
    assert_eq!(half["progress"]["ran"], 2);
    assert_eq!(half["finished"], 2);
    let before = results(&dir);
    assert_eq!(before.len(), 2);
    // Restarted as a whole: the two finished jobs are skipped and kept byte for byte.
    let full = phase_map(&dir, &samples, &[]);
    assert_eq!(full["progress"]["skipped"], 2);
    assert_eq!(full["progress"]["ran"], 2);
    // One sample for the four DEM jobs (issue 20, point 4): prepared once, by the first
    // shard, and the report says what preparation cost.
    let prep = &full["sample_preparation"];
    assert_eq!((prep["prepared"].as_u64(), prep["loaded"].as_u64()), (Some(1), Some(3)), "{prep}");
    assert!(std::fs::read_to_string(dir.join("report.md"))
        .unwrap()
        .contains("**Sample preparation.** 1 DEM job(s) prepared"));
    let after = results(&dir);
    assert_eq!(after.len(), 4);
    for b in &before {
        assert!(after.contains(b), "finished job {} was redone or changed", b.0);
    }
    // A single run in one go gives the same table.
    let single = tmp("single");
    phase_map(&single, &samples, &[]);
    let o = stripes().arg("collect").arg(&dir).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let a = std::fs::read_to_string(dir.join("phase_map.csv")).unwrap();
    let b = std::fs::read_to_string(single.join("phase_map.csv")).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.lines().count(), 5);
    assert!(a.starts_with("model,frequency,amplitude,sample,phase,stripe_count,contrast,mobility"));
    // A different sweep in the same directory is refused.
    let o = stripes()
        .arg("phase-map")
        .arg(scene())
        .args(TINY)
        .args(["--seeds", "2", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("different sweep"));
    for d in ["samples", "sharded", "single"] {
        let _ = std::fs::remove_dir_all(tmp(d));
    }
}

/// GNU parallel, installed if missing; `None` if it cannot be had on this machine.
fn gnu_parallel() -> Option<()> {
    let have = || Command::new("parallel").arg("--version").output().is_ok_and(|o| o.status.success());
    if !have() {
        let _ = Command::new("apt-get").args(["install", "-y", "-qq", "parallel"]).output();
        if !have() {
            let _ = Command::new("apt-get").args(["update", "-qq"]).output();
            let _ = Command::new("apt-get").args(["install", "-y", "-qq", "parallel"]).output();
        }
    }
    have().then_some(())
}

#[test]
fn a_tiny_sweep_runs_through_gnu_parallel() {
    gnu_parallel().expect("GNU parallel could not be installed (apt-get install parallel)");
    let dir = tmp("parallel");
    let samples = tmp("parallel-samples");
    let bin = env!("CARGO_BIN_EXE_stripes");
    // Exactly the recipe of docs/guide.md: one shard per parallel task, then collect.
    let script = format!(
        "parallel --will-cite --halt now,fail=1 -j 2 '{bin} phase-map {} {} --out {} --sample-cache {} --jobs 1 --shard {{}}/4 > /dev/null' ::: 0 1 2 3",
        scene().display(),
        TINY.iter().map(|a| format!("'{a}'")).collect::<Vec<_>>().join(" "),
        dir.display(),
        samples.display()
    );
    let o = Command::new("bash").arg("-c").arg(&script).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = stripes().arg("collect").arg(&dir).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value = serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap();
    assert_eq!(summary["finished"], 4);
    assert_eq!(std::fs::read_to_string(dir.join("phase_map.csv")).unwrap().lines().count(), 5);
    let _ = std::fs::remove_dir_all(dir);
    let _ = std::fs::remove_dir_all(samples);
}

#[test]
fn the_automaton_ablation_switches_off_each_ingredient_and_reports_every_configuration() {
    let dir = tmp("ablate");
    let samples = tmp("ablate-samples");
    let o = stripes()
        .arg("ablate")
        .arg(scene())
        .args([
            "--set",
            "particles.count=60",
            "--set",
            "box.length=0.006",
            "--set",
            "prepare.duration=0.005",
        ])
        .args(["--set", "run.duration=0.5", "--model", "automaton", "--quiet", "--out"])
        .arg(&dir)
        .arg("--sample-cache")
        .arg(&samples)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value = serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap();
    let configs: Vec<&str> = summary["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["config"].as_str().unwrap())
        .collect();
    assert_eq!(
        configs,
        [
            "reference",
            "threshold-off",
            "flight-cap-off",
            "stochastic-off",
            "knock-off",
            "lateral-none",
            "sideways-off",
            "rolling-off",
            "frustration-off",
            "trains-off",
            "strict"
        ]
    );
    // Each job's result keeps its labels: the sample index is not overwritten by what
    // preparing the sample cost.
    for e in std::fs::read_dir(dir.join("jobs")).unwrap() {
        let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(e.unwrap().path().join("result.json")).unwrap()).unwrap();
        assert!(r["sample"].is_u64(), "{r}");
        assert!(r["sample_preparation"].is_object(), "{r}");
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("| strict | 1 |") && report.contains("Scale: scene"), "{report}");
    let _ = std::fs::remove_dir_all(dir);
    let _ = std::fs::remove_dir_all(samples);
}

#[test]
fn a_sweep_whose_jobs_fail_still_writes_a_report_naming_each_error() {
    let out = tmp("failing");
    let samples = tmp("failing-samples");
    let _ = std::fs::remove_dir_all(&out);
    // A ceiling below the grains' centres: every scene is valid (checked before any job
    // starts), but every job stops at its start, when the grains are found outside the box.
    let o = stripes()
        .arg("phase-map")
        .arg(scene())
        .args(TINY)
        .args(["--set", "box.height=1e-4", "--out"])
        .arg(&out)
        .arg("--sample-cache")
        .arg(&samples)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("4 job(s) failed") && stderr.contains("report.md"), "{stderr}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Jobs that stopped with an error"), "{report}");
    assert_eq!(report.matches("stopped: ").count(), 4, "{report}");
    assert!(report.contains("left the box"), "{report}");
    let errors = std::fs::read_dir(out.join("jobs"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().join("error.txt").exists())
        .count();
    assert_eq!(errors, 4);
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&samples);
}

#[test]
fn every_job_and_every_range_is_checked_before_any_job_starts() {
    let (out, samples) = (tmp("preflight"), tmp("preflight-samples"));
    let run = |extra: &[&str]| {
        let o = stripes()
            .arg("phase-map")
            .arg(scene())
            .args([
                "--set",
                "particles.count=60",
                "--set",
                "box.length=0.006",
                "--set",
                "run.duration=0.1",
            ])
            .args(["--model", "dem", "--quiet"])
            .args(extra)
            .arg("--out")
            .arg(&out)
            .arg("--sample-cache")
            .arg(&samples)
            .output()
            .unwrap();
        assert!(!o.status.success(), "accepted {extra:?}");
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(
            !out.join("jobs").exists() && !samples.exists(),
            "a job started before the check: {err}"
        );
        err
    };
    // A step far above the contact-time bound in every job: the sweep stops before the first.
    let err = run(&["--frequency", "10:20:2", "--amplitude", "0.005:0.025:2", "--set", "run.dt=1e-3"]);
    assert!(
        err.contains("job `") && err.contains("run.dt") && !err.contains("job(s) failed"),
        "{err}"
    );
    // Two of four jobs with a negative amplitude: named by job and key.
    let err = run(&["--frequency", "10:20:2", "--amplitude=-0.01:0.01:2"]);
    assert!(err.contains("job `") && err.contains("drive.amplitude"), "{err}");
    let err = run(&["--frequency", "29:5:3", "--amplitude", "0.01:0.02:2"]);
    assert!(
        err.contains("--frequency 29:5:3") && err.contains("LO = 29 is above HI = 5"),
        "{err}"
    );
    let err = run(&["--frequency", "5:29:3", "--amplitude", "0.01:0.02:0"]);
    assert!(err.contains("--amplitude 0.01:0.02:0") && err.contains("N = 0"), "{err}");
}
