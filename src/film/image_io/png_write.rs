//! 8-bit sRGB PNG output: previews (exposure and tone curve) and ready-made
//! pictures, encoded in memory and written atomically.
//!
//! Encoding is apart from writing so that a render can encode its preview
//! while the EXR is written, and still put the PNG in place only once the
//! EXR has succeeded.

use super::{output_error, write_atomically, Image};
use crate::error::Result;
use crate::film::tonemap::Tonemap;
use std::path::Path;

/// A PNG file's bytes, ready to be written.
pub struct EncodedPng(Vec<u8>);

/// Writes an 8-bit sRGB PNG after scaling by 2^exposure and clamping.
pub fn write_png(path: &Path, image: &Image, exposure: f32) -> Result<()> {
    write_png_tonemapped(path, image, exposure, Tonemap::Clip)
}

/// Writes an 8-bit sRGB PNG after scaling by 2^exposure and the tone curve `tonemap`.
pub fn write_png_tonemapped(
    path: &Path,
    image: &Image,
    exposure: f32,
    tonemap: Tonemap,
) -> Result<()> {
    let png = encode_png_tonemapped(image, exposure, tonemap).map_err(|m| output_error(path, m))?;
    write_encoded_png(path, &png)
}

/// Writes `png` to `path` atomically.
pub fn write_encoded_png(path: &Path, png: &EncodedPng) -> Result<()> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, &png.0).map_err(|e| e.to_string())
    })
}

/// The PNG of `image` scaled by 2^exposure and mapped by `tonemap`; the
/// default compression for a finished image, the fast one for a partial one.
pub fn encode_png_tonemapped(
    image: &Image,
    exposure: f32,
    tonemap: Tonemap,
) -> std::result::Result<EncodedPng, String> {
    use rayon::prelude::*;
    let scale = exposure.exp2();
    let mut bytes = vec![0u8; image.pixels.len() * 3];
    // In parallel: the sRGB curve of a 4096² image takes half a second on one
    // core, which an interrupted render (answering within a second) cannot spare.
    const ROW: usize = 4096;
    bytes
        .par_chunks_mut(3 * ROW)
        .zip(image.pixels.par_chunks(ROW))
        .for_each(|(out, pixels)| {
            for (o, c) in out.chunks_exact_mut(3).zip(pixels) {
                o[0] = tonemap.srgb8(c.r, scale);
                o[1] = tonemap.srgb8(c.g, scale);
                o[2] = tonemap.srgb8(c.b, scale);
            }
        });
    let size = (image.width as u32, image.height as u32);
    encode(size, &bytes, compression_for(image.partial))
}

/// PNG compression: the default for a finished image; the fast kind (several
/// times faster, a slightly larger file) for a partial one, written during a
/// render (checkpoints) or after a stop request, when time matters most.
fn compression_for(partial: bool) -> png::Compression {
    match partial {
        true => png::Compression::Fast,
        false => png::Compression::Default,
    }
}

/// Writes ready-made 8-bit sRGB pixels (row-major RGB, e.g. a plot) as a PNG.
pub fn write_png_srgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    if rgb.len() != width as usize * height as usize * 3 {
        return Err(output_error(path, "pixel buffer does not match the size"));
    }
    let png = encode((width, height), rgb, png::Compression::Default)
        .map_err(|m| output_error(path, m))?;
    write_encoded_png(path, &png)
}

fn encode(
    (width, height): (u32, u32),
    rgb: &[u8],
    compression: png::Compression,
) -> std::result::Result<EncodedPng, String> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(compression);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(rgb).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(EncodedPng(out))
}
