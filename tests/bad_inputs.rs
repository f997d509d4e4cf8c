//! Bad or odd input on the command line: each case is refused with an error that names the
//! option or scene key (and the size, for sizes), or is run with a warning that says what was
//! changed. Nothing here runs more than a few hundred milliseconds.

mod common;
use common::{stripes, tiny_scene};

use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("stripes-bad-inputs-{name}-{}", std::process::id()))
}

/// Runs `stripes args`, which must fail with a message holding every one of `want`, and
/// must leave `out` (if given) absent.
fn refused(args: &[&str], want: &[&str], out: Option<&Path>) {
    let (ok, _, stderr) = stripes(args);
    assert!(!ok, "{args:?} succeeded");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    for w in want {
        assert!(stderr.contains(w), "{args:?}: `{stderr}` lacks `{w}`");
    }
    if let Some(out) = out {
        assert!(!out.exists(), "{args:?} left {}", out.display());
    }
}

/// Regression: `--set box.length=1000 --set box.width=1000` aborted on a 7 TB allocation.
#[test]
fn a_1000_m_box_is_refused_naming_the_key_and_the_size() {
    let d = scratch("box");
    let scene = tiny_scene(&d);
    let out = d.join("run");
    let o = out.display().to_string();
    refused(
        &[
            "run",
            &scene,
            "--set",
            "box.length=1000",
            "--set",
            "box.width=1000",
            "--out",
            &o,
            "--quiet",
        ],
        &["box.length", "9.070e11 lattice sites", "7.3e12 bytes"],
        Some(&out),
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: `automaton.cell=1e-7` aborted on a 20 GB lattice; a cell larger than the box
/// gave a 1 x 1 lattice and a phase. (The lattice checks are `cellular::validate_lattice`.)
#[test]
fn an_automaton_lattice_too_large_or_degenerate_is_refused_naming_the_key() {
    let d = scratch("cell");
    let scene = tiny_scene(&d);
    let out = d.join("a");
    let o = out.display().to_string();
    for (cell, want) in [
        ("automaton.cell=1e-7", &["automaton.cell", "1.000e10 cells", "at most"][..]),
        ("automaton.cell=1", &["automaton.cell", "gives 1 cell(s)", "at least 3"][..]),
        ("automaton.cell=0.009", &["automaton.cell", "gives 2 cell(s)", "at least 3"][..]),
    ] {
        refused(&["automaton", &scene, "--set", cell, "--out", &o, "--quiet"], want, Some(&out));
        refused(&["compare", &scene, "--set", cell, "--out", &o, "--quiet"], want, Some(&out));
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// The automaton steps whole periods: a duration between two (2.2 periods) is run as 2 with a
/// warning saying so.
#[test]
fn the_automaton_says_when_it_rounds_the_duration_to_whole_periods() {
    let d = scratch("periods");
    let scene = tiny_scene(&d);
    let samples = d.join("samples").display().to_string();
    let out = d.join("a").display().to_string();
    let (ok, stdout, stderr) = stripes(&[
        "automaton",
        &scene,
        "--set",
        "run.duration=0.11",
        "--out",
        &out,
        "--sample-cache",
        &samples,
        "--quiet",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("not a whole number of drive periods") && stderr.contains("ran 2 periods (0.1 s)"),
        "{stderr}"
    );
    let s: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert!(s["warnings"].to_string().contains("whole number of drive periods"), "{s}");
    assert_eq!(s["periods"], 2);
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: the collision lab returned nonsense with exit 0 (a gain of energy and a
/// negative contact time, a contact that never happened, 2 steps); it refuses what it
/// cannot resolve, naming the option.
#[test]
fn the_collision_lab_refuses_what_it_cannot_resolve() {
    let d = scratch("collide");
    let out = d.join("c");
    let o = out.display().to_string();
    for (args, want) in [
        (
            &["--normal", "linear", "--kn", "1000", "--gamma-n", "1e9"][..],
            &["not resolved", "the contact ended before it began", "gamma_n"][..],
        ),
        (
            &["--v", "1e10"][..],
            &["not resolved", "at v = 1e10 m/s", "pass through each other"][..],
        ),
        (&["--dt", "1e-30"][..], &["not resolved", "dt = 1e-30 s", "double precision"][..]),
        (&["--dissipation", "1"][..], &["not resolved", "1.4 steps", "at least 5 needed"][..]),
        (&["--mu", "nan"][..], &["--mu", "not NaN"][..]),
        (&["--rho", "nan"][..], &["--rho", "not NaN"][..]),
    ] {
        let mut all = vec!["collide", "--out", &o];
        all.extend_from_slice(args);
        refused(&all, want, Some(&out));
    }
    // An ordinary impact still runs.
    let (ok, _, stderr) = stripes(&["collide", "--out", &o]);
    assert!(ok, "{stderr}");
    std::fs::remove_dir_all(d).unwrap();
}

/// Small silent changes that are now refused: `contact-time --points 0` (was 2), `--seeds 0`
/// (was one sample), a NaN classifier threshold, more snapshots per period than steps.
#[test]
fn small_silent_changes_are_refused_naming_the_option() {
    let d = scratch("small");
    let scene = tiny_scene(&d);
    let out = d.join("o");
    let o = out.display().to_string();
    refused(
        &["contact-time", "--points", "0", "--out", &o],
        &["--points", "at least 2"],
        Some(&out),
    );
    refused(
        &[
            "phase-map",
            &scene,
            "--frequency",
            "5",
            "--amplitude",
            "0.01",
            "--seeds",
            "0",
            "--out",
            &o,
        ],
        &["--seeds"],
        Some(&out),
    );
    refused(&["ablate", &scene, "--seeds", "0", "--out", &o], &["--seeds"], Some(&out));
    refused(
        &["analyze", &d.display().to_string(), "--mobility-min", "nan", "--out", &o],
        &["--mobility-min", "NaN"],
        Some(&out),
    );
    refused(
        &["analyze", &d.display().to_string(), "--contrast-min", "nan", "--out", &o],
        &["--contrast-min"],
        Some(&out),
    );
    refused(
        &["analyze", &d.display().to_string(), "--threshold", "nan", "--out", &o],
        &["--threshold", "not NaN"],
        Some(&out),
    );
    refused(
        &["run", &scene, "--set", "run.snapshots_per_period=100000", "--out", &o, "--quiet"],
        &["run.snapshots_per_period", "at most 3125 per period"],
        Some(&out),
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: a sweep reused the results of its jobs after its scene file changed, and the
/// report printed the new scene above the old results. The sweep's identity covers the
/// resolved scene; a changed scene is refused naming the changed key.
#[test]
fn a_sweep_refuses_its_directory_after_its_scene_file_changed() {
    let d = scratch("sweep");
    let scene = tiny_scene(&d);
    let samples = d.join("samples").display().to_string();
    let out = d.join("pm").display().to_string();
    let map = || {
        stripes(&[
            "phase-map",
            &scene,
            "--frequency",
            "20",
            "--amplitude",
            "0.025",
            "--model",
            "automaton",
            "--set",
            "run.duration=0.1",
            "--out",
            &out,
            "--sample-cache",
            &samples,
            "--quiet",
        ])
    };
    let (ok, _, stderr) = map();
    assert!(ok, "{stderr}");
    // Regression: the mobility colour bar had no unit.
    let svg = std::fs::read_to_string(Path::new(&out).join("phase_automaton_mobility.svg")).unwrap();
    assert!(svg.contains("mobility (mean diameters per period)"), "the colour bar has no unit");
    // The same sweep again: every job is skipped, nothing refused.
    let (ok, stdout, stderr) = map();
    assert!(ok, "{stderr}");
    assert!(stdout.contains("\"skipped\":1"), "{stdout}");
    let text = std::fs::read_to_string(&scene).unwrap().replace("seed = 4", "seed = 5");
    std::fs::write(&scene, text).unwrap();
    let (ok, _, stderr) = map();
    assert!(!ok, "a changed scene reused the old results");
    assert!(
        stderr.contains("another resolved scene") && stderr.contains("run.seed: 4 -> 5"),
        "{stderr}"
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: `automaton SCENE --calibrate RUN` ignored the scene without a word.
#[test]
fn automaton_refuses_a_scene_beside_calibrate() {
    let d = scratch("calibrate");
    let scene = tiny_scene(&d);
    refused(
        &["automaton", &scene, "--calibrate", "some-run"],
        &["cannot be used with '--calibrate"],
        None,
    );
    std::fs::remove_dir_all(d).unwrap();
}
