//! Helpers shared by the command-line tests.

use std::process::Command;

/// Runs the `stripes` binary: `(success, stdout, stderr)`.
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
