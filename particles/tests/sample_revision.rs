//! Prepared samples are cached on disk under a key of their scene, which cannot see the
//! code that prepared them. This test pins the bits of one small prepared sample: a change to
//! the DEM that moves them fails here, and the fix is to bump `prepare::SAMPLE_REVISION` (so
//! that every cache prepares its samples afresh) and to pin the new hash.

mod common;

use particles::measure::fnv1a;
use particles::prepare::{self, SAMPLE_REVISION};

/// `(SAMPLE_REVISION, hash of the sample)` the code last produced.
const PINNED: (u64, u64) = (8, 0x12ae_3970_6504_6b21);

#[test]
fn prepared_sample_is_pinned_to_the_sample_revision() {
    // 60 grains relaxed for 0.02 s: every force law, the integrator and the automatic time
    // step take part (revision 4: `dt = "auto"` learnt to keep the Haff-Werner viscous branch
    // stable at slow drives, which changed every sample prepared with it; revision 5: each
    // particle pair is evaluated once, which changed the order of every grain's additions;
    // revision 6: the Haff-Werner viscous branch is integrated implicitly, issue 41;
    // revision 7: that branch is the explicit law again up to gamma_t dt / m_t = 2/3;
    // revision 8: `dt = "auto"` lets that ratio reach 3.6, since the ledger books the kick).
    let scene = common::tray_scene(0.02, 0.01, 60, common::AUTO, 3, |s| {
        s.prepare.speed = 0.05;
        s.prepare.duration = 0.02;
    });
    let state = prepare::prepare(&scene, |_| {}).unwrap();
    let mut bytes = Vec::new();
    for i in 0..state.len() {
        for c in state.pos[i].iter().chain(std::iter::once(&state.radius[i])) {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    let got = (SAMPLE_REVISION, fnv1a(&bytes));
    assert_eq!(
        got,
        PINNED,
        "the prepared sample changed: bump prepare::SAMPLE_REVISION (now {SAMPLE_REVISION}) so that cached samples of the old \
         code are not reused, and pin ({}, {:#018x}) here",
        SAMPLE_REVISION + (got.1 != PINNED.1 && SAMPLE_REVISION == PINNED.0) as u64,
        got.1
    );
}
