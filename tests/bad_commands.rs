//! Commands used the wrong way: one overwrite rule for every command, an analysis that would
//! write over its own run, `compare --resume`, `single` away from the repository, and the
//! messages that used to name the wrong thing. Each case runs in well under a second, except
//! the `compare` and `single` ones (about a second each).

mod common;
use common::{stripes, tiny_scene};

use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stripes-bad-commands-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Regression: `analyze`, `collide`, `single`, `contact-time` and `bench` overwrote a
/// directory silently while the README said every command refuses; now every command refuses
/// a directory holding files unless `--force`, and leaves its files alone.
#[test]
fn every_command_refuses_a_directory_that_holds_files() {
    let d = scratch("overwrite");
    let scene = tiny_scene(&d);
    let cache = s(&d.join("samples"));
    let run = s(&d.join("run"));
    let (ok, _, stderr) = stripes(&["run", &scene, "--out", &run, "--sample-cache", &cache, "--quiet"]);
    assert!(ok, "{stderr}");
    let full = d.join("full");
    std::fs::create_dir_all(&full).unwrap();
    std::fs::write(full.join("mine.txt"), "keep").unwrap();
    let f = s(&full);
    for args in [
        vec!["analyze", &run, "--out", &f],
        vec!["collide", "--out", &f],
        vec!["single", "--duration", "0.2", "--out", &f],
        vec!["contact-time", "--points", "2", "--out", &f],
        vec!["bench", "--out", &f],
        vec!["eccentricity", "--out", &f],
        vec!["automaton", &scene, "--out", &f, "--sample-cache", &cache, "--quiet"],
        vec!["run", &scene, "--out", &f, "--sample-cache", &cache, "--quiet"],
        vec!["compare", &scene, "--out", &f, "--sample-cache", &cache, "--quiet"],
    ] {
        let (ok, _, stderr) = stripes(&args);
        assert!(!ok, "{args:?} wrote into a directory holding files");
        assert!(
            stderr.contains("already holds files") && stderr.contains("--force"),
            "{args:?}: {stderr}"
        );
        assert_eq!(std::fs::read_to_string(full.join("mine.txt")).unwrap(), "keep");
        assert_eq!(std::fs::read_dir(&full).unwrap().count(), 1, "{args:?} left files behind");
    }
    // The directory is checked before a sample is prepared: a refused command leaves no
    // sample behind either.
    let fresh = d.join("fresh-cache");
    for cmd in ["run", "automaton", "compare"] {
        let (ok, _, _) = stripes(&[cmd, &scene, "--out", &f, "--sample-cache", &s(&fresh), "--quiet"]);
        assert!(!ok);
        assert!(!fresh.exists(), "`{cmd}` prepared a sample before refusing its directory");
    }
    // With --force the command runs.
    let (ok, _, stderr) = stripes(&["collide", "--out", &f, "--force"]);
    assert!(ok, "{stderr}");
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: `analyze RUN --out RUN` replaced the run's own `config.json` and
/// `summary.json`, and later analyses lost its period.
#[test]
fn an_analysis_into_its_own_run_directory_is_refused() {
    let d = scratch("self");
    let scene = tiny_scene(&d);
    let cache = s(&d.join("samples"));
    let run = s(&d.join("run"));
    let (ok, _, stderr) = stripes(&["run", &scene, "--out", &run, "--sample-cache", &cache, "--quiet"]);
    assert!(ok, "{stderr}");
    let before = std::fs::read_to_string(d.join("run/config.json")).unwrap();
    for extra in [&[][..], &["--force"][..]] {
        let mut args = vec!["analyze", &run, "--out", &run];
        args.extend_from_slice(extra);
        let (ok, _, stderr) = stripes(&args);
        assert!(!ok && stderr.contains("is the run directory itself"), "{stderr}");
    }
    assert_eq!(std::fs::read_to_string(d.join("run/config.json")).unwrap(), before);
    std::fs::remove_dir_all(d).unwrap();
}

/// A comparison can be continued: `compare --resume` on its own directory finishes (a
/// finished DEM run is reused, not redone), where a plain second `compare` is refused.
#[test]
fn compare_resume_continues_its_own_directory() {
    let d = scratch("resume");
    let scene = tiny_scene(&d);
    let cache = s(&d.join("samples"));
    let out = s(&d.join("cmp"));
    let args = ["compare", &scene, "--out", &out, "--sample-cache", &cache, "--quiet"];
    let (ok, first, stderr) = stripes(&args);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = stripes(&args);
    assert!(!ok && stderr.contains("--resume"), "{stderr}");
    let mut resume = args.to_vec();
    resume.push("--resume");
    let (ok, again, stderr) = stripes(&resume);
    assert!(ok, "{stderr}");
    let dem = |out: &str| -> serde_json::Value {
        let v: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
        v["dem"]["analysis"].clone()
    };
    assert_eq!(dem(&first), dem(&again), "the resumed comparison changed the DEM side");
    // Issue 43, findings 1 and 2: a resume with another scene, or with a key changed by
    // --set, is refused naming each differing key, before anything is written (config.json
    // is the finished comparison's, byte for byte).
    let config = std::fs::read(d.join("cmp/config.json")).unwrap();
    let other = d.join("other.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(
        &other,
        text.replace("count = 40", "count = 30")
            .replace("frequency = 20.0", "frequency = 3.0"),
    )
    .unwrap();
    let other = s(&other);
    for (args, keys) in [
        (
            vec!["compare", &other, "--out", &out, "--sample-cache", &cache, "--quiet", "--resume"],
            &["particles.count: 40 -> 30", "drive.frequency: 20.0 -> 3.0"][..],
        ),
        (
            vec![
                "compare",
                &scene,
                "--out",
                &out,
                "--sample-cache",
                &cache,
                "--quiet",
                "--resume",
                "--set",
                "contact.friction=0.5",
            ],
            &["contact.friction: 0.7 -> 0.5"][..],
        ),
        (
            vec![
                "compare",
                &scene,
                "--out",
                &out,
                "--sample-cache",
                &cache,
                "--quiet",
                "--resume",
                "--set",
                "run.duration=0.1",
            ],
            &["run.duration: 0.2 -> 0.1"][..],
        ),
    ] {
        let (ok, _, stderr) = stripes(&args);
        assert!(!ok, "{args:?} resumed another scene");
        for k in keys {
            assert!(stderr.contains(k), "{args:?} does not name {k}: {stderr}");
        }
        assert_eq!(
            std::fs::read(d.join("cmp/config.json")).unwrap(),
            config,
            "{args:?} rewrote config.json"
        );
    }
    // A longer duration extends the DEM run and the comparison.
    let mut longer = resume.clone();
    longer.extend(["--set", "run.duration=0.3"]);
    let (ok, _, stderr) = stripes(&longer);
    assert!(ok, "{stderr}");
    let dem_summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(d.join("cmp/dem/summary.json")).unwrap()).unwrap();
    assert!((dem_summary["simulated_s"].as_f64().unwrap() - 0.3).abs() < 1e-6, "{dem_summary}");
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: `single` worked only from the repository root (its default scene was a
/// relative path); it now runs from any directory.
#[test]
fn single_runs_from_any_directory() {
    let d = scratch("single");
    let out = Path::new("single-out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_stripes"))
        .current_dir(&d)
        .args(["single", "--duration", "0.2", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(d.join(out).join("summary.json").is_file());
    std::fs::remove_dir_all(d).unwrap();
}

/// Regressions: messages that named the wrong thing.
#[test]
fn messages_name_what_is_wrong() {
    let d = scratch("messages");
    let scene = tiny_scene(&d);
    let out = s(&d.join("o"));
    // `--set box=5` showed an internal type name; it says what `box` is.
    let (ok, _, stderr) = stripes(&["run", &scene, "--set", "box=5", "--out", &out]);
    assert!(!ok && stderr.contains("`box` is a table of keys"), "{stderr}");
    // `--cell -0.001` got clap's `--` tip; it is refused as a value.
    let (ok, _, stderr) = stripes(&["analyze", &s(&d), "--cell", "-0.001", "--out", &out]);
    assert!(
        !ok && stderr.contains("--cell") && stderr.contains("positive") && !stderr.contains("tip:"),
        "{stderr}"
    );
    // `collide --mu nan` failed later without naming `--mu`.
    let (ok, _, stderr) = stripes(&["collide", "--mu", "nan", "--out", &out]);
    assert!(!ok && stderr.contains("--mu"), "{stderr}");
    // An empty STRIPES_SAMPLE_CACHE was reported as a missing `--sample-cache`; it counts as
    // unset.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_stripes"))
        .env("STRIPES_SAMPLE_CACHE", "")
        .args(["run", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("[default: out/samples]"), "{help}");
    assert!(!Path::new(&out).exists());
    std::fs::remove_dir_all(d).unwrap();
}
