//! The checkpoint of `stripes events`: the engine's complete state ([`events::State`]), the
//! observer's sums, the energy at the start and where the sampling stands, in one file
//! (`checkpoint.bin`) written atomically. A run continued from it with `--resume` goes on
//! bit for bit as if it had not stopped.
//!
//! Layout (little-endian): the magic `STRIPES-EVENTS-CKPT-7\n` (7: the bulk's sums and the
//! escaped grains' counts, issue 43; an older layout is refused by its number), the scene's
//! fingerprint (u64), then the payload, then an FNV-1a checksum (u64) of the payload. Vectors
//! are a u64 length followed by their items. A file cut short or altered fails its checksum and
//! is refused with the byte count, never half read.

use events::observe::{BulkSums, Observer, PhaseSums, Profile};
use events::phase_field::PhaseField;
use events::segregation::Mixing;
use events::sim::{Counts, Ledger};
use events::thinned::Thinned;
use events::{Next, State, Vec2};

use crate::rundir::bytes::{seal, unseal, Reader, Writer};

const MAGIC: &[u8] = b"STRIPES-EVENTS-CKPT-7\n";
/// The magic without its layout number.
const MAGIC_STEM: &[u8] = b"STRIPES-EVENTS-CKPT-";
/// The header read apart from the sealed payload: the magic and the scene's fingerprint.
const HEAD: usize = MAGIC.len() + 8;

/// Where a run stands at a checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// The scene's fingerprint (everything but the duration).
    pub fingerprint: u64,
    /// The last sample index carried out (samples are at `k / (f * per_period)`).
    pub sample: u64,
    /// Frames written to `snapshots.bin`.
    pub frames: u64,
    /// Total energy at t = 0 (J), for the ledger.
    pub e0: f64,
    pub state: State,
    pub observer: Observer,
}

/// A list of vectors: its length, then each vector's two components.
fn write_vecs(o: &mut Writer, v: &[Vec2]) {
    o.u64(v.len() as u64);
    for p in v {
        o.f64(p.x);
        o.f64(p.y);
    }
}

/// An event prediction: a tag and three slots.
fn write_next(o: &mut Writer, n: &Next) {
    let (tag, a, b, c) = match *n {
        Next::Pair { j, count } => (0, j as u64, count, 0),
        Next::Wall { w } => (1, w as u64, 0, 0),
        Next::Tooth { tooth, piece } => (2, tooth as u64, piece as u64, 0),
        Next::Cell { to, wrap } => (3, to.0 as u64, to.1 as u64, wrap.to_bits()),
        Next::Look => (4, 0, 0, 0),
        Next::Nothing => (5, 0, 0, 0),
    };
    for x in [tag, a, b, c] {
        o.u64(x);
    }
}

/// The list [`write_vecs`] wrote.
fn read_vecs(i: &mut Reader<'_>) -> Result<Vec<Vec2>, String> {
    let n = i.count(16, "vectors")?;
    (0..n).map(|_| Ok(Vec2::new(i.f64()?, i.f64()?))).collect()
}

/// The prediction [`write_next`] wrote.
fn read_next(i: &mut Reader<'_>) -> Result<Next, String> {
    let (tag, a, b, c) = (i.u64()?, i.u64()?, i.u64()?, i.u64()?);
    Ok(match tag {
        0 => Next::Pair { j: a as usize, count: b },
        1 => Next::Wall { w: a as usize },
        2 => Next::Tooth {
            tooth: a as i64,
            piece: b as u8,
        },
        3 => Next::Cell {
            to: (a as usize, b as usize),
            wrap: f64::from_bits(c),
        },
        4 => Next::Look,
        5 => Next::Nothing,
        t => return Err(format!("unknown event tag {t} at byte {}", i.at() - 32)),
    })
}

/// The checkpoint's bytes.
pub fn encode(c: &Checkpoint) -> Vec<u8> {
    let mut o = Writer::default();
    o.u64(c.sample);
    o.u64(c.frames);
    o.f64(c.e0);
    let s = &c.state;
    o.f64(s.time);
    write_vecs(&mut o, &s.r);
    write_vecs(&mut o, &s.v);
    o.f64s(&s.w);
    o.f64s(&s.t);
    o.f64s(&s.radius);
    o.usizes(&s.species);
    o.u64(s.cell.len() as u64);
    for &(x, z) in &s.cell {
        o.u64(x as u64);
        o.u64(z as u64);
    }
    o.u64(s.collisions.len() as u64);
    s.collisions.iter().for_each(|&x| o.u64(x));
    o.f64s(&s.last_collision);
    o.u64(s.next.len() as u64);
    s.next.iter().for_each(|n| write_next(&mut o, n));
    o.u64(s.beyond_cell.len() as u64);
    for (t, n) in &s.beyond_cell {
        o.f64(*t);
        write_next(&mut o, n);
    }
    o.u64(s.window.len() as u64);
    for &(t, k) in &s.window {
        o.f64(t);
        o.u64(k as u64);
    }
    o.usizes(&s.last_partner);
    o.u64(s.members.len() as u64);
    s.members.iter().for_each(|m| o.usizes(m));
    o.u64(s.scheduled.len() as u64);
    for t in &s.scheduled {
        match t {
            Some(t) => {
                o.u64(1);
                o.f64(*t);
            }
            None => {
                o.u64(0);
                o.f64(0.0);
            }
        }
    }
    for x in [s.counts.pair, s.counts.wall, s.counts.cell, s.counts.stale] {
        o.u64(x);
    }
    o.f64(s.ledger.wall_work);
    o.f64(s.ledger.dissipated);
    for t in &s.free_times {
        o.f64s(&t.kept);
        o.u64(t.stride);
        o.u64(t.skipped);
    }
    let b = &c.observer;
    o.f64(b.bin);
    o.u64(b.bins as u64);
    o.u64(b.across_bins as u64);
    for profiles in [&b.species, &b.across] {
        write_profiles(&mut o, profiles);
    }
    o.u64(b.samples);
    o.f64(b.height_sum);
    o.f64(b.vx_sum);
    for lists in [&b.vx, &b.vz, &b.w, &b.z] {
        o.u64(lists.len() as u64);
        lists.iter().for_each(|v| o.f64s(v));
    }
    for x in [b.velocity_stride, b.velocity_skipped, b.velocity_samples] {
        o.u64(x);
    }
    o.f64s(&b.side.kept);
    o.u64(b.side.stride);
    o.u64(b.side.skipped);
    match &b.field {
        None => o.u64(0),
        Some(f) => {
            o.u64(1);
            o.u64(f.frames as u64);
            o.f64(f.tooth);
            o.u64(f.across as u64);
            o.u64(f.up as u64);
            o.f64(f.teeth);
            for v in [&f.mass, &f.px, &f.pz] {
                o.f64s(v);
            }
            o.usizes(&f.samples.iter().map(|&n| n as usize).collect::<Vec<_>>());
        }
    }
    match &b.mixing {
        None => o.u64(0),
        Some(m) => {
            o.u64(1);
            for v in [&m.neighbours, &m.same] {
                o.usizes(&v.iter().map(|&n| n as usize).collect::<Vec<_>>());
            }
            o.usizes(&m.count);
            o.u64(m.samples);
        }
    }
    o.u64(b.phases.len() as u64);
    for p in &b.phases {
        o.u64(p.samples);
        o.f64(p.com);
        o.f64(p.k);
        o.f64(p.r);
    }
    for per_phase in [&b.phase_heights, &b.phase_across] {
        o.u64(per_phase.len() as u64);
        for profiles in per_phase {
            write_profiles(&mut o, profiles);
        }
    }
    o.u64(b.bulk.len() as u64);
    for s in &b.bulk {
        o.u64(s.count);
        o.f64(s.mvx2);
        o.f64(s.mvz2);
    }
    o.u64(b.escaped);
    o.u64(b.escaped_samples);
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&c.fingerprint.to_le_bytes());
    bytes.extend_from_slice(&o.0);
    seal(&mut bytes, HEAD);
    bytes
}

/// A list of profiles: its length, then each profile's seven columns.
fn write_profiles(o: &mut Writer, profiles: &[Profile]) {
    o.u64(profiles.len() as u64);
    for p in profiles {
        for v in [&p.count, &p.mvx2, &p.mvz2, &p.iw2, &p.vx, &p.vz, &p.m] {
            o.f64s(v);
        }
    }
}

/// The list [`write_profiles`] wrote.
fn read_profiles(i: &mut Reader<'_>) -> Result<Vec<Profile>, String> {
    let n = i.count(56, "records")?;
    (0..n)
        .map(|_| {
            Ok(Profile {
                count: i.f64s()?,
                mvx2: i.f64s()?,
                mvz2: i.f64s()?,
                iw2: i.f64s()?,
                vx: i.f64s()?,
                vz: i.f64s()?,
                m: i.f64s()?,
            })
        })
        .collect()
}

/// Reads a checkpoint; the error says what is wrong (not a checkpoint, cut short, altered).
pub fn decode(bytes: &[u8]) -> Result<Checkpoint, String> {
    if !bytes.starts_with(MAGIC) {
        if let Some(rest) = bytes.strip_prefix(MAGIC_STEM) {
            let layout: String = rest.iter().take_while(|b| b.is_ascii_digit()).map(|&b| b as char).collect();
            return Err(format!(
                "a checkpoint of layout {layout}, written by an older `stripes events`; this one reads layout {} \
                 (it keeps the bulk's sums and the escaped grains, issue 43): run the scene again without --resume",
                String::from_utf8_lossy(&MAGIC[MAGIC_STEM.len()..MAGIC.len() - 1])
            ));
        }
        return Err("not a checkpoint of `stripes events`".into());
    }
    let body = unseal(bytes, HEAD)?;
    let fingerprint = u64::from_le_bytes(body[MAGIC.len()..HEAD].try_into().expect("8 bytes"));
    let mut i = Reader::new(&body[HEAD..]);
    let (sample, frames, e0) = (i.u64()?, i.u64()?, i.f64()?);
    let time = i.f64()?;
    let (r, v, w, t, radius) = (read_vecs(&mut i)?, read_vecs(&mut i)?, i.f64s()?, i.f64s()?, i.f64s()?);
    let species = i.usizes()?;
    let n = i.count(16, "records")?;
    let cell = (0..n)
        .map(|_| Ok((i.u64()? as usize, i.u64()? as usize)))
        .collect::<Result<_, String>>()?;
    let n = i.count(8, "records")?;
    let collisions = (0..n).map(|_| i.u64()).collect::<Result<_, _>>()?;
    let last_collision = i.f64s()?;
    let n = i.count(32, "records")?;
    let next = (0..n).map(|_| read_next(&mut i)).collect::<Result<_, _>>()?;
    let n = i.count(40, "records")?;
    let beyond_cell = (0..n).map(|_| Ok((i.f64()?, read_next(&mut i)?))).collect::<Result<_, String>>()?;
    let n = i.count(16, "records")?;
    let window = (0..n).map(|_| Ok((i.f64()?, i.u64()? as u32))).collect::<Result<_, String>>()?;
    let last_partner = i.usizes()?;
    let n = i.count(8, "records")?;
    let members = (0..n).map(|_| i.usizes()).collect::<Result<_, _>>()?;
    let n = i.count(16, "records")?;
    let scheduled = (0..n)
        .map(|_| {
            let (flag, t) = (i.u64()?, i.f64()?);
            Ok((flag == 1).then_some(t))
        })
        .collect::<Result<_, String>>()?;
    let counts = Counts {
        pair: i.u64()?,
        wall: i.u64()?,
        cell: i.u64()?,
        stale: i.u64()?,
    };
    let ledger = Ledger {
        wall_work: i.f64()?,
        dissipated: i.f64()?,
    };
    let mut thinned = || -> Result<Thinned, String> {
        Ok(Thinned {
            kept: i.f64s()?,
            stride: i.u64()?,
            skipped: i.u64()?,
        })
    };
    let free_times = [thinned()?, thinned()?];
    let state = State {
        time,
        r,
        v,
        w,
        t,
        radius,
        species,
        cell,
        collisions,
        last_collision,
        next,
        beyond_cell,
        window,
        last_partner,
        members,
        scheduled,
        counts,
        ledger,
        free_times,
    };
    let (bin, bins, across_bins) = (i.f64()?, i.u64()? as usize, i.u64()? as usize);
    let mut profiles = Vec::new();
    for _ in 0..2 {
        profiles.push(read_profiles(&mut i)?);
    }
    let across = profiles.pop().expect("two");
    let species = profiles.pop().expect("two");
    let (samples, height_sum, vx_sum) = (i.u64()?, i.f64()?, i.f64()?);
    let mut lists = Vec::new();
    for _ in 0..4 {
        let n = i.count(8, "records")?;
        lists.push((0..n).map(|_| i.f64s()).collect::<Result<Vec<_>, _>>()?);
    }
    let z = lists.pop().expect("four");
    let ws = lists.pop().expect("four");
    let vz = lists.pop().expect("four");
    let vx = lists.pop().expect("four");
    let (velocity_stride, velocity_skipped, velocity_samples) = (i.u64()?, i.u64()?, i.u64()?);
    let side = Thinned {
        kept: i.f64s()?,
        stride: i.u64()?,
        skipped: i.u64()?,
    };
    let field = match i.u64()? {
        0 => None,
        1 => {
            let (frames, tooth, across, up, teeth) = (i.u64()? as usize, i.f64()?, i.u64()? as usize, i.u64()? as usize, i.f64()?);
            let (mass, px, pz) = (i.f64s()?, i.f64s()?, i.f64s()?);
            let samples: Vec<u64> = i.usizes()?.into_iter().map(|n| n as u64).collect();
            let cells = frames.saturating_mul(across).saturating_mul(up);
            if [mass.len(), px.len(), pz.len()].iter().any(|&n| n != cells) || samples.len() != frames {
                return Err("the phase field does not have the boxes it claims".into());
            }
            Some(PhaseField {
                frames,
                tooth,
                across,
                up,
                teeth,
                mass,
                px,
                pz,
                samples,
            })
        }
        other => return Err(format!("unknown phase-field flag {other}")),
    };
    let mixing = match i.u64()? {
        0 => None,
        1 => {
            let neighbours: Vec<u64> = i.usizes()?.into_iter().map(|n| n as u64).collect();
            let same: Vec<u64> = i.usizes()?.into_iter().map(|n| n as u64).collect();
            let count = i.usizes()?;
            if neighbours.len() != count.len() || same.len() != count.len() {
                return Err("the neighbour record does not have the species it claims".into());
            }
            Some(Mixing {
                neighbours,
                same,
                count,
                samples: i.u64()?,
            })
        }
        other => return Err(format!("unknown neighbour-record flag {other}")),
    };
    let n = i.count(32, "records")?;
    let mut phases = Vec::with_capacity(n);
    for _ in 0..n {
        phases.push(PhaseSums {
            samples: i.u64()?,
            com: i.f64()?,
            k: i.f64()?,
            r: i.f64()?,
        });
    }
    let mut per_phase = Vec::new();
    for _ in 0..2 {
        let n = i.count(8, "records")?;
        let mut phase = Vec::with_capacity(n);
        for _ in 0..n {
            phase.push(read_profiles(&mut i)?);
        }
        per_phase.push(phase);
    }
    let phase_across = per_phase.pop().expect("two");
    let phase_heights = per_phase.pop().expect("two");
    let n = i.count(24, "records")?;
    let bulk = (0..n)
        .map(|_| {
            Ok(BulkSums {
                count: i.u64()?,
                mvx2: i.f64()?,
                mvz2: i.f64()?,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let (escaped, escaped_samples) = (i.u64()?, i.u64()?);
    if phases.is_empty()
        || [&phase_heights, &phase_across]
            .iter()
            .any(|p| !p.is_empty() && p.len() != phases.len())
    {
        return Err("the phase records do not have the phases they claim".into());
    }
    if i.left() != 0 {
        return Err(format!("{} bytes left over after the checkpoint", i.left()));
    }
    if species.iter().any(|p| p.count.len() != bins) || across.iter().any(|p| p.count.len() != across_bins) {
        return Err("the profiles do not have the bins they claim".into());
    }
    if bulk.len() != species.len() {
        return Err("the bulk's sums do not have the species the profiles have".into());
    }
    Ok(Checkpoint {
        fingerprint,
        sample,
        frames,
        e0,
        state,
        observer: Observer {
            bin,
            bins,
            species,
            across_bins,
            across,
            samples,
            height_sum,
            vx_sum,
            vx,
            vz,
            w: ws,
            z,
            velocity_stride,
            velocity_skipped,
            velocity_samples,
            side,
            field,
            mixing,
            // Checkpoints are written by `stripes events`, whose observer keeps everything.
            distributions: true,
            phases,
            phase_heights,
            phase_across,
            bulk,
            escaped,
            escaped_samples,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small_run() -> Checkpoint {
        let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml"));
        let scene = crate::scene::events::load(path, &["run.duration=0.5".into(), "run.transient=0".into()]).unwrap();
        let mut sim = events::Simulation::new(crate::scene::events::config(&scene).unwrap()).unwrap();
        let e0 = sim.energy();
        let base = sim.config.base.expect("the ratchet has a sawtooth base");
        let mut observer = Observer::new(1, 1e-3, 0.06, sim.config.width)
            .with_phase_field(&base, sim.config.width, 0.02)
            .with_phases(4, true);
        for k in 1..=20 {
            sim.run_until(k as f64 * 0.01).unwrap();
            observer.sample(&sim);
        }
        // The ratchet has one species; a mixture's neighbour record travels too.
        let mut mixing = Mixing::new(&[0, 1, 1]);
        mixing.add(&[0.0, 1e-3, 5e-3], &[1e-3, 1e-3, 1e-3], &[6e-4; 3], &[0, 1, 1], None);
        observer.mixing = Some(mixing);
        Checkpoint {
            fingerprint: 42,
            sample: 20,
            frames: 20,
            e0,
            state: sim.export_state(),
            observer,
        }
    }

    #[test]
    fn a_checkpoint_reads_back_exactly_and_a_cut_or_altered_one_is_refused() {
        let c = small_run();
        let bytes = encode(&c);
        assert_eq!(decode(&bytes).unwrap(), c);
        for cut in [0, 10, MAGIC.len() + 4, bytes.len() / 2, bytes.len() - 1] {
            assert!(decode(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut altered = bytes.clone();
        let k = altered.len() / 3;
        altered[k] ^= 1;
        assert!(decode(&altered).unwrap_err().contains("checksum"));
        // A checkpoint of the layout before the bulk's sums is refused by its number.
        let mut older = bytes.clone();
        older[MAGIC.len() - 2] = b'6';
        let e = decode(&older).unwrap_err();
        assert!(e.contains("a checkpoint of layout 6") && e.contains("reads layout 7"), "{e}");
    }
}
