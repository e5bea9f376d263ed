//! The `.slab` file: a 64-byte versioned header, then every record as six
//! little-endian half floats (radiance r, g, b, transmittance r, g, b).
//! docs/slab-format.md documents it byte by byte.

use super::param::{Grid, Param};
use crate::math::color::Rgb;
use crate::math::{Bounds3, Vec3};
use half::f16;
use std::io::{Read, Write};
use std::path::Path;

/// The first eight bytes of every slab file.
pub const MAGIC: [u8; 8] = *b"BRUMESLB";
/// The format version this build writes and reads.
pub const VERSION: u32 = 1;
/// Bytes before the records.
pub const HEADER_BYTES: usize = 64;
/// Bytes per record: six half floats.
pub const RECORD_BYTES: u64 = 12;
/// Largest nodes per axis a file may declare (a grid beyond is a damaged header).
pub const MAX_NODES: u32 = 4096;

/// What the header says: the box, the grid and how it was baked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabHeader {
    /// The box whose leaving light is recorded, in the baking scene's space.
    pub bounds: Bounds3,
    /// Nodes per axis.
    pub grid: Grid,
    /// Samples per recorded line.
    pub spp: u32,
    /// Seed of the bake's random streams.
    pub seed: u64,
}

impl SlabHeader {
    /// Bytes of the whole file.
    pub fn file_bytes(&self) -> u64 {
        HEADER_BYTES as u64 + self.grid.records() * RECORD_BYTES
    }

    fn encode(&self) -> [u8; HEADER_BYTES] {
        let mut h = [0u8; HEADER_BYTES];
        h[0..8].copy_from_slice(&MAGIC);
        h[8..12].copy_from_slice(&VERSION.to_le_bytes());
        h[12..16].copy_from_slice(&(HEADER_BYTES as u32).to_le_bytes());
        h[16..20].copy_from_slice(&self.grid.spatial.to_le_bytes());
        h[20..24].copy_from_slice(&self.grid.angular.to_le_bytes());
        let corners = self.bounds.min.to_array().into_iter();
        for (k, v) in corners.chain(self.bounds.max.to_array()).enumerate() {
            h[24 + 4 * k..28 + 4 * k].copy_from_slice(&v.to_le_bytes());
        }
        h[48..52].copy_from_slice(&self.spp.to_le_bytes());
        h[52..60].copy_from_slice(&self.seed.to_le_bytes());
        h
    }

    /// The header in `h`, or what is wrong with it in words.
    fn decode(h: &[u8; HEADER_BYTES]) -> Result<SlabHeader, String> {
        if h[0..8] != MAGIC {
            return Err("is not a brume slab file (it does not start with BRUMESLB)".into());
        }
        let u32_at = |i: usize| u32::from_le_bytes(h[i..i + 4].try_into().unwrap());
        let f32_at = |i: usize| f32::from_le_bytes(h[i..i + 4].try_into().unwrap());
        let version = u32_at(8);
        if version != VERSION {
            return Err(format!(
                "is a slab file of format version {version}; this brume reads version {VERSION}: bake it again"
            ));
        }
        if u32_at(12) as usize != HEADER_BYTES {
            return Err(format!(
                "has a header of {} bytes, not {HEADER_BYTES}",
                u32_at(12)
            ));
        }
        let grid = Grid {
            spatial: u32_at(16),
            angular: u32_at(20),
        };
        for (name, n) in [("spatial", grid.spatial), ("angular", grid.angular)] {
            if !(2..=MAX_NODES).contains(&n) {
                return Err(format!(
                    "declares {n} {name} nodes per axis (a slab has 2 to {MAX_NODES}): the header is damaged"
                ));
            }
        }
        let min = Vec3::new(f32_at(24), f32_at(28), f32_at(32));
        let max = Vec3::new(f32_at(36), f32_at(40), f32_at(44));
        if !(min.is_finite() && max.is_finite() && min.cmplt(max).all()) {
            return Err(format!(
                "declares the box {min} to {max}, which is not a box: the header is damaged"
            ));
        }
        Ok(SlabHeader {
            bounds: Bounds3::new(min, max),
            grid,
            spp: u32_at(48),
            seed: u64::from_le_bytes(h[52..60].try_into().unwrap()),
        })
    }
}

/// A baked slab: its header and the file's bytes, records decoded at lookup.
///
/// The bytes are kept as the file holds them (header, then little-endian
/// halves): reading a slab is one read with no decode pass, and the same
/// bytes feed the scene hash (`file_bytes`) without a second read.
#[derive(Debug)]
pub struct LightSlab {
    header: SlabHeader,
    param: Param,
    /// The whole file: the header, then six halves per record (radiance rgb,
    /// transmittance rgb), in record order.
    bytes: Vec<u8>,
}

impl LightSlab {
    /// A slab of `header` with every record filled by `record(index)`
    /// (radiance, transmittance); returns how many values were beyond the
    /// half-float range and were clamped to its largest finite value.
    pub fn from_records(
        header: SlabHeader,
        mut record: impl FnMut(u64) -> (Rgb, Rgb),
    ) -> (LightSlab, u64) {
        let n = header.grid.records();
        let mut bytes = Vec::with_capacity(header.file_bytes() as usize);
        bytes.extend_from_slice(&header.encode());
        let mut clamped = 0u64;
        for index in 0..n {
            let (l, t) = record(index);
            for v in l.to_array().into_iter().chain(t.to_array()) {
                let h = f16::from_f32(v.min(f16::MAX.to_f32()));
                clamped += u64::from(v > f16::MAX.to_f32());
                bytes.extend_from_slice(&h.to_le_bytes());
            }
        }
        let param = Param::new(header.bounds, header.grid);
        (
            LightSlab {
                header,
                param,
                bytes,
            },
            clamped,
        )
    }

    /// The header.
    pub fn header(&self) -> &SlabHeader {
        &self.header
    }

    /// The parametrisation of its lines.
    pub fn param(&self) -> &Param {
        &self.param
    }

    /// The file's bytes (header and records), as written and read.
    pub fn file_bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Radiance and transmittance of flat record `index`, as stored.
    #[inline]
    pub fn record(&self, index: usize) -> (Rgb, Rgb) {
        let at = HEADER_BYTES + RECORD_BYTES as usize * index;
        let r: &[u8; RECORD_BYTES as usize] = self.bytes[at..at + RECORD_BYTES as usize]
            .try_into()
            .expect("12 bytes");
        let h = |k: usize| f16::from_le_bytes([r[2 * k], r[2 * k + 1]]).to_f32();
        (Rgb::new(h(0), h(1), h(2)), Rgb::new(h(3), h(4), h(5)))
    }

    /// The file's bytes: header, then the records.
    pub fn write_to(&self, out: &mut impl Write) -> std::io::Result<()> {
        out.write_all(&self.bytes)
    }

    /// Reads the slab file at `path`; an error says what is wrong in words
    /// (the caller names the file and the key). The header and the file's
    /// length are checked before the records are allocated.
    pub fn read(path: &Path) -> Result<LightSlab, String> {
        let mut file = std::fs::File::open(path).map_err(|e| format!("cannot open: {e}"))?;
        let len = file.metadata().map_err(|e| e.to_string())?.len();
        let mut h = [0u8; HEADER_BYTES];
        if len < HEADER_BYTES as u64 {
            return Err(format!(
                "is {len} bytes long, shorter than a slab file's {HEADER_BYTES}-byte header"
            ));
        }
        file.read_exact(&mut h).map_err(|e| e.to_string())?;
        let header = SlabHeader::decode(&h)?;
        if len != header.file_bytes() {
            return Err(format!(
                "is {len} bytes long, but its header ({} x {} nodes) needs {}: the file is truncated or damaged",
                header.grid.spatial,
                header.grid.angular,
                header.file_bytes()
            ));
        }
        crate::error::limits::check(len as u128).map_err(|refusal| {
            format!(
                "needs {} of memory, {refusal}",
                crate::error::limits::format_bytes(len as u128)
            )
        })?;
        // Not zero-filled first: read_to_end writes into the reserved room.
        let mut bytes = Vec::with_capacity(len as usize);
        bytes.extend_from_slice(&h);
        file.take(len - HEADER_BYTES as u64)
            .read_to_end(&mut bytes)
            .map_err(|e| e.to_string())?;
        if bytes.len() as u64 != len {
            return Err(format!(
                "shrank to {} bytes while it was read (expected {len})",
                bytes.len()
            ));
        }
        Ok(LightSlab {
            param: Param::new(header.bounds, header.grid),
            header,
            bytes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> SlabHeader {
        SlabHeader {
            bounds: Bounds3::new(Vec3::new(-1.0, -2.0, 0.0), Vec3::new(1.0, 0.5, 3.0)),
            grid: Grid {
                spatial: 3,
                angular: 2,
            },
            spp: 7,
            seed: 0xDEAD_BEEF_0000_0001,
        }
    }

    /// A written slab reads back equal (header and half-float records), and
    /// its length is the header's plus 12 bytes per record.
    #[test]
    fn a_written_slab_reads_back() {
        let (slab, clamped) = LightSlab::from_records(header(), |i| {
            (Rgb::splat(i as f32 * 0.25), Rgb::new(0.5, 0.125, 1.0))
        });
        assert_eq!(clamped, 0);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.slab");
        let mut f = std::fs::File::create(&path).unwrap();
        slab.write_to(&mut f).unwrap();
        drop(f);
        let len = std::fs::metadata(&path).unwrap().len();
        assert_eq!(len, 64 + 12 * 6 * 9 * 4);
        let back = LightSlab::read(&path).unwrap();
        assert_eq!(back.header(), slab.header());
        for i in 0..header().grid.records() as usize {
            assert_eq!(back.record(i), slab.record(i));
        }
        assert_eq!(back.record(5).0, Rgb::splat(1.25));
    }

    /// Damaged files are refused in words before their records are allocated.
    #[test]
    fn damaged_files_are_refused() {
        let (slab, _) = LightSlab::from_records(header(), |_| (Rgb::BLACK, Rgb::WHITE));
        let mut bytes = Vec::new();
        slab.write_to(&mut bytes).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("b.slab");
        let refuse = |b: &[u8]| {
            std::fs::write(&path, b).unwrap();
            LightSlab::read(&path).unwrap_err()
        };
        assert!(refuse(&bytes[..100]).contains("truncated"));
        assert!(refuse(&bytes[..10]).contains("shorter"));
        let mut other = bytes.clone();
        other[8] = 2;
        assert!(refuse(&other).contains("version 2"));
        let mut huge = bytes.clone();
        huge[16..20].copy_from_slice(&100_000u32.to_le_bytes());
        assert!(refuse(&huge).contains("damaged"));
        assert!(refuse(
            b"not a slab file at all, but long enough to hold a header of sixty-four bytes"
        )
        .contains("BRUMESLB"));
    }

    /// Radiance beyond the half-float range is clamped and counted, never infinite.
    #[test]
    fn values_beyond_half_range_are_clamped_and_counted() {
        let (slab, clamped) =
            LightSlab::from_records(header(), |_| (Rgb::new(1e6, 1.0, 1.0), Rgb::WHITE));
        assert_eq!(clamped, header().grid.records());
        assert_eq!(slab.record(0).0.r, 65504.0);
    }
}
