//! `stripes compare` on the vibrated box (`scenes/vibrated-box-dem.toml`, a DEM scene with
//! `drive.direction = "z"`): the DEM, the event-driven model with the DEM's restitution table
//! and with the fitted Walton rule, side by side. A short run: the contract, not the physics
//! (that is docs/results/vibrated-box-dem/report.md).

mod common;
use common::stripes;

/// `stripes compare` on the vibrated box into a fresh directory named `name`: the directory,
/// and whether it succeeded with its stdout's last line and stderr. `args` follow the scene.
fn compare(name: &str, args: &[&str]) -> (std::path::PathBuf, bool, serde_json::Value, String) {
    let tmp = std::env::temp_dir().join(format!("stripes-cli-{name}-{}", std::process::id()));
    let (out, cache) = (tmp.join("cmp"), tmp.join("samples"));
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box-dem.toml");
    let mut all = vec!["compare", scene];
    all.extend_from_slice(args);
    let (out, cache) = (out.display().to_string(), cache.display().to_string());
    all.extend(["--quiet", "--out", &out, "--sample-cache", &cache]);
    let (ok, stdout, stderr) = stripes(&all);
    let v = stdout.lines().last().and_then(|l| serde_json::from_str(l).ok()).unwrap_or_default();
    (tmp, ok, v, stderr)
}

#[test]
fn compare_on_the_vibrated_box_runs_three_models_and_writes_their_report() {
    let (tmp, ok, v, stderr) = compare("vibrated-box", &["--seeds", "2", "--transient", "0.1", "--set", "run.duration=0.3"]);
    assert!(ok, "{stderr}");
    let (out, cache) = (tmp.join("cmp").display().to_string(), tmp.join("samples").display().to_string());
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box-dem.toml");
    let models = v["models"].as_array().unwrap();
    let names: Vec<&str> = models.iter().map(|m| m["model"].as_str().unwrap()).collect();
    assert_eq!(names, ["dem", "events-table", "events-walton"]);
    for m in models {
        let h = m["mean_height_mm"][0].as_f64().unwrap();
        // Grains of about 1 mm under a drive of V = 0.4 m/s: well off the floor, below the top.
        assert!(h > 1.0 && h < 50.0, "{m}");
        assert!(m["k_over_r"][0].as_f64().unwrap() > 1.0, "{m}");
        assert_eq!(m["seeds"], 2);
        assert!(m["cpu_s_per_simulated_s"][0].as_f64().unwrap() > 0.0);
    }
    // The fitted rule reads the table: the linear law's e at the mean radius, 0.9 by design.
    let e = v["walton_fit"]["pair"]["e"].as_f64().unwrap();
    assert!((e - 0.9).abs() < 0.01, "{e}");
    assert_eq!(v["walton_fit"]["wall"]["beta0"], -1.0, "smooth walls");
    for f in [
        "report.md",
        "restitution.csv",
        "restitution_floor.csv",
        "events-table.toml",
        "density.png",
        "temperature.svg",
        "profiles.csv",
    ] {
        assert!(tmp.join("cmp").join(f).is_file(), "missing {f}");
    }
    let report = std::fs::read_to_string(tmp.join("cmp/report.md")).unwrap();
    assert!(report.contains("| events-table |") && report.contains("times faster than the DEM"));
    // The event-driven scene it wrote runs on its own.
    let again = tmp.join("events").display().to_string();
    let table = tmp.join("cmp/events-table.toml").display().to_string();
    let (ok, _, stderr) = stripes(&["events", &table, "--set", "run.duration=0.2", "--quiet", "--out", &again]);
    assert!(ok, "{stderr}");
    // A second comparison into the same directory is refused without --force.
    let (ok, _, stderr) = stripes(&["compare", scene, "--quiet", "--out", &out, "--sample-cache", &cache]);
    assert!(!ok && stderr.contains("--force"), "{stderr}");
    let _ = std::fs::remove_dir_all(tmp);
}

#[test]
fn compare_runs_a_frictionless_box_although_its_lab_measures_beta_a_hair_below_smooth() {
    let (tmp, ok, v, stderr) = compare(
        "vibrated-box-mu0",
        &[
            "--seeds",
            "1",
            "--transient",
            "0.05",
            "--set",
            "run.duration=0.1",
            "--set",
            "contact.friction=0",
        ],
    );
    assert!(ok, "{stderr}");
    assert_eq!(v["walton_fit"]["pair"]["beta0"], -1.0, "a smooth fit without friction");
    // The table the event-driven model read keeps beta within [-1, 1].
    let table = std::fs::read_to_string(tmp.join("cmp/restitution.csv")).unwrap();
    for line in table.lines().skip(1) {
        let beta: f64 = line.split(',').nth(3).unwrap().parse().unwrap();
        assert!((-1.0..=-0.98).contains(&beta), "{line}");
    }
    let _ = std::fs::remove_dir_all(tmp);
}
