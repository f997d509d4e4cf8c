//! The command-line contract of `stripes collide` and the study commands.

mod common;
use common::stripes;

fn temp_out(name: &str) -> String {
    let d = std::env::temp_dir().join(format!("stripes-cli-{name}-{}", std::process::id()));
    d.display().to_string()
}

#[test]
fn collide_prints_the_spec_keys_as_its_last_line_and_writes_the_run_directory() {
    let out = temp_out("collide");
    let (ok, stdout, stderr) = stripes(&[
        "collide",
        "--normal",
        "linear",
        "--kn",
        "1.5e5",
        "--r1",
        "0.1",
        "--rho",
        "1140",
        "--v",
        "10",
        "--eccentricity",
        "0.95",
        "--out",
        &out,
    ]);
    assert!(ok, "{stderr}");
    let last = stdout.lines().last().unwrap();
    let v: serde_json::Value = serde_json::from_str(last).unwrap();
    for key in ["eps_n", "eps_n_hs", "eps_t", "t_c", "phi", "max_overlap", "steps"] {
        assert!(v.get(key).is_some(), "missing {key} in {last}");
    }
    assert!(v["eps_n_hs"].as_f64().unwrap() < 0.0, "chapter 4: negative at e = 0.95");
    assert!((v["eps_n"].as_f64().unwrap() - 1.0).abs() < 1e-5);
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(format!("{out}/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["eps_n"], v["eps_n"]);
    let config: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(format!("{out}/config.json")).unwrap()).unwrap();
    assert_eq!(config["eccentricity"], 0.95);
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn bad_collide_input_gives_a_clear_error_naming_the_option() {
    let out = temp_out("bad");
    for (args, expect) in [
        (vec!["collide", "--tangential", "cundall-strack"], "--kt"),
        (vec!["collide", "--normal", "linear"], "--kn"),
        (vec!["collide", "--dt", "1e-3"], "`dt`"),
        (vec!["collide", "--eccentricity", "1.2"], "eccentricity"),
        (vec!["collide", "--wall", "--eccentricity", "0.5"], "eccentricity"),
        (vec!["collide", "--v", "-1"], "`v`"),
    ] {
        let mut a = args.clone();
        a.extend(["--out", &out]);
        let (ok, _, stderr) = stripes(&a);
        assert!(!ok, "{args:?} should fail");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
    }
}

#[test]
fn eccentricity_study_writes_table_and_plots() {
    let out = temp_out("ecc");
    let (ok, stdout, stderr) = stripes(&["eccentricity", "--points", "6", "--steps-per-contact", "300", "--out", &out]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert_eq!(v["studies"].as_array().unwrap().len(), 4);
    for f in [
        "eccentricity.csv",
        "eps_n_hs.png",
        "eps_n_hs.svg",
        "phi.png",
        "summary.json",
        "config.json",
    ] {
        assert!(std::path::Path::new(&format!("{out}/{f}")).exists(), "{f}");
    }
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn the_restitution_table_of_a_scene_feeds_the_event_driven_model() {
    let d = std::env::temp_dir().join(format!("stripes-cli-collide-table-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let out = d.join("table").display().to_string();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/stripes.toml");
    let (ok, stdout, stderr) = stripes(&[
        "collide", "--table", "--scene", scene, "--g-n", "0.05,0.2", "--ratios", "0.1,1,5", "--out", &out,
    ]);
    assert!(ok, "{stderr}");
    let s: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert_eq!(s["restitution"]["impacts"], 6);
    assert_eq!(s["restitution_floor"]["impacts"], 6);
    for f in [
        "restitution.csv",
        "restitution_floor.csv",
        "restitution_beta.png",
        "restitution_floor_eps_n.png",
    ] {
        assert!(d.join("table").join(f).is_file(), "{f} missing");
    }
    let text = std::fs::read_to_string(d.join("table").join("restitution.csv")).unwrap();
    assert!(text.starts_with("g_n,g_t_over_g_n,eps_n,beta\n"), "{text}");
    // Every coefficient is a restitution: eps_n in (0, 1], beta in [-1, 1].
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(v[2] > 0.0 && v[2] <= 1.0 && v[3] >= -1.0 && v[3] <= 1.0, "{line}");
    }
    // The event-driven model runs the ratchet with this table as its pair and floor rules.
    let events = d.join("ev").display().to_string();
    let ratchet = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml");
    let pair = format!("rules.pair={{table = \"{}\"}}", d.join("table").join("restitution.csv").display());
    let floor = format!(
        "rules.floor={{table = \"{}\"}}",
        d.join("table").join("restitution_floor.csv").display()
    );
    let (ok, stdout, stderr) = stripes(&[
        "events",
        ratchet,
        "--out",
        &events,
        "--quiet",
        "--set",
        &pair,
        "--set",
        &floor,
        "--set",
        "run.duration=2",
        "--set",
        "run.transient=0.5",
    ]);
    assert!(ok, "{stderr}");
    let s: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    assert!(s["collisions"].as_u64().unwrap() > 1000, "{s}");
    // A zero ratio is refused naming it.
    let (ok, _, stderr) = stripes(&[
        "collide",
        "--table",
        "--ratios",
        "0,1",
        "--out",
        &d.join("bad").display().to_string(),
    ]);
    assert!(!ok && stderr.contains("must be positive"), "{stderr}");
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 43: `collide` without `--out` is a calculator (it prints its result, writes nothing,
/// and a second call needs no --force), and a `collide --table` that fails leaves nothing, so
/// its corrected rerun needs no --force either.
#[test]
fn collide_is_a_calculator_and_a_failed_table_leaves_nothing() {
    let d = std::path::PathBuf::from(temp_out("calculator"));
    std::fs::create_dir_all(&d).unwrap();
    for _ in 0..2 {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_stripes"))
            .current_dir(&d)
            .args(["collide", "--v", "0.2"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap();
        assert!(v["eps_n"].as_f64().unwrap() > 0.0, "{v}");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "the calculator wrote files");
    }
    let out = d.join("table").display().to_string();
    let table = ["collide", "--table", "--g-n", "0.1", "--ratios", "1", "--quiet", "--out", &out];
    let mut bad = table.to_vec();
    bad.extend(["--dt", "1e-3"]);
    let (ok, _, stderr) = stripes(&bad);
    assert!(!ok && stderr.contains("dt"), "{stderr}");
    assert!(!d.join("table").exists(), "a failed table left files");
    let (ok, _, stderr) = stripes(&table);
    assert!(ok, "the corrected rerun: {stderr}");
    assert!(d.join("table/restitution_beta.png").is_file());
    std::fs::remove_dir_all(d).unwrap();
}
