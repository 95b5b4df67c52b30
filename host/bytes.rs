//! Little-endian fields of vkrt's own binary files: the path tracer's checkpoints
//! (`integrator::path::checkpoint`) and the prepared-scene cache's metadata (`prepare::cache`).
//! One writer and one reader, so that both formats read a field the same way: a read that runs
//! past the end names the field and the byte where it stopped, and a count is checked against
//! the bytes left before anything is allocated for it (a damaged file is an error, never a huge
//! allocation). What the fields mean stays with each format.

use anyhow::{bail, Context as _, Result};

/// Appends little-endian fields to a byte vector.
#[derive(Debug, Default)]
pub struct ByteWriter(Vec<u8>);

impl ByteWriter {
    pub fn with_capacity(bytes: usize) -> Self {
        Self(Vec::with_capacity(bytes))
    }
    /// Bytes as they are, no length.
    pub fn raw(&mut self, b: &[u8]) {
        self.0.extend_from_slice(b);
    }
    pub fn u32(&mut self, v: u32) {
        self.raw(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.raw(&v.to_le_bytes());
    }
    pub fn f32(&mut self, v: f32) {
        self.raw(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.raw(&v.to_le_bytes());
    }
    /// A string as its length in a u32, then its UTF-8 (checkpoints).
    pub fn str_u32(&mut self, s: &str) {
        self.u32(s.len() as u32);
        self.raw(s.as_bytes());
    }
    /// Bytes as their length in a u64, then the bytes (cache metadata).
    pub fn bytes_u64(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.raw(b);
    }
    pub fn into_inner(self) -> Vec<u8> {
        self.0
    }
}

/// Reads little-endian fields from a byte slice.
#[derive(Debug)]
pub struct ByteReader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> ByteReader<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }
    /// Bytes read so far.
    pub fn position(&self) -> usize {
        self.pos
    }
    /// Bytes left.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
    /// The next `n` bytes of `field`.
    pub fn take(&mut self, n: usize, field: &str) -> Result<&'a [u8]> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.data.len());
        let Some(end) = end else { bail!("truncated at field `{field}` (byte {})", self.pos) };
        let s = &self.data[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn array<const N: usize>(&mut self, field: &str) -> Result<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N, field)?);
        Ok(a)
    }
    pub fn u32(&mut self, field: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(field)?))
    }
    pub fn u64(&mut self, field: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.array(field)?))
    }
    pub fn f32(&mut self, field: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(field)?))
    }
    pub fn f64(&mut self, field: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(field)?))
    }
    /// A string written by [`ByteWriter::str_u32`].
    pub fn str_u32(&mut self, field: &str) -> Result<String> {
        let n = self.u32(field)? as usize;
        String::from_utf8(self.take(n, field)?.to_vec()).with_context(|| format!("field `{field}` is not UTF-8"))
    }
    /// A u64 count of things of at least `min_bytes` each, no more than the bytes left can hold.
    pub fn count_u64(&mut self, min_bytes: usize, field: &str) -> Result<usize> {
        let n = self.u64(field)?;
        let left = self.remaining();
        if n > (left / min_bytes.max(1)) as u64 {
            bail!("field `{field}` is {n}, more than the {left} bytes left can hold");
        }
        Ok(n as usize)
    }
    /// Bytes written by [`ByteWriter::bytes_u64`].
    pub fn bytes_u64(&mut self, field: &str) -> Result<&'a [u8]> {
        let n = self.count_u64(1, field)?;
        self.take(n, field)
    }
    /// A string written as [`ByteWriter::bytes_u64`] of its UTF-8.
    pub fn str_u64(&mut self, field: &str) -> Result<String> {
        Ok(std::str::from_utf8(self.bytes_u64(field)?).with_context(|| format!("field `{field}` is not UTF-8"))?.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_round_trip_and_a_cut_names_the_field() {
        let mut w = ByteWriter::default();
        w.u32(7);
        w.u64(u64::MAX);
        w.f32(-0.5);
        w.f64(1e300);
        w.str_u32("ü");
        w.bytes_u64(b"abc");
        let bytes = w.into_inner();
        let mut r = ByteReader::new(&bytes);
        assert_eq!(r.u32("a").unwrap(), 7);
        assert_eq!(r.u64("b").unwrap(), u64::MAX);
        assert_eq!(r.f32("c").unwrap(), -0.5);
        assert_eq!(r.f64("d").unwrap(), 1e300);
        assert_eq!(r.str_u32("e").unwrap(), "ü");
        assert_eq!(r.str_u64("f").unwrap(), "abc");
        assert_eq!(r.remaining(), 0);
        let e = ByteReader::new(&bytes[..2]).u32("width").unwrap_err().to_string();
        assert_eq!(e, "truncated at field `width` (byte 0)");
        // A count the bytes left cannot hold is refused before any allocation.
        let mut huge = ByteWriter::default();
        huge.u64(1 << 40);
        let e = ByteReader::new(&huge.into_inner()).count_u64(8, "inputs").unwrap_err().to_string();
        assert!(e.contains("field `inputs` is 1099511627776"), "{e}");
    }
}
