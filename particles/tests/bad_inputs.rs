//! Bad scene values: validation refuses a scene whose sizes would exhaust memory, naming the
//! key and the size, and holds little memory doing so (an allocator counts the bytes live
//! at once). The readers of scene text and checkpoint bytes live in the root crate and are
//! fuzzed there (`tests/bad_readers.rs`).

mod common;

use particles::scene::TimeStep;

#[path = "../../test-support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::SERIAL;

/// Bytes validation may hold beyond the input: a fixed allowance for messages and small
/// tables.
const FACTOR: usize = 64;
const ALLOWANCE: usize = 256 * 1024;

fn bounded<T>(len: usize, what: &str, read: impl FnOnce() -> T) -> T {
    counting_alloc::held_within(FACTOR, ALLOWANCE, len, what, read)
}

/// Regression: `--set box.length=1000 --set box.width=1000` aborted the process allocating
/// 7 TB for the initial lattice; the scene is refused naming the key and the size.
#[test]
fn a_box_of_1000_m_by_1000_m_is_refused_naming_the_key_and_the_size() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut scene = common::tray_scene(0.01, 0.005, 20, TimeStep::Seconds(8e-6), 4, common::unchanged);
    scene.tray.length = 1000.0;
    scene.tray.width = 1000.0;
    let e = bounded(0, "validate", || scene.validate()).unwrap_err().to_string();
    assert!(
        e.contains("box.length") && e.contains("lattice sites") && e.contains("bytes"),
        "{e}"
    );
    // A tray at the bound's side that is still reasonable passes.
    common::tray_scene(4.0, 0.02, 20, TimeStep::Seconds(8e-6), 4, common::unchanged);
}
