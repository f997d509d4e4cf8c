//! `stripes mechanism` continues a finished run from its checkpoint and classifies how the
//! grains move on the floor. A dilute layer at the stripe scene's drive (3 Hz, 10 mm,
//! Gamma 0.36 < 7 mu / 2) has free grains that roll without slip: their velocity relative to
//! the tray is -5/7 of the tray's (the closed form of a sphere rolling on an accelerating
//! floor), and the run directory is left as it was.

mod common;
use common::stripes;

use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stripes-mechanism-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn free_grains_roll_at_five_sevenths_of_the_tray_velocity() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stripes.toml");
    let (run, samples) = (tmp("run"), tmp("samples"));
    let (ok, _, err) = stripes(&[
        "run",
        scene.to_str().unwrap(),
        "--quiet",
        "--out",
        run.to_str().unwrap(),
        "--sample-cache",
        samples.to_str().unwrap(),
        "--set",
        "particles.count=150",
        "--set",
        "box.length=0.05",
        "--set",
        "prepare.duration=0.01",
        "--set",
        "run.duration=0.67",
        "--set",
        "run.threads=1",
    ]);
    assert!(ok, "run failed: {err}");
    let before = std::fs::read(run.join("checkpoint.bin")).unwrap();
    let (ok, stdout, err) = stripes(&[
        "mechanism",
        run.to_str().unwrap(),
        "--quiet",
        "--periods",
        "1",
        "--per-period",
        "12",
        "--sample-cache",
        samples.to_str().unwrap(),
    ]);
    assert!(ok, "mechanism failed: {err}");
    let s: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert!((s["gamma"].as_f64().unwrap() - 0.362).abs() < 0.01, "{s}");
    let out = &s["outside"];
    let sum: f64 = ["held", "rolling", "sliding", "airborne"]
        .iter()
        .map(|k| out[k].as_f64().unwrap())
        .sum();
    assert!((sum - 1.0).abs() < 1e-12, "fractions add up to 1: {sum}");
    assert_eq!(out["grain_instants"], 150 * 12);
    let slope = out["slope"].as_f64().unwrap();
    assert!((slope + 5.0 / 7.0).abs() < 0.05, "free grains roll: slope {slope}, want -5/7");
    assert!(out["rolling"].as_f64().unwrap() > 0.5, "{out}");
    assert!(run.join("mechanism/mechanism.csv").exists() && run.join("mechanism/mechanism.png").exists());
    assert_eq!(std::fs::read(run.join("checkpoint.bin")).unwrap(), before, "the run is untouched");

    // The coarse model's parameters, from the run's own frames: a free grain rolling without
    // slip swings (5/7) 2A = 14.3 mm back and forth relative to the tray between turning
    // points (its centre follows the tray at 2/7 of its velocity). The periodic tray is
    // longer than twice that, so the move is not taken for its periodic image.
    let c = &s["coarse"];
    assert!(c["half_periods"].as_u64().unwrap() >= 3, "{c}");
    let text = std::fs::read_to_string(run.join("mechanism/automaton.toml")).unwrap();
    let p: toml::Value = toml::from_str(&text).unwrap();
    assert_eq!(p["source"]["grains"].as_integer(), Some(150));
    assert_eq!(p["source"]["periodic"].as_bool(), Some(true));
    let median = p["excursion"]["swing"]["median"].as_float().unwrap();
    let rolling = 5.0 / 7.0 * 2.0 * 0.01;
    assert!((median - rolling).abs() < 0.05 * rolling, "median swing {median} m, want {rolling}");
    assert!(p["excursion"]["by_contacts"].as_array().is_some_and(|a| !a.is_empty()));
    assert!(run.join("mechanism/coarse.json").exists());
}

#[test]
fn a_run_without_half_periods_is_named_with_the_quantity() {
    // One snapshot per period, always at the same phase: no two turning-point frames half a
    // period apart, and the error says which quantity needs them.
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/stripes.toml");
    let (run, samples) = (tmp("short"), tmp("short-samples"));
    let (ok, _, err) = stripes(&[
        "run",
        scene.to_str().unwrap(),
        "--quiet",
        "--out",
        run.to_str().unwrap(),
        "--sample-cache",
        samples.to_str().unwrap(),
        "--set",
        "particles.count=20",
        "--set",
        "box.length=0.02",
        "--set",
        "prepare.duration=0.01",
        "--set",
        "run.duration=0.7",
        "--set",
        "run.snapshots_per_period=1",
        "--set",
        "run.threads=1",
    ]);
    assert!(ok, "run failed: {err}");
    let (ok, _, err) = stripes(&[
        "mechanism",
        run.to_str().unwrap(),
        "--quiet",
        "--periods",
        "1",
        "--sample-cache",
        samples.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("excursion per half period"), "{err}");
}
