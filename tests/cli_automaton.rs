//! The command-line contract of `stripes automaton` and `stripes compare` (issue 5), on a
//! tiny tray so that the DEM parts take about a second.

mod common;
use common::stripes;

use std::path::Path;

/// A 2 cm x 5 mm tray with 40 grains (packing 0.18), 0.02 s of preparation, 0.5 s of run.
fn tiny_scene(dir: &Path) -> String {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("tiny.toml");
    std::fs::write(
        &p,
        r#"
[box]
length = 0.02
width = 0.005
[drive]
frequency = 20.0
amplitude = 0.025
[particles]
count = 40
radius_min = 0.25e-3
radius_max = 0.5e-3
[prepare]
duration = 0.02
[run]
duration = 0.5
dt = 8e-6
seed = 4
threads = 1
"#,
    )
    .unwrap();
    p.display().to_string()
}

fn last_json(stdout: &str) -> serde_json::Value {
    serde_json::from_str(stdout.lines().last().expect("a line")).expect("JSON")
}

#[test]
fn automaton_writes_snapshots_that_analyze_reads_and_prints_the_analyze_keys() {
    let d = std::env::temp_dir().join(format!("stripes-cli-automaton-{}", std::process::id()));
    let scene = tiny_scene(&d);
    let samples = d.join("samples").display().to_string();
    for rule in ["physical", "strict"] {
        let out = d.join(rule).display().to_string();
        let (ok, stdout, stderr) = stripes(&[
            "automaton",
            &scene,
            "--rule",
            rule,
            "--out",
            &out,
            "--sample-cache",
            &samples,
            "--quiet",
        ]);
        assert!(ok, "{stderr}");
        let s = last_json(&stdout);
        assert!(s.get("stripe_count_final").is_some_and(|v| v.is_u64()), "{s}");
        assert!(s.get("stripe_onset_s").is_some(), "{s}");
        assert_eq!(s["mass_initial"], 40);
        assert_eq!(s["mass_final"], 40);
        assert_eq!(s["periods"], 10);
        // The written states are what `stripes analyze` reads.
        let (ok, stdout, stderr) = stripes(&["analyze", &out, "--out", &format!("{out}/again")]);
        assert!(ok, "{stderr}");
        let a = last_json(&stdout);
        assert_eq!(a["frames"], 11, "t = 0 and one frame per period");
        assert_eq!(a["stripe_count_final"], s["stripe_count_final"]);
    }
    // A bad [automaton] value names its key.
    let (ok, _, stderr) = stripes(&[
        "automaton",
        &scene,
        "--set",
        "automaton.activation=1.5",
        "--sample-cache",
        &samples,
        "--quiet",
    ]);
    assert!(!ok);
    assert!(stderr.contains("automaton.activation"), "{stderr}");
    // A snapshot every 3rd period and the one after (pairs one period apart, for the
    // mobility), and at the last: t = 0, periods 3, 4, 6, 7, 9 and 10, and the same final
    // state as writing every period.
    let out = d.join("every3").display().to_string();
    let (ok, stdout, stderr) = stripes(&[
        "automaton",
        &scene,
        "--set",
        "automaton.snapshot_every=3",
        "--out",
        &out,
        "--sample-cache",
        &samples,
        "--quiet",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(last_json(&stdout)["periods"], 10);
    let (ok, stdout, stderr) = stripes(&["analyze", &out, "--out", &format!("{out}/again")]);
    assert!(ok, "{stderr}");
    let analysed = last_json(&stdout);
    assert_eq!(analysed["frames"], 7, "t = 0, periods 3, 4, 6, 7, 9 and the last");
    assert!(
        analysed["mobility"].is_number(),
        "pairs one period apart give a mobility: {analysed}"
    );
    let last = |dir: &str| {
        let b = std::fs::read(Path::new(dir).join("snapshots.bin")).unwrap();
        let n = u64::from_le_bytes(b[8..16].try_into().unwrap()) as usize;
        b[b.len() - 24 * n..].to_vec()
    };
    assert_eq!(last(&out), last(&d.join("physical").display().to_string()), "the same last state");
    // Zero, or more than the run's periods, is refused by key, and leaves nothing.
    for bad in ["0", "11"] {
        let dir = d.join(format!("bad{bad}"));
        let (ok, _, stderr) = stripes(&[
            "automaton",
            &scene,
            "--set",
            &format!("automaton.snapshot_every={bad}"),
            "--out",
            &dir.display().to_string(),
            "--sample-cache",
            &samples,
            "--quiet",
        ]);
        assert!(!ok, "snapshot_every = {bad} was accepted");
        assert!(stderr.contains("automaton.snapshot_every"), "{stderr}");
        assert!(!dir.exists(), "a failed start left {}", dir.display());
    }
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn compare_runs_both_models_on_one_sample_and_writes_the_report() {
    let d = std::env::temp_dir().join(format!("stripes-cli-compare-{}", std::process::id()));
    let scene = tiny_scene(&d);
    let samples = d.join("samples").display().to_string();
    let out = d.join("cmp").display().to_string();
    let (ok, stdout, stderr) = stripes(&[
        "compare",
        &scene,
        "--set",
        "run.duration=0.2",
        "--out",
        &out,
        "--sample-cache",
        &samples,
        "--quiet",
    ]);
    assert!(ok, "{stderr}");
    let s = last_json(&stdout);
    assert!(s["dem"]["analysis"].get("stripe_count_final").is_some(), "{s}");
    assert!(s["automaton"]["analysis"].get("stripe_count_final").is_some(), "{s}");
    // Regression: the summary said "9 files" after writing about 80: the two runs and their
    // analyses are listed too.
    let files: Vec<&str> = s["files"].as_array().unwrap().iter().map(|f| f.as_str().unwrap()).collect();
    for end in [
        "dem/snapshots.bin",
        "automaton/snapshots.bin",
        "automaton/analysis/summary.json",
        "report.md",
    ] {
        assert!(files.iter().any(|f| f.ends_with(end)), "{end} not listed in {files:?}");
    }
    assert!(files.len() > 40, "{} files listed", files.len());
    let report = std::fs::read_to_string(Path::new(&out).join("report.md")).unwrap();
    for needle in [
        "| DEM |",
        "| automaton |",
        "stripe_count.png",
        "density_map_dem.png",
        "density_map_automaton.png",
        "dem-analysis/top_view.png",
        "automaton/analysis/top_view.png",
    ] {
        assert!(report.contains(needle), "report lacks {needle}");
    }
    // The automaton derived from the DEM run: this 0.2 s run holds no band, so there is no
    // cell to derive, and the summary and the report say why.
    let note = s["derived_note"].as_str().expect("a derived automaton or a note why there is none");
    assert!(s["derived"].is_null() && note.contains("cell.size_m"), "{s}");
    assert!(report.contains("No automaton derived from this DEM run"), "{report}");
    // The top views the report shows are there.
    for view in ["dem-analysis/top_view.png", "automaton/analysis/top_view.png"] {
        assert!(Path::new(&out).join(view).is_file(), "{view} missing");
    }
    // Reusing the DEM run gives the same automaton side.
    let out2 = d.join("cmp2").display().to_string();
    let dem = format!("{out}/dem");
    // `compare` reusing the DEM run, with `extra` arguments.
    let compare_reusing = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            &scene,
            "--set",
            "run.duration=0.2",
            "--dem-run",
            &dem,
            "--out",
            &out2,
            "--sample-cache",
            &samples,
            "--quiet",
        ];
        args.extend_from_slice(extra);
        stripes(&args)
    };
    let (ok, stdout, stderr) = compare_reusing(&[]);
    assert!(ok, "{stderr}");
    assert_eq!(last_json(&stdout)["automaton"]["analysis"], s["automaton"]["analysis"]);
    // Regression: a DEM summary that could not be read was taken for a missing one. A run
    // stopped before its end has none, and is compared without its speed; a summary that
    // is there but not JSON is an error naming it.
    let reuse = || compare_reusing(&["--force"]);
    let summary = Path::new(&dem).join("summary.json");
    std::fs::write(&summary, "{ not json").unwrap();
    let (ok, _, stderr) = reuse();
    assert!(!ok && stderr.contains("summary.json"), "{stderr}");
    std::fs::remove_file(&summary).unwrap();
    let (ok, _, stderr) = reuse();
    assert!(ok, "a DEM run without its summary: {stderr}");
    // A DEM run of another scene is refused: the whole scene is checked, and the refusal
    // names the key (another seed is another sample too).
    for (set, says) in [("run.seed=5", "run.seed: 4 -> 5"), ("drive.frequency=10", "drive.frequency")] {
        let (ok, _, stderr) = compare_reusing(&["--set", set, "--force"]);
        assert!(!ok && stderr.contains(says), "{set}: {stderr}");
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// `automaton.parameters` (issue 40): the tiny scene run with the measured rule from a
/// parameter file of the stripe scene's layout, rewritten to the tiny scene's source; the
/// same seed twice gives the same snapshots; a file of another scene is refused by key
/// unless forced, and the forced run says so in its summary; the `swing` rule needs the
/// file's swing field and runs with it.
#[test]
fn the_measured_rule_runs_from_a_parameter_file_and_refuses_another_scenes() {
    let d = std::env::temp_dir().join(format!("stripes-cli-measured-{}", std::process::id()));
    let scene = tiny_scene(&d);
    let samples = d.join("samples").display().to_string();
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/automaton-stripes-seed1.toml"))
        .unwrap()
        .replace("grains = 2000", "grains = 40")
        .replace("mean_diameter_m = 0.000751158012619811", "mean_diameter_m = 0.00075")
        .replace("length_m = 0.1", "length_m = 0.02")
        .replace("width_m = 0.02", "width_m = 0.005")
        .replace("drive = [[0.0, 3.0, 0.01]]", "drive = [[0.0, 20.0, 0.025]]");
    let file = d.join("automaton.toml");
    std::fs::write(&file, text).unwrap();
    let set = format!("automaton.parameters={}", file.display());
    let run = |name: &str, extra: &[&str]| {
        let out = d.join(name).display().to_string();
        let mut args = vec![
            "automaton",
            &scene,
            "--set",
            &set,
            "--out",
            &out,
            "--sample-cache",
            &samples,
            "--quiet",
        ];
        args.extend_from_slice(extra);
        let (ok, stdout, stderr) = stripes(&args);
        (ok, stdout, stderr, out)
    };
    let (ok, stdout, stderr, one) = run("one", &[]);
    assert!(ok, "{stderr}");
    let s = last_json(&stdout);
    assert_eq!(s["rule"], "measured");
    assert_eq!((s["mass_initial"].as_u64(), s["mass_final"].as_u64()), (Some(40), Some(40)));
    assert_eq!(s["cells"]["nx"], 26, "the file's 0.758 mm cell on 20 mm");
    assert!(
        s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .all(|w| !w.as_str().unwrap().contains("parameters")),
        "{s}"
    );
    let (ok, _, stderr, two) = run("two", &[]);
    assert!(ok, "{stderr}");
    let bytes = |dir: &str| std::fs::read(Path::new(dir).join("snapshots.bin")).unwrap();
    assert_eq!(bytes(&one), bytes(&two), "same seed, same snapshots");
    // The analysis reads the run.
    let (ok, stdout, stderr) = stripes(&["analyze", &one, "--out", &format!("{one}/again")]);
    assert!(ok, "{stderr}");
    assert_eq!(last_json(&stdout)["frames"], 11);
    // Another scene's file: refused, naming the key and the file; forced, warned.
    let (ok, _, stderr, _) = run("other", &["--set", "particles.count=41"]);
    assert!(
        !ok && stderr.contains("automaton.parameters") && stderr.contains("source.grains"),
        "{stderr}"
    );
    assert!(stderr.contains("automaton.toml"), "{stderr}");
    let (ok, stdout, stderr, _) = run(
        "forced",
        &["--set", "particles.count=41", "--set", "automaton.parameters_force=true"],
    );
    assert!(ok, "{stderr}");
    let w = last_json(&stdout)["warnings"].to_string();
    assert!(w.contains("parameters_force") && w.contains("source.grains"), "{w}");
    // rule measured without a file is refused by key.
    let (ok, _, stderr) = stripes(&[
        "automaton",
        &scene,
        "--rule",
        "measured",
        "--out",
        &d.join("none").display().to_string(),
        "--quiet",
    ]);
    assert!(!ok && stderr.contains("automaton.parameters"), "{stderr}");
    // rule swing: refused with a file that has no swing field, naming the key; with the
    // field (measured on the stripe scene's DEM run) it runs, grains conserved, same seed
    // same snapshots.
    let (ok, _, stderr, _) = run("no-field", &["--rule", "swing"]);
    assert!(
        !ok && stderr.contains("swing_field") && stderr.contains("automaton.toml"),
        "{stderr}"
    );
    let field = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/swing-field-stripes-seed1.toml")).unwrap();
    std::fs::write(&file, format!("{}\n{field}", std::fs::read_to_string(&file).unwrap())).unwrap();
    let (ok, stdout, stderr, swing) = run("swing", &["--rule", "swing"]);
    assert!(ok, "{stderr}");
    let s = last_json(&stdout);
    assert_eq!(s["rule"], "swing");
    assert_eq!((s["mass_initial"].as_u64(), s["mass_final"].as_u64()), (Some(40), Some(40)));
    let (ok, _, stderr, again) = run("swing-again", &["--rule", "swing"]);
    assert!(ok, "{stderr}");
    assert_eq!(bytes(&swing), bytes(&again), "same seed, same snapshots");
    assert_ne!(bytes(&swing), bytes(&one), "another rule, other moves");
    std::fs::remove_dir_all(&d).ok();
}
