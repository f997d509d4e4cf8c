//! One entry point for every kind of run the analysis reads, so the DEM, the automaton and
//! LAMMPS are judged by the same code:
//!
//! - a `stripes run` directory (its `snapshots.bin`) or a `snapshots.bin` file
//!   ([`crate::snapshot`]);
//! - an automaton run: `stripes automaton` writes its lattice states in the same
//!   `snapshots.bin` format, one grain per occupied site with its centre at the cell's
//!   centre (x, y) and at the height of its pile level (z), velocities zero; it is read
//!   exactly like a DEM run, and displacements between frames are whole cells;
//! - a LAMMPS / LIGGGHTS text dump ([`crate::lammps`]), recognised by its first line
//!   `ITEM: TIMESTEP`; its time is `timestep * dt`.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::snapshot::{read_snapshots, Frame, Header};

/// The kind of input found at a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum InputKind {
    /// `snapshots.bin` of a DEM or automaton run.
    Snapshots,
    /// LAMMPS text dump.
    LammpsDump,
}

/// A loaded run: where it came from, its header and its frames in time order.
#[derive(Clone, Debug)]
pub struct Run {
    pub file: PathBuf,
    pub kind: InputKind,
    pub header: Header,
    pub frames: Vec<Frame>,
}

/// Loads a run directory, a `snapshots.bin` file or a LAMMPS dump; `dt` (s) converts LAMMPS
/// timesteps to time and is ignored for snapshots. Fails with a message naming the file
/// when it is of neither kind, holds no complete frame, or its times do not increase.
pub fn load(path: &Path, dt: f64) -> Result<Run, String> {
    let file = if path.is_dir() {
        path.join("snapshots.bin")
    } else {
        path.to_path_buf()
    };
    let mut head = [0u8; 16];
    let got = std::fs::File::open(&file)
        .and_then(|mut f| f.read(&mut head))
        .map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    let (kind, header, frames) = if head[..got].starts_with(b"STRPSNP1") {
        let (h, f) = read_snapshots(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
        (InputKind::Snapshots, h, f)
    } else if String::from_utf8_lossy(&head[..got]).trim_start().starts_with("ITEM:") {
        let (h, f) = crate::lammps::read_dump(&file, dt)?;
        (InputKind::LammpsDump, h, f)
    } else {
        return Err(format!(
            "{} is neither a stripes snapshot file (magic STRPSNP1) nor a LAMMPS text dump (`ITEM: TIMESTEP`)",
            file.display()
        ));
    };
    if frames.is_empty() {
        return Err(format!("{} holds no complete frame", file.display()));
    }
    for (k, w) in frames.windows(2).enumerate() {
        if w[1].time.partial_cmp(&w[0].time) != Some(std::cmp::Ordering::Greater) {
            return Err(format!(
                "{}: frame {} (t = {} s) does not come after frame {k} (t = {} s)",
                file.display(),
                k + 1,
                w[1].time,
                w[0].time
            ));
        }
    }
    Ok(Run {
        file,
        kind,
        header,
        frames,
    })
}
