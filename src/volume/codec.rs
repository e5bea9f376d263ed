//! Decoders for OpenVDB's compressed data chunks: ZIP (zlib, via flate2) and
//! BLOSC. BLOSC is decoded here in safe Rust (the blosc1 frame, byte
//! unshuffle and the LZ4 block format) rather than through the C library
//! that vdb-rs links: the C decoder trusts offsets inside the frame, and a
//! damaged file must give an error, never a crash.

use super::bytes::Reader;
use super::error::{FResult, FormatError};

/// OpenVDB per-grid compression flag: zlib.
pub(crate) const COMPRESS_ZIP: u32 = 0x1;
/// OpenVDB per-grid compression flag: inactive values omitted.
pub(crate) const COMPRESS_ACTIVE_MASK: u32 = 0x2;
/// OpenVDB per-grid compression flag: blosc.
pub(crate) const COMPRESS_BLOSC: u32 = 0x4;

/// Reads one `readData` chunk of exactly `out.len()` bytes, compressed as the
/// grid's flags say. Each compressed chunk starts with an i64 byte count; a
/// negative count means the bytes follow uncompressed.
pub(crate) fn read_chunk(r: &mut Reader, compression: u32, out: &mut [u8]) -> FResult<()> {
    if compression & (COMPRESS_BLOSC | COMPRESS_ZIP) == 0 {
        out.copy_from_slice(r.take(out.len())?);
        return Ok(());
    }
    let at = r.pos();
    let n = r.i64()?;
    if n <= 0 {
        let raw = n.unsigned_abs();
        if raw != out.len() as u64 {
            return Err(FormatError::corrupt(
                at,
                format!("expected a {}-byte chunk, the file says {raw}", out.len()),
            ));
        }
        out.copy_from_slice(r.take(out.len())?);
        return Ok(());
    }
    if n as u64 > r.remaining() as u64 {
        return Err(FormatError::corrupt(
            at,
            format!(
                "compressed chunk of {n} bytes runs past the end of the file ({} left)",
                r.remaining()
            ),
        ));
    }
    let src = r.take(n as usize)?;
    let result = if compression & COMPRESS_BLOSC != 0 {
        blosc_decompress(src, out)
    } else {
        zlib_decompress(src, out)
    };
    result.map_err(|e| FormatError::corrupt(at, e))
}

/// Inflates a zlib stream into exactly `out.len()` bytes.
fn zlib_decompress(src: &[u8], out: &mut [u8]) -> Result<(), String> {
    let mut z = flate2::Decompress::new(true);
    let status = z
        .decompress(src, out, flate2::FlushDecompress::Finish)
        .map_err(|e| format!("zlib: {e}"))?;
    if z.total_out() as usize != out.len() || status != flate2::Status::StreamEnd {
        return Err(format!(
            "zlib chunk inflates to {} bytes (stream {}), expected {}",
            z.total_out(),
            if status == flate2::Status::StreamEnd {
                "complete"
            } else {
                "incomplete"
            },
            out.len()
        ));
    }
    Ok(())
}

fn le32(b: &[u8], at: usize) -> Result<u32, String> {
    b.get(at..at + 4)
        .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .ok_or_else(|| format!("blosc frame truncated at offset {at}"))
}

/// Size of a blosc1 frame's header.
const BLOSC_HEADER: usize = 16;

/// Decodes a blosc1 frame into exactly `out.len()` bytes.
fn blosc_decompress(src: &[u8], out: &mut [u8]) -> Result<(), String> {
    let Some((frame, src)) = BloscFrame::parse(src, out.len())? else {
        return Ok(());
    };
    if frame.flags & 0x2 != 0 {
        // memcpyed: the data follows the header as is.
        let body = src
            .get(BLOSC_HEADER..BLOSC_HEADER + frame.nbytes)
            .ok_or("blosc memcpy frame truncated")?;
        out.copy_from_slice(body);
        return Ok(());
    }
    if frame.blocksize == 0 {
        return Err("blosc block size is zero".into());
    }
    if frame.flags & 0x4 != 0 {
        return Err("blosc bit-shuffle is not supported".into());
    }
    let shuffle = frame.flags & 0x1 != 0 && frame.typesize > 1;
    let (nbytes, blocksize) = (frame.nbytes, frame.blocksize);
    let mut tmp = vec![0u8; blocksize.min(nbytes)];
    for j in 0..nbytes.div_ceil(blocksize) {
        let start = j * blocksize;
        let bsize = blocksize.min(nbytes - start);
        let dest: &mut [u8] = if shuffle {
            &mut tmp[..bsize]
        } else {
            &mut out[start..start + bsize]
        };
        frame.decode_block(src, j, dest)?;
        if shuffle {
            unshuffle(
                frame.typesize,
                &tmp[..bsize],
                &mut out[start..start + bsize],
            );
        }
    }
    Ok(())
}

/// The fields of a blosc1 header that decoding needs.
struct BloscFrame {
    flags: u8,
    typesize: usize,
    nbytes: usize,
    blocksize: usize,
}

impl BloscFrame {
    /// Reads the header of a frame that must decode to `expected` bytes; returns
    /// it with the frame cut to its compressed size, or None for an empty frame.
    fn parse(src: &[u8], expected: usize) -> Result<Option<(BloscFrame, &[u8])>, String> {
        if src.len() < BLOSC_HEADER {
            return Err("blosc frame shorter than its header".into());
        }
        let nbytes = le32(src, 4)? as usize;
        let cbytes = le32(src, 12)? as usize;
        if nbytes != expected {
            return Err(format!(
                "blosc frame holds {nbytes} bytes, expected {expected}"
            ));
        }
        if cbytes > src.len() {
            return Err(format!(
                "blosc frame claims {cbytes} bytes, chunk has {}",
                src.len()
            ));
        }
        if nbytes == 0 {
            return Ok(None);
        }
        let frame = BloscFrame {
            flags: src[2],
            typesize: src[3].max(1) as usize,
            nbytes,
            blocksize: le32(src, 8)? as usize,
        };
        Ok(Some((frame, &src[..cbytes])))
    }

    /// Decodes block `j` (its splits, each stored or compressed) into `dest`, the block's bytes.
    fn decode_block(&self, src: &[u8], j: usize, dest: &mut [u8]) -> Result<(), String> {
        let bsize = dest.len();
        let leftover = bsize < self.blocksize;
        let dont_split = self.flags & 0x10 != 0;
        let typesize = self.typesize;
        let nsplits = if !dont_split && typesize <= 16 && bsize / typesize >= 128 && !leftover {
            typesize
        } else {
            1
        };
        let neblock = bsize / nsplits;
        let mut off = le32(src, BLOSC_HEADER + 4 * j)? as usize;
        for s in 0..nsplits {
            let cb = le32(src, off)? as usize;
            off += 4;
            let chunk = src
                .get(off..off.saturating_add(cb))
                .ok_or("blosc split runs past the frame")?;
            let d = &mut dest[s * neblock..(s + 1) * neblock];
            if cb == neblock {
                d.copy_from_slice(chunk);
            } else {
                match self.flags >> 5 {
                    1 => lz4_block_decompress(chunk, d)?,
                    3 => zlib_decompress(chunk, d)?,
                    c => {
                        return Err(format!(
                            "blosc codec {c} is not supported (lz4 and zlib are)"
                        ))
                    }
                }
            }
            off += cb;
        }
        Ok(())
    }
}

/// Undoes blosc's byte shuffle: byte `j` of element `i` was stored at `j * n + i`.
fn unshuffle(typesize: usize, src: &[u8], dest: &mut [u8]) {
    let n = src.len() / typesize;
    for i in 0..n {
        for j in 0..typesize {
            dest[i * typesize + j] = src[j * n + i];
        }
    }
    let rem = n * typesize;
    dest[rem..].copy_from_slice(&src[rem..]);
}

/// Decodes one LZ4 block into exactly `out.len()` bytes.
fn lz4_block_decompress(src: &[u8], out: &mut [u8]) -> Result<(), String> {
    let bad = || "lz4 block is damaged".to_string();
    let (mut i, mut o) = (0usize, 0usize);
    let read_len = |i: &mut usize, mut len: usize| -> Result<usize, String> {
        if len == 15 {
            loop {
                let b = *src.get(*i).ok_or_else(bad)?;
                *i += 1;
                len += b as usize;
                if b != 255 {
                    break;
                }
            }
        }
        Ok(len)
    };
    loop {
        let token = *src.get(i).ok_or_else(bad)?;
        i += 1;
        let lit = read_len(&mut i, (token >> 4) as usize)?;
        let s = src.get(i..i.saturating_add(lit)).ok_or_else(bad)?;
        out.get_mut(o..o.saturating_add(lit))
            .ok_or_else(bad)?
            .copy_from_slice(s);
        i += lit;
        o += lit;
        if i == src.len() {
            break;
        }
        let lo = *src.get(i).ok_or_else(bad)? as usize;
        let hi = *src.get(i + 1).ok_or_else(bad)? as usize;
        i += 2;
        let offset = lo | (hi << 8);
        if offset == 0 || offset > o {
            return Err(bad());
        }
        let mlen = read_len(&mut i, (token & 15) as usize)? + 4;
        if mlen > out.len() - o {
            return Err(bad());
        }
        for k in 0..mlen {
            out[o + k] = out[o + k - offset];
        }
        o += mlen;
    }
    if o != out.len() {
        return Err(format!(
            "lz4 block inflates to {o} bytes, expected {}",
            out.len()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn zip_chunk_round_trip() {
        let data: Vec<u8> = (0..400u32).map(|i| (i % 7) as u8).collect();
        let mut enc = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
        enc.write_all(&data).unwrap();
        let z = enc.finish().unwrap();
        let mut file = (z.len() as i64).to_le_bytes().to_vec();
        file.extend_from_slice(&z);
        let mut out = vec![0u8; 400];
        read_chunk(&mut Reader::at(&file, 0).unwrap(), COMPRESS_ZIP, &mut out).unwrap();
        assert_eq!(out, data);
        let mut short = vec![0u8; 399];
        assert!(read_chunk(&mut Reader::at(&file, 0).unwrap(), COMPRESS_ZIP, &mut short).is_err());
    }

    #[test]
    fn lz4_overlapping_match() {
        // literals "ab", then a 6-byte match at offset 2, then an empty last sequence
        let src = [0x22, b'a', b'b', 0x02, 0x00, 0x00];
        let mut out = [0u8; 8];
        lz4_block_decompress(&src, &mut out).unwrap();
        assert_eq!(&out, b"abababab");
        let mut short = [0u8; 7];
        assert!(lz4_block_decompress(&src, &mut short).is_err());
        assert!(lz4_block_decompress(&[0x22, b'a', b'b', 0x09, 0x00, 0x00], &mut out).is_err());
    }

    #[test]
    fn negative_size_means_raw_bytes() {
        let mut file = (-4i64).to_le_bytes().to_vec();
        file.extend_from_slice(&[1, 2, 3, 4]);
        let mut out = [0u8; 4];
        read_chunk(&mut Reader::at(&file, 0).unwrap(), COMPRESS_BLOSC, &mut out).unwrap();
        assert_eq!(out, [1, 2, 3, 4]);
    }
}
