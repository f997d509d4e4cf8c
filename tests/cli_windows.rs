//! `stripes windows`: analysed windows of one run joined over time (synthetic windows: the
//! join, the gap, the reference counts, the fit's start, and the refusals).

mod common;
use common::stripes;

use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stripes-windows-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A window directory as `stripes analyze` leaves it: `camera_count.csv` (frames one period
/// of 1/3 s apart from `from`, with `counts`) and the `summary.json` fields the join reads.
fn window(dir: &Path, name: &str, from: f64, counts: &[usize]) -> String {
    let w = dir.join(name);
    std::fs::create_dir_all(&w).unwrap();
    let mut csv = String::from("t,tray_x,offset_periods,count,contrast,power_fit,log_fit\n");
    for (k, c) in counts.iter().enumerate() {
        csv.push_str(&format!("{},0.01,0,{c},2.0,nan,nan\n", from + k as f64 / 3.0));
    }
    std::fs::write(w.join("camera_count.csv"), csv).unwrap();
    let summary = r#"{"camera": {"drive": {"stages": [{"start": 0.0}, {"start": 2.0}]},
        "lifetimes": {"mean_s": 1.5, "stderr_s": 0.2, "longest_seen_s": 4.0}}}"#;
    std::fs::write(w.join("summary.json"), summary).unwrap();
    w.display().to_string()
}

#[test]
fn windows_join_in_time_order_with_their_gap_and_the_reference_beside() {
    let d = scratch("join");
    // Counts rise to 6 at 12 s after t3, then decay: the fit starts at the peak.
    let late = window(&d, "late", 32.0, &[5, 5, 4, 4, 4, 3, 3, 3, 3, 2, 2, 2]);
    let early = window(&d, "early", 3.0, &[0, 1, 2, 3, 4, 5, 6, 6, 5, 5]);
    let out = d.join("out").display().to_string();
    let (ok, stdout, stderr) = stripes(&["windows", &late, &early, "--out", &out, "--reference", "1.5:2,100:4", "--quiet"]);
    assert!(ok, "{stderr}");
    let s: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert_eq!(s["frames"], 22);
    assert_eq!(s["t3_s"], 2.0);
    assert_eq!(s["stripe_count_max"], 6);
    let gap = &s["gaps_s"][0];
    assert!((gap[0].as_f64().unwrap() - 6.0).abs() < 1e-9 && gap[1] == 32.0, "{s}");
    // The first frame with 6 stripes: t = 3 + 6/3 = 5 s, 3 s after t3.
    assert!((s["coarsening_from_s"].as_f64().unwrap() - 3.0).abs() < 1e-9, "{s}");
    assert!(
        s["coarsening_law"]["power"]["rate"].as_f64().unwrap() > 0.0,
        "a decaying count: {s}"
    );
    assert_eq!(s["count_grows"], false);
    // Reference at 1.5 s after t3: frames at 3.0-4.333 s (t - t3 = 1.0-2.333, within 1 s of 1.5).
    assert_eq!(s["reference"][0]["run_counts"], serde_json::json!([0, 1, 2, 3, 4]));
    assert_eq!(s["reference"][1]["run_counts"], serde_json::json!([]));
    let counts = std::fs::read_to_string(d.join("out/counts.csv")).unwrap();
    assert_eq!(counts.lines().count(), 23, "a header and 22 frames");
    assert!(counts.lines().nth(1).unwrap().starts_with("3,1,0,"), "early first: {counts}");
    let report = std::fs::read_to_string(d.join("out/report.md")).unwrap();
    assert!(report.contains("No frames in 6.0-32.0 s"), "{report}");
    assert!(d.join("out/count_log.png").is_file());
}

#[test]
fn a_count_that_grows_after_its_peak_is_not_called_a_coarsening() {
    let d = scratch("grows");
    // One stripe from the start, the peak (3) early, then a dip and a slow rise to 3 again.
    let a = window(&d, "a", 3.0, &[1, 3, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 3]);
    let out = d.join("out").display().to_string();
    let (ok, stdout, stderr) = stripes(&["windows", &a, "--out", &out, "--quiet"]);
    assert!(ok, "{stderr}");
    let s: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert_eq!(s["count_grows"], true, "{s}");
    assert!(s["warnings"][0].as_str().unwrap().contains("grows rather than decays"), "{s}");
}

#[test]
fn overlapping_windows_are_refused_and_leave_nothing_behind() {
    let d = scratch("overlap");
    let a = window(&d, "a", 3.0, &[1, 2, 3]);
    let b = window(&d, "b", 3.5, &[1, 2]);
    let out = d.join("out");
    let (ok, _, stderr) = stripes(&["windows", &a, &b, "--out", &out.display().to_string(), "--quiet"]);
    assert!(
        !ok && stderr.contains("overlap") && stderr.contains(&a) && stderr.contains(&b),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
    let (ok, _, stderr) = stripes(&["windows", &d.display().to_string(), "--quiet", "--out", &out.display().to_string()]);
    assert!(!ok && stderr.contains("no camera_count.csv"), "{stderr}");
    let (ok, _, stderr) = stripes(&["windows", &a, "--reference", "0:3"]);
    assert!(!ok && stderr.contains("T:S"), "{stderr}");
}
