//! The command-line contract of `stripes bench` (issue 7): files, and `rows` with `name`,
//! `speed_ratio` and `error` in `summary.json`, which is also the last line of stdout.

use std::process::Command;

#[test]
fn bench_writes_the_table_the_plot_and_rows_with_name_speed_ratio_and_error() {
    let out = std::env::temp_dir().join(format!("stripes-cli-bench-{}", std::process::id()));
    let out_s = out.display().to_string();
    // A tiny tray and no dense-packing row keep this test to seconds.
    let result = Command::new(env!("CARGO_BIN_EXE_stripes"))
        .args([
            "bench",
            "--quick",
            "--tray-count",
            "20",
            "--tray-duration",
            "0.013",
            "--dense-steps",
            "0",
            "--out",
            &out_s,
        ])
        .output()
        .expect("run stripes");
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let last = stdout.lines().last().expect("a summary line");
    let summary: serde_json::Value = serde_json::from_str(last).expect("the last line is JSON");
    let on_disk: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary, on_disk);
    let rows = summary["rows"].as_array().expect("rows");
    assert!(rows.len() > 20, "{} rows", rows.len());
    for r in rows {
        assert!(r["name"].is_string(), "{r}");
        // Refused settings carry null numbers and say why in `outcome`.
        if r["outcome"].as_str().unwrap().starts_with("refused") {
            assert!(r["error"].is_null());
        } else {
            assert!(r["speed_ratio"].as_f64().unwrap() > 0.0, "{r}");
            assert!(r["error"].as_f64().unwrap() >= 0.0, "{r}");
        }
    }
    // The defaults are on the front of the lab study (the tray's is timing-dependent).
    let lab_default = rows
        .iter()
        .find(|r| r["axis"] == "default" && r["study"] == "collision")
        .expect("a lab default row");
    assert_eq!(lab_default["on_front"], true, "{lab_default}");
    for f in ["bench.md", "bench.csv", "pareto.png", "pareto.svg", "config.json"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let table = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(table.starts_with("| study | setting |"), "{table}");
    std::fs::remove_dir_all(out).unwrap();
}
