//! `stripes events` as a new user calls it: the mixture scene (shortened) runs, writes its
//! profiles and snapshots, `stripes analyze` reads the run, and bad input is refused with
//! nothing left behind.

mod common;
use common::stripes;

/// A numeric CSV file: its header and its rows.
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    (header, rows)
}

fn last_json(stdout: &str) -> serde_json::Value {
    serde_json::from_str(stdout.lines().last().unwrap()).unwrap()
}

#[test]
fn the_mixture_runs_writes_its_profiles_and_analyze_reads_it() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let out = d.join("mix").display().to_string();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mixture.toml");
    let short = ["--set", "run.duration=0.6", "--set", "run.transient=0.2"];
    let mut args = vec!["events", scene, "--out", &out, "--quiet"];
    args.extend(short);
    let (ok, stdout, stderr) = stripes(&args);
    assert!(ok, "{stderr}");
    let s = last_json(&stdout);
    for key in [
        "collisions",
        "collisions_per_s",
        "energy_ledger_error",
        "mean_height_m",
        "current_x_m_per_s",
    ] {
        assert!(s[key].is_number(), "{key} missing in {s}");
    }
    assert!(s["collisions"].as_u64().unwrap() > 10_000);
    assert!(s["energy_ledger_error"].as_f64().unwrap() < 1e-9);
    let h = s["mean_height_m"].as_f64().unwrap();
    assert!(h > 0.0 && h < 0.0512, "{h}");
    // The light grains are colder than the heavy ones in the bulk (the paper: about 0.6).
    let ratio = s["temperature_ratio_bulk"].as_f64().unwrap();
    assert!(ratio > 0.2 && ratio < 1.0, "{ratio}");
    for f in [
        "config.json",
        "scene.toml",
        "snapshots.bin",
        "profiles.csv",
        "density_profile.png",
        "temperature_profile.png",
        "profiles_across.csv",
        "temperature_ratio.png",
        "density_across.png",
        "velocity_distribution.csv",
        "velocity_distribution.png",
        "free_times.csv",
        "free_times.png",
        "angular_distribution.csv",
        "angular_distribution.png",
        "velocity_by_height.csv",
        "angular_by_height.png",
        "side_imbalance.csv",
        "side_imbalance.png",
        "summary.json",
    ] {
        assert!(d.join("mix").join(f).is_file(), "{f} missing");
    }
    // The rescaled v_x density of each species integrates to about one over [-6, 6) (bins
    // of 0.2), and so does the paper's fit.
    let (_, rows) = read_csv(&d.join("mix").join("velocity_distribution.csv"));
    assert_eq!(rows.len(), 60);
    for col in 1..=3 {
        let integral: f64 = rows.iter().map(|r| r[col] * 0.2).sum();
        assert!((integral - 1.0).abs() < 0.03, "column {col}: {integral}");
    }
    // The spins too; by height, each third's columns are densities of their own.
    for (file, columns) in [("angular_distribution.csv", 2), ("velocity_by_height.csv", 6)] {
        let (header, rows) = read_csv(&d.join("mix").join(file));
        assert!(header.len() >= 2 + 2 && header.len() <= columns + 2, "{file}: {header:?}");
        for col in 1..header.len() {
            let integral: f64 = rows.iter().map(|r| r[col] * 0.2).sum();
            assert!((integral - 1.0).abs() < 0.03, "{file} column {}: {integral}", header[col]);
        }
    }
    // The side cluster's record: one imbalance per sample, within [-1, 1], its threshold at
    // least two independent spreads (300 grains: 2 / sqrt(300)).
    let side = &s["side_cluster"];
    assert_eq!(side["samples"].as_u64(), s["samples"].as_u64(), "{side}");
    let rms = side["imbalance_rms"].as_f64().unwrap();
    assert!(rms > 0.0 && rms <= 1.0, "{side}");
    assert!(side["threshold"].as_f64().unwrap() >= 2.0 / 300f64.sqrt() - 1e-12, "{side}");
    // The neighbour record: per species its grains, a share of its own kind between 0 and
    // 1, the chance share (150 - 1) / (300 - 1), and their ratio.
    let seg = &s["segregation"];
    assert_eq!(seg["samples"].as_u64(), s["samples"].as_u64(), "{seg}");
    for sp in seg["species"].as_array().unwrap() {
        assert_eq!(sp["grains"], 150, "{seg}");
        assert!((sp["chance_fraction"].as_f64().unwrap() - 149.0 / 299.0).abs() < 1e-12, "{seg}");
        let (same, ratio) = (sp["same_fraction"].as_f64().unwrap(), sp["ratio"].as_f64().unwrap());
        assert!((0.0..=1.0).contains(&same) && (ratio - same * 299.0 / 149.0).abs() < 1e-9, "{seg}");
        assert!(sp["neighbours_per_grain"].as_f64().unwrap() > 0.0, "{seg}");
    }
    // The same seed gives the same numbers, and profiles on other bins the same bulk ratio
    // (issue 43, finding 8: it moved from 0.65 to 0.62 and 0.77 with run.bin; it is summed
    // grain by grain now, with no warning about the bin).
    let out2 = d.join("mix2").display().to_string();
    let mut again = vec!["events", scene, "--out", &out2, "--quiet", "--set", "run.bin=0.01"];
    again.extend(short);
    let (ok, stdout2, stderr2) = stripes(&again);
    assert!(ok, "{stderr2}");
    let s2 = last_json(&stdout2);
    assert_eq!(s2["collisions"], s["collisions"]);
    assert_eq!(s2["mean_height_m"], s["mean_height_m"]);
    assert_eq!(s2["temperature_ratio_bulk"], s["temperature_ratio_bulk"]);
    assert!(!s2["warnings"].to_string().contains("run.bin"), "{s2}");
    // The box has a lid: nothing escapes.
    assert_eq!(s["escaped_grain_samples"], 0, "{s}");
    // A second run into the same directory is refused, --force replaces it.
    let (ok, _, stderr) = stripes(&args);
    assert!(!ok && stderr.contains("--force"), "{stderr}");
    // `stripes analyze` reads the run (its period from config.json).
    let (ok, stdout, stderr) = stripes(&["analyze", &out]);
    assert!(ok, "{stderr}");
    let a = last_json(&stdout);
    assert!(a["frames"].as_u64().unwrap_or(1) > 0);
    // A vertical box is not a tray: no stripe phase is claimed for it.
    assert_eq!(a["phase"], "unclassified", "{a}");
    assert!(a["warnings"].to_string().contains("vertical box"), "{a}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn bad_event_scenes_are_refused_and_leave_nothing() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-bad-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mixture.toml");
    for (set, says) in [
        ("box.width=0.01", "do not fit"),
        ("rules.pair.e=[1.5, 0.8, 0.7]", "rules.pair[0].e"),
        ("rules.pair.beta0=-2", "rules.pair[0].beta0"),
        ("rules.pair.mu=-0.1", "rules.pair[0].mu"),
        ("drive.amplitude=0.05", "drive.amplitude"),
        // 4e10 samples: a run that would never end, refused before it starts.
        ("drive.frequency=1e9", "run.samples_per_period"),
    ] {
        let out = d.join("bad").display().to_string();
        let (ok, _, stderr) = stripes(&["events", scene, "--set", set, "--out", &out, "--quiet"]);
        assert!(!ok, "{set} accepted");
        assert!(stderr.contains(says), "{set}: {stderr}");
        assert!(!d.join("bad").exists(), "{set} left {out}");
    }
    // A grain on a fixed floor without a guard collapses: the run stops with an error naming
    // the particle, and leaves nothing behind.
    let out = d.join("collapse").display().to_string();
    let (ok, _, stderr) = stripes(&[
        "events",
        scene,
        "--out",
        &out,
        "--quiet",
        "--set",
        "drive.floor=fixed",
        "--set",
        "drive.lid=none",
        "--set",
        "rules.floor.e=0.5",
        "--set",
        "rules.pair.v0=1e-9",
        "--set",
        "run.duration=5",
        "--set",
        "run.transient=0",
    ]);
    assert!(!ok && stderr.contains("collapse") && stderr.contains("particles"), "{stderr}");
    assert!(!d.join("collapse").exists());
    // A box that nothing moves runs (elastic here, so it does not slow down), and says so.
    let out = d.join("still").display().to_string();
    let vibrated_box = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml");
    let (ok, stdout, stderr) = stripes(&[
        "events",
        vibrated_box,
        "--out",
        &out,
        "--quiet",
        "--set",
        "drive.peak_speed=0",
        "--set",
        "rules.pair.e=1",
        "--set",
        "run.duration=0.2",
        "--set",
        "run.transient=0",
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("nothing moves the grains"), "{stderr}");
    assert!(last_json(&stdout)["warnings"].to_string().contains("nothing moves"), "{stdout}");
    // Issue 43, finding 10: a large guard.min_rebound_speed gave negative dissipation with no
    // warning. One faster than the grains is refused (src/scene/events_checks.rs); one just
    // below them, on smooth elastic pairs, adds energy in slow collisions, and says so.
    let out = d.join("pumped").display().to_string();
    let (ok, stdout, stderr) = stripes(&[
        "events",
        vibrated_box,
        "--out",
        &out,
        "--quiet",
        "--set",
        "guard.min_rebound_speed=0.19",
        "--set",
        "rules.pair.e=1",
        "--set",
        "rules.pair.mu=0",
        "--set",
        "run.duration=0.3",
        "--set",
        "run.transient=0",
    ]);
    assert!(ok, "{stderr}");
    let s = last_json(&stdout);
    assert!(s["dissipated_j"].as_f64().unwrap() < 0.0, "{s}");
    assert!(
        s["warnings"].to_string().contains("instead of dissipating it (dissipated_j < 0)")
            && stderr.contains("guard.min_rebound_speed = 0.19 m/s"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 43, finding 9: with no lid, grains that fly above the box's height piled into the
/// top profile bin with nothing said (H = 0.171 m in a 0.05 m box without gravity; a box
/// without gravity and lid is refused). With gravity they come back, but while above the box
/// they are counted and warned about: here the vibrated box cut to 10 mm and driven at 0.6 m/s
/// (a ballistic rise of about 18 mm).
#[test]
fn grains_above_an_open_top_are_counted_and_warned_about() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-escaped-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml");
    let out = d.join("low").display().to_string();
    let mut args = vec!["events", scene, "--out", &out, "--quiet"];
    for set in ["box.height=0.01", "drive.peak_speed=0.6", "run.duration=0.3", "run.transient=0.1"] {
        args.extend(["--set", set]);
    }
    let (ok, stdout, stderr) = stripes(&args);
    assert!(ok, "{stderr}");
    let s = last_json(&stdout);
    let escaped = s["escaped_grain_samples"].as_u64().unwrap();
    let samples = s["samples"].as_u64().unwrap();
    assert!(escaped > 0, "{s}");
    let fraction = s["escaped_fraction"].as_f64().unwrap();
    assert!((fraction - escaped as f64 / (50 * samples) as f64).abs() < 1e-12, "{s}");
    let with_any = s["escaped_samples"].as_u64().unwrap();
    assert!(with_any > 0 && with_any <= samples && with_any <= escaped, "{s}");
    let said = format!("{escaped} of {} sampled grain positions", 50 * samples);
    assert!(stderr.contains(&said) && stderr.contains("open top"), "{stderr}");
    assert!(s["warnings"].to_string().contains(&said), "{s}");
    // A sweep's run says it too, by its job.
    let sweep = d.join("sweep").display().to_string();
    let mut args = vec!["events-sweep", scene, "--out", &sweep, "--quiet", "--vary", "drive.peak_speed=0.6"];
    for set in ["box.height=0.01", "run.duration=0.3", "run.transient=0.1"] {
        args.extend(["--set", set]);
    }
    let (ok, stdout, stderr) = stripes(&args);
    assert!(ok, "{stderr}");
    let w = last_json(&stdout)["warnings"].to_string();
    assert!(w.contains("run p000-s1: ") && w.contains("above the box's open top"), "{w}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_ratchet_run_extended_with_resume_matches_the_whole_run_byte_for_byte() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-resume-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml");
    let (whole, part) = (d.join("whole").display().to_string(), d.join("part").display().to_string());
    let run = |out: &str, duration: &str, extra: &[&str]| {
        let set = format!("run.duration={duration}");
        let mut args = vec![
            "events",
            scene,
            "--out",
            out,
            "--quiet",
            "--set",
            "run.transient=0.5",
            "--set",
            &set,
        ];
        args.extend_from_slice(extra);
        stripes(&args)
    };
    let (ok, stdout, stderr) = run(&whole, "3", &[]);
    assert!(ok, "{stderr}");
    let full = last_json(&stdout);
    assert!(full["segregation"].is_null(), "one species: no neighbour record");
    assert!(run(&part, "1.5", &[]).0);
    // Resuming needs --resume: a plain second run is refused.
    assert!(!run(&part, "3", &[]).0);
    let (ok, stdout, stderr) = run(&part, "3", &["--resume"]);
    assert!(ok, "{stderr}");
    let resumed = last_json(&stdout);
    assert_eq!(resumed["resumed"], true);
    for key in ["collisions", "current_x_m_per_s", "mean_height_m", "energy_ledger_error"] {
        assert_eq!(resumed[key], full[key], "{key}");
    }
    for f in ["snapshots.bin", "profiles.csv"] {
        let a = std::fs::read(d.join("whole").join(f)).unwrap();
        let b = std::fs::read(d.join("part").join(f)).unwrap();
        assert!(a == b, "{f} differs after --resume");
    }
    // Another scene, or a checkpoint cut short, is refused with the reason.
    let (ok, _, stderr) = run(&part, "4", &["--resume", "--set", "rules.pair.e=0.7"]);
    assert!(!ok && stderr.contains("rules.pair.e: 0.8 -> 0.7"), "{stderr}");
    // Issue 43, finding 3: a shorter run.duration on a finished run is refused (the summary
    // said 2 s beside the 3 s run's samples), and nothing changes.
    let scene_before = std::fs::read(d.join("part").join("scene.toml")).unwrap();
    let (ok, _, stderr) = run(&part, "2", &["--resume"]);
    assert!(
        !ok && stderr.contains("run.duration: 3 -> 2") && stderr.contains("only extend"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(d.join("part").join("scene.toml")).unwrap(), scene_before);
    let ckpt = d.join("part").join("checkpoint.bin");
    let bytes = std::fs::read(&ckpt).unwrap();
    std::fs::write(&ckpt, &bytes[..bytes.len() / 2]).unwrap();
    let (ok, _, stderr) = run(&part, "4", &["--resume"]);
    assert!(!ok && stderr.contains("cut short"), "{stderr}");
    // Issue 43, messages: a run stopped before its first checkpoint was told "nothing was
    // written" beside 48 MB of snapshots; the message says what the directory holds.
    std::fs::remove_file(&ckpt).unwrap();
    let (ok, _, stderr) = run(&part, "4", &["--resume"]);
    assert!(
        !ok && !stderr.contains("nothing was written") && stderr.contains("before a first checkpoint") && stderr.contains("MB)"),
        "{stderr}"
    );
    let none = d.join("none").display().to_string();
    let (ok, _, stderr) = run(&none, "4", &["--resume"]);
    assert!(!ok && stderr.contains("nothing was written"), "{stderr}");
    assert!(!d.join("none").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// A sweep's `runs.csv` without its speed column (`collisions_per_s`, which depends on the
/// machine), as text cells.
fn runs_without_speed(dir: &std::path::Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let speed = header.iter().position(|h| *h == "collisions_per_s").unwrap();
    text.lines()
        .map(|l| {
            l.split(',')
                .enumerate()
                .filter(|(k, _)| *k != speed)
                .map(|(_, v)| v.to_string())
                .collect()
        })
        .collect()
}

#[test]
fn a_sweep_gives_the_same_tables_on_one_thread_and_on_two() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-sweep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml");
    let sweep = |name: &str, threads: &str| {
        let out = d.join(name).display().to_string();
        let (ok, stdout, stderr) = stripes(&[
            "events-sweep",
            scene,
            "--vary",
            "base.asymmetry=0.1,0.5",
            "--seeds",
            "2",
            "--threads",
            threads,
            "--set",
            "run.duration=2",
            "--set",
            "run.transient=0.5",
            "--out",
            &out,
            "--quiet",
        ]);
        assert!(ok, "{stderr}");
        (last_json(&stdout), d.join(name))
    };
    let (one, dir1) = sweep("one", "1");
    let (_, dir2) = sweep("two", "2");
    assert_eq!(one["runs"], 4);
    // Measures other than the speed are identical whatever the thread count.
    let table = runs_without_speed;
    assert_eq!(table(&dir1), table(&dir2));
    assert_eq!(table(&dir1).len(), 5);
    let means = std::fs::read_to_string(dir1.join("means.csv")).unwrap();
    assert!(
        means.starts_with("base.asymmetry,runs,current_x_m_per_s_mean,current_x_m_per_s_stderr"),
        "{means}"
    );
    assert_eq!(means.lines().count(), 3);
    assert!(dir1.join("current_x.png").is_file());
    // A value that is not a number is refused before anything runs.
    let bad = d.join("bad").display().to_string();
    let (ok, _, stderr) = stripes(&["events-sweep", scene, "--vary", "base.asymmetry=0.1,wide", "--out", &bad]);
    assert!(
        !ok && stderr.contains("`wide` is not a number") && !d.join("bad").exists(),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 43 and issue 42 step 3: the event-driven sweep is a sweep of the one engine. Two
/// shards collected give the tables of one run; a re-run continues (every finished run kept,
/// none redone); a different sweep in the same directory is refused.
#[test]
fn an_events_sweep_runs_in_shards_continues_and_refuses_another_sweep() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-shards-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml");
    let sweep = |dir: &std::path::Path, extra: &[&str]| {
        let out = dir.display().to_string();
        let mut a = vec![
            "events-sweep",
            scene,
            "--vary",
            "base.asymmetry=0.1,0.5",
            "--seeds",
            "2",
            "--set",
            "run.duration=1",
            "--set",
            "run.transient=0.25",
            "--out",
            &out,
            "--quiet",
        ];
        a.extend_from_slice(extra);
        stripes(&a)
    };
    let (one, sharded) = (d.join("one"), d.join("sharded"));
    let (ok, stdout, stderr) = sweep(&one, &[]);
    assert!(ok, "{stderr}");
    assert_eq!(last_json(&stdout)["progress"]["ran"], 4);
    for shard in ["0/2", "1/2"] {
        let (ok, _, stderr) = sweep(&sharded, &["--shard", shard]);
        assert!(ok, "{stderr}");
    }
    let (ok, _, stderr) = stripes(&["collect", &sharded.display().to_string()]);
    assert!(ok, "{stderr}");
    let table = runs_without_speed;
    assert_eq!(table(&one), table(&sharded));
    assert_eq!(table(&one).len(), 5);
    // The same sweep again: nothing is rerun, the tables are the same.
    let (ok, stdout, stderr) = sweep(&one, &[]);
    assert!(ok, "{stderr}");
    let again = last_json(&stdout);
    assert_eq!(
        (again["progress"]["ran"].as_u64(), again["progress"]["skipped"].as_u64()),
        (Some(0), Some(4))
    );
    // Another sweep in the same directory is refused, and leaves its results alone.
    let (ok, _, stderr) = sweep(&one, &["--set", "run.bin=0.002"]);
    assert!(!ok && stderr.contains("holds a sweep of another resolved scene"), "{stderr}");
    let (ok, _, stderr) = stripes(&[
        "events-sweep",
        scene,
        "--vary",
        "base.asymmetry=0.2",
        "--out",
        &one.display().to_string(),
        "--quiet",
    ]);
    assert!(!ok && stderr.contains("holds a"), "{stderr}");
    assert_eq!(table(&one).len(), 5);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_sweep_of_a_two_species_scene_tabulates_and_plots_the_bulk_temperature_ratio() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-sweep2-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/mixture.toml");
    let out = d.join("mix").display().to_string();
    let (ok, stdout, stderr) = stripes(&[
        "events-sweep",
        scene,
        "--vary",
        "drive.frequency=40,60",
        "--set",
        "run.duration=0.6",
        "--set",
        "run.transient=0.2",
        "--out",
        &out,
        "--quiet",
        "--log",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(last_json(&stdout)["runs"], 2);
    let means = std::fs::read_to_string(d.join("mix").join("means.csv")).unwrap();
    let header: Vec<&str> = means.lines().next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "temperature_ratio_bulk_mean")
        .expect("the ratio's column");
    for row in means.lines().skip(1) {
        let ratio: f64 = row.split(',').nth(col).unwrap().parse().unwrap();
        assert!(ratio > 0.2 && ratio < 1.0, "{row}");
    }
    assert!(d.join("mix").join("temperature_ratio_bulk.png").is_file());
    let _ = std::fs::remove_dir_all(&d);
}

/// On a sawtooth base the run writes the phase-resolved field over one tooth (the ratchet
/// paper's Figs 13-14): six frames, each with as many samples, boxes of w / 6.
#[test]
fn the_ratchet_writes_its_phase_fields() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-fields-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let out = d.join("ratchet").display().to_string();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml");
    let (ok, _, stderr) = stripes(&[
        "events",
        scene,
        "--out",
        &out,
        "--quiet",
        "--set",
        "run.duration=1.2",
        "--set",
        "run.transient=0",
        "--set",
        "run.samples_per_period=12",
    ]);
    assert!(ok, "{stderr}");
    let (_, rows) = read_csv(&d.join("ratchet").join("phase_fields.csv"));
    // 1.2 s at 25 Hz and 12 samples per period: about 360 samples, 60 per frame (the last
    // sample may fall a rounding error past the duration).
    for frame in 0..6 {
        let mine: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == frame as f64).collect();
        assert!(!mine.is_empty(), "frame {frame}");
        assert!(mine.iter().all(|r| r[1] == 60.0 || r[1] == 59.0), "frame {frame}: {:?}", mine[0]);
        // Six boxes across the 6 mm tooth, centred at 0.5, 1.5, ... mm.
        let mut xs: Vec<f64> = mine.iter().map(|r| r[2]).collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        assert_eq!(xs.len(), 6, "{xs:?}");
        assert!((xs[0] - 0.0005).abs() < 1e-12 && (xs[5] - 0.0055).abs() < 1e-12, "{xs:?}");
    }
    assert!(d.join("ratchet").join("phase_fields.png").is_file());
    // A periodic box has no sides: no side-cluster record.
    assert!(!d.join("ratchet").join("side_imbalance.csv").exists());
    std::fs::remove_dir_all(&d).unwrap();
}

/// Runs `stripes` in the working directory `cwd`: `(success, stdout, stderr)`.
fn stripes_in(cwd: &std::path::Path, args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_stripes"))
        .current_dir(cwd)
        .args(args)
        .output()
        .expect("run stripes");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Issue 43, finding 6 and messages: a table edited between a run and its `--resume` is
/// refused, naming the table (the run's two halves used different tables); and a relative
/// table path is recorded absolute in the run's scene.toml, so a rerun of that scene from
/// another directory reads the same table.
#[test]
fn a_resume_refuses_an_edited_table_and_a_relative_table_path_travels() {
    let d = std::env::temp_dir().join(format!("stripes-cli-events-table-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("elsewhere")).unwrap();
    let table = "g_n,g_t_over_g_n,eps_n,beta\n0.01,0,0.9,-0.5\n0.01,2,0.9,-1\n1,0,0.8,0.5\n1,2,0.8,0\n";
    std::fs::write(d.join("t.csv"), table).unwrap();
    let scene = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/vibrated-box.toml"))
        .unwrap()
        .replace(
            "[rules.pair]\ne = 0.9\nmu = 0.5\nbeta0 = 0.5\n",
            "[rules.pair]\ntable = \"t.csv\"\n",
        );
    assert!(scene.contains("table = \"t.csv\""));
    std::fs::write(d.join("box.toml"), scene).unwrap();
    let short = ["--set", "run.transient=0", "--quiet"];
    let mut args = vec!["events", "box.toml", "--out", "run", "--set", "run.duration=0.2"];
    args.extend(short);
    let (ok, _, stderr) = stripes_in(&d, &args);
    assert!(ok, "{stderr}");
    let recorded = std::fs::read_to_string(d.join("run").join("scene.toml")).unwrap();
    assert!(recorded.contains(&d.join("t.csv").display().to_string()), "{recorded}");
    // The run's own scene reruns from another directory.
    let own = d.join("run").join("scene.toml").display().to_string();
    let mut args = vec!["events", &own, "--out", "again", "--set", "run.duration=0.1"];
    args.extend(short);
    let (ok, _, stderr) = stripes_in(&d.join("elsewhere"), &args);
    assert!(ok, "{stderr}");
    // An edited table is refused on --resume, by name, and nothing changes.
    std::fs::write(d.join("t.csv"), table.replace("0.8,0.5", "0.7,0.5")).unwrap();
    let mut args = vec!["events", "box.toml", "--out", "run", "--set", "run.duration=0.4", "--resume"];
    args.extend(short);
    let (ok, _, stderr) = stripes_in(&d, &args);
    assert!(!ok && stderr.contains("the content of rules.pair.table"), "{stderr}");
    assert_eq!(std::fs::read_to_string(d.join("run").join("scene.toml")).unwrap(), recorded);
    // The table restored, the same resume extends the run.
    std::fs::write(d.join("t.csv"), table).unwrap();
    let (ok, stdout, stderr) = stripes_in(&d, &args);
    assert!(ok, "{stderr}");
    assert_eq!(last_json(&stdout)["resumed"], true);
    let _ = std::fs::remove_dir_all(&d);
}
