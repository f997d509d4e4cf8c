//! A lock on a run directory while a command writes it: `<dir>/.lock` holds the writer's
//! process id, created exclusively. A second writer is refused with the holder's pid; a lock
//! left by a process that no longer runs (killed) is taken over with a note. The lock is
//! removed when the guard drops, whether the command succeeded or failed.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::rundir::output::CliError;

/// Holds `<dir>/.lock` until dropped.
#[derive(Debug)]
pub struct RunLock {
    path: PathBuf,
}

impl RunLock {
    /// Locks `dir` (created if missing). Errors name the directory and the process that
    /// holds it.
    pub fn acquire(dir: &Path) -> Result<Self, CliError> {
        std::fs::create_dir_all(dir).map_err(|e| format!("cannot create output directory {}: {e}", dir.display()))?;
        let path = dir.join(".lock");
        for _ in 0..2 {
            match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(mut f) => {
                    writeln!(f, "{}", std::process::id())?;
                    return Ok(Self { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let holder = std::fs::read_to_string(&path).unwrap_or_default();
                    let pid: Option<u32> = holder.trim().parse().ok();
                    if pid.is_some_and(alive) {
                        return Err(format!(
                            "{} is being written by another process (pid {}, see {}); wait for it or choose another --out",
                            dir.display(),
                            pid.unwrap_or_default(),
                            path.display()
                        )
                        .into());
                    }
                    eprintln!(
                        "note: {} held a lock of a process that no longer runs ({}); taking it over",
                        dir.display(),
                        holder.trim()
                    );
                    std::fs::remove_file(&path)?;
                }
                Err(e) => return Err(format!("cannot lock {}: {e}", path.display()).into()),
            }
        }
        Err(format!("cannot lock {}: another process keeps taking it", dir.display()).into())
    }
}

impl Drop for RunLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Whether process `pid` runs (Linux: `/proc/<pid>` exists; elsewhere assumed alive, so a
/// stale lock must be removed by hand there).
fn alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    if cfg!(target_os = "linux") {
        Path::new(&format!("/proc/{pid}")).exists()
    } else {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_locked_directory_refuses_a_second_writer_and_a_dead_holder_is_taken_over() {
        let d = std::env::temp_dir().join(format!("stripes-lock-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        let first = RunLock::acquire(&d).unwrap();
        let e = RunLock::acquire(&d).unwrap_err().to_string();
        assert!(e.contains("being written by another process"), "{e}");
        drop(first);
        assert!(!d.join(".lock").exists());
        // A pid that cannot run (beyond the kernel's pid_max of 2^22).
        std::fs::write(d.join(".lock"), "4294967295\n").unwrap();
        let taken = RunLock::acquire(&d).unwrap();
        drop(taken);
        std::fs::remove_dir_all(&d).unwrap();
    }
}
