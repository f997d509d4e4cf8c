//! The one byte codec of the root crate's binary files (DEM and event-driven checkpoints,
//! prepared samples): little-endian writing and reading, and a checksum trailer. Every read
//! checks the length, a record count read from a file is checked against the bytes left
//! before anything is sized by it, and a sealed file whose bytes were cut or altered is
//! refused before it is parsed.

use particles::Vec3;

/// Little-endian writer.
#[derive(Default)]
pub struct Writer(pub Vec<u8>);

impl Writer {
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u32(&mut self, v: u32) {
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
    /// A list of numbers: its length, then each.
    pub fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|&x| self.f64(x));
    }
    /// A list of indices: its length, then each as a `u64`.
    pub fn usizes(&mut self, v: &[usize]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|&x| self.u64(x as u64));
    }
}

/// FNV-1a of the bytes: the checksum of sealed files (the one implementation, the state
/// hash's).
pub use particles::measure::fnv1a;

/// Seals a file: appends the FNV-1a of `bytes[from..]` (the part after a header that is
/// read apart) as its last 8 bytes.
pub fn seal(bytes: &mut Vec<u8>, from: usize) {
    let sum = fnv1a(&bytes[from..]);
    bytes.extend_from_slice(&sum.to_le_bytes());
}

/// The bytes of a sealed file without the trailer, once the checksum of `bytes[from..]`
/// matches; an error says that the file was cut short or altered.
pub fn unseal(bytes: &[u8], from: usize) -> Result<&[u8], String> {
    if bytes.len() < from + 8 {
        return Err(format!("cut short: {} bytes", bytes.len()));
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    if fnv1a(&body[from..]).to_le_bytes() != sum {
        return Err(format!(
            "its checksum does not match ({} bytes): the file was cut short or altered",
            bytes.len()
        ));
    }
    Ok(body)
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
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let len = self.bytes.len();
        let end = self.at.checked_add(n).filter(|&e| e <= len).ok_or_else(|| {
            format!(
                "truncated file: it ends at byte {len}, inside a field of {n} bytes that starts at byte {}",
                self.at
            )
        })?;
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
    /// Where the reader stands, in bytes from the start.
    pub fn at(&self) -> usize {
        self.at
    }
    /// The bytes not read yet.
    pub fn left(&self) -> usize {
        self.bytes.len() - self.at
    }
    /// A list [`Writer::f64s`] wrote.
    pub fn f64s(&mut self) -> Result<Vec<f64>, String> {
        let n = self.count(8, "numbers")?;
        (0..n).map(|_| self.f64()).collect()
    }
    /// A list [`Writer::usizes`] wrote.
    pub fn usizes(&mut self) -> Result<Vec<usize>, String> {
        let n = self.count(8, "indices")?;
        (0..n).map(|_| self.u64().map(|x| x as usize)).collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cut_file_names_where_it_ends_and_what_was_being_read() {
        let mut w = Writer::default();
        w.u64(7);
        w.f64(1.5);
        let mut bytes = w.0;
        bytes.truncate(12);
        let mut r = Reader::new(&bytes);
        assert_eq!(r.u64(), Ok(7));
        assert_eq!(
            r.f64(),
            Err("truncated file: it ends at byte 12, inside a field of 8 bytes that starts at byte 8".to_string())
        );
    }

    /// Every checkpoint and sample is sealed: the bytes read back as written, and a file cut
    /// anywhere or with any bit flipped after its header is refused before it is parsed.
    #[test]
    fn a_sealed_file_reads_back_and_a_cut_or_flipped_one_is_refused() {
        let mut w = Writer::default();
        w.0.extend_from_slice(b"HEAD");
        w.f64s(&[1.0, -2.5, f64::MIN_POSITIVE]);
        w.usizes(&[3, 0, usize::MAX >> 1]);
        let mut bytes = w.0.clone();
        seal(&mut bytes, 4);
        let body = unseal(&bytes, 4).unwrap();
        assert_eq!(body, &w.0[..]);
        let mut r = Reader::new(&body[4..]);
        assert_eq!(r.f64s().unwrap(), vec![1.0, -2.5, f64::MIN_POSITIVE]);
        assert_eq!(r.usizes().unwrap(), vec![3, 0, usize::MAX >> 1]);
        for cut in 0..bytes.len() {
            assert!(unseal(&bytes[..cut], 4).is_err(), "cut at {cut} accepted");
        }
        for byte in 4..bytes.len() {
            for bit in 0..8 {
                let mut flipped = bytes.clone();
                flipped[byte] ^= 1 << bit;
                assert!(unseal(&flipped, 4).is_err(), "bit {bit} of byte {byte} flipped and accepted");
            }
        }
    }
}
