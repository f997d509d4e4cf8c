//! Run directories: resolved configuration, `summary.json`, CSV tables and plots, all
//! written atomically.

use std::path::{Path, PathBuf};

use analysis::plot::LinePlot;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

/// Error type of the CLI: a message for the user.
pub type CliError = Box<dyn std::error::Error + Send + Sync>;

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

    /// Writes `summary.json` (with the list of files written) and returns it as one line of
    /// JSON for stdout.
    pub fn finish(mut self, summary: serde_json::Value) -> Result<String, CliError> {
        let mut summary = summary;
        let files: Vec<String> = self.written.iter().map(|p| p.display().to_string()).collect();
        if let serde_json::Value::Object(map) = &mut summary {
            map.insert("out".into(), self.path.display().to_string().into());
            map.insert("files".into(), files.into());
        }
        self.json("summary.json", &summary)?;
        Ok(serde_json::to_string(&summary)?)
    }
}

/// Parses "x,y,z" into a vector.
pub fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected three comma-separated numbers like 0,0,10, got `{s}`"));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p.parse().map_err(|_| format!("`{p}` is not a number"))?;
    }
    Ok(v)
}

/// The progress bar of every long command (hidden with `--quiet`).
pub fn progress_bar(len: u64, quiet: bool, what: &str) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template("{msg:>12} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta_precise}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}
