//! Atomic output files: a reader never sees a half-written file, and a crash leaves the
//! previous version in place. Each writer renders to a temporary file in the same
//! directory, flushes it to disk and renames it over the target.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Write};
use std::path::Path;

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or_else(|| Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, format!("{} is not a file path", path.display())))?;
    // Unique per process and call, so that concurrent writers of one file never share a
    // temporary; the last rename wins and every reader sees a whole file.
    static SERIAL: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let serial = SERIAL.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = dir.join(format!(".{}.{}-{serial}.tmp", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut f = File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes `value` as pretty JSON followed by a newline, atomically.
pub fn write_json_atomic<T: serde::Serialize>(path: &Path, value: &T) -> io::Result<()> {
    let mut text = serde_json::to_string_pretty(value).map_err(io::Error::other)?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

/// Writes a numeric table as CSV, atomically. Numbers use Rust's shortest round-trip
/// formatting, so [`read_csv`] returns exactly the values written; NaN is written `nan`.
pub fn write_csv_atomic(path: &Path, header: &[&str], rows: &[Vec<f64>]) -> io::Result<()> {
    let mut text = header.join(",");
    text.push('\n');
    for (r, row) in rows.iter().enumerate() {
        if row.len() != header.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{}: row {r} has {} values for {} columns", path.display(), row.len(), header.len()),
            ));
        }
        for (k, v) in row.iter().enumerate() {
            if k > 0 {
                text.push(',');
            }
            if v.is_nan() {
                text.push_str("nan");
            } else {
                text.push_str(&v.to_string());
            }
        }
        text.push('\n');
    }
    write_atomic(path, text.as_bytes())
}

/// Reads a numeric CSV table written by [`write_csv_atomic`]: `(header, rows)`.
pub fn read_csv(path: &Path) -> io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let reader = BufReader::new(File::open(path)?);
    let mut lines = reader.lines();
    let header: Vec<String> = match lines.next() {
        Some(line) => line?.split(',').map(|s| s.trim().to_string()).collect(),
        None => return Err(io::Error::new(io::ErrorKind::InvalidData, format!("{} is empty", path.display()))),
    };
    let mut rows = Vec::new();
    for (n, line) in lines.enumerate() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let row: Result<Vec<f64>, _> = line.split(',').map(|s| s.trim().parse::<f64>()).collect();
        let row = row.map_err(|e| io::Error::new(io::ErrorKind::InvalidData, format!("{} line {}: {e}", path.display(), n + 2)))?;
        if row.len() != header.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "{} line {}: {} values for {} columns",
                    path.display(),
                    n + 2,
                    row.len(),
                    header.len()
                ),
            ));
        }
        rows.push(row);
    }
    Ok((header, rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("stripes-io-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn csv_round_trips_exactly() {
        let d = temp_dir("csv");
        let p = d.join("t.csv");
        let rows = vec![vec![0.1, 1e-300, -3.0], vec![f64::NAN, 2.0f64.sqrt(), 1e22]];
        write_csv_atomic(&p, &["a", "b", "c"], &rows).unwrap();
        let (h, back) = read_csv(&p).unwrap();
        assert_eq!(h, ["a", "b", "c"]);
        assert!(back[1][0].is_nan());
        assert_eq!(back[0], rows[0]);
        assert_eq!(back[1][1..], rows[1][1..]);
        // No temporary file left behind.
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn ragged_rows_are_refused_and_leave_the_old_file() {
        let d = temp_dir("ragged");
        let p = d.join("t.csv");
        write_csv_atomic(&p, &["a"], &[vec![1.0]]).unwrap();
        assert!(write_csv_atomic(&p, &["a", "b"], &[vec![1.0]]).is_err());
        assert_eq!(read_csv(&p).unwrap().1, vec![vec![1.0]]);
        std::fs::remove_dir_all(d).unwrap();
    }
}
