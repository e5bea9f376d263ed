//! JPEG images (8-bit, baseline or progressive; grey, YCbCr or CMYK,
//! decoded to RGB) for textures, read by the zune-jpeg crate after the
//! header is checked against the file's length and the memory limit.

use crate::error::limits::{self, format_bytes};
use crate::error::{Error, Result};
use std::path::Path;
use zune_jpeg::zune_core::bytestream::ZCursor;
use zune_jpeg::zune_core::colorspace::ColorSpace;
use zune_jpeg::zune_core::options::DecoderOptions;
use zune_jpeg::JpegDecoder;

/// Bytes the entropy-coded data of an 8 × 8 block takes at least: its DC
/// difference and end-of-block, one-bit Huffman codes at the shortest, for
/// one component (a quarter of a byte).
const LEAST_BITS_PER_BLOCK: u128 = 2;

fn input(path: &Path, message: String) -> Error {
    Error::Input {
        path: path.to_path_buf(),
        message,
    }
}

/// Reads a JPEG: width, height and row-major 8-bit RGB samples scaled to
/// [0, 1] (still in the file's encoding), row 0 at the top.
pub fn read_jpeg(path: &Path) -> Result<(usize, usize, Vec<[f32; 3]>)> {
    super::check_input(path, "JPEG")?;
    let fail = |m: String| input(path, format!("cannot read JPEG: {m}"));
    let bytes = std::fs::read(path).map_err(|e| fail(e.to_string()))?;
    // JPEG's own limit (16-bit sizes): brume's checks below judge the size.
    let options = DecoderOptions::default()
        .jpeg_set_out_colorspace(ColorSpace::RGB)
        .set_max_width(usize::from(u16::MAX))
        .set_max_height(usize::from(u16::MAX));
    let mut decoder = JpegDecoder::new_with_options(ZCursor::new(&bytes), options);
    decoder.decode_headers().map_err(|e| fail(e.to_string()))?;
    let info = decoder
        .info()
        .ok_or_else(|| fail("no image header".into()))?;
    let (w, h) = (info.width as u128, info.height as u128);
    let decoded = w * h * 12;
    let describe = format!(
        "declares {w}x{h} pixels ({} decoded)",
        format_bytes(decoded)
    );
    let least = (w.div_ceil(8) * h.div_ceil(8) * LEAST_BITS_PER_BLOCK).div_ceil(8);
    if (bytes.len() as u128) < least {
        return Err(input(
            path,
            format!(
                "{describe} but the file is {}: each 8x8 block takes at least {LEAST_BITS_PER_BLOCK} bits, so they need at least {}; the file is truncated or damaged",
                format_bytes(bytes.len() as u128),
                format_bytes(least)
            ),
        ));
    }
    limits::check(decoded).map_err(|refusal| input(path, format!("{describe}, {refusal}")))?;
    let samples = decoder.decode().map_err(|e| fail(e.to_string()))?;
    let (width, height) = (info.width as usize, info.height as usize);
    if samples.len() != width * height * 3 {
        return Err(fail("unexpected sample layout".into()));
    }
    let pixels = samples
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]].map(|v| v as f32 / 255.0))
        .collect();
    Ok((width, height, pixels))
}
