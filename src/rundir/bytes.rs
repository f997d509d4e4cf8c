//! Little-endian byte writing and reading for the root crate's binary files (DEM checkpoints,
//! prepared samples). Every read checks the length, and a record count read from a file is
//! checked against the bytes left before anything is sized by it.

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
}
