//! Checkpoints: the complete dynamic state of a [`Simulation`] in a small binary format, so a
//! resumed run continues bit for bit as if it had never stopped.
//!
//! Layout (little endian): magic `STRPCKP1`, `u64` scene fingerprint, `f64` time, `u64` steps,
//! ledger (`f64` injected, dissipated), `f64` stored energy, `u64` N, then per particle
//! position, velocity, spin, half-step velocity, half-step spin, force, torque (7 x 3 `f64`),
//! then the live pair histories (`u64` count, then `u32 i, u32 j, 3 f64`), then the wall
//! histories (`u64` count, then `3 f64` each), then `u64` caller data (e.g. snapshots written).

use crate::sim::Simulation;
use crate::Vec3;

const MAGIC: &[u8; 8] = b"STRPCKP1";

/// Little-endian writer.
#[derive(Default)]
pub struct Writer(pub Vec<u8>);

impl Writer {
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_bits().to_le_bytes());
    }
    pub fn vec3(&mut self, v: &Vec3) {
        for c in v.iter() {
            self.f64(*c);
        }
    }
}

/// Little-endian reader; every read checks the length.
pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len()).ok_or("truncated file")?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    pub fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8 bytes")))
    }
    pub fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4 bytes")))
    }
    pub fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub fn vec3(&mut self) -> Result<Vec3, String> {
        Ok(Vec3::new(self.f64()?, self.f64()?, self.f64()?))
    }
    /// A record count read from the file, checked against the bytes left: `count` records of
    /// `record` bytes each must fit, so nothing is sized beyond the input.
    pub fn count(&mut self, record: usize, what: &str) -> Result<usize, String> {
        let n = self.u64()?;
        let left = (self.bytes.len() - self.at) / record.max(1);
        if n > left as u64 {
            return Err(format!("truncated file: it claims {n} {what} but holds bytes for at most {left}"));
        }
        Ok(n as usize)
    }
}

impl Simulation {
    /// Serialises the dynamic state; `fingerprint` identifies the scene (checked on restore)
    /// and `extra` is caller data stored alongside (e.g. the number of snapshots written).
    pub fn checkpoint(&self, fingerprint: u64, extra: u64) -> Vec<u8> {
        let mut w = Writer::default();
        w.0.extend_from_slice(MAGIC);
        w.u64(fingerprint);
        w.f64(self.time);
        w.u64(self.steps);
        w.f64(self.ledger.injected);
        w.f64(self.ledger.dissipated);
        w.f64(self.stored_energy);
        let s = &self.state;
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
        let pairs = self.pair_histories();
        w.u64(pairs.len() as u64);
        for (i, j, h) in pairs {
            w.0.extend_from_slice(&(i as u32).to_le_bytes());
            w.0.extend_from_slice(&(j as u32).to_le_bytes());
            w.vec3(&h);
        }
        let walls = self.wall_histories();
        w.u64(walls.len() as u64);
        for h in walls {
            w.vec3(h);
        }
        w.u64(extra);
        w.0
    }

    /// Restores a checkpoint written by [`Self::checkpoint`] into a simulation built from the
    /// same scene and sample; returns the caller data.
    pub fn restore(&mut self, bytes: &[u8], fingerprint: u64) -> Result<u64, String> {
        let mut r = Reader::new(bytes);
        if r.take(8)? != MAGIC {
            return Err("not a stripes checkpoint".into());
        }
        if r.u64()? != fingerprint {
            return Err("the checkpoint belongs to a different scene (a key or the sample changed)".into());
        }
        self.time = r.f64()?;
        self.steps = r.u64()?;
        self.ledger.injected = r.f64()?;
        self.ledger.dissipated = r.f64()?;
        self.stored_energy = r.f64()?;
        let n = r.u64()? as usize;
        if n != self.state.len() {
            return Err(format!("the checkpoint has {n} particles, the scene {}", self.state.len()));
        }
        let s = &mut self.state;
        for i in 0..n {
            s.pos[i] = r.vec3()?;
            s.vel[i] = r.vec3()?;
            s.omega[i] = r.vec3()?;
            s.vel_half[i] = r.vec3()?;
            s.omega_half[i] = r.vec3()?;
            s.force[i] = r.vec3()?;
            s.torque[i] = r.vec3()?;
        }
        let count = r.count(4 + 4 + 24, "pair histories")?;
        let mut pairs = Vec::with_capacity(count);
        for _ in 0..count {
            pairs.push((r.u32()? as usize, r.u32()? as usize, r.vec3()?));
        }
        let count = r.count(24, "wall histories")?;
        let mut walls = Vec::with_capacity(count);
        for _ in 0..count {
            walls.push(r.vec3()?);
        }
        let extra = r.u64()?;
        self.set_histories(&pairs, walls)?;
        Ok(extra)
    }
}
