//! DEM checkpoints: the dynamic state of a [`Simulation`] ([`SavedState`], exported by the
//! physics crate as plain data) in a small binary format, so a resumed run continues bit for
//! bit as if it had never stopped.
//!
//! Layout (little endian): magic `STRPCKP4`, `u64` scene fingerprint, `f64` time, `u64` steps,
//! ledger (`f64` injected, dissipated), `f64` stored energy, `u64` N, then per particle
//! position, velocity, spin, half-step velocity, half-step spin, force, torque (7 x 3 `f64`),
//! then the live pair histories (`u64` count, then `u32 i, u32 j, 3 f64`), then the wall
//! histories (`u64` count, then `3 f64` each), then the rolling springs of the
//! spring-dashpot-slider in the same two layouts (pairs, then walls; counts 0 without them),
//! then the grains' places in the simulation's
//! arrays (`u64` count, 0 while every grain is at its own index, then `u32` each: see
//! `SavedState::order`), then `u64` caller data (e.g. snapshots written), then the FNV-1a of
//! every byte after the magic ([`crate::rundir::bytes::seal`]): a file cut short or altered
//! is refused before it is read. `STRPCKP3` is the same layout without the checksum. A
//! checkpoint of an older layout is read as one without rolling springs (`STRPCKP2`: no rolling springs; its
//! runs had no rolling spring to keep), and `STRPCKP1` also as one whose grains are at their
//! own indices. `STRPCKP5`, written only for clumps (`particles.shape = "clump"`), is
//! `STRPCKP4` with the rigid bodies after the places: `u64` count, then per body its centre,
//! velocity (3 `f64` each), orientation quaternion and conjugate momentum (4 `f64` each;
//! `particles::rigid::SavedBody`); a sphere run's checkpoint stays `STRPCKP4`, byte for byte.

use particles::rigid::SavedBody;
use particles::saved::SavedState;
use particles::sim::{Ledger, Simulation};
use particles::Vec3;

use crate::rundir::bytes::{seal, unseal, Reader, Writer};

const MAGIC: &[u8; 8] = b"STRPCKP4";
/// [`MAGIC`]'s layout with the rigid bodies of a clump run after the places.
const MAGIC_WITH_BODIES: &[u8; 8] = b"STRPCKP5";
/// The same layout without the checksum.
const MAGIC_UNSEALED: &[u8; 8] = b"STRPCKP3";
/// The layout without the rolling springs.
const MAGIC_WITHOUT_ROLLS: &[u8; 8] = b"STRPCKP2";
/// The layout without the rolling springs and the grains' places.
const MAGIC_WITHOUT_PLACES: &[u8; 8] = b"STRPCKP1";

/// The checkpoint of `sim`; `fingerprint` identifies the scene (checked on restore) and
/// `extra` is caller data stored alongside (e.g. the number of snapshots written).
pub fn encode(sim: &Simulation, fingerprint: u64, extra: u64) -> Vec<u8> {
    let s = sim.export_state();
    let mut w = Writer::default();
    w.0.extend_from_slice(if s.bodies.is_empty() { MAGIC } else { MAGIC_WITH_BODIES });
    w.u64(fingerprint);
    w.f64(s.time);
    w.u64(s.steps);
    w.f64(s.ledger.injected);
    w.f64(s.ledger.dissipated);
    w.f64(s.stored_energy);
    w.u64(s.len() as u64);
    for i in 0..s.len() {
        for v in [
            &s.pos[i],
            &s.vel[i],
            &s.omega[i],
            &s.vel_half[i],
            &s.omega_half[i],
            &s.force[i],
            &s.torque[i],
        ] {
            w.vec3(v);
        }
    }
    write_springs(&mut w, &s.pair_histories, &s.wall_histories);
    write_springs(&mut w, &s.pair_rolls, &s.wall_rolls);
    w.u64(s.order.len() as u64);
    for &g in &s.order {
        w.u32(g);
    }
    if !s.bodies.is_empty() {
        w.u64(s.bodies.len() as u64);
        for b in &s.bodies {
            w.vec3(&b.x);
            w.vec3(&b.v);
            for c in b.q.iter().chain(&b.p) {
                w.f64(*c);
            }
        }
    }
    w.u64(extra);
    seal(&mut w.0, MAGIC.len());
    w.0
}

/// Per-pair springs: the pair's two places and the spring.
type PairSprings = Vec<(usize, usize, Vec3)>;

/// One kind of per-contact spring: the pairs' (`u64` count, then `u32 i, u32 j, 3 f64`), then
/// the walls' (`u64` count, then `3 f64`).
fn write_springs(w: &mut Writer, pairs: &[(usize, usize, Vec3)], walls: &[Vec3]) {
    w.u64(pairs.len() as u64);
    for (i, j, h) in pairs {
        w.u32(*i as u32);
        w.u32(*j as u32);
        w.vec3(h);
    }
    w.u64(walls.len() as u64);
    for h in walls {
        w.vec3(h);
    }
}

/// The springs [`write_springs`] wrote; `what` names them in a cut file's message.
fn read_springs(r: &mut Reader<'_>, what: &str) -> Result<(PairSprings, Vec<Vec3>), String> {
    let count = r.count(4 + 4 + 24, &format!("pair {what}"))?;
    let mut pairs = Vec::with_capacity(count);
    for _ in 0..count {
        pairs.push((r.u32()? as usize, r.u32()? as usize, r.vec3()?));
    }
    let count = r.count(24, &format!("wall {what}"))?;
    let mut walls = Vec::with_capacity(count);
    for _ in 0..count {
        walls.push(r.vec3()?);
    }
    Ok((pairs, walls))
}

/// The scene fingerprint a checkpoint was written with (`None`: not a stripes checkpoint, or
/// cut short before it). Read before the checksum, to say whose checkpoint a refused one is.
pub fn fingerprint_of(bytes: &[u8]) -> Option<u64> {
    let known = [MAGIC, MAGIC_WITH_BODIES, MAGIC_UNSEALED, MAGIC_WITHOUT_ROLLS, MAGIC_WITHOUT_PLACES];
    if bytes.len() < 16 || !known.iter().any(|m| bytes.starts_with(*m)) {
        return None;
    }
    Some(u64::from_le_bytes(bytes[8..16].try_into().ok()?))
}

/// Restores a checkpoint written by [`encode`] into `sim`, built from the same scene and
/// sample; returns the caller data. An error says what does not match.
pub fn restore(sim: &mut Simulation, bytes: &[u8], fingerprint: u64) -> Result<u64, String> {
    let (saved, extra) = decode(bytes, fingerprint, sim.len())?;
    sim.import_state(saved).map_err(|e| e.to_string())?;
    Ok(extra)
}

/// The state and caller data in `bytes`, which must belong to the scene `fingerprint` and
/// hold `particles` particles.
fn decode(bytes: &[u8], fingerprint: u64, particles: usize) -> Result<(SavedState, u64), String> {
    let bytes = if bytes.starts_with(MAGIC) || bytes.starts_with(MAGIC_WITH_BODIES) {
        unseal(bytes, MAGIC.len())?
    } else {
        bytes
    };
    let mut r = Reader::new(bytes);
    let (places, rolls, bodies) = match r.take(8)? {
        m if m == MAGIC_WITH_BODIES => (true, true, true),
        m if m == MAGIC || m == MAGIC_UNSEALED => (true, true, false),
        m if m == MAGIC_WITHOUT_ROLLS => (true, false, false),
        m if m == MAGIC_WITHOUT_PLACES => (false, false, false),
        _ => return Err("not a stripes checkpoint".into()),
    };
    if r.u64()? != fingerprint {
        return Err("the checkpoint belongs to a different scene (a key or the sample changed)".into());
    }
    let time = r.f64()?;
    let steps = r.u64()?;
    let ledger = Ledger {
        injected: r.f64()?,
        dissipated: r.f64()?,
    };
    let stored_energy = r.f64()?;
    let n = r.u64()? as usize;
    if n != particles {
        return Err(format!("the checkpoint has {n} particles, the scene {particles}"));
    }
    let mut s = SavedState {
        time,
        steps,
        ledger,
        stored_energy,
        pos: Vec::with_capacity(n),
        vel: Vec::with_capacity(n),
        omega: Vec::with_capacity(n),
        vel_half: Vec::with_capacity(n),
        omega_half: Vec::with_capacity(n),
        force: Vec::with_capacity(n),
        torque: Vec::with_capacity(n),
        pair_histories: Vec::new(),
        wall_histories: Vec::new(),
        pair_rolls: Vec::new(),
        wall_rolls: Vec::new(),
        order: Vec::new(),
        bodies: Vec::new(),
    };
    for _ in 0..n {
        s.pos.push(r.vec3()?);
        s.vel.push(r.vec3()?);
        s.omega.push(r.vec3()?);
        s.vel_half.push(r.vec3()?);
        s.omega_half.push(r.vec3()?);
        s.force.push(r.vec3()?);
        s.torque.push(r.vec3()?);
    }
    (s.pair_histories, s.wall_histories) = read_springs(&mut r, "histories")?;
    if rolls {
        (s.pair_rolls, s.wall_rolls) = read_springs(&mut r, "rolling springs")?;
    }
    if places {
        let count = r.count(4, "places")?;
        s.order.reserve_exact(count);
        for _ in 0..count {
            s.order.push(r.u32()?);
        }
    }
    if bodies {
        let count = r.count(14 * 8, "rigid bodies")?;
        s.bodies.reserve_exact(count);
        for _ in 0..count {
            let (x, v) = (r.vec3()?, r.vec3()?);
            let mut qp = [0.0; 8];
            for c in &mut qp {
                *c = r.f64()?;
            }
            s.bodies.push(SavedBody {
                x,
                v,
                q: [qp[0], qp[1], qp[2], qp[3]],
                p: [qp[4], qp[5], qp[6], qp[7]],
            });
        }
    }
    let extra = r.u64()?;
    Ok((s, extra))
}
