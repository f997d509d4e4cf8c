//! VTK output for ParaView: a time series that opens in one click.
//!
//! - [`write_grains`]: one VTK XML PolyData file (`.vtp`) per frame, one point (and vertex)
//!   per grain with the point data `id`, `radius` (m), `velocity` (m/s) and
//!   `angular_velocity` (rad/s). Show them with the Glyph filter: sphere, scale by `radius`,
//!   scale factor 2 (a glyph's default size is a diameter).
//! - [`write_quads`]: the container (e.g. the tray's floor and side walls) as a separate
//!   `.vtp` of quadrilaterals with its `velocity`.
//! - [`Pvd`]: the collection file (`.pvd`) listing every file with its physical time (s)
//!   and part (0 grains, 1 container), rewritten after every frame so that a killed run
//!   still leaves a valid series.
//!
//! Numbers are written with the digits that matter: single precision (7 significant digits,
//! about 3e-8 m at 0.4 m, the precision of `snapshots.bin`) in exponent form, e.g.
//! `2.8078575e-15` rather than `0.0000000000000028078573734439517`; times with 9 digits.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A number as the shortest decimal that reads back to the same `f32`.
pub fn short(x: f64) -> String {
    let v = x as f32;
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:e}")
    }
}

/// A time (s) to 9 significant digits, shortest form.
pub fn short_time(t: f64) -> String {
    let rounded: f64 = format!("{t:.8e}").parse().unwrap_or(t);
    if rounded == 0.0 {
        "0".into()
    } else {
        format!("{rounded:e}")
    }
}

/// The grains of one frame, as plain arrays (one entry per grain).
pub struct Grains<'a> {
    pub time: f64,
    pub radius: &'a [f64],
    pub pos: &'a [[f64; 3]],
    pub vel: &'a [[f64; 3]],
    pub omega: &'a [[f64; 3]],
}

fn array(s: &mut String, name: &str, kind: &str, components: usize, values: impl Iterator<Item = String>) {
    let _ = writeln!(
        s,
        "        <DataArray type=\"{kind}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">"
    );
    for v in values {
        let _ = writeln!(s, "          {v}");
    }
    let _ = writeln!(s, "        </DataArray>");
}

fn vec3(v: &[f64; 3]) -> String {
    format!("{} {} {}", short(v[0]), short(v[1]), short(v[2]))
}

/// Writes the grains of a frame as a `.vtp` file (atomically); grain `i` has `id` i.
pub fn write_grains(path: &Path, g: &Grains) -> std::io::Result<()> {
    let n = g.radius.len();
    if [g.pos.len(), g.vel.len(), g.omega.len()].iter().any(|&k| k != n) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "grains: radius, pos, vel and omega differ in length",
        ));
    }
    let mut s = String::with_capacity(160 * n + 1024);
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <PolyData>\n    \
         <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n    </FieldData>\n    \
         <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n      <PointData Scalars=\"radius\" Vectors=\"velocity\">",
        short_time(g.time)
    );
    array(&mut s, "id", "Int64", 1, (0..n).map(|i| i.to_string()));
    array(&mut s, "radius", "Float32", 1, g.radius.iter().map(|r| short(*r)));
    array(&mut s, "velocity", "Float32", 3, g.vel.iter().map(vec3));
    array(&mut s, "angular_velocity", "Float32", 3, g.omega.iter().map(vec3));
    let _ = writeln!(s, "      </PointData>\n      <Points>");
    array(&mut s, "Points", "Float32", 3, g.pos.iter().map(vec3));
    let _ = writeln!(s, "      </Points>\n      <Verts>");
    array(&mut s, "connectivity", "Int64", 1, (0..n).map(|i| i.to_string()));
    array(&mut s, "offsets", "Int64", 1, (1..=n).map(|i| i.to_string()));
    let _ = writeln!(s, "      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>");
    crate::io::write_atomic(path, s.as_bytes())
}

/// A flat quadrilateral of the container (corners in order) and its velocity (m/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    pub corners: [[f64; 3]; 4],
    pub velocity: [f64; 3],
}

/// Writes quadrilaterals (the container) as a `.vtp` file (atomically), with the cell data
/// `velocity`.
pub fn write_quads(path: &Path, time: f64, quads: &[Quad]) -> std::io::Result<()> {
    let m = quads.len();
    let mut s = String::with_capacity(400 * m + 1024);
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <PolyData>\n    \
         <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n    </FieldData>\n    \
         <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"{m}\">\n      <CellData Vectors=\"velocity\">",
        short_time(time),
        4 * m
    );
    array(&mut s, "velocity", "Float32", 3, quads.iter().map(|q| vec3(&q.velocity)));
    let _ = writeln!(s, "      </CellData>\n      <Points>");
    array(
        &mut s,
        "Points",
        "Float32",
        3,
        quads.iter().flat_map(|q| q.corners.iter().map(vec3)),
    );
    let _ = writeln!(s, "      </Points>\n      <Polys>");
    array(&mut s, "connectivity", "Int64", 1, (0..4 * m).map(|i| i.to_string()));
    array(&mut s, "offsets", "Int64", 1, (1..=m).map(|k| (4 * k).to_string()));
    let _ = writeln!(s, "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>");
    crate::io::write_atomic(path, s.as_bytes())
}

/// A ParaView collection file: every dataset with its time and part.
pub struct Pvd {
    path: PathBuf,
    entries: Vec<(f64, usize, String)>,
}

impl Pvd {
    /// A collection written to `path`; file names are given relative to its directory.
    pub fn new(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            entries: Vec::new(),
        }
    }

    /// Keeps the entries with time at most `t` (a resumed run drops what comes after its
    /// checkpoint).
    pub fn keep_until(&mut self, t: f64) {
        self.entries.retain(|e| e.0 <= t);
    }

    /// Reads the entries of an existing collection (none if it cannot be read).
    pub fn open(path: &Path) -> Self {
        let mut pvd = Self::new(path);
        let text = std::fs::read_to_string(path).unwrap_or_default();
        for line in text.lines().filter(|l| l.contains("<DataSet")) {
            let attr = |name: &str| {
                let key = format!("{name}=\"");
                line.split(&key).nth(1).and_then(|r| r.split('"').next()).map(str::to_string)
            };
            if let (Some(t), Some(p), Some(f)) = (attr("timestep"), attr("part"), attr("file")) {
                if let (Ok(t), Ok(p)) = (t.parse(), p.parse()) {
                    pvd.entries.push((t, p, f));
                }
            }
        }
        pvd
    }

    /// Adds a dataset and rewrites the collection (atomically).
    pub fn push(&mut self, time: f64, part: usize, file: &str) -> std::io::Result<()> {
        self.entries.push((time, part, file.to_string()));
        self.write()
    }

    /// Writes the collection (atomically).
    pub fn write(&self) -> std::io::Result<()> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, part, file) in &self.entries {
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{}\" group=\"\" part=\"{part}\" file=\"{file}\"/>",
                short_time(*t)
            );
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        crate::io::write_atomic(&self.path, s.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_only_the_digits_that_matter() {
        assert_eq!(short(2.8078573734439517e-15), "2.8078575e-15");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(0.1), "1e-1");
        assert_eq!(short_time(0.0125 + 1e-15), "1.25e-2");
    }

    #[test]
    fn grains_quads_and_collection() {
        let d = std::env::temp_dir().join(format!("stripes-vtk-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let g = Grains {
            time: 0.5,
            radius: &[0.1, 0.2],
            pos: &[[0.1, 0.2, 0.1], [0.5, 0.5, 0.2]],
            vel: &[[0.0; 3], [1.0, 0.0, 0.0]],
            omega: &[[0.0, 3.0, 0.0], [0.0; 3]],
        };
        write_grains(&d.join("g.vtp"), &g).unwrap();
        let text = std::fs::read_to_string(d.join("g.vtp")).unwrap();
        for key in [
            "NumberOfPoints=\"2\"",
            "Name=\"id\"",
            "Name=\"radius\"",
            "Name=\"velocity\"",
            "Name=\"angular_velocity\"",
            "0 3e0 0",
        ] {
            assert!(text.contains(key), "{key}");
        }
        let q = Quad {
            corners: [[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            velocity: [0.5, 0.0, 0.0],
        };
        write_quads(&d.join("t.vtp"), 0.5, &[q]).unwrap();
        assert!(std::fs::read_to_string(d.join("t.vtp")).unwrap().contains("NumberOfPolys=\"1\""));
        let mut pvd = Pvd::new(&d.join("s.pvd"));
        pvd.push(0.0, 0, "g.vtp").unwrap();
        pvd.push(0.5, 1, "t.vtp").unwrap();
        let mut back = Pvd::open(&d.join("s.pvd"));
        assert_eq!(back.entries, vec![(0.0, 0, "g.vtp".to_string()), (0.5, 1, "t.vtp".to_string())]);
        back.keep_until(0.1);
        assert_eq!(back.entries.len(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }
}
