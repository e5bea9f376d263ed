//! What an EXR or PNG header declares, checked before a pixel is allocated.
//!
//! Two checks, in this order, each refusing with one line that names the
//! file and the declared size:
//!
//! 1. The file must be long enough to hold what it declares: every chunk of
//!    an EXR is in the file (its offset and a chunk header of 8 bytes at
//!    least) and no compression packs more than a known number of bytes
//!    into one ([`max_ratio`]); a PNG's image data is one zlib stream.
//!    A file of a few hundred bytes declaring gigabytes is damaged, and
//!    raising the memory limit would not help, so this comes first. The
//!    allocation a valid file needs is then proportional to its length.
//! 2. The decoded image must fit the memory limit ([`crate::error::limits`]).

use crate::error::limits::{self, format_bytes};
use crate::error::{Error, Result};
use exr::compression::Compression;
use exr::meta::attribute::SampleType;
use exr::meta::header::Header;
use std::path::Path;

/// What a reader keeps of an EXR, which sets the decoded size.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Keep {
    /// R, G, B of one layer as three f32 (12 bytes per pixel).
    Rgb,
    /// Every channel of every layer as a 4-byte value.
    AllChannels,
}

/// Largest number of bytes one compressed byte of a `sample` channel can
/// stand for (an upper bound over every valid stream), `None` when brume
/// cannot decode the compression.
fn max_ratio(compression: Compression, sample: SampleType) -> Option<u128> {
    use Compression::*;
    Some(match compression {
        Uncompressed => 1,
        // A run of at most 128 equal bytes takes 2 bytes.
        RLE => 64,
        // deflate: a 258-byte match in 2 bits at best.
        ZIP1 | ZIP16 => 1032,
        // deflate of the 3 bytes PXR24 keeps of each f32.
        PXR24 if sample == SampleType::F32 => 1376,
        PXR24 => 1032,
        // Huffman runs: 256 16-bit values in 10 bits at best (410).
        PIZ => 512,
        // A flat 4×4 block of halves in 3 bytes; other types are stored as is.
        B44 | B44A if sample == SampleType::F16 => 11,
        B44 | B44A => 1,
        // An 8×8 block of f32 (256 bytes) keeps at least a DC half and an
        // end-of-block code (4 bytes) before deflate: 66048, doubled for margin.
        DWAA(_) | DWAB(_) => 131_072,
        HTJ2K32 | HTJ2K256 => return None,
    })
}

/// A header's sizes: pixels, what brume decodes and the least file that holds it.
#[derive(Default)]
struct Declared {
    /// The largest layer, width × height.
    largest: (u128, u128),
    /// Layers in the file.
    layers: usize,
    /// Bytes the reader keeps.
    decoded: u128,
    /// Least file length that can hold every chunk.
    least_file: u128,
    /// The compression of the layer needing the most file bytes, for the message.
    compression: Option<(Compression, u128)>,
}

impl Declared {
    fn exr(headers: &[Header], keep: Keep) -> std::result::Result<Declared, String> {
        let mut d = Declared {
            layers: headers.len(),
            ..Declared::default()
        };
        let mut heaviest = 0;
        for h in headers {
            if h.deep {
                return Err(
                    "holds deep data (several samples per pixel), which brume does not read".into(),
                );
            }
            let (w, ht) = (h.layer_size.width() as u128, h.layer_size.height() as u128);
            if w * ht > d.largest.0 * d.largest.1 {
                d.largest = (w, ht);
            }
            let mut file = 16 * h.chunk_count as u128;
            let mut ratio_seen = 1;
            for c in &h.channels.list {
                let ratio = max_ratio(h.compression, c.sample_type)
                    .ok_or_else(|| format!("uses {}, which brume cannot decode", h.compression))?;
                let (sx, sy) = (c.sampling.x().max(1) as u128, c.sampling.y().max(1) as u128);
                let raw = (w / sx) * (ht / sy) * c.sample_type.bytes_per_sample() as u128;
                file += raw.div_ceil(ratio);
                ratio_seen = ratio_seen.max(ratio);
            }
            d.least_file += file;
            if file >= heaviest {
                heaviest = file;
                d.compression = Some((h.compression, ratio_seen));
            }
            d.decoded = match keep {
                Keep::Rgb => d.decoded.max(w * ht * 12),
                Keep::AllChannels => d.decoded + w * ht * 4 * h.channels.list.len() as u128,
            };
        }
        Ok(d)
    }

    /// `60000x60000 pixels (43.2 GB decoded)`.
    fn describe(&self) -> String {
        let (w, h) = self.largest;
        let layers = match self.layers {
            0 | 1 => String::new(),
            n => format!("{n} layers, the largest "),
        };
        format!(
            "declares {layers}{w}x{h} pixels ({} decoded)",
            format_bytes(self.decoded)
        )
    }
}

fn input(path: &Path, message: String) -> Error {
    Error::Input {
        path: path.to_path_buf(),
        message,
    }
}

/// Refuses an EXR whose header declares more than its length can hold or
/// more than the memory limit, reading only the header.
pub(crate) fn check_exr(path: &Path, keep: Keep) -> Result<()> {
    let cannot = |e: &dyn std::fmt::Display| input(path, format!("cannot read EXR: {e}"));
    let file_len = std::fs::metadata(path).map_err(|e| cannot(&e))?.len();
    if let Some(kind) = not_exr(path) {
        return Err(input(path, format!("is {kind}, not an EXR image")));
    }
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| cannot(&e))?;
    let declared = Declared::exr(&meta.headers, keep).map_err(|m| cannot(&m))?;
    if (file_len as u128) < declared.least_file {
        let (compression, ratio) = declared
            .compression
            .unwrap_or((Compression::Uncompressed, 1));
        let packing = match ratio {
            1 => format!("with {compression} they need"),
            r => format!("{compression} packs at most {r} bytes into one, so they need"),
        };
        return Err(input(
            path,
            format!(
                "{} but the file is {}: {packing} at least {}; the file is truncated or damaged",
                declared.describe(),
                format_bytes(file_len as u128),
                format_bytes(declared.least_file)
            ),
        ));
    }
    limits::check(declared.decoded)
        .map_err(|refusal| input(path, format!("{}, {refusal}", declared.describe())))
}

/// Zlib (deflate) packs at most this many bytes into one.
const ZLIB_RATIO: u128 = 1032;

/// Refuses a PNG whose header declares more than its length can hold or more
/// than the memory limit: after `read_info`, before the frame buffer.
pub(crate) fn check_png(
    path: &Path,
    info: &png::Info,
    output_samples: usize,
    file_len: u64,
) -> Result<()> {
    let (w, h) = (info.width as u128, info.height as u128);
    let bits = info.color_type.samples() as u128 * info.bit_depth as u8 as u128;
    // Filtered rows, one filter byte each (interlaced images hold more).
    let raw = h * (1 + (w * bits).div_ceil(8));
    let decoded = w * h * output_samples as u128 * 4;
    let describe = format!(
        "declares {w}x{h} pixels ({} decoded)",
        format_bytes(decoded)
    );
    // Signature, IHDR, one IDAT and IEND: 45 bytes besides the data.
    let least_file = 45 + raw.div_ceil(ZLIB_RATIO);
    if (file_len as u128) < least_file {
        return Err(input(
            path,
            format!(
                "{describe} but the file is {}: zlib packs at most {ZLIB_RATIO} bytes into one, so they need at least {}; the file is truncated or damaged",
                format_bytes(file_len as u128),
                format_bytes(least_file)
            ),
        ));
    }
    limits::check(decoded).map_err(|refusal| input(path, format!("{describe}, {refusal}")))
}

/// The EXR magic number (OpenEXR's `20000630`, little-endian).
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// What the file at `path` is when its first bytes are not an EXR's (None
/// when they are, or when it cannot be read: the EXR reader says why).
fn not_exr(path: &Path) -> Option<String> {
    use std::io::Read;
    let mut head = Vec::with_capacity(16);
    std::fs::File::open(path)
        .and_then(|f| f.take(16).read_to_end(&mut head))
        .ok()?;
    if head.starts_with(&EXR_MAGIC) {
        return None;
    }
    Some(match head.as_slice() {
        [] => "empty (0 bytes)".into(),
        [0x89, b'P', b'N', b'G', ..] => "a PNG image".into(),
        [b'#', b'?', ..] => "a Radiance .hdr image".into(),
        [0x20, 0x42, 0x44, 0x56, ..] => "an OpenVDB file".into(),
        h if std::str::from_utf8(h).is_ok() && !h.contains(&0) => "text".into(),
        h => {
            let bytes: Vec<String> = h.iter().take(8).map(|b| format!("{b:02x}")).collect();
            format!("data of an unknown kind (first bytes {})", bytes.join(" "))
        }
    })
}
