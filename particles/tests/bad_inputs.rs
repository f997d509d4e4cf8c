//! Bad input to the particle crate's readers: checkpoints and scenes. Random bytes, random
//! record counts and random values must give an error or a valid result, never a panic, and
//! never make the reader hold more than a small multiple of the input's size (an allocator
//! counts the bytes live at once). Named regressions pin sizes that used to abort the process.

mod common;

use std::sync::atomic::Ordering;

use particles::prepare::initial_state;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::tray;
use particles::wall::Motion;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "../../test-support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{LIVE, PEAK, SERIAL};

/// Bytes a reader may hold beyond the input: parsed records, a vector's doubling, a TOML
/// tree, plus a fixed allowance for messages and small tables.
const FACTOR: usize = 64;
const ALLOWANCE: usize = 256 * 1024;

fn bounded<T>(len: usize, what: &str, read: impl FnOnce() -> T) -> T {
    let base = LIVE.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let out = read();
    let peak = PEAK.load(Ordering::SeqCst).saturating_sub(base);
    let limit = FACTOR * len + ALLOWANCE;
    assert!(
        peak <= limit,
        "{what}: {len} input bytes made the reader hold {peak} bytes (limit {limit})"
    );
    out
}

fn small_tray() -> Scene {
    common::tray_scene(0.01, 0.005, 20, "[run]\nduration = 0.1\ndt = 8e-6\nseed = 4\n", &[])
}

fn simulation(scene: &Scene) -> Simulation {
    let setup = tray::setup(scene, Motion::Fixed).unwrap();
    Simulation::new(setup, initial_state(scene).unwrap()).unwrap()
}

/// Regression: `--set box.length=1000 --set box.width=1000` aborted the process allocating
/// 7 TB for the initial lattice; the scene is refused naming the key and the size.
#[test]
fn a_box_of_1000_m_by_1000_m_is_refused_naming_the_key_and_the_size() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let text = common::tray_toml(0.01, 0.005, 20, "[run]\nduration = 0.1\ndt = 8e-6\nseed = 4\n");
    let big = ["box.length=1000".to_string(), "box.width=1000".to_string()];
    let scene = Scene::parse(&text, &big, "test").unwrap();
    let e = bounded(0, "validate", || scene.validate()).unwrap_err().to_string();
    assert!(
        e.contains("box.length") && e.contains("lattice sites") && e.contains("bytes"),
        "{e}"
    );
    // A tray at the bound's side that is still reasonable passes.
    common::tray_scene(4.0, 0.02, 20, "[run]\nduration = 0.1\ndt = 8e-6\nseed = 4\n", &[]);
}

/// Random bytes, random record counts, random flips and cuts of a real checkpoint: restore
/// gives an error or the state, never a panic, and never sizes anything by a bare claim.
#[test]
fn random_checkpoints_never_panic_nor_allocate_beyond_their_size() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = small_tray();
    let mut sim = simulation(&scene);
    for _ in 0..2000 {
        sim.step().unwrap();
    }
    let good = sim.checkpoint(7, 3);
    let fresh = simulation(&scene);
    assert_eq!(simulation(&scene).restore(&good, 7), Ok(3));
    // Offsets of the two record counts: after the particles, and after the pair records.
    let n = fresh.state.len();
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
        let _ = bounded(len, &format!("checkpoint case {k}"), || target.restore(&b, 7));
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
    let base = common::tray_toml(0.01, 0.005, 20, "[run]\nduration = 0.1\ndt = 8e-6\nseed = 4\n");
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
            (base.clone(), o)
        };
        let len = text.len() + overrides.iter().map(String::len).sum::<usize>();
        let result = bounded(len, &format!("scene case {k}"), || {
            Scene::parse(&text, &overrides, "fuzz").and_then(|s| s.validate().map(|_| s))
        });
        match result {
            Ok(_) => valid += 1,
            Err(e) => assert!(!e.to_string().is_empty(), "case {k}: an empty error"),
        }
    }
    // The random values reach validation: some scenes pass, most are refused.
    assert!((10..300).contains(&valid), "{valid} of 400 random scenes valid");
}
