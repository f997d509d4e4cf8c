//! Bad input to the root crate's readers of the DEM's files: checkpoints and scene text.
//! Random bytes, random record counts and random values must give an error or a valid
//! result, never a panic, and never make the reader hold more than a small multiple of the
//! input's size (an allocator counts the bytes live at once).
//!
//! The readers are the command line's own modules, compiled into this test with `#[path]`
//! (the command line is a binary crate; a global allocator belongs to one test binary).

#[path = "../src/rundir/bytes.rs"]
#[allow(dead_code)]
pub mod bytes;
/// `bytes` at the path `dem/checkpoint.rs` imports it from.
mod rundir {
    pub use super::bytes;
}
#[path = "../src/dem/checkpoint.rs"]
mod dem_checkpoint;
#[path = "../src/scene/text/overrides.rs"]
#[allow(dead_code)]
mod overrides;

#[path = "../test-support/counting_alloc.rs"]
mod counting_alloc;

use counting_alloc::SERIAL;
use particles::prepare::initial_state;
use particles::scene::{Scene, SceneError};
use particles::sim::Simulation;
use particles::time_step;
use particles::tray;
use particles::wall::Motion;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;

/// Bytes a reader may hold beyond the input: parsed records, a vector's doubling, a TOML
/// tree, plus a fixed allowance for messages and small tables.
const FACTOR: usize = 64;
const ALLOWANCE: usize = 256 * 1024;

fn bounded<T>(len: usize, what: &str, read: impl FnOnce() -> T) -> T {
    counting_alloc::held_within(FACTOR, ALLOWANCE, len, what, read)
}

/// A tray of 20 grains with the thesis' radii and drive on 10 mm x 5 mm.
const SMALL_TRAY: &str = "[box]\nlength = 0.01\nwidth = 0.005\n[drive]\nfrequency = 20.0\namplitude = 0.025\n\
                          [particles]\ncount = 20\nradius_min = 0.25e-3\nradius_max = 0.5e-3\n\
                          [run]\nduration = 0.1\ndt = 8e-6\nseed = 4\n";

/// Scene text with `--set` overrides, as the command line reads it.
fn parse_scene(text: &str, set: &[String], origin: &str) -> Result<Scene, SceneError> {
    overrides::parse(text, set, origin, |doc| {
        Scene::deserialize(toml::Value::Table(doc)).map_err(|e| e.to_string())
    })
}

fn simulation(scene: &Scene) -> Simulation {
    let setup = tray::setup(scene, Motion::Fixed, time_step::for_scene(scene).unwrap()).unwrap();
    Simulation::new(setup, initial_state(scene).unwrap()).unwrap()
}

/// Random bytes, random record counts, random flips and cuts of a real checkpoint: restore
/// gives an error or the state, never a panic, and never sizes anything by a bare claim.
#[test]
fn random_checkpoints_never_panic_nor_allocate_beyond_their_size() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = parse_scene(SMALL_TRAY, &[], "test").unwrap();
    scene.validate().unwrap();
    let mut sim = simulation(&scene);
    for _ in 0..2000 {
        sim.step().unwrap();
    }
    let good = dem_checkpoint::encode(&sim, 7, 3);
    let mut restored = simulation(&scene);
    assert_eq!(dem_checkpoint::restore(&mut restored, &good, 7), Ok(3));
    assert_eq!(dem_checkpoint::encode(&restored, 7, 3), good, "a restored run saves the same bytes");
    // The fingerprint a refused checkpoint was written with is read without its checksum.
    assert_eq!(dem_checkpoint::fingerprint_of(&good), Some(7));
    assert_eq!(dem_checkpoint::fingerprint_of(&good[..12]), None, "cut before the fingerprint");
    assert_eq!(dem_checkpoint::fingerprint_of(b"NOTACKPT and more bytes"), None);
    // Offsets of the two record counts: after the particles, and after the pair records.
    let n = sim.len();
    let pairs_at = 8 + 8 + 8 + 8 + 3 * 8 + 8 + n * 7 * 24;
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for k in 0..400 {
        let mut b = good.clone();
        match k % 5 {
            0 => b = (0..rng.gen_range(0..300)).map(|_| rng.gen()).collect(),
            1 => b.truncate(rng.gen_range(0..good.len())),
            2 => {
                let claim: u64 = if rng.gen() { rng.gen() } else { rng.gen_range(0..1000) };
                b[pairs_at..pairs_at + 8].copy_from_slice(&claim.to_le_bytes());
            }
            3 => {
                let pairs = u64::from_le_bytes(good[pairs_at..pairs_at + 8].try_into().unwrap()) as usize;
                let walls_at = pairs_at + 8 + pairs * 32;
                let claim: u64 = rng.gen();
                b[walls_at..walls_at + 8].copy_from_slice(&claim.to_le_bytes());
            }
            _ => {
                for _ in 0..rng.gen_range(1..8) {
                    let at = rng.gen_range(0..b.len());
                    b[at] = rng.gen();
                }
            }
        }
        let mut target = simulation(&scene);
        let len = b.len();
        let _ = bounded(len, &format!("checkpoint case {k}"), || dem_checkpoint::restore(&mut target, &b, 7));
    }
}

/// The scene keys a random scene draws values for.
const KEYS: [&str; 14] = [
    "box.length",
    "box.width",
    "drive.frequency",
    "drive.amplitude",
    "particles.count",
    "particles.radius_min",
    "particles.radius_max",
    "material.young",
    "material.dissipation",
    "run.duration",
    "run.dt",
    "run.snapshots_per_period",
    "run.steps_per_contact",
    "contact.friction",
];

/// Random bytes and scenes with random values: parse and validate give a scene or an error
/// naming a key, never a panic, and hold little memory whatever sizes the values claim.
#[test]
fn random_scenes_never_panic_nor_allocate_beyond_their_size() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut rng = ChaCha8Rng::seed_from_u64(32);
    let values = [
        "0",
        "-1",
        "1e300",
        "1e-300",
        "nan",
        "inf",
        "-inf",
        "18446744073709551615",
        "\"auto\"",
        "1000",
        "1e-7",
    ];
    let mut valid = 0;
    for k in 0..400 {
        let (text, overrides): (String, Vec<String>) = if k % 4 == 0 {
            let bytes: Vec<u8> = (0..rng.gen_range(0..200)).map(|_| rng.gen()).collect();
            (String::from_utf8_lossy(&bytes).into_owned(), Vec::new())
        } else {
            let o = (0..rng.gen_range(1..4))
                .map(|_| {
                    let v = if rng.gen() {
                        values[rng.gen_range(0..values.len())].to_string()
                    } else {
                        format!("{:e}", rng.gen::<f64>() * 10f64.powi(rng.gen_range(-12..12)))
                    };
                    format!("{}={v}", KEYS[rng.gen_range(0..KEYS.len())])
                })
                .collect();
            (SMALL_TRAY.to_string(), o)
        };
        let len = text.len() + overrides.iter().map(String::len).sum::<usize>();
        let result = bounded(len, &format!("scene case {k}"), || {
            parse_scene(&text, &overrides, "fuzz").and_then(|s| s.validate().map(|_| s))
        });
        match result {
            Ok(_) => valid += 1,
            Err(e) => assert!(!e.to_string().is_empty(), "case {k}: an empty error"),
        }
    }
    // The random values reach validation: some scenes pass, most are refused.
    assert!((10..300).contains(&valid), "{valid} of 400 random scenes valid");
}
