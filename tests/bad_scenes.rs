//! A corpus of bad scene files (`tests/bad_scenes/*.toml`); the first line of each says
//! `# error: <text>`, and `stripes run` must stop before simulating with a message holding it.

use std::process::Command;

#[test]
fn every_bad_scene_gives_its_stated_error() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    let tmp = std::env::temp_dir().join(format!("stripes-bad-{}", std::process::id()));
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let expect = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# error: "))
            .unwrap_or_else(|| panic!("{}: no `# error:` line", path.display()));
        let out = Command::new(env!("CARGO_BIN_EXE_stripes"))
            .args(["run", path.to_str().unwrap(), "--quiet", "--out"])
            .arg(tmp.join("run"))
            .arg("--sample-cache")
            .arg(tmp.join("samples"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{} was accepted", path.display());
        assert!(stderr.contains(expect), "{}: expected `{expect}`, got: {stderr}", path.display());
        // Issue 19, point 10: in the user's words, not Rust's.
        for rust in ["usize", "u64", "f64", "untagged enum"] {
            assert!(!stderr.contains(rust), "{}: `{rust}` in: {stderr}", path.display());
        }
        // Issue 19, point 8: a failed start leaves no run directory.
        assert!(!tmp.join("run").exists(), "{}: left a run directory", path.display());
        assert!(
            !tmp.join("samples").exists(),
            "{}: failed only after preparing a sample",
            path.display()
        );
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} bad scenes found");
    let _ = std::fs::remove_dir_all(tmp);
}
