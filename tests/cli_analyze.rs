//! The command-line contract of `stripes analyze`: the same layer read
//! from a `snapshots.bin` and from a LAMMPS dump gives the same stripes and phase, the
//! summary is the last stdout line and the plots and tables are written.

mod common;
use common::stripes;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use analysis::snapshot::{Header, SnapshotWriter};

const L: f64 = 0.4;
const W: f64 = 0.02;
const T: f64 = 0.05;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stripes-cli-analyze-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Deterministic pseudo-random numbers in [0, 1) (SplitMix64).
fn unit(k: u64) -> f64 {
    let mut z = k.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D1_049B_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// Three 2 cm bands (one across the seam) of 600 grains each on 300 background grains;
/// frame `f` shifts every grain by up to +-0.5 mm.
fn layer() -> (Vec<f64>, Vec<[f64; 3]>) {
    let (mut r, mut base) = (Vec::new(), Vec::new());
    for i in 0..2100u64 {
        let ri = 2.5e-4 + 2.5e-4 * unit(3 * i);
        let x = if i < 1800 {
            [0.0, 0.13, 0.27][(i % 3) as usize] + 0.02 * (unit(3 * i + 1) - 0.5)
        } else {
            L * unit(3 * i + 1)
        };
        r.push(ri);
        base.push([x.rem_euclid(L), ri + (W - 2.0 * ri) * unit(3 * i + 2), ri]);
    }
    (r, base)
}

fn frame(base: &[[f64; 3]], f: u64) -> Vec<[f64; 3]> {
    base.iter()
        .enumerate()
        .map(|(i, p)| [(p[0] + 1e-3 * (unit(1_000_000 * f + i as u64) - 0.5)).rem_euclid(L), p[1], p[2]])
        .collect()
}

fn summary_of(stdout: &str, out: &Path) -> serde_json::Value {
    let last = stdout.lines().last().expect("stdout has a last line");
    let s: serde_json::Value = serde_json::from_str(last).expect("last line is JSON");
    let file: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s, file, "stdout's last line is summary.json");
    s
}

#[test]
fn snapshots_and_a_lammps_dump_of_the_same_layer_give_the_same_analysis() {
    let (r, base) = layer();
    let dir = temp_dir("same");
    // As a stripes run directory.
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    let mut w = SnapshotWriter::create(
        &run.join("snapshots.bin"),
        Header {
            length: L,
            width: W,
            radii: r.clone(),
        },
    )
    .unwrap();
    // As a LAMMPS dump with xlo = -0.2, columns shuffled, atoms in reverse id order.
    let mut dump = String::new();
    for f in 0..25u64 {
        let pos = frame(&base, f);
        w.push(f as f64 * T, pos.iter().copied(), std::iter::repeat([0.0; 3])).unwrap();
        let _ = write!(
            dump,
            "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS pp ff ff\n-0.2 0.2\n0 {W}\n-0.001 0.1\nITEM: ATOMS x y z id radius vx vy vz\n",
            f * 6250,
            r.len()
        );
        for i in (0..r.len()).rev() {
            let p = pos[i];
            let _ = writeln!(dump, "{} {} {} {} {} 0 0 0", p[0] - 0.2, p[1], p[2], i + 1, r[i]);
        }
    }
    w.sync().unwrap();
    drop(w);
    std::fs::write(dir.join("tray.dump"), dump).unwrap();

    let (ok, stdout, stderr) = stripes(&["analyze", run.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let out = run.join("analysis");
    let s = summary_of(&stdout, &out);
    assert_eq!(s["stripe_count_final"], 3, "{s}");
    assert_eq!(s["stripe_onset_s"], 0.0);
    assert_eq!(s["phase"], "stripes");
    assert_eq!(s["input_kind"], "snapshots");
    assert!(s["contrast"].as_f64().unwrap() > 2.0);
    assert!(s["mobility"].as_f64().unwrap() > 0.1);
    assert!(s["msd_plateau_before"].is_null(), "stripes from the first frame: no `before`");
    // Uniform steps of +-0.5 mm in x, independent each frame: D = (1e-3)^2 / 12.
    let after = s["msd_plateau_after"].as_f64().unwrap();
    assert!((after / (1e-6 / 12.0) - 1.0).abs() < 0.05, "{after}");
    // The three sharp bands are stripes under every threshold set of the sensitivity sweep.
    assert_eq!(s["phase_robust"], true, "{s}");
    assert_eq!(s["phase_votes"]["stripes"], 27, "{s}");
    let sensitivity = std::fs::read_to_string(out.join("phase_sensitivity.csv")).unwrap();
    assert_eq!(sensitivity.lines().count(), 28);
    assert!(sensitivity.lines().skip(1).all(|l| l.ends_with(",stripes")), "{sensitivity}");
    for f in [
        "density_map.png",
        "density_map.svg",
        "top_view.png",
        "top_view.svg",
        "stripe_count.png",
        "msd.png",
        "tracer_trajectory.png",
        "radii.png",
        "density_map.csv",
        "coarsening.csv",
        "stripes.csv",
        "msd.csv",
        "tracer.csv",
        "radii.csv",
        "autocorrelation.csv",
        "count_density_final.csv",
        "config.json",
    ] {
        assert!(std::fs::metadata(out.join(f)).map(|m| m.len() > 0).unwrap_or(false), "{f} missing");
    }

    // One analysis given twice (the run and its analysis directory) is refused, naming both.
    let (ok, _, stderr) = stripes(&["seeds", run.to_str().unwrap(), out.to_str().unwrap()]);
    assert!(
        !ok && stderr.contains("same analysis") && stderr.contains(out.to_str().unwrap()),
        "{stderr}"
    );
    // A copy of it elsewhere is another run to the command: no spread and no pattern
    // distance; a directory without an analysis is named.
    let copy = dir.join("analysis-copy");
    std::fs::create_dir_all(&copy).unwrap();
    for f in std::fs::read_dir(&out).unwrap() {
        let f = f.unwrap().path();
        if f.is_file() {
            std::fs::copy(&f, copy.join(f.file_name().unwrap())).unwrap();
        }
    }
    let seeds_out = dir.join("seeds");
    let (ok, stdout, stderr) = stripes(&[
        "seeds",
        run.to_str().unwrap(),
        copy.to_str().unwrap(),
        "--out",
        seeds_out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let e = summary_of(&stdout, &seeds_out);
    assert_eq!(e["warnings"], serde_json::json!([]), "{e}");
    assert_eq!(e["pattern_distance_max"], 0.0, "{e}");
    assert_eq!(e["pooled"]["spacing_m"]["sd"], 0.0, "{e}");
    assert_eq!(e["pooled"]["spacing_m"]["mean"], s["spacing_m"], "{e}");
    assert_eq!(e["pooled"]["stripe_count_final"]["mean"], 3.0, "{e}");
    let table = std::fs::read_to_string(seeds_out.join("seeds.csv")).unwrap();
    assert_eq!(table.lines().count(), 3, "{table}");
    assert!(seeds_out.join("spacing_over_time.png").is_file());
    // Issue 43, messages: `seeds` printed "3 warning(s)" without the warnings. A copy whose
    // summary claims another grain count is pooled with a warning, printed where it is seen
    // and counted in the summary line.
    let summary_path = copy.join("summary.json");
    let mut other: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&summary_path).unwrap()).unwrap();
    other["particles"] = serde_json::json!(other["particles"].as_f64().unwrap() + 1.0);
    std::fs::write(&summary_path, other.to_string()).unwrap();
    let warned_out = dir.join("seeds-warned");
    let (ok, stdout, stderr) = stripes(&[
        "seeds",
        run.to_str().unwrap(),
        copy.to_str().unwrap(),
        "--out",
        warned_out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let e = summary_of(&stdout, &warned_out);
    assert_eq!(e["warnings"].as_array().unwrap().len(), 1, "{e}");
    assert!(
        stderr.contains("warning: the runs differ in their grain counts") && stderr.contains("1 warning(s)"),
        "{stderr}"
    );
    let (ok, _, stderr) = stripes(&["seeds", run.to_str().unwrap(), dir.to_str().unwrap()]);
    assert!(!ok && stderr.contains("stripes analyze"), "{stderr}");

    let dump_out = dir.join("lammps-analysis");
    let (ok, stdout, stderr) = stripes(&[
        "analyze",
        dir.join("tray.dump").to_str().unwrap(),
        "--out",
        dump_out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let d = summary_of(&stdout, &dump_out);
    assert_eq!(d["input_kind"], "lammps-dump");
    for key in [
        "stripe_count_final",
        "stripe_onset_s",
        "phase",
        "particles",
        "frames",
        "tail_stripe_count",
    ] {
        assert_eq!(d[key], s[key], "{key}");
    }
    // The snapshot stores positions in single precision: equal to about 1e-7 relative.
    for key in ["contrast", "mobility", "msd_plateau_after", "mean_area_fraction", "period_s"] {
        let (a, b) = (d[key].as_f64().unwrap(), s[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-4 * b.abs(), "{key}: dump {a}, snapshots {b}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn unreadable_inputs_and_bad_options_are_named() {
    let dir = temp_dir("bad");
    let junk = dir.join("junk.txt");
    std::fs::write(&junk, "hello").unwrap();
    let (ok, _, stderr) = stripes(&["analyze", junk.to_str().unwrap()]);
    assert!(!ok && stderr.contains("neither a stripes snapshot file"), "{stderr}");
    let (ok, _, stderr) = stripes(&["analyze", dir.to_str().unwrap()]);
    assert!(!ok && stderr.contains("snapshots.bin"), "{stderr}");
    let (ok, _, stderr) = stripes(&["analyze", junk.to_str().unwrap(), "--plateau-before", "3"]);
    assert!(!ok && stderr.contains("--plateau-before"), "{stderr}");
    let (ok, _, stderr) = stripes(&["analyze", junk.to_str().unwrap(), "--top-view", "1,NaN"]);
    assert!(!ok && stderr.contains("--top-view"), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Writes a run directory like `stripes run`'s: `config.json` with the drive frequency and
/// `snapshots.bin` with a t = 0 frame and then one frame per period at the turning point.
fn small_run(name: &str, frames: u64) -> PathBuf {
    let dir = temp_dir(name);
    let (r, base) = layer();
    let header = Header {
        length: L,
        width: W,
        radii: r.clone(),
    };
    let mut w = SnapshotWriter::create(&dir.join("snapshots.bin"), header).unwrap();
    for f in 0..frames {
        let t = if f == 0 { 0.0 } else { 0.25 * T + (f - 1) as f64 * T };
        let pos = frame(&base, f);
        w.push(t, pos.into_iter(), std::iter::repeat_n([0.0; 3], r.len())).unwrap();
    }
    w.sync().unwrap();
    std::fs::write(
        dir.join("config.json"),
        format!("{{\"scene\": {{\"drive\": {{\"frequency\": {}}}}}}}", 1.0 / T),
    )
    .unwrap();
    dir
}

/// Issue 19, point 1: a cut `snapshots.bin` is analysed with a warning that names the whole
/// frames read, and the period comes from the run's metadata, not from the snapshot spacing
/// (which, with a t = 0 frame a quarter period early, is T / 4 for two frames).
#[test]
fn a_cut_snapshot_file_warns_and_keeps_the_drive_period() {
    let run = small_run("cut", 5);
    let snap = run.join("snapshots.bin");
    let header_len = 32 + 8 * 2100;
    let frame_len = 8 + 24 * 2100;
    let f = std::fs::OpenOptions::new().write(true).open(&snap).unwrap();
    f.set_len((header_len + 2 * frame_len + frame_len / 2) as u64).unwrap();
    let (ok, stdout, stderr) = stripes(&["analyze", run.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("cut off") && stderr.contains("the 2 whole frames"), "{stderr}");
    let s = summary_of(&stdout, &run.join("analysis"));
    assert_eq!(s["frames"], 2);
    assert!((s["period_s"].as_f64().unwrap() - T).abs() < 1e-12, "{s}");
    assert!(s["period_source"].as_str().unwrap().contains("metadata"), "{s}");
    assert!(s["warnings"][0].as_str().unwrap().contains("2 whole frames"), "{s}");
    std::fs::remove_dir_all(run).unwrap();
}

/// Issue 19, point 2: one frame gives no phase, and says why.
#[test]
fn one_frame_gets_no_phase() {
    let run = small_run("one", 1);
    let (ok, stdout, stderr) = stripes(&["analyze", run.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let s = summary_of(&stdout, &run.join("analysis"));
    assert!(s["phase"].is_null(), "{s}");
    assert!(s["phase_note"].as_str().unwrap().contains("too few frames"), "{s}");
    assert!(stderr.contains("too few frames"), "{stderr}");
    // Persistence needs frames: one frame holds no stationary band and no spacing.
    assert_eq!(s["stationary_stripe_count"], 0, "{s}");
    assert!(s["stripe_spacing_m"].is_null(), "{s}");
    std::fs::remove_dir_all(run).unwrap();
}

/// Issue 19, point 14: without grains in stripes the radii plot says so in its legend, and
/// the tracer plots follow x across the periodic seam.
#[test]
fn plots_say_what_happened() {
    let dir = temp_dir("plain");
    let n = 300u64;
    let r: Vec<f64> = (0..n).map(|i| 2.5e-4 + 2.5e-4 * unit(7 * i)).collect();
    let mut w = SnapshotWriter::create(
        &dir.join("snapshots.bin"),
        Header {
            length: L,
            width: W,
            radii: r.clone(),
        },
    )
    .unwrap();
    for f in 0..4u64 {
        let pos: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                // Evenly spread in x (no band), moving a little every frame.
                let x = L * (i as f64 + 0.5) / n as f64 + 1e-4 * unit(7 * i + 1 + 1000 * f);
                [x.rem_euclid(L), 0.001 + 0.018 * unit(7 * i + 2), r[i as usize]]
            })
            .collect();
        w.push(f as f64 * T, pos.into_iter(), std::iter::repeat_n([0.0; 3], n as usize))
            .unwrap();
    }
    w.sync().unwrap();
    drop(w);
    let (ok, stdout, stderr) = stripes(&["analyze", dir.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let s = summary_of(&stdout, &dir.join("analysis"));
    assert_eq!(s["stripe_count_final"], 0, "{s}");
    let radii = std::fs::read_to_string(dir.join("analysis/radii.svg")).unwrap();
    assert!(
        radii.contains("no grain in a stripe"),
        "radii.svg does not say why one curve is missing"
    );
    let text = std::fs::read_to_string(dir.join("analysis/tracer_trajectory.svg")).unwrap();
    assert!(text.contains("followed across the periodic seam"));
    // Regression: a run without velocities (here all zero, as the automaton's) drew an empty
    // phase-space plot; it is not drawn.
    assert!(!dir.join("analysis/tracer_phase_space.svg").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// Writes an event-driven run's snapshots as `stripes events` does: a vertical box `width`
/// wide seen from the side, its header a slab one largest grain diameter thick, grains
/// stacked in z; no config.json.
fn vertical_box_run(name: &str) -> PathBuf {
    let dir = temp_dir(name);
    let (width, r) = (0.05, 1e-3);
    let n = 200u64;
    let header = Header {
        length: width,
        width: 2.0 * r,
        radii: vec![r; n as usize],
    };
    let mut w = SnapshotWriter::create(&dir.join("snapshots.bin"), header).unwrap();
    for f in 0..8u64 {
        let pos: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let x = (r + (i % 24) as f64 * 2.05 * r + 1e-4 * unit(f * 1000 + i)).min(width - r);
                [x, r, r + (i / 24) as f64 * 2.05 * r]
            })
            .collect();
        w.push(0.01 * f as f64, pos.into_iter(), std::iter::repeat_n([0.0; 3], n as usize))
            .unwrap();
    }
    w.sync().unwrap();
    dir
}

/// Issue 43, finding 7: an event-driven run without its config.json is analysed as the
/// vertical box its header shows, with a warning that says what was assumed; a garbled
/// config.json (no scene, or a scene of another box) is refused by name; a tray without one
/// is analysed as a tray with the same kind of warning.
#[test]
fn a_run_without_or_with_a_garbled_description_is_named() {
    let run = vertical_box_run("no-config");
    let (ok, stdout, stderr) = stripes(&["analyze", run.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("no config.json") && stderr.contains("assumed an event-driven vertical box"),
        "{stderr}"
    );
    let s = summary_of(&stdout, &run.join("analysis"));
    assert_eq!(s["geometry"], "vertical-box", "{s}");
    assert_eq!(s["phase"], "unclassified", "a vertical box is not called stripes: {s}");
    std::fs::remove_dir_all(run.join("analysis")).unwrap();
    for (config, want) in [
        (r#"{"args": {}}"#, "holds no `scene`"),
        ("{ garbled", "is not JSON"),
        (
            r#"{"scene": {"box": {"length": 0.4, "width": 0.02}, "drive": {"frequency": 20.0}}}"#,
            "0.4 m long",
        ),
        (
            r#"{"scene": {"box": {"width": 0.05, "height": 0.05}, "drive": {"frequency": 20.0}}}"#,
            "neither a tray nor",
        ),
        (
            r#"{"scene": {"model": "events", "box": {"width": 0.08}, "drive": {"frequency": 20.0}}}"#,
            "0.08 m wide",
        ),
    ] {
        std::fs::write(run.join("config.json"), config).unwrap();
        let (ok, _, stderr) = stripes(&["analyze", run.to_str().unwrap()]);
        assert!(!ok, "{config} was accepted");
        assert!(stderr.contains("config.json") && stderr.contains(want), "{config}: {stderr}");
        assert!(!run.join("analysis").exists(), "{config}: a refused analysis wrote files");
    }
    std::fs::write(
        run.join("config.json"),
        r#"{"scene": {"model": "events", "box": {"width": 0.05}, "drive": {"frequency": 12.5}}}"#,
    )
    .unwrap();
    let (ok, stdout, stderr) = stripes(&["analyze", run.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let s = summary_of(&stdout, &run.join("analysis"));
    assert_eq!(s["geometry"], "vertical-box", "{s}");
    assert!((s["period_s"].as_f64().unwrap() - 0.08).abs() < 1e-12, "{s}");
    std::fs::remove_dir_all(run).unwrap();

    let tray = small_run("tray-no-config", 3);
    std::fs::remove_file(tray.join("config.json")).unwrap();
    let (ok, stdout, stderr) = stripes(&["analyze", tray.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("assumed a tray seen from above"), "{stderr}");
    assert_eq!(summary_of(&stdout, &tray.join("analysis"))["geometry"], "tray");
    std::fs::remove_dir_all(tray).unwrap();
}

/// Issue 43, bounds: a `--cell` that would make a density map of billions of cells is
/// refused naming the option and the size, before anything is allocated or written.
#[test]
fn a_density_map_too_large_is_refused_by_its_option() {
    let run = small_run("huge-map", 3);
    let (ok, _, stderr) = stripes(&["analyze", run.to_str().unwrap(), "--cell", "1e-9"]);
    assert!(!ok, "a 4e8-cell map was accepted");
    assert!(
        stderr.contains("--cell 0.000000001 m") || stderr.contains("--cell 1e-9"),
        "{stderr}"
    );
    assert!(stderr.contains("4.000e8 cells"), "{stderr}");
    assert!(!run.join("analysis").exists(), "a refused analysis wrote files");
    std::fs::remove_dir_all(run).unwrap();
}

/// Issue 39, step 4: a run of 4 frames per period whose bands ride the tray (lab-frame
/// positions `x + A sin(2 pi t / T)`) is measured at the turning points in the tray's frame:
/// the camera's stripes sit where the bands are on the tray, the summary states the count
/// rule and the frames' phase, and `--map-frame` chooses the density map's frame.
#[test]
fn the_camera_measures_bands_in_the_tray_frame_at_the_turning_points() {
    let dir = temp_dir("camera");
    let (r, base) = layer();
    let amplitude = 0.01;
    let mut w = SnapshotWriter::create(
        &dir.join("snapshots.bin"),
        Header {
            length: L,
            width: W,
            radii: r.clone(),
        },
    )
    .unwrap();
    for f in 0..48u64 {
        let t = f as f64 * T / 4.0;
        let x_tray = amplitude * (std::f64::consts::TAU * t / T).sin();
        let pos: Vec<[f64; 3]> = frame(&base, f)
            .into_iter()
            .map(|p| [(p[0] + x_tray).rem_euclid(L), p[1], p[2]])
            .collect();
        w.push(t, pos.into_iter(), std::iter::repeat_n([0.0; 3], r.len())).unwrap();
    }
    w.sync().unwrap();
    drop(w);
    std::fs::write(
        dir.join("config.json"),
        format!(
            "{{\"scene\": {{\"drive\": {{\"frequency\": {}, \"amplitude\": {amplitude}}}}}}}",
            1.0 / T
        ),
    )
    .unwrap();
    let (ok, stdout, stderr) = stripes(&["analyze", dir.to_str().unwrap(), "--top-view", "0.1,0.5"]);
    assert!(ok, "{stderr}");
    let out = dir.join("analysis");
    let s = summary_of(&stdout, &out);
    let c = &s["camera"];
    assert_eq!(c["strobe_frames"], 12, "{c}");
    assert!(c["strobe_offset_max_periods"].as_f64().unwrap() < 1e-9, "{c}");
    assert_eq!(c["stripe_count_last"], 3, "{c}");
    assert_eq!(c["stripe_onset_s"], 0.25 * T, "{c}");
    assert!(c["label_note"].is_null(), "{c}");
    assert!((c["rule"]["threshold"].as_f64().unwrap() - s["stripe_params"]["threshold"].as_f64().unwrap()).abs() < 1e-15);
    assert_eq!(c["coarsening_law"]["better"], "undetermined", "a constant count: {c}");
    assert_eq!(c["lifetimes"]["censored"], 3, "{c}");
    // The bands' centres on the tray: 0, 0.13 and 0.27 m.
    let table = std::fs::read_to_string(out.join("camera_stripes.csv")).unwrap();
    let rows: Vec<Vec<f64>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let t_last = rows.iter().map(|r| r[0]).fold(0.0, f64::max);
    assert!((t_last - 11.25 * T).abs() < 1e-9, "{t_last}");
    let last: Vec<f64> = rows.iter().filter(|r| r[0] == t_last).map(|r| r[2]).collect();
    assert_eq!(last.len(), 3, "{table}");
    for want in [0.0, 0.13, 0.27] {
        let near = |got: &f64| {
            let d = (got - want).rem_euclid(L);
            d.min(L - d) < 1.5e-3
        };
        assert!(last.iter().any(near), "no stripe at {want} m on the tray: {last:?}");
    }
    for f in [
        "camera_count.csv",
        "camera_profiles.csv",
        "stripe_tracks.csv",
        "profile_correlation.csv",
        "stripe_count_log.png",
        "camera_profile_last.png",
        "top_view.png",
    ] {
        assert!(std::fs::metadata(out.join(f)).map(|m| m.len() > 0).unwrap_or(false), "{f} missing");
    }
    let (ok, _, stderr) = stripes(&["analyze", dir.to_str().unwrap(), "--force", "--map-frame", "lab"]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = stripes(&["analyze", dir.to_str().unwrap(), "--force", "--map-frame", "side"]);
    assert!(!ok && stderr.contains("--map-frame"), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}
