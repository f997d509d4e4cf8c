//! Run directories: resolved configuration, `summary.json`, CSV tables and plots, all
//! written atomically.

use std::path::{Path, PathBuf};

use analysis::plot::LinePlot;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

/// Error type of the CLI: a message for the user.
pub type CliError = Box<dyn std::error::Error + Send + Sync>;

/// The one rule of every command's output directory: a directory that already holds files
/// is refused unless `--force` (replace them). `stripes run` and the sweeps add `--resume`.
///
/// With `--force` the previous output's `summary.json` and the files it lists are removed
/// first, so that a new run that fails part-way never leaves the old summary (or old tables)
/// beside its own files as if they belonged to it. Files the summary does not list, and
/// anything outside the directory, are left alone.
pub fn claim(dir: &Path, force: bool) -> Result<(), CliError> {
    if !non_empty(dir) {
        return Ok(());
    }
    if !force {
        return Err(format!(
            "{} already holds files; use --force to replace them, or another --out",
            dir.display()
        )
        .into());
    }
    remove_previous_outputs(dir)
}

/// The claim of a run that `--resume` can continue (`stripes run`, `stripes events`): with
/// `resume`, the directory must hold the checkpoint it continues (the scene is then checked
/// by [`crate::rundir::resume`]); else a directory that holds files is refused unless `force`,
/// which removes the previous output: the files its summary lists, as [`claim`] does, and
/// `run_files`, those the model always writes (files or folders). Returns whether the
/// directory is new (then a failed start removes it).
pub fn claim_run(dir: &Path, resume: bool, force: bool, run_files: &[&str]) -> Result<bool, CliError> {
    claim_resumable(dir, dir, "a run", resume, force, run_files)
}

/// [`claim_run`] of a directory whose run keeps its checkpoint in `checkpoint_dir` (a
/// comparison's DEM run in `dir/dem`); `what` names what an occupied directory may hold in
/// the message (e.g. "an earlier comparison").
pub fn claim_resumable(
    dir: &Path,
    checkpoint_dir: &Path,
    what: &str,
    resume: bool,
    force: bool,
    run_files: &[&str],
) -> Result<bool, CliError> {
    if resume {
        if !checkpoint_dir.join("checkpoint.bin").is_file() {
            return Err(format!("--resume: {}", crate::rundir::resume::no_checkpoint(checkpoint_dir)).into());
        }
        return Ok(false);
    }
    if !non_empty(dir) {
        return Ok(!dir.exists());
    }
    if !force {
        return Err(format!(
            "{} already holds files ({what}?); use --resume to continue it, --force to replace it, or another --out",
            dir.display()
        )
        .into());
    }
    remove_previous_outputs(dir)?;
    for f in run_files {
        let p = dir.join(f);
        let gone = if p.is_dir() {
            std::fs::remove_dir_all(&p)
        } else {
            std::fs::remove_file(&p)
        };
        if let Err(e) = gone {
            if e.kind() != std::io::ErrorKind::NotFound {
                return Err(format!("--force: cannot remove {}: {e}", p.display()).into());
            }
        }
    }
    Ok(false)
}

/// Removes `dir/summary.json` and the files inside `dir` that it lists under `files`.
fn remove_previous_outputs(dir: &Path) -> Result<(), CliError> {
    let summary = dir.join("summary.json");
    let Ok(text) = std::fs::read_to_string(&summary) else {
        return Ok(());
    };
    /// The part of a summary read here: the files the run wrote (none listed in a summary
    /// that is not one of ours).
    #[derive(serde::Deserialize)]
    struct Listed {
        #[serde(default)]
        files: Vec<PathBuf>,
    }
    let listed = serde_json::from_str::<Listed>(&text).map_or_else(|_| Vec::new(), |l| l.files);
    let inside = |p: &Path| {
        let parent = p.parent().and_then(|d| d.canonicalize().ok());
        parent.is_some() && parent == dir.canonicalize().ok()
    };
    for p in listed.iter().chain([&summary]) {
        if !(p.is_file() && inside(p)) {
            continue;
        }
        std::fs::remove_file(p).map_err(|e| format!("--force: cannot remove {}: {e}", p.display()))?;
    }
    Ok(())
}

/// An output directory of one run.
pub struct RunDir {
    pub path: PathBuf,
    written: Vec<PathBuf>,
}

impl RunDir {
    /// Creates `path` (and parents) and writes the resolved configuration to `config.json`.
    pub fn create(path: &Path, config: &impl Serialize) -> Result<Self, CliError> {
        std::fs::create_dir_all(path).map_err(|e| format!("cannot create output directory {}: {e}", path.display()))?;
        let mut dir = Self {
            path: path.to_path_buf(),
            written: Vec::new(),
        };
        dir.json("config.json", config)?;
        Ok(dir)
    }

    /// An output directory whose `config.json` is left as it is for now (a resume writes it
    /// only once the run it continues is known to be the one asked for).
    pub fn open(path: &Path) -> Result<Self, CliError> {
        std::fs::create_dir_all(path).map_err(|e| format!("cannot create output directory {}: {e}", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            written: Vec::new(),
        })
    }

    /// Writes a JSON file.
    pub fn json(&mut self, name: &str, value: &impl Serialize) -> Result<(), CliError> {
        let p = self.path.join(name);
        analysis::io::write_json_atomic(&p, value).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        self.written.push(p);
        Ok(())
    }

    /// Writes a numeric CSV table.
    pub fn csv(&mut self, name: &str, header: &[&str], rows: &[Vec<f64>]) -> Result<(), CliError> {
        let p = self.path.join(name);
        analysis::io::write_csv_atomic(&p, header, rows).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        self.written.push(p);
        Ok(())
    }

    /// Writes a text file (a CSV with label columns, a report).
    pub fn text(&mut self, name: &str, text: &str) -> Result<(), CliError> {
        let p = self.path.join(name);
        analysis::io::write_atomic(&p, text.as_bytes()).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        self.written.push(p);
        Ok(())
    }

    /// Saves a plot as `<stem>.png` and `<stem>.svg`.
    pub fn plot(&mut self, stem: &str, plot: &LinePlot) -> Result<(), CliError> {
        let files = plot.save(&self.path.join(stem)).map_err(|e| format!("cannot draw {stem}: {e}"))?;
        self.written.extend(files);
        Ok(())
    }

    /// Records files written by other means, for the summary's file list.
    pub fn note_files(&mut self, files: impl IntoIterator<Item = PathBuf>) {
        self.written.extend(files);
    }

    /// Records every file under the subdirectory `sub` (written by the commands this one ran,
    /// e.g. `compare`'s DEM and automaton runs), in path order, so the summary counts them.
    pub fn note_tree(&mut self, sub: &Path) {
        fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
            let Ok(entries) = std::fs::read_dir(dir) else { return };
            let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
            paths.sort();
            for p in paths {
                if p.is_dir() {
                    walk(&p, out);
                } else if p.file_name().is_some_and(|n| n != ".lock") {
                    out.push(p);
                }
            }
        }
        let mut found = Vec::new();
        walk(&self.path.join(sub), &mut found);
        found.retain(|p| !self.written.contains(p));
        self.written.extend(found);
    }

    /// Where this directory is and what has been written into it so far, as a typed summary
    /// ends (see [`RunDir::finish_typed`]).
    pub fn written(&self) -> Written {
        Written {
            out: self.path.display().to_string(),
            files: self.written.iter().map(|p| p.display().to_string()).collect(),
        }
    }

    /// Writes a typed summary, which ends with [`RunDir::written`], as `summary.json` (through
    /// a JSON value, so its keys are sorted).
    pub fn finish_typed(mut self, summary: &impl Serialize) -> Result<(), CliError> {
        let value = serde_json::to_value(summary)?;
        self.json("summary.json", &value)
    }
}

/// The last fields of every summary: the output directory and the files written into it.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Written {
    pub out: String,
    pub files: Vec<String>,
}

/// Whether `dir` exists and holds anything.
pub fn non_empty(dir: &Path) -> bool {
    // A run's own lock (`crate::rundir::lock`) is not content.
    std::fs::read_dir(dir).is_ok_and(|d| d.flatten().any(|e| e.file_name() != ".lock"))
}

/// Environment variable that sets the cache of prepared samples (`--sample-cache`).
pub const SAMPLE_CACHE_ENV: &str = "STRIPES_SAMPLE_CACHE";

/// The default cache of prepared samples: `$STRIPES_SAMPLE_CACHE` (if set and not empty),
/// else `out/samples` (relative to the current directory).
pub fn default_sample_cache() -> PathBuf {
    // An empty variable (`STRIPES_SAMPLE_CACHE= stripes run ...`) counts as unset: an empty
    // default would otherwise be reported by clap as a missing `--sample-cache`.
    std::env::var_os(SAMPLE_CACHE_ENV)
        .filter(|v| !v.is_empty())
        .map_or_else(|| PathBuf::from("out/samples"), PathBuf::from)
}

/// The progress of every long command (nothing with `--quiet`). On a terminal, a bar on
/// stderr; off a terminal (CI logs, Slurm, a pipe), one line on stderr every tenth of the work
/// or every minute, whichever comes first (see [`progress_line`]). The bar's message (e.g.
/// the simulated time) appears in both.
pub fn progress_bar(len: u64, quiet: bool, what: &str) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    if !std::io::stderr().is_terminal() {
        let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
        let (watched, what) = (bar.clone(), what.to_string());
        std::thread::spawn(move || log_progress(&watched, &what));
        return bar;
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template("{prefix:>12} [{bar:40}] {percent:>3}% {msg} {elapsed_precise} eta {eta_precise}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix(what.to_string());
    bar
}

/// Longest silence of the line progress off a terminal.
const PROGRESS_EVERY: Duration = Duration::from_secs(60);

/// Prints [`progress_line`]s for `bar` until it is finished.
fn log_progress(bar: &ProgressBar, what: &str) {
    let (mut decile, mut printed) = (0, Instant::now());
    while !bar.is_finished() {
        std::thread::sleep(Duration::from_millis(200));
        let (pos, len) = (bar.position(), bar.length().unwrap_or(0).max(1));
        let now_decile = (pos.min(len) * 10 / len).min(9);
        if now_decile > decile || printed.elapsed() >= PROGRESS_EVERY {
            if bar.is_finished() {
                break;
            }
            eprintln!("{}", progress_line(what, pos, len, bar.elapsed(), &bar.message()));
            (decile, printed) = (now_decile, Instant::now());
        }
    }
}

/// One progress line: `run: 30% (4500/15000 at 2.1e4/s), t = 0.036 s of 0.12 s, elapsed 0:00:05, eta 0:00:12`;
/// the rate is the counter's (steps, samples), next to it so that no number in the message
/// reads as its unit.
pub fn progress_line(what: &str, pos: u64, len: u64, elapsed: Duration, message: &str) -> String {
    let secs = elapsed.as_secs_f64();
    let rate = pos as f64 / secs.max(1e-9);
    let eta = if pos > 0 {
        hms(secs * (len.saturating_sub(pos)) as f64 / pos as f64)
    } else {
        "unknown".into()
    };
    let msg = if message.is_empty() {
        String::new()
    } else {
        format!(", {message}")
    };
    format!(
        "{what}: {}% ({pos}/{len} at {rate:.2e}/s){msg}, elapsed {}, eta {eta}",
        100 * pos.min(len) / len.max(1),
        hms(secs)
    )
}

fn hms(s: f64) -> String {
    let s = s.round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// A number written by serde_json, where NaN becomes `null`: read back as NaN.
pub fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Rows of three numbers written by serde_json, each `null` read back as NaN.
pub fn nan_if_null_triples<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<[f64; 3]>, D::Error> {
    use serde::Deserialize;
    let rows = Vec::<[Option<f64>; 3]>::deserialize(d)?;
    Ok(rows.into_iter().map(|r| r.map(|x| x.unwrap_or(f64::NAN))).collect())
}

#[cfg(test)]
mod claim_tests {
    use super::*;

    /// `--force` removes the old summary and the files it lists, and nothing else: not a file
    /// of the user's in the directory, not a listed file outside it.
    #[test]
    fn force_removes_the_previous_outputs_and_only_them() {
        let root = std::env::temp_dir().join(format!("stripes-claim-{}", std::process::id()));
        let dir = root.join("out");
        std::fs::create_dir_all(&dir).unwrap();
        let outside = root.join("elsewhere.csv");
        for f in [dir.join("a.csv"), dir.join("notes.txt"), outside.clone()] {
            std::fs::write(f, "x").unwrap();
        }
        let files = [dir.join("a.csv"), outside.clone(), dir.join("summary.json")];
        let summary = serde_json::json!({ "files": files });
        std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
        assert!(claim(&dir, false).unwrap_err().to_string().contains("--force"));
        claim(&dir, true).unwrap();
        assert!(!dir.join("a.csv").exists() && !dir.join("summary.json").exists());
        assert!(dir.join("notes.txt").exists() && outside.exists());
        // Without a summary (a run that failed), --force still lets the new run start.
        claim(&dir, true).unwrap();
        std::fs::remove_dir_all(root).unwrap();
    }

    /// A comparison claims its directory by the same rule, its checkpoint in `dem/`: a resume
    /// needs `dem/checkpoint.bin` (named), an occupied directory names "an earlier
    /// comparison", and `--force` removes what the old summary lists.
    #[test]
    fn a_comparison_claims_its_directory_by_the_same_rule() {
        let root = std::env::temp_dir().join(format!("stripes-claim-compare-{}", std::process::id()));
        let (dir, dem) = (root.join("cmp"), root.join("cmp/dem"));
        let claim = |resume, force| claim_resumable(&dir, &dem, "an earlier comparison", resume, force, &[]);
        assert!(claim(false, false).unwrap(), "a new directory is fresh");
        std::fs::create_dir_all(&dem).unwrap();
        std::fs::write(dir.join("report.md"), "x").unwrap();
        std::fs::write(
            dir.join("summary.json"),
            serde_json::json!({ "files": [dir.join("report.md")] }).to_string(),
        )
        .unwrap();
        let e = claim(true, false).unwrap_err().to_string();
        assert!(
            e.contains("--resume") && e.contains("dem") && e.contains("no checkpoint.bin"),
            "{e}"
        );
        let e = claim(false, false).unwrap_err().to_string();
        assert!(e.contains("(an earlier comparison?)") && e.contains("--force"), "{e}");
        std::fs::write(dem.join("checkpoint.bin"), "x").unwrap();
        assert!(!claim(true, false).unwrap(), "a resume with its checkpoint goes on");
        assert!(dir.join("report.md").exists(), "a resume removes nothing");
        assert!(!claim(false, true).unwrap());
        assert!(!dir.join("report.md").exists() && !dir.join("summary.json").exists());
        std::fs::remove_dir_all(root).unwrap();
    }

    /// The claim of a resumable run, one for the DEM and the event-driven model: `--resume`
    /// needs the checkpoint; a directory holding files is refused naming `--resume` and
    /// `--force`; `--force` removes the listed files and the model's own, not the user's.
    #[test]
    fn a_resumable_run_claims_its_directory_by_one_rule() {
        let root = std::env::temp_dir().join(format!("stripes-claim-run-{}", std::process::id()));
        let dir = root.join("out");
        assert!(claim_run(&dir, false, false, &["vtk"]).unwrap(), "a new directory is fresh");
        std::fs::create_dir_all(dir.join("vtk")).unwrap();
        for f in ["snapshots.bin", "notes.txt", "vtk/frame_0.vtu"] {
            std::fs::write(dir.join(f), "x").unwrap();
        }
        let e = claim_run(&dir, true, false, &["vtk"]).unwrap_err().to_string();
        assert!(e.contains("--resume") && e.contains("no checkpoint.bin"), "{e}");
        let e = claim_run(&dir, false, false, &["vtk"]).unwrap_err().to_string();
        assert!(
            e.contains("already holds files") && e.contains("--resume") && e.contains("--force"),
            "{e}"
        );
        assert!(!claim_run(&dir, false, true, &["vtk", "snapshots.bin", "checkpoint.bin"]).unwrap());
        assert!(!dir.join("vtk").exists() && !dir.join("snapshots.bin").exists() && dir.join("notes.txt").exists());
        std::fs::write(dir.join("checkpoint.bin"), "x").unwrap();
        assert!(!claim_run(&dir, true, false, &[]).unwrap(), "a resumed directory is not fresh");
        std::fs::remove_dir_all(root).unwrap();
    }
}

#[cfg(test)]
mod progress_tests {
    use super::*;

    #[test]
    fn a_progress_line_keeps_the_counters_rate_beside_the_counter() {
        let line = progress_line("events", 5, 10, Duration::from_secs(2), "t = 1 s of 2 s, 400 collisions");
        assert_eq!(
            line,
            "events: 50% (5/10 at 2.50e0/s), t = 1 s of 2 s, 400 collisions, elapsed 0:00:02, eta 0:00:02"
        );
    }
}
