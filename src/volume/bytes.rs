//! A bounds-checked little-endian reader over the bytes of a file: every
//! length read from the file is checked against what is left before anything
//! is allocated, so damaged files give errors instead of aborts.

use super::error::{FResult, FormatError};

/// A cursor over a byte slice; all reads fail cleanly past the end.
pub(crate) struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// A reader at offset `pos` of `data` (fails if `pos` is past the end).
    pub(crate) fn at(data: &'a [u8], pos: u64) -> FResult<Self> {
        let mut r = Reader { data, pos: 0 };
        r.seek(pos)?;
        Ok(r)
    }

    /// Current offset from the start of the file.
    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    /// Bytes left after the cursor.
    pub(crate) fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// Moves to an absolute offset inside the data.
    pub(crate) fn seek(&mut self, pos: u64) -> FResult<()> {
        match usize::try_from(pos) {
            Ok(p) if p <= self.data.len() => {
                self.pos = p;
                Ok(())
            }
            _ => Err(FormatError::corrupt(
                self.pos,
                format!(
                    "offset {pos} is past the end of the file ({} bytes)",
                    self.data.len()
                ),
            )),
        }
    }

    /// Takes the next `n` bytes.
    pub(crate) fn take(&mut self, n: usize) -> FResult<&'a [u8]> {
        if n > self.remaining() {
            return Err(FormatError::corrupt(
                self.pos,
                format!(
                    "truncated: need {n} bytes, only {} left in the file",
                    self.remaining()
                ),
            ));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// Fails unless `count` items of at least `min_item_bytes` each can still fit.
    pub(crate) fn check_fits(&self, count: u64, min_item_bytes: u64, what: &str) -> FResult<()> {
        let need = count.saturating_mul(min_item_bytes);
        if need > self.remaining() as u64 {
            return Err(FormatError::corrupt(
                self.pos,
                format!(
                    "{what}: {count} entries need at least {need} bytes, only {} left",
                    self.remaining()
                ),
            ));
        }
        Ok(())
    }

    fn array<const N: usize>(&mut self) -> FResult<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    /// One byte.
    pub(crate) fn u8(&mut self) -> FResult<u8> {
        Ok(self.take(1)?[0])
    }

    /// Little-endian u32.
    pub(crate) fn u32(&mut self) -> FResult<u32> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    /// Little-endian i32.
    pub(crate) fn i32(&mut self) -> FResult<i32> {
        Ok(i32::from_le_bytes(self.array()?))
    }

    /// Little-endian i64.
    pub(crate) fn i64(&mut self) -> FResult<i64> {
        Ok(i64::from_le_bytes(self.array()?))
    }

    /// Little-endian u64.
    pub(crate) fn u64(&mut self) -> FResult<u64> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    /// Little-endian f32.
    pub(crate) fn f32(&mut self) -> FResult<f32> {
        Ok(f32::from_le_bytes(self.array()?))
    }

    /// Little-endian f64.
    pub(crate) fn f64(&mut self) -> FResult<f64> {
        Ok(f64::from_le_bytes(self.array()?))
    }

    /// Three little-endian f64.
    pub(crate) fn vec3d(&mut self) -> FResult<[f64; 3]> {
        Ok([self.f64()?, self.f64()?, self.f64()?])
    }

    /// An OpenVDB string: u32 length then bytes (not NUL terminated).
    pub(crate) fn string(&mut self) -> FResult<String> {
        let at = self.pos;
        let n = self.u32()? as usize;
        let bytes = self.take(n).map_err(|_| {
            FormatError::corrupt(
                at,
                format!("string length {n} runs past the end of the file"),
            )
        })?;
        Ok(String::from_utf8_lossy(bytes).into_owned())
    }

    /// A bit mask of `words` u64 words.
    pub(crate) fn mask(&mut self, out: &mut [u64]) -> FResult<()> {
        let bytes = self.take(out.len() * 8)?;
        for (w, chunk) in out.iter_mut().zip(bytes.chunks_exact(8)) {
            let mut a = [0u8; 8];
            a.copy_from_slice(chunk);
            *w = u64::from_le_bytes(a);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_past_end_fail_cleanly() {
        let data = [1u8, 0, 0, 0, 5];
        let mut r = Reader::at(&data, 0).unwrap();
        assert_eq!(r.u32().unwrap(), 1);
        assert!(r.u32().is_err());
        assert_eq!(r.u8().unwrap(), 5);
        assert!(r.u8().is_err());
        assert!(Reader::at(&data, 6).is_err());
    }

    #[test]
    fn huge_string_length_is_an_error() {
        let data = [0xff, 0xff, 0xff, 0xff, b'a'];
        let mut r = Reader::at(&data, 0).unwrap();
        assert!(r.string().is_err());
    }
}
