//! Bad input to the readers of snapshots and LAMMPS dumps: random bytes, random headers and
//! random cuts of valid files. Each must give a frame list or an error, never a panic, and
//! never allocate more than a small multiple of the input's size (an allocator counts the
//! bytes live at once). Named regressions pin the claims that used to abort the process.

use std::path::{Path, PathBuf};

use analysis::input::load;
use analysis::lammps::read_dump_noting;
use analysis::snapshot::read_snapshots_counting;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "../../test-support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::SERIAL;

/// Bytes a reader may hold beyond the input: the file read whole, parsed values as `f64`
/// (a text value of two bytes becomes eight, an `f32` becomes an `f64` in a position and
/// in a velocity), a vector's doubling, plus a fixed allowance for buffers and messages.
const FACTOR: usize = 48;
const ALLOWANCE: usize = 256 * 1024;

/// Runs `read` on `bytes` written to a file; panics (failing the test) if the peak of live
/// bytes grows beyond `FACTOR * len + ALLOWANCE`.
fn bounded<T>(dir: &Path, bytes: &[u8], what: &str, read: impl FnOnce(&Path) -> T) -> T {
    let path = dir.join("input");
    std::fs::write(&path, bytes).unwrap();
    counting_alloc::held_within(FACTOR, ALLOWANCE, bytes.len(), what, || read(&path))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stripes-bad-readers-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn snapshot_bytes(n: u64, length: f64, width: f64, radii: &[f64], frames: usize, rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut b = b"STRPSNP1".to_vec();
    b.extend_from_slice(&n.to_le_bytes());
    b.extend_from_slice(&length.to_le_bytes());
    b.extend_from_slice(&width.to_le_bytes());
    for r in radii {
        b.extend_from_slice(&r.to_le_bytes());
    }
    for k in 0..frames {
        b.extend_from_slice(&(k as f64 * 0.05).to_le_bytes());
        for _ in 0..radii.len() * 6 {
            b.extend_from_slice(&rng.gen_range(0.0f32..0.02).to_le_bytes());
        }
    }
    b
}

const DUMP: &str = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff ff\n0 0.4\n0 0.02\n-0.001 0.1\n\
ITEM: ATOMS id radius x y z vx vy vz\n1 0.0003 0.1 0.01 0.0003 0 0 0\n2 0.0004 0.2 0.015 0.0004 1 2 3\n\
ITEM: TIMESTEP\n6250\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff ff\n0 0.4\n0 0.02\n-0.001 0.1\n\
ITEM: ATOMS id radius x y z vx vy vz\n1 0.0003 0.11 0.01 0.0003 0 0 0\n2 0.0004 0.21 0.015 0.0004 0 0 0\n";

/// Regression: a snapshot header claiming 2^61 grains panicked with "capacity overflow".
#[test]
fn a_snapshot_header_claiming_2_to_the_61_grains_is_an_error_naming_the_claim() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let d = scratch("snap61");
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let bytes = snapshot_bytes(1 << 61, 0.4, 0.02, &[3e-4, 4e-4], 2, &mut rng);
    let e = bounded(&d, &bytes, "2^61 grains", read_snapshots_counting).unwrap_err().to_string();
    assert!(e.contains("claims 2305843009213693952 grains"), "{e}");
    let e = bounded(&d, &bytes, "2^61 grains via load", |p| load(p, 8e-6))
        .unwrap_err()
        .to_string();
    assert!(e.contains("claims 2305843009213693952 grains"), "{e}");
    // A header of non-physical sizes is refused, naming the field.
    for (length, width, radius, want) in [
        (f64::NAN, 0.02, 3e-4, "box length NaN"),
        (0.4, -1.0, 3e-4, "box width -1"),
        (0.4, 0.02, 0.0, "grain 0 has radius 0"),
    ] {
        let bytes = snapshot_bytes(1, length, width, &[radius], 1, &mut rng);
        let e = bounded(&d, &bytes, want, read_snapshots_counting).unwrap_err().to_string();
        assert!(e.contains(want), "`{e}` lacks `{want}`");
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// Regression: a dump claiming 99999999999999 atoms aborted the process at allocation.
#[test]
fn a_dump_claiming_99999999999999_atoms_is_an_error_naming_the_claim() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let d = scratch("dump-atoms");
    let text = DUMP.replacen("ITEM: NUMBER OF ATOMS\n2", "ITEM: NUMBER OF ATOMS\n99999999999999", 1);
    let e = bounded(&d, text.as_bytes(), "1e14 atoms", |p| read_dump_noting(p, 8e-6))
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 4: timestep 0 claims 99999999999999 atoms"), "{e}");
    std::fs::remove_dir_all(d).unwrap();
}

/// A dump whose box changes between frames, or whose atoms leave the side walls, is refused
/// naming the timestep (the analysis needs one tray); a negative id is named as such.
#[test]
fn a_dump_whose_box_changes_or_whose_atoms_leave_the_walls_is_refused_naming_the_timestep() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let d = scratch("dump-box");
    let moved = {
        let at = DUMP.find("ITEM: TIMESTEP\n6250").unwrap();
        format!("{}{}", &DUMP[..at], DUMP[at..].replacen("0 0.02\n", "0 0.03\n", 1))
    };
    let e = bounded(&d, moved.as_bytes(), "box change", |p| read_dump_noting(p, 8e-6))
        .unwrap_err()
        .to_string();
    assert!(e.contains("the box changes at timestep 6250"), "{e}");
    let outside = DUMP.replacen("2 0.0004 0.21 0.015", "2 0.0004 0.21 0.025", 1);
    let e = bounded(&d, outside.as_bytes(), "outside", |p| read_dump_noting(p, 8e-6))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("atom 2 at y = 0.025 m lies outside the side walls") && e.contains("timestep 6250"),
        "{e}"
    );
    let (_, frames, notes) = bounded(&d, DUMP.as_bytes(), "clean", |p| read_dump_noting(p, 8e-6)).unwrap();
    assert_eq!(frames.len(), 2);
    assert!(notes.warnings.is_empty(), "{:?}", notes.warnings);
    let e = bounded(&d, DUMP.replacen("\n2 0.0004", "\n-10 0.0004", 1).as_bytes(), "id", |p| {
        read_dump_noting(p, 8e-6)
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("id `-10` is negative"), "{e}");
    std::fs::remove_dir_all(d).unwrap();
}

/// A truncated snapshot file gives its whole frames and the count of ignored bytes; a
/// truncated header is an error.
#[test]
fn a_truncated_snapshot_file_gives_what_can_honestly_be_read() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let d = scratch("snap-cut");
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let bytes = snapshot_bytes(3, 0.4, 0.02, &[3e-4, 4e-4, 5e-4], 4, &mut rng);
    let (header_len, frame) = (32 + 3 * 8, 8 + 3 * 24);
    for cut in 0..bytes.len() {
        let got = bounded(&d, &bytes[..cut], "cut", read_snapshots_counting);
        if cut < header_len {
            assert!(got.is_err(), "cut {cut}");
        } else {
            let (_, frames, rest) = got.unwrap();
            assert_eq!(frames.len(), (cut - header_len) / frame, "cut {cut}");
            assert_eq!(rest, (cut - header_len) % frame, "cut {cut}");
        }
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// Random bytes, random headers, random cuts and random byte flips of valid files: the
/// readers never panic and never hold more than `FACTOR` times the input.
#[test]
fn random_input_to_every_reader_never_panics_nor_allocates_beyond_its_size() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let d = scratch("fuzz");
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut snapshot = snapshot_bytes(2, 0.4, 0.02, &[3e-4, 4e-4], 3, &mut rng);
    let mut cases: Vec<(String, Vec<u8>)> = Vec::new();
    for k in 0..300 {
        let len = rng.gen_range(0..200);
        let mut b: Vec<u8> = (0..len).map(|_| rng.gen()).collect();
        match k % 6 {
            // Random bytes behind each magic.
            0 => {
                b.splice(0..0, *b"STRPSNP1");
            }
            1 => {
                b.splice(0..0, *b"ITEM: TIMESTEP\n");
            }
            // A random header claim: any u64 grain count.
            2 => {
                let n: u64 = if rng.gen() { rng.gen() } else { rng.gen_range(0..8) };
                snapshot[8..16].copy_from_slice(&n.to_le_bytes());
                b = snapshot.clone();
                b.truncate(rng.gen_range(0..=b.len()));
            }
            // A valid file with random bytes flipped.
            3 => {
                b = if rng.gen() { snapshot.clone() } else { DUMP.as_bytes().to_vec() };
                for _ in 0..rng.gen_range(1..6) {
                    let at = rng.gen_range(0..b.len());
                    b[at] = rng.gen();
                }
            }
            // A dump with a random number in a random line.
            4 => {
                let mut lines: Vec<String> = DUMP.lines().map(String::from).collect();
                let at = rng.gen_range(0..lines.len());
                let value = match rng.gen_range(0..4) {
                    0 => rng.gen::<u64>().to_string(),
                    1 => format!("{:e}", rng.gen::<f64>() * 1e300),
                    2 => "-1".into(),
                    _ => "nan".into(),
                };
                lines[at] = value;
                b = lines.join("\n").into_bytes();
                b.truncate(rng.gen_range(0..=b.len()));
            }
            // A dump cut anywhere.
            _ => {
                b = DUMP.as_bytes()[..rng.gen_range(0..=DUMP.len())].to_vec();
            }
        }
        cases.push((format!("case {k}"), b));
    }
    for (what, bytes) in &cases {
        let _ = bounded(&d, bytes, what, read_snapshots_counting);
        let _ = bounded(&d, bytes, what, |p| read_dump_noting(p, 8e-6));
        let _ = bounded(&d, bytes, what, |p| load(p, 8e-6));
    }
    std::fs::remove_dir_all(d).unwrap();
}
