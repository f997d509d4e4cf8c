//! The checkpoint of `stripes events`: the engine's complete state ([`events::State`]), the
//! observer's sums, the energy at the start and where the sampling stands, in one file
//! (`checkpoint.bin`) written atomically. A run continued from it with `--resume` goes on
//! bit for bit as if it had not stopped.
//!
//! Layout (little-endian): the magic `STRIPES-EVENTS-CKPT-6\n`, the scene's fingerprint
//! (u64), then the payload, then an FNV-1a checksum (u64) of the payload. Vectors are a
//! u64 length followed by their items. A file cut short or altered fails its checksum and
//! is refused with the byte count, never half read.

use events::observe::{Observer, PhaseSums, Profile};
use events::phase_field::PhaseField;
use events::segregation::Mixing;
use events::sim::{Counts, Ledger};
use events::thinned::Thinned;
use events::{Next, State, Vec2};

const MAGIC: &[u8] = b"STRIPES-EVENTS-CKPT-6\n";

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

/// FNV-1a over bytes.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

#[derive(Default)]
struct Out(Vec<u8>);

impl Out {
    fn u(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn fs(&mut self, v: &[f64]) {
        self.u(v.len() as u64);
        v.iter().for_each(|&x| self.f(x));
    }
    fn us(&mut self, v: &[usize]) {
        self.u(v.len() as u64);
        v.iter().for_each(|&x| self.u(x as u64));
    }
    fn vecs(&mut self, v: &[Vec2]) {
        self.u(v.len() as u64);
        for p in v {
            self.f(p.x);
            self.f(p.y);
        }
    }
    fn next(&mut self, n: &Next) {
        // A tag and three slots.
        let (tag, a, b, c) = match *n {
            Next::Pair { j, count } => (0, j as u64, count, 0),
            Next::Wall { w } => (1, w as u64, 0, 0),
            Next::Tooth { tooth, piece } => (2, tooth as u64, piece as u64, 0),
            Next::Cell { to, wrap } => (3, to.0 as u64, to.1 as u64, wrap.to_bits()),
            Next::Look => (4, 0, 0, 0),
            Next::Nothing => (5, 0, 0, 0),
        };
        self.u(tag);
        self.u(a);
        self.u(b);
        self.u(c);
    }
}

struct In<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl In<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| format!("ends at byte {} where {n} more were expected", self.bytes.len()))?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8 bytes")))
    }
    fn f(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u()?))
    }
    /// A length, refused if the rest of the file cannot hold that many items of `size` bytes.
    fn len(&mut self, size: usize) -> Result<usize, String> {
        let n = self.u()?;
        let room = (self.bytes.len() - self.at) / size.max(1);
        if n > room as u64 {
            return Err(format!("claims {n} items at byte {} where at most {room} fit", self.at));
        }
        Ok(n as usize)
    }
    fn fs(&mut self) -> Result<Vec<f64>, String> {
        let n = self.len(8)?;
        (0..n).map(|_| self.f()).collect()
    }
    fn us(&mut self) -> Result<Vec<usize>, String> {
        let n = self.len(8)?;
        (0..n).map(|_| self.u().map(|x| x as usize)).collect()
    }
    fn vecs(&mut self) -> Result<Vec<Vec2>, String> {
        let n = self.len(16)?;
        (0..n).map(|_| Ok(Vec2::new(self.f()?, self.f()?))).collect()
    }
    fn next(&mut self) -> Result<Next, String> {
        let (tag, a, b, c) = (self.u()?, self.u()?, self.u()?, self.u()?);
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
            t => return Err(format!("unknown event tag {t} at byte {}", self.at - 32)),
        })
    }
}

/// The checkpoint's bytes.
pub fn encode(c: &Checkpoint) -> Vec<u8> {
    let mut o = Out::default();
    o.u(c.sample);
    o.u(c.frames);
    o.f(c.e0);
    let s = &c.state;
    o.f(s.time);
    o.vecs(&s.r);
    o.vecs(&s.v);
    o.fs(&s.w);
    o.fs(&s.t);
    o.fs(&s.radius);
    o.us(&s.species);
    o.u(s.cell.len() as u64);
    for &(x, z) in &s.cell {
        o.u(x as u64);
        o.u(z as u64);
    }
    o.u(s.collisions.len() as u64);
    s.collisions.iter().for_each(|&x| o.u(x));
    o.fs(&s.last_collision);
    o.u(s.next.len() as u64);
    s.next.iter().for_each(|n| o.next(n));
    o.u(s.beyond_cell.len() as u64);
    for (t, n) in &s.beyond_cell {
        o.f(*t);
        o.next(n);
    }
    o.u(s.window.len() as u64);
    for &(t, k) in &s.window {
        o.f(t);
        o.u(k as u64);
    }
    o.us(&s.last_partner);
    o.u(s.members.len() as u64);
    s.members.iter().for_each(|m| o.us(m));
    o.u(s.scheduled.len() as u64);
    for t in &s.scheduled {
        match t {
            Some(t) => {
                o.u(1);
                o.f(*t);
            }
            None => {
                o.u(0);
                o.f(0.0);
            }
        }
    }
    for x in [s.counts.pair, s.counts.wall, s.counts.cell, s.counts.stale] {
        o.u(x);
    }
    o.f(s.ledger.wall_work);
    o.f(s.ledger.dissipated);
    for t in &s.free_times {
        o.fs(&t.kept);
        o.u(t.stride);
        o.u(t.skipped);
    }
    let b = &c.observer;
    o.f(b.bin);
    o.u(b.bins as u64);
    o.u(b.across_bins as u64);
    for profiles in [&b.species, &b.across] {
        write_profiles(&mut o, profiles);
    }
    o.u(b.samples);
    o.f(b.height_sum);
    o.f(b.vx_sum);
    for lists in [&b.vx, &b.vz, &b.w, &b.z] {
        o.u(lists.len() as u64);
        lists.iter().for_each(|v| o.fs(v));
    }
    for x in [b.velocity_stride, b.velocity_skipped, b.velocity_samples] {
        o.u(x);
    }
    o.fs(&b.side.kept);
    o.u(b.side.stride);
    o.u(b.side.skipped);
    match &b.field {
        None => o.u(0),
        Some(f) => {
            o.u(1);
            o.u(f.frames as u64);
            o.f(f.tooth);
            o.u(f.across as u64);
            o.u(f.up as u64);
            o.f(f.teeth);
            for v in [&f.mass, &f.px, &f.pz] {
                o.fs(v);
            }
            o.us(&f.samples.iter().map(|&n| n as usize).collect::<Vec<_>>());
        }
    }
    match &b.mixing {
        None => o.u(0),
        Some(m) => {
            o.u(1);
            for v in [&m.neighbours, &m.same] {
                o.us(&v.iter().map(|&n| n as usize).collect::<Vec<_>>());
            }
            o.us(&m.count);
            o.u(m.samples);
        }
    }
    o.u(b.phases.len() as u64);
    for p in &b.phases {
        o.u(p.samples);
        o.f(p.com);
        o.f(p.k);
        o.f(p.r);
    }
    for per_phase in [&b.phase_heights, &b.phase_across] {
        o.u(per_phase.len() as u64);
        for profiles in per_phase {
            write_profiles(&mut o, profiles);
        }
    }
    let payload = o.0;
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&c.fingerprint.to_le_bytes());
    bytes.extend_from_slice(&payload);
    bytes.extend_from_slice(&fnv1a(&payload).to_le_bytes());
    bytes
}

/// A list of profiles: its length, then each profile's seven columns.
fn write_profiles(o: &mut Out, profiles: &[Profile]) {
    o.u(profiles.len() as u64);
    for p in profiles {
        for v in [&p.count, &p.mvx2, &p.mvz2, &p.iw2, &p.vx, &p.vz, &p.m] {
            o.fs(v);
        }
    }
}

/// The list [`write_profiles`] wrote.
fn read_profiles(i: &mut In<'_>) -> Result<Vec<Profile>, String> {
    let n = i.len(56)?;
    (0..n)
        .map(|_| {
            Ok(Profile {
                count: i.fs()?,
                mvx2: i.fs()?,
                mvz2: i.fs()?,
                iw2: i.fs()?,
                vx: i.fs()?,
                vz: i.fs()?,
                m: i.fs()?,
            })
        })
        .collect()
}

/// Reads a checkpoint; the error says what is wrong (not a checkpoint, cut short, altered).
pub fn decode(bytes: &[u8]) -> Result<Checkpoint, String> {
    if !bytes.starts_with(MAGIC) {
        return Err("not a checkpoint of `stripes events`".into());
    }
    let head = MAGIC.len() + 8;
    if bytes.len() < head + 8 {
        return Err(format!("cut short: {} bytes", bytes.len()));
    }
    let fingerprint = u64::from_le_bytes(bytes[MAGIC.len()..head].try_into().expect("8 bytes"));
    let (payload, sum) = bytes[head..].split_at(bytes.len() - head - 8);
    if fnv1a(payload).to_le_bytes() != sum {
        return Err(format!(
            "its checksum does not match ({} bytes): the file was cut short or altered",
            bytes.len()
        ));
    }
    let mut i = In { bytes: payload, at: 0 };
    let (sample, frames, e0) = (i.u()?, i.u()?, i.f()?);
    let time = i.f()?;
    let (r, v, w, t, radius) = (i.vecs()?, i.vecs()?, i.fs()?, i.fs()?, i.fs()?);
    let species = i.us()?;
    let n = i.len(16)?;
    let cell = (0..n)
        .map(|_| Ok((i.u()? as usize, i.u()? as usize)))
        .collect::<Result<_, String>>()?;
    let n = i.len(8)?;
    let collisions = (0..n).map(|_| i.u()).collect::<Result<_, _>>()?;
    let last_collision = i.fs()?;
    let n = i.len(32)?;
    let next = (0..n).map(|_| i.next()).collect::<Result<_, _>>()?;
    let n = i.len(40)?;
    let beyond_cell = (0..n).map(|_| Ok((i.f()?, i.next()?))).collect::<Result<_, String>>()?;
    let n = i.len(16)?;
    let window = (0..n).map(|_| Ok((i.f()?, i.u()? as u32))).collect::<Result<_, String>>()?;
    let last_partner = i.us()?;
    let n = i.len(8)?;
    let members = (0..n).map(|_| i.us()).collect::<Result<_, _>>()?;
    let n = i.len(16)?;
    let scheduled = (0..n)
        .map(|_| {
            let (flag, t) = (i.u()?, i.f()?);
            Ok((flag == 1).then_some(t))
        })
        .collect::<Result<_, String>>()?;
    let counts = Counts {
        pair: i.u()?,
        wall: i.u()?,
        cell: i.u()?,
        stale: i.u()?,
    };
    let ledger = Ledger {
        wall_work: i.f()?,
        dissipated: i.f()?,
    };
    let mut thinned = || -> Result<Thinned, String> {
        Ok(Thinned {
            kept: i.fs()?,
            stride: i.u()?,
            skipped: i.u()?,
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
    let (bin, bins, across_bins) = (i.f()?, i.u()? as usize, i.u()? as usize);
    let mut profiles = Vec::new();
    for _ in 0..2 {
        profiles.push(read_profiles(&mut i)?);
    }
    let across = profiles.pop().expect("two");
    let species = profiles.pop().expect("two");
    let (samples, height_sum, vx_sum) = (i.u()?, i.f()?, i.f()?);
    let mut lists = Vec::new();
    for _ in 0..4 {
        let n = i.len(8)?;
        lists.push((0..n).map(|_| i.fs()).collect::<Result<Vec<_>, _>>()?);
    }
    let z = lists.pop().expect("four");
    let ws = lists.pop().expect("four");
    let vz = lists.pop().expect("four");
    let vx = lists.pop().expect("four");
    let (velocity_stride, velocity_skipped, velocity_samples) = (i.u()?, i.u()?, i.u()?);
    let side = Thinned {
        kept: i.fs()?,
        stride: i.u()?,
        skipped: i.u()?,
    };
    let field = match i.u()? {
        0 => None,
        1 => {
            let (frames, tooth, across, up, teeth) = (i.u()? as usize, i.f()?, i.u()? as usize, i.u()? as usize, i.f()?);
            let (mass, px, pz) = (i.fs()?, i.fs()?, i.fs()?);
            let samples: Vec<u64> = i.us()?.into_iter().map(|n| n as u64).collect();
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
    let mixing = match i.u()? {
        0 => None,
        1 => {
            let neighbours: Vec<u64> = i.us()?.into_iter().map(|n| n as u64).collect();
            let same: Vec<u64> = i.us()?.into_iter().map(|n| n as u64).collect();
            let count = i.us()?;
            if neighbours.len() != count.len() || same.len() != count.len() {
                return Err("the neighbour record does not have the species it claims".into());
            }
            Some(Mixing {
                neighbours,
                same,
                count,
                samples: i.u()?,
            })
        }
        other => return Err(format!("unknown neighbour-record flag {other}")),
    };
    let n = i.len(32)?;
    let mut phases = Vec::with_capacity(n);
    for _ in 0..n {
        phases.push(PhaseSums {
            samples: i.u()?,
            com: i.f()?,
            k: i.f()?,
            r: i.f()?,
        });
    }
    let mut per_phase = Vec::new();
    for _ in 0..2 {
        let n = i.len(8)?;
        let mut phase = Vec::with_capacity(n);
        for _ in 0..n {
            phase.push(read_profiles(&mut i)?);
        }
        per_phase.push(phase);
    }
    let phase_across = per_phase.pop().expect("two");
    let phase_heights = per_phase.pop().expect("two");
    if phases.is_empty()
        || [&phase_heights, &phase_across]
            .iter()
            .any(|p| !p.is_empty() && p.len() != phases.len())
    {
        return Err("the phase records do not have the phases they claim".into());
    }
    if i.at != payload.len() {
        return Err(format!("{} bytes left over after the checkpoint", payload.len() - i.at));
    }
    if species.iter().any(|p| p.count.len() != bins) || across.iter().any(|p| p.count.len() != across_bins) {
        return Err("the profiles do not have the bins they claim".into());
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
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small_run() -> Checkpoint {
        let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ratchet.toml"));
        let scene = crate::scene::events::load(path, &["run.duration=0.5".into(), "run.transient=0".into()]).unwrap();
        let mut sim = events::Simulation::new(scene.config().unwrap()).unwrap();
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
    }
}
