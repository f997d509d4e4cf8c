//! Helpers shared by the command-line tests.

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `stripes` binary: `(success, stdout, stderr)`.
#[allow(dead_code)]
pub fn stripes(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_stripes"))
        .args(args)
        .output()
        .expect("run stripes");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `stripes run scenes/<scene>` into `out` with `--set` for each of `settings`, then `extra`;
/// with `cache`, that sample cache.
#[allow(dead_code)]
pub fn run(scene: &str, out: &Path, cache: Option<&Path>, settings: &[&str], extra: &[&str]) -> Output {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(scene);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_stripes"));
    cmd.arg("run").arg(scene).arg("--out").arg(out);
    if let Some(c) = cache {
        cmd.arg("--sample-cache").arg(c);
    }
    for s in settings {
        cmd.args(["--set", s]);
    }
    cmd.args(extra);
    cmd.output().expect("stripes runs")
}

/// The summary JSON, the last line on stdout of a command that must have succeeded.
#[allow(dead_code)]
pub fn summary(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "run failed: {}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    serde_json::from_str(stdout.lines().last().expect("a summary line")).expect("JSON summary")
}

/// A 2 cm x 5 mm tray with 40 grains, 0.02 s of preparation and 0.2 s of run, written into
/// `dir` (created); returns its path.
#[allow(dead_code)]
pub fn tiny_scene(dir: &Path) -> String {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("tiny.toml");
    std::fs::write(
        &p,
        "[box]\nlength = 0.02\nwidth = 0.005\n[drive]\nfrequency = 20.0\namplitude = 0.025\n\
         [particles]\ncount = 40\nradius_min = 0.25e-3\nradius_max = 0.5e-3\n[prepare]\nduration = 0.02\n\
         [run]\nduration = 0.2\ndt = 8e-6\nseed = 4\nthreads = 1\n",
    )
    .unwrap();
    p.display().to_string()
}
