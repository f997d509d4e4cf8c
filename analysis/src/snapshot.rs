//! Snapshots of a layer of grains: the common input of the analysis, written by the DEM
//! (`stripes run`) and read back here. LAMMPS dumps and automaton states convert to the same
//! [`Frame`] type.
//!
//! File format `snapshots.bin` (little endian), an append-only stream:
//! - header: magic `STRPSNP1`, `u64` N, `f64` box length L (x, periodic), `f64` width W (y),
//!   then N radii (`f64`, m);
//! - frames, each: `f64` time (s), then N records of six `f32`: x, y, z (m), vx, vy, vz (m/s).
//!
//! Positions are stored in single precision (about 3e-8 m at L = 0.4 m), far below any length
//! the analysis resolves. A reader stops cleanly at a truncated last frame (a run killed while
//! writing), and [`SnapshotWriter::open_append`] truncates the stream to a given number of
//! frames, so a resumed run continues the same file.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"STRPSNP1";

/// The constant part of a snapshot stream.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// Box length along x (m), periodic.
    pub length: f64,
    /// Box width along y (m).
    pub width: f64,
    /// Radii (m), one per grain.
    pub radii: Vec<f64>,
}

/// One snapshot: positions and velocities at a time.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub time: f64,
    pub pos: Vec<[f64; 3]>,
    pub vel: Vec<[f64; 3]>,
}

impl Header {
    fn bytes(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(32 + 8 * self.radii.len());
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&(self.radii.len() as u64).to_le_bytes());
        b.extend_from_slice(&self.length.to_le_bytes());
        b.extend_from_slice(&self.width.to_le_bytes());
        for r in &self.radii {
            b.extend_from_slice(&r.to_le_bytes());
        }
        b
    }

    fn frame_size(&self) -> u64 {
        8 + 24 * self.radii.len() as u64
    }
}

/// Appends frames to a snapshot stream.
pub struct SnapshotWriter {
    out: BufWriter<File>,
    header: Header,
}

impl SnapshotWriter {
    /// Creates (or replaces) the stream with this header.
    pub fn create(path: &Path, header: Header) -> io::Result<Self> {
        let mut f = File::create(path)?;
        f.write_all(&header.bytes())?;
        Ok(Self {
            out: BufWriter::new(f),
            header,
        })
    }

    /// Opens an existing stream for appending after its first `frames` frames (anything
    /// after them is cut off). The header must match.
    pub fn open_append(path: &Path, header: Header, frames: u64) -> io::Result<Self> {
        let mut f = OpenOptions::new().read(true).write(true).open(path)?;
        let mut head = vec![0u8; header.bytes().len()];
        f.read_exact(&mut head)?;
        if head != header.bytes() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!("{}: header differs from this run", path.display()),
            ));
        }
        let end = head.len() as u64 + frames * header.frame_size();
        if f.metadata()?.len() < end {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!("{}: fewer than {frames} frames", path.display()),
            ));
        }
        f.set_len(end)?;
        f.seek(SeekFrom::End(0))?;
        Ok(Self {
            out: BufWriter::new(f),
            header,
        })
    }

    /// Appends a frame.
    pub fn push(&mut self, time: f64, pos: impl Iterator<Item = [f64; 3]>, vel: impl Iterator<Item = [f64; 3]>) -> io::Result<()> {
        self.out.write_all(&time.to_le_bytes())?;
        let mut count = 0;
        for (p, v) in pos.zip(vel) {
            for c in p.iter().chain(v.iter()) {
                self.out.write_all(&(*c as f32).to_le_bytes())?;
            }
            count += 1;
        }
        if count != self.header.radii.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("frame has {count} grains, header {}", self.header.radii.len()),
            ));
        }
        Ok(())
    }

    /// Flushes buffered frames to the file and the disk.
    pub fn sync(&mut self) -> io::Result<()> {
        self.out.flush()?;
        self.out.get_ref().sync_data()
    }
}

/// Reads a snapshot stream: the header and every complete frame.
pub fn read_snapshots(path: &Path) -> io::Result<(Header, Vec<Frame>)> {
    read_snapshots_counting(path).map(|(h, f, _)| (h, f))
}

/// [`read_snapshots`], also returning how many bytes after the last complete frame were
/// ignored (a partial frame: the file was cut while being written or copied).
pub fn read_snapshots_counting(path: &Path) -> io::Result<(Header, Vec<Frame>, usize)> {
    let mut bytes = Vec::new();
    File::open(path)?.read_to_end(&mut bytes)?;
    let bad = |m: &str| io::Error::new(io::ErrorKind::InvalidData, format!("{}: {m}", path.display()));
    if bytes.len() < 32 || &bytes[..8] != MAGIC {
        return Err(bad("not a stripes snapshot file"));
    }
    let u64_at = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"));
    let f64_at = |at: usize| f64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"));
    // The grain count is checked against the bytes present before anything is sized from
    // it: a corrupt count must not overflow or allocate beyond the file.
    let n_raw = u64_at(8);
    let room = (bytes.len() as u64 - 32) / 8;
    if n_raw > room {
        return Err(bad(&format!(
            "truncated header: it claims {n_raw} grains, whose radii need {} bytes, but the file has {}",
            n_raw.saturating_mul(8).saturating_add(32),
            bytes.len()
        )));
    }
    let n = n_raw as usize;
    let header_len = 32 + 8 * n;
    let header = Header {
        length: f64_at(16),
        width: f64_at(24),
        radii: (0..n).map(|k| f64_at(32 + 8 * k)).collect(),
    };
    for (what, v) in [("box length", header.length), ("box width", header.width)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(&format!("header {what} {v} m is not a positive number")));
        }
    }
    if let Some(k) = header.radii.iter().position(|r| !(r.is_finite() && *r > 0.0)) {
        return Err(bad(&format!(
            "grain {k} has radius {} m in the header, not a positive number",
            header.radii[k]
        )));
    }
    let size = header.frame_size() as usize;
    let mut frames = Vec::new();
    let mut at = header_len;
    while at + size <= bytes.len() {
        let time = f64_at(at);
        let f32_at = |k: usize| f32::from_le_bytes(bytes[k..k + 4].try_into().expect("4 bytes")) as f64;
        let mut pos = Vec::with_capacity(n);
        let mut vel = Vec::with_capacity(n);
        for i in 0..n {
            let b = at + 8 + 24 * i;
            pos.push([f32_at(b), f32_at(b + 4), f32_at(b + 8)]);
            vel.push([f32_at(b + 12), f32_at(b + 16), f32_at(b + 20)]);
        }
        frames.push(Frame { time, pos, vel });
        at += size;
    }
    Ok((header, frames, bytes.len() - at))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_read_truncate_and_append() {
        let d = std::env::temp_dir().join(format!("stripes-snap-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("snapshots.bin");
        let header = Header {
            length: 0.4,
            width: 0.02,
            radii: vec![3e-4, 4e-4],
        };
        let frame = |t: f64| {
            (
                t,
                vec![[0.1 + t, 0.01, 3e-4], [0.2, 0.015, 4e-4]],
                vec![[t, 0.0, 0.0], [0.0, -t, 0.0]],
            )
        };
        let mut w = SnapshotWriter::create(&p, header.clone()).unwrap();
        for t in [0.0, 0.05, 0.1] {
            let (t, pos, vel) = frame(t);
            w.push(t, pos.into_iter(), vel.into_iter()).unwrap();
        }
        w.sync().unwrap();
        drop(w);
        let (h, frames) = read_snapshots(&p).unwrap();
        assert_eq!(h, header);
        assert_eq!(frames.len(), 3);
        assert!((frames[2].pos[0][0] - 0.2).abs() < 1e-7);
        // Resume after two frames: the third is replaced.
        let mut w = SnapshotWriter::open_append(&p, header.clone(), 2).unwrap();
        let (_, pos, vel) = frame(0.2);
        w.push(0.1, pos.into_iter(), vel.into_iter()).unwrap();
        w.sync().unwrap();
        drop(w);
        let (_, frames) = read_snapshots(&p).unwrap();
        assert_eq!(frames.len(), 3);
        assert!((frames[2].pos[0][0] - 0.3).abs() < 1e-7);
        // A truncated tail is ignored.
        let len = std::fs::metadata(&p).unwrap().len();
        OpenOptions::new().write(true).open(&p).unwrap().set_len(len - 5).unwrap();
        assert_eq!(read_snapshots(&p).unwrap().1.len(), 2);
        assert_eq!(read_snapshots_counting(&p).unwrap().2, (8 + 2 * 24) - 5);
        std::fs::remove_dir_all(d).unwrap();
    }
}
