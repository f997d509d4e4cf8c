//! LAMMPS (and LIGGGHTS) text dumps of a granular layer, read into the suite's own
//! [`Header`] and [`Frame`] types, so that a LAMMPS run of the tray goes through exactly the
//! analysis of a `stripes run`.
//!
//! Each frame of the dump is
//! ```text
//! ITEM: TIMESTEP
//! 12500
//! ITEM: NUMBER OF ATOMS
//! 1000
//! ITEM: BOX BOUNDS pp ff ff
//! 0 0.1
//! 0 0.02
//! -0.001 0.1
//! ITEM: ATOMS id radius x y z vx vy vz
//! 1 0.00031 0.0123 0.0051 0.00031 0.01 0 0
//! ...
//! ```
//! as written by `dump ID all custom EVERY FILE id radius x y z vx vy vz`. Columns may come
//! in any order; required are `id`, `radius` and a position per axis (`x`, or the unwrapped
//! `xu`, or the scaled `xs`, likewise for y and z). `vx`, `vy`, `vz` are each optional (zero
//! when absent; any subset is used). Atoms are sorted by id, so grain `k` of every frame is the same atom.
//!
//! Conventions: the box length `L = xhi - xlo` (periodic x) and width `W = yhi - ylo` come
//! from the first frame's `BOX BOUNDS`; positions are shifted to `x - xlo`, `y - ylo` so
//! they live in `[0, L) x [0, W)` like the suite's own snapshots; time is
//! `timestep * dt` (s) with the run's time step `dt`. Triclinic boxes are refused. Every
//! frame must hold the same atoms with the same radii in the same box, and every atom must lie
//! between the side walls (an error names the first offending atom id and timestep).

use std::io::BufRead;
use std::path::Path;

use crate::snapshot::{Frame, Header};

/// The LAMMPS time step of the thesis tray (s), the default of `--dt`.
pub const DEFAULT_DT: f64 = 8e-6;

/// Why a LAMMPS dump cannot be read. Each names the file, and the line (numbered from 1),
/// field, atom and timestep where they are known.
#[derive(Debug)]
pub enum DumpError {
    /// `dt` is not a positive time step (s).
    TimeStep { dt: f64 },
    /// The file cannot be opened.
    Open { file: String, source: std::io::Error },
    /// The file cannot be read (at `line`, while reading `what`, if known).
    Read {
        file: String,
        line: Option<usize>,
        what: &'static str,
        source: std::io::Error,
    },
    /// The file is not a dump the analysis can use: `problem` says what is wrong, at `line`
    /// (None: across frames or at the end of the file).
    Content {
        file: String,
        line: Option<usize>,
        problem: String,
    },
}

impl std::fmt::Display for DumpError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DumpError::TimeStep { dt } => write!(f, "--dt must be a positive time step in s, got {dt}"),
            DumpError::Open { file, source } => write!(f, "cannot open {file}: {source}"),
            DumpError::Read {
                file,
                line: Some(line),
                what,
                source,
            } => write!(f, "{file} line {line}: cannot read {what}: {source}"),
            DumpError::Read {
                file, line: None, source, ..
            } => write!(f, "cannot read {file}: {source}"),
            DumpError::Content {
                file,
                line: Some(line),
                problem,
            } => write!(f, "{file} line {line}: {problem}"),
            DumpError::Content { file, line: None, problem } => write!(f, "{file}: {problem}"),
        }
    }
}

impl std::error::Error for DumpError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            DumpError::Open { source, .. } | DumpError::Read { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// A [`DumpError::Content`] of `file`.
fn content(file: &str, line: Option<usize>, problem: String) -> DumpError {
    DumpError::Content {
        file: file.to_string(),
        line,
        problem,
    }
}

/// How one axis' position is given in the dump.
#[derive(Clone, Copy, Debug, PartialEq)]
enum PosCol {
    /// `x` or `xu`: absolute coordinate.
    Absolute(usize),
    /// `xs`: fraction of the box.
    Scaled(usize),
}

struct Columns {
    id: usize,
    radius: usize,
    pos: [PosCol; 3],
    /// `vx`, `vy`, `vz`, each optional (zero when absent).
    vel: [Option<usize>; 3],
    count: usize,
}

/// The columns of an `ITEM: ATOMS` line (line `line` of `file`).
fn columns(names: &[&str], file: &str, line: usize) -> Result<Columns, DumpError> {
    let find = |n: &str| names.iter().position(|c| *c == n);
    let need = |n: &str| {
        find(n).ok_or_else(|| {
            let problem = format!("`ITEM: ATOMS` has no `{n}` column (columns: {})", names.join(" "));
            content(file, Some(line), problem)
        })
    };
    let axis = |a: &str| -> Result<PosCol, DumpError> {
        if let Some(k) = find(a).or_else(|| find(&format!("{a}u"))) {
            Ok(PosCol::Absolute(k))
        } else if let Some(k) = find(&format!("{a}s")) {
            Ok(PosCol::Scaled(k))
        } else {
            let problem = format!("`ITEM: ATOMS` has no `{a}`, `{a}u` or `{a}s` column (columns: {})", names.join(" "));
            Err(content(file, Some(line), problem))
        }
    };
    Ok(Columns {
        id: need("id")?,
        radius: need("radius")?,
        pos: [axis("x")?, axis("y")?, axis("z")?],
        vel: [find("vx"), find("vy"), find("vz")],
        count: names.len(),
    })
}

/// One parsed dump frame: timestep, box bounds, and per-atom (id, radius, pos, vel).
struct RawFrame {
    step: u64,
    bounds: [[f64; 2]; 3],
    atoms: Vec<(u64, f64, [f64; 3], [f64; 3])>,
    /// Velocity columns present in this frame.
    vel: [bool; 3],
}

/// What [`read_dump_noting`] noticed besides the frames.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DumpNotes {
    /// The velocity columns used (any subset of `vx`, `vy`, `vz`, as in every frame); the
    /// others read as zero.
    pub velocity_columns: Vec<String>,
    /// Problems that did not stop the reading, e.g. a cut-off last frame.
    pub warnings: Vec<String>,
}

/// Lines of a dump, numbered from 1, with a look ahead to tell the last line.
struct Lines {
    lines: std::iter::Peekable<std::iter::Enumerate<std::io::Lines<std::io::BufReader<std::fs::File>>>>,
    name: String,
    /// The file's size in bytes: no frame can hold more atoms than lines of at least
    /// [`MIN_ATOM_LINE`] bytes fit in it.
    size: u64,
}

/// The shortest atom line: five one-character values and their separators (`1 1 1 1 1\n`).
const MIN_ATOM_LINE: u64 = 10;

/// Why a frame could not be read; `cut` when the file ends inside it (or its last line is
/// the bad one), as when a run is killed while writing.
struct FrameError {
    error: DumpError,
    line: usize,
    cut: bool,
}

impl Lines {
    fn next(&mut self, what: &'static str) -> Result<Option<(usize, String)>, DumpError> {
        match self.lines.next() {
            None => Ok(None),
            Some((k, Ok(l))) => Ok(Some((k + 1, l))),
            Some((k, Err(source))) => Err(DumpError::Read {
                file: self.name.clone(),
                line: Some(k + 1),
                what,
                source,
            }),
        }
    }

    fn at_end(&mut self) -> bool {
        self.lines.peek().is_none()
    }
}

/// Reads the frame whose `ITEM: TIMESTEP` line was line `start`.
fn read_frame(lines: &mut Lines, start: usize) -> Result<RawFrame, FrameError> {
    let name = lines.name.clone();
    let mut last = start;
    // A bad line that is the file's last is a cut-off frame, not a malformed one.
    let bad = |lines: &mut Lines, line: usize, problem: String| FrameError {
        error: content(&name, Some(line), problem),
        line,
        cut: lines.at_end(),
    };
    let eof = |last: usize, what: &str| FrameError {
        error: content(&name, None, format!("file ends inside a frame, before {what}")),
        line: last,
        cut: true,
    };
    let next = |lines: &mut Lines, last: &mut usize, what: &'static str| -> Result<(usize, String), FrameError> {
        match lines.next(what) {
            Ok(Some((ln, l))) => {
                *last = ln;
                Ok((ln, l))
            }
            Ok(None) => Err(eof(*last, what)),
            Err(error) => Err(FrameError {
                error,
                line: *last + 1,
                cut: false,
            }),
        }
    };
    let (ln, l) = next(lines, &mut last, "the timestep")?;
    let step: u64 = match l.trim().parse() {
        Ok(s) => s,
        Err(_) => return Err(bad(lines, ln, format!("timestep `{}` is not a non-negative integer", l.trim()))),
    };
    let (ln, l) = next(lines, &mut last, "ITEM: NUMBER OF ATOMS")?;
    if !l.starts_with("ITEM: NUMBER OF ATOMS") {
        return Err(bad(lines, ln, format!("expected `ITEM: NUMBER OF ATOMS` (timestep {step})")));
    }
    let (ln, l) = next(lines, &mut last, "the number of atoms")?;
    let Ok(n) = l.trim().parse::<usize>() else {
        return Err(bad(lines, ln, format!("number of atoms `{}` is not an integer", l.trim())));
    };
    // `n` comes from the file: checked against the file's size before it sizes anything.
    if n as u64 > lines.size / MIN_ATOM_LINE {
        return Err(FrameError {
            error: content(
                &name,
                Some(ln),
                format!(
                    "timestep {step} claims {n} atoms, more than the {} bytes of the file can hold",
                    lines.size
                ),
            ),
            line: ln,
            cut: false,
        });
    }
    let (ln, l) = next(lines, &mut last, "ITEM: BOX BOUNDS")?;
    if !l.starts_with("ITEM: BOX BOUNDS") {
        return Err(bad(lines, ln, format!("expected `ITEM: BOX BOUNDS` (timestep {step})")));
    }
    if l.contains("xy") {
        return Err(bad(lines, ln, format!("triclinic boxes are not supported (timestep {step})")));
    }
    let mut bounds = [[0.0; 2]; 3];
    for (a, b) in bounds.iter_mut().enumerate() {
        let (ln, l) = next(lines, &mut last, "the box bounds")?;
        let v: Vec<f64> = l.split_whitespace().filter_map(|s| s.parse().ok()).collect();
        if v.len() != 2 || v[1].partial_cmp(&v[0]) != Some(std::cmp::Ordering::Greater) {
            return Err(bad(
                lines,
                ln,
                format!(
                    "{name} line {ln}: box bounds of axis {} must be two numbers lo < hi, got `{}` (timestep {step})",
                    ["x", "y", "z"][a],
                    l.trim()
                ),
            ));
        }
        *b = [v[0], v[1]];
    }
    let (ln, l) = next(lines, &mut last, "ITEM: ATOMS")?;
    let Some(cols) = l.strip_prefix("ITEM: ATOMS") else {
        return Err(bad(lines, ln, format!("expected `ITEM: ATOMS` (timestep {step})")));
    };
    let names: Vec<&str> = cols.split_whitespace().collect();
    let c = columns(&names, &name, ln).map_err(|error| FrameError {
        error,
        line: ln,
        cut: lines.at_end(),
    })?;
    let mut atoms = Vec::with_capacity(n);
    for _ in 0..n {
        let (ln, l) = match next(lines, &mut last, "an atom") {
            Ok(x) => x,
            Err(mut e) if e.cut => {
                e.error = content(&name, None, format!("timestep {step} ends after {} of {n} atoms", atoms.len()));
                return Err(e);
            }
            Err(e) => return Err(e),
        };
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() != c.count {
            let m = format!("{} values for {} columns (timestep {step})", f.len(), c.count);
            return Err(bad(lines, ln, m));
        }
        // A bad value on the file's last line is a cut-off frame.
        let cut = lines.at_end();
        let bad_here = |problem: String| FrameError {
            error: content(&name, Some(ln), problem),
            line: ln,
            cut,
        };
        let num = |k: usize| -> Result<f64, FrameError> {
            let v: f64 = f[k].parse().map_err(|_| {
                let problem = format!("column `{}` = `{}` is not a number (timestep {step})", names[k], f[k]);
                bad_here(problem)
            })?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad_here(format!("column `{}` is not finite (timestep {step})", names[k])))
            }
        };
        let atom = (|| -> Result<_, FrameError> {
            let id: u64 = f[c.id].parse().map_err(|_| {
                let what = if f[c.id].parse::<i64>().is_ok() {
                    "is negative; atom ids are positive integers"
                } else {
                    "is not an integer"
                };
                bad_here(format!("id `{}` {what} (timestep {step})", f[c.id]))
            })?;
            let radius = num(c.radius)?;
            let mut pos = [0.0; 3];
            for a in 0..3 {
                pos[a] = match c.pos[a] {
                    PosCol::Absolute(k) => num(k)?,
                    PosCol::Scaled(k) => bounds[a][0] + num(k)? * (bounds[a][1] - bounds[a][0]),
                };
            }
            let mut vel = [0.0; 3];
            for (v, k) in vel.iter_mut().zip(c.vel) {
                if let Some(k) = k {
                    *v = num(k)?;
                }
            }
            Ok((id, radius, pos, vel))
        })()?;
        atoms.push(atom);
    }
    atoms.sort_by_key(|a| a.0);
    Ok(RawFrame {
        step,
        bounds,
        atoms,
        vel: c.vel.map(|k| k.is_some()),
    })
}

/// Reads every frame of a LAMMPS text dump (see the module docs); `dt` is the run's time
/// step (s). Errors name the file, line and field.
pub fn read_dump(path: &Path, dt: f64) -> Result<(Header, Vec<Frame>), DumpError> {
    read_dump_noting(path, dt).map(|(h, f, _)| (h, f))
}

/// [`read_dump`], keeping the complete frames of a dump cut off inside a frame (a killed
/// run) with a warning that names the line, and saying which velocity columns were used.
pub fn read_dump_noting(path: &Path, dt: f64) -> Result<(Header, Vec<Frame>, DumpNotes), DumpError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(DumpError::TimeStep { dt });
    }
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| DumpError::Open {
        file: name.clone(),
        source,
    })?;
    let size = file
        .metadata()
        .map_err(|source| DumpError::Read {
            file: name.clone(),
            line: None,
            what: "its size",
            source,
        })?
        .len();
    let mut lines = Lines {
        size,
        lines: std::io::BufReader::new(file).lines().enumerate().peekable(),
        name: name.clone(),
    };
    let mut notes = DumpNotes::default();
    let mut raw: Vec<RawFrame> = Vec::new();
    while let Some((ln, l)) = lines.next("ITEM: TIMESTEP")? {
        if l.trim().is_empty() {
            continue;
        }
        if !l.starts_with("ITEM: TIMESTEP") {
            return Err(content(&name, Some(ln), format!("expected `ITEM: TIMESTEP`, found `{}`", l.trim())));
        }
        match read_frame(&mut lines, ln) {
            Ok(f) => raw.push(f),
            Err(e) if e.cut && !raw.is_empty() => {
                notes.warnings.push(format!(
                    "{name} is cut off at line {} inside the frame that starts at line {ln} ({}); analysing the {} complete frames before it",
                    e.line,
                    e.error,
                    raw.len()
                ));
                break;
            }
            Err(e) => return Err(e.error),
        }
    }
    let first = raw
        .first()
        .ok_or_else(|| content(&name, None, "no `ITEM: TIMESTEP` frame in the file".into()))?;
    let [bx, by, _] = first.bounds;
    let (length, width) = (bx[1] - bx[0], by[1] - by[0]);
    for w in first.atoms.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(content(
                &name,
                None,
                format!("atom id {} appears twice at timestep {}", w[0].0, first.step),
            ));
        }
    }
    let header = Header {
        length,
        width,
        radii: first.atoms.iter().map(|a| a.1).collect(),
    };
    for (a, r) in first.atoms.iter().map(|a| (a.0, a.1)) {
        if !(r > 0.0 && 2.0 * r < length) {
            return Err(content(
                &name,
                None,
                format!("atom {a} has radius {r} m, outside (0, L/2) (timestep {})", first.step),
            ));
        }
    }
    let mut frames = Vec::with_capacity(raw.len());
    for f in &raw {
        if f.atoms.len() != header.radii.len() {
            return Err(content(
                &name,
                None,
                format!(
                    "timestep {} holds {} atoms, the first frame {} (atoms lost or added)",
                    f.step,
                    f.atoms.len(),
                    header.radii.len()
                ),
            ));
        }
        if f.vel != first.vel {
            return Err(content(
                &name,
                None,
                format!("timestep {} has other velocity columns than the first frame", f.step),
            ));
        }
        if f.bounds[0] != first.bounds[0] || f.bounds[1] != first.bounds[1] {
            return Err(content(
                &name,
                None,
                format!(
                    "the box changes at timestep {}: x {:?}, y {:?} against x {:?}, y {:?} in the first frame; \
                 the analysis needs one tray (a fixed periodic length and width)",
                    f.step, f.bounds[0], f.bounds[1], first.bounds[0], first.bounds[1]
                ),
            ));
        }
        for (a, b) in f.atoms.iter().zip(&first.atoms) {
            // x is periodic (and `xu` unwrapped), but y is bounded by the tray's side walls.
            let y = a.2[1];
            let slack = 1e-9 * width;
            if !(y >= by[0] - slack && y <= by[1] + slack) {
                return Err(content(
                    &name,
                    None,
                    format!(
                        "atom {} at y = {y} m lies outside the side walls [{}, {}] at timestep {}",
                        a.0, by[0], by[1], f.step
                    ),
                ));
            }
            if a.0 != b.0 {
                return Err(content(
                    &name,
                    None,
                    format!("timestep {} has atom id {} where the first frame has {}", f.step, a.0, b.0),
                ));
            }
            if a.1 != b.1 {
                return Err(content(
                    &name,
                    None,
                    format!("atom {} changes radius from {} to {} m at timestep {}", a.0, b.1, a.1, f.step),
                ));
            }
        }
        frames.push(Frame {
            time: f.step as f64 * dt,
            pos: f.atoms.iter().map(|a| [a.2[0] - bx[0], a.2[1] - by[0], a.2[2]]).collect(),
            vel: f.atoms.iter().map(|a| a.3).collect(),
        });
    }
    notes.velocity_columns = ["vx", "vy", "vz"]
        .iter()
        .zip(first.vel)
        .filter(|(_, on)| *on)
        .map(|(n, _)| n.to_string())
        .collect();
    Ok((header, frames, notes))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dump(text: &str, name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("stripes-lammps-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("tray.dump");
        std::fs::write(&p, text).unwrap();
        p
    }

    const TWO_FRAMES: &str = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff ff\n-0.2 0.2\n0 0.02\n-0.001 0.1\n\
ITEM: ATOMS x radius id y z vx vy vz\n0.1 0.0004 2 0.01 0.0004 1 2 3\n-0.1 0.0003 1 0.005 0.0003 0 0 0\n\
ITEM: TIMESTEP\n6250\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff ff\n-0.2 0.2\n0 0.02\n-0.001 0.1\n\
ITEM: ATOMS x radius id y z vx vy vz\n-0.05 0.0003 1 0.006 0.0003 0 0 0\n0.15 0.0004 2 0.011 0.0004 0 0 0\n";

    #[test]
    fn columns_in_any_order_sorted_by_id_and_shifted_into_the_box() {
        let p = dump(TWO_FRAMES, "ok");
        let (h, f) = read_dump(&p, 8e-6).unwrap();
        assert_eq!(h.radii, vec![0.0003, 0.0004]);
        assert!((h.length - 0.4).abs() < 1e-15 && (h.width - 0.02).abs() < 1e-15);
        assert_eq!(f.len(), 2);
        assert!((f[1].time - 0.05).abs() < 1e-15);
        assert!((f[0].pos[0][0] - 0.1).abs() < 1e-15, "id 1 first, x - xlo");
        assert!((f[0].pos[1][0] - 0.3).abs() < 1e-15);
        assert_eq!(f[0].vel[1], [1.0, 2.0, 3.0]);
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }

    #[test]
    fn errors_name_the_field_atom_and_timestep() {
        let cases = [
            (
                TWO_FRAMES.replace("ITEM: ATOMS x radius id", "ITEM: ATOMS x rad id"),
                "no `radius` column",
            ),
            (TWO_FRAMES.replacen("0.1 0.0004 2", "0.1 abc 2", 1), "`radius` = `abc`"),
            (TWO_FRAMES.replacen("0.15 0.0004 2", "0.15 0.0005 2", 1), "atom 2 changes radius"),
            (
                TWO_FRAMES.replacen("-0.05 0.0003 1", "-0.05 0.0003 3", 1),
                "timestep 6250 has atom id 2 where",
            ),
            (
                TWO_FRAMES[..TWO_FRAMES.rfind("0.15").unwrap()].replacen("0.0004 2", "0.0004 x", 1),
                "id `x` is not an integer",
            ),
            (
                TWO_FRAMES[..TWO_FRAMES.find("ITEM: TIMESTEP\n6250").unwrap()].replacen("0.1 0.0004 2 0.01 0.0004 1 2 3\n", "", 1),
                "timestep 0 ends after 1 of 2 atoms",
            ),
            (String::new(), "no `ITEM: TIMESTEP` frame"),
        ];
        for (k, (text, want)) in cases.iter().enumerate() {
            let p = dump(text, &format!("bad{k}"));
            let e = read_dump(&p, 8e-6).unwrap_err().to_string();
            assert!(e.contains(want), "case {k}: `{e}` lacks `{want}`");
            std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
        }
    }

    /// Issue 19, point 3: a dump cut off by a killed run keeps its complete frames.
    #[test]
    fn a_cut_off_dump_keeps_its_complete_frames_and_names_the_line() {
        for (k, cut) in [TWO_FRAMES.rfind("0.15").unwrap(), TWO_FRAMES.len() - 30, TWO_FRAMES.len() - 100]
            .into_iter()
            .enumerate()
        {
            let p = dump(&TWO_FRAMES[..cut], &format!("cut{k}"));
            let (h, f, notes) = read_dump_noting(&p, 8e-6).unwrap();
            assert_eq!((h.radii.len(), f.len()), (2, 1), "case {k}");
            assert_eq!(notes.warnings.len(), 1, "case {k}");
            let w = &notes.warnings[0];
            assert!(
                w.contains("cut off at line") && w.contains("starts at line 12") && w.contains("1 complete frames"),
                "case {k}: {w}"
            );
            std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
        }
        // A malformed line that is not the last stays an error.
        let p = dump(&TWO_FRAMES.replacen("-0.05 0.0003 1 0.006", "-0.05 0.0003 1", 1), "midbad");
        assert!(read_dump_noting(&p, 8e-6)
            .unwrap_err()
            .to_string()
            .contains("7 values for 8 columns"));
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }

    /// Issue 19, point 4: any subset of the velocity columns is used, and named.
    #[test]
    fn a_subset_of_velocity_columns_is_used_and_named() {
        let text = TWO_FRAMES
            .replace(" vz", "")
            .replace(" 1 2 3\n", " 1 2\n")
            .replace(" 0 0 0\n", " 0 0\n");
        let p = dump(&text, "vxvy");
        let (_, f, notes) = read_dump_noting(&p, 8e-6).unwrap();
        assert_eq!(notes.velocity_columns, vec!["vx", "vy"]);
        assert_eq!(f[0].vel[1], [1.0, 2.0, 0.0]);
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }

    #[test]
    fn scaled_positions_and_missing_velocities() {
        let text = "ITEM: TIMESTEP\n10\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp ff\n0 0.4\n0 0.02\n0 0.1\n\
ITEM: ATOMS id radius xs ys zs\n1 0.0003 0.5 0.5 0.01\n";
        let p = dump(text, "scaled");
        let (_, f) = read_dump(&p, 1e-3).unwrap();
        assert!((f[0].pos[0][0] - 0.2).abs() < 1e-15 && (f[0].pos[0][1] - 0.01).abs() < 1e-15);
        assert_eq!(f[0].vel[0], [0.0; 3]);
        assert!((f[0].time - 0.01).abs() < 1e-15);
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }
}
