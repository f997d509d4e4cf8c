//! Legacy VTK files of a frame, for ParaView: one `POLYDATA` point per grain with the scalar
//! `radius` and the vector `velocity` (use the Glyph filter with a sphere scaled by radius).

use std::fmt::Write as _;
use std::path::Path;

use crate::snapshot::{Frame, Header};

/// Writes `frame` as an ASCII legacy VTK file (atomically).
pub fn write_vtk(path: &Path, header: &Header, frame: &Frame) -> std::io::Result<()> {
    let n = header.radii.len();
    let mut s = String::with_capacity(100 * n + 256);
    let _ = writeln!(
        s,
        "# vtk DataFile Version 3.0\nstripes t = {} s\nASCII\nDATASET POLYDATA\nPOINTS {n} double",
        frame.time
    );
    for p in &frame.pos {
        let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
    }
    let _ = writeln!(s, "VERTICES {n} {}", 2 * n);
    for i in 0..n {
        let _ = writeln!(s, "1 {i}");
    }
    let _ = writeln!(s, "POINT_DATA {n}\nSCALARS radius double 1\nLOOKUP_TABLE default");
    for r in &header.radii {
        let _ = writeln!(s, "{r}");
    }
    let _ = writeln!(s, "VECTORS velocity double");
    for v in &frame.vel {
        let _ = writeln!(s, "{} {} {}", v[0], v[1], v[2]);
    }
    crate::io::write_atomic(path, s.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vtk_has_all_sections() {
        let d = std::env::temp_dir().join(format!("stripes-vtk-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let header = Header {
            length: 1.0,
            width: 1.0,
            radii: vec![0.1, 0.2],
        };
        let frame = Frame {
            time: 0.5,
            pos: vec![[0.1, 0.2, 0.1], [0.5, 0.5, 0.2]],
            vel: vec![[0.0; 3], [1.0, 0.0, 0.0]],
        };
        let p = d.join("f.vtk");
        write_vtk(&p, &header, &frame).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        for key in ["POINTS 2 double", "VERTICES 2 4", "SCALARS radius", "VECTORS velocity", "1 0 0"] {
            assert!(text.contains(key), "{key}");
        }
        std::fs::remove_dir_all(d).unwrap();
    }
}
