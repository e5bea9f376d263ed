//! EXR (linear float) and PNG (tonemapped sRGB) output, written atomically.
//!
//! Every file is first written to a temporary file in the destination folder
//! and renamed over the destination only on success, so a failed or
//! interrupted write never destroys an existing image.

use crate::error::{Error, Result};
use crate::math::color::Rgb;
use exr::prelude::ReadChannels as _;
use exr::prelude::ReadLayers as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Temporary files being written now, for [`discard_temporaries`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes the temporary files of writes under way: called before an
/// immediate exit (a second Ctrl-C) so that no `.NAME.tmp-PID` is left behind.
pub fn discard_temporaries() {
    let pending = match PENDING.lock() {
        Ok(p) => p,
        Err(poisoned) => poisoned.into_inner(),
    };
    for tmp in pending.iter() {
        let _ = std::fs::remove_file(tmp);
    }
}

fn set_pending(tmp: &Path, pending: bool) {
    let mut list = match PENDING.lock() {
        Ok(p) => p,
        Err(poisoned) => poisoned.into_inner(),
    };
    list.retain(|p| p != tmp);
    if pending {
        list.push(tmp.to_path_buf());
    }
}

mod film_exr;
mod hdr;
mod jpeg;
pub use hdr::{read_hdr, rgbe_to_rgb};
pub use jpeg::read_jpeg;
mod header;
mod png_write;
pub use film_exr::{read_film_exr, write_film_exr, write_film_exr_beauty, write_film_exr_with};
pub use png_write::{
    encode_png_tonemapped, write_encoded_png, write_png, write_png_srgb8, write_png_tonemapped,
    EncodedPng,
};

/// A finished (or partial) image in linear RGB with what produced it.
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Row-major pixels, row 0 at the top.
    pub pixels: Vec<Rgb>,
    /// Samples per pixel reached.
    pub spp: u32,
    /// True when the render was stopped before its budget.
    pub partial: bool,
}

fn output_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// A temporary sibling of `path` in the same folder (same file system, so rename is atomic).
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Writes through `write` into a temporary file, then renames it onto `path`
/// (onto the target of `path` when it is a symbolic link, which stays a link).
fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> std::result::Result<(), String>,
) -> Result<()> {
    let dest = crate::film::output_safety::destination(path);
    let tmp = temp_path(&dest);
    set_pending(&tmp, true);
    let result = match write(&tmp) {
        Err(message) => {
            let _ = std::fs::remove_file(&tmp);
            Err(output_error(path, message))
        }
        Ok(()) => std::fs::rename(&tmp, &dest).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            output_error(path, e.to_string())
        }),
    };
    set_pending(&tmp, false);
    result
}

/// Writes `text` atomically (through a temporary file, like the images).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, text).map_err(|e| e.to_string())
    })
}

/// Writes a file through `write` atomically (through a temporary file,
/// like the images): a failed or interrupted write leaves `path` as it was.
pub fn write_file_with(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<()> {
    write_atomically(path, |tmp| {
        let file = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        let mut out = std::io::BufWriter::new(file);
        write(&mut out).map_err(|e| e.to_string())?;
        let file = out.into_inner().map_err(|e| e.to_string())?;
        file.sync_all().map_err(|e| e.to_string())
    })
}

/// Writes a linear RGB float EXR, recording spp and completeness in the header.
pub fn write_exr(path: &Path, image: &Image) -> Result<()> {
    use exr::meta::attribute::{AttributeValue, Text};
    use exr::prelude::{
        Image as ExrImage, Layer, LayerAttributes, SpecificChannels, Vec2, WritableImage,
    };
    let (w, h) = (image.width, image.height);
    let layer = Layer::new(
        (w, h),
        LayerAttributes::named("rgb"),
        exr_encoding(image.partial),
        SpecificChannels::rgb(|p: Vec2<usize>| {
            let c = image.pixels[p.y() * w + p.x()];
            (c.r, c.g, c.b)
        }),
    );
    let mut exr_image = ExrImage::from_layer(layer);
    let other = &mut exr_image.attributes.other;
    other.insert(
        Text::from("brume:spp"),
        AttributeValue::I32(image.spp as i32),
    );
    other.insert(
        Text::from("brume:complete"),
        AttributeValue::I32(if image.partial { 0 } else { 1 }),
    );
    write_atomically(path, |tmp| {
        exr_image.write().to_file(tmp).map_err(|e| e.to_string())
    })
}

/// True when `path` is an EXR brume wrote and marked complete (`brume:complete` = 1).
pub fn exr_is_complete(path: &Path) -> bool {
    matches!(brume_header(path), Some(BrumeHeader { complete: true, .. }))
}

/// What the header of an image brume wrote says about its samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BrumeHeader {
    /// `brume:complete` = 1: the render reached its budget.
    pub complete: bool,
    /// `brume:spp`: samples per pixel held.
    pub spp: u32,
}

/// The `brume:complete` and `brume:spp` attributes of the EXR at `path`;
/// `None` for a missing file, a file that is not a regular file (never
/// opened), not an EXR or an EXR brume did not write. Reads the header only.
pub fn brume_header(path: &Path) -> Option<BrumeHeader> {
    use exr::meta::attribute::{AttributeValue, Text};
    use exr::meta::MetaData;
    crate::error::regular_file(path).ok()?;
    let meta = MetaData::read_from_file(path, false).ok()?;
    let int = |key: &str| {
        let key = Text::from(key);
        meta.headers.iter().find_map(|h| {
            match h
                .own_attributes
                .other
                .get(&key)
                .or_else(|| h.shared_attributes.other.get(&key))
            {
                Some(AttributeValue::I32(v)) => Some(*v),
                _ => None,
            }
        })
    };
    let complete = int("brume:complete")?;
    let spp = u32::try_from(int("brume:spp")?).ok()?;
    Some(BrumeHeader {
        complete: complete == 1,
        spp,
    })
}

/// Refuses, before opening it, an input image that is not a regular file.
fn check_input(path: &Path, format: &str) -> Result<()> {
    crate::error::regular_file(path)
        .map(|_| ())
        .map_err(|problem| Error::Input {
            path: path.to_path_buf(),
            message: format!("cannot read {format}: {problem}"),
        })
}

/// One named channel of an EXR beside the beauty's R, G, B: OpenEXR layer
/// naming, e.g. `A`, `albedo.R`, `normal.X`, `depth.Z`; row-major values.
pub type NamedChannel = (String, Vec<f32>);

/// Reads every channel of every layer of an EXR: width, height and the
/// channels by their full names (a named layer's channels as `layer.channel`).
pub fn read_exr_channels(path: &Path) -> Result<(usize, usize, Vec<NamedChannel>)> {
    check_input(path, "EXR")?;
    header::check_exr(path, header::Keep::AllChannels)?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .map_err(|e| Error::Input {
            path: path.to_path_buf(),
            message: format!("cannot read EXR: {e}"),
        })?;
    let mut size = (0, 0);
    let mut out = Vec::new();
    for layer in &image.layer_data {
        size = (layer.size.width(), layer.size.height());
        // brume's own single-part files name their part `rgb`; keep channel names as written.
        let prefix = match &layer.attributes.layer_name {
            Some(name) if !name.eq("rgb") && image.layer_data.len() > 1 => {
                format!("{name}.")
            }
            _ => String::new(),
        };
        for channel in &layer.channel_data.list {
            let values = channel.sample_data.values_as_f32().collect();
            out.push((format!("{prefix}{}", channel.name), values));
        }
    }
    Ok((size.0, size.1, out))
}

/// Reads an RGB EXR back (for tests and tools): width, height, pixels.
pub fn read_exr(path: &Path) -> Result<(usize, usize, Vec<Rgb>)> {
    use exr::prelude::read_first_rgba_layer_from_file;
    check_input(path, "EXR")?;
    header::check_exr(path, header::Keep::Rgb)?;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                resolution.width(),
                vec![Rgb::BLACK; resolution.width() * resolution.height()],
            )
        },
        |(w, pixels), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[pos.y() * *w + pos.x()] = Rgb::new(r, g, b)
        },
    )
    .map_err(|e| Error::Input {
        path: path.to_path_buf(),
        message: format!("cannot read EXR: {e}"),
    })?;
    let size = image.layer_data.size;
    Ok((
        size.width(),
        size.height(),
        image.layer_data.channel_data.pixels.1,
    ))
}

/// The samples of a PNG file as stored (sRGB-encoded or not), each in [0, 1].
pub struct PngSamples {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Samples per pixel: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA.
    pub channels: usize,
    /// Row-major, row 0 at the top, `channels` values per pixel.
    pub values: Vec<f32>,
}

/// Reads a PNG of any bit depth and colour type (palettes expanded), for textures.
pub fn read_png(path: &Path) -> Result<PngSamples> {
    let input = |message: String| Error::Input {
        path: path.to_path_buf(),
        message,
    };
    check_input(path, "PNG")?;
    let file = std::fs::File::open(path).map_err(|e| input(format!("cannot read PNG: {e}")))?;
    let file_len = file
        .metadata()
        .map_err(|e| input(format!("cannot read PNG: {e}")))?
        .len();
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder
        .read_info()
        .map_err(|e| input(format!("cannot read PNG: {e}")))?;
    let samples = reader.output_color_type().0.samples();
    header::check_png(path, reader.info(), samples, file_len)?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let frame = reader
        .next_frame(&mut buf)
        .map_err(|e| input(format!("cannot read PNG: {e}")))?;
    let bytes = &buf[..frame.buffer_size()];
    let channels = frame.color_type.samples();
    let values: Vec<f32> = match frame.bit_depth {
        png::BitDepth::Sixteen => bytes
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]) as f32 / 65535.0)
            .collect(),
        // EXPAND turns 1-, 2- and 4-bit samples into bytes.
        _ => bytes.iter().map(|&b| b as f32 / 255.0).collect(),
    };
    let (width, height) = (frame.width as usize, frame.height as usize);
    if values.len() != width * height * channels {
        return Err(input("cannot read PNG: unexpected sample layout".into()));
    }
    Ok(PngSamples {
        width,
        height,
        channels,
        values,
    })
}

/// EXR encoding: small files for a finished image; run-length (about as fast
/// as no compression) for a partial one, for the same reason as [`compression_for`].
pub(crate) fn exr_encoding(partial: bool) -> exr::prelude::Encoding {
    use exr::prelude::{Blocks, Compression, Encoding, LineOrder};
    match partial {
        true => Encoding {
            compression: Compression::RLE,
            blocks: Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        },
        false => Encoding::SMALL_LOSSLESS,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trip_and_failed_write_keeps_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let image = Image {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| Rgb::new(i as f32, 0.5, -1.0)).collect(),
            spp: 4,
            partial: false,
        };
        write_exr(&path, &image).unwrap();
        let (w, h, pixels) = read_exr(&path).unwrap();
        assert_eq!((w, h), (3, 2));
        assert_eq!(pixels, image.pixels);
        let missing = dir.path().join("no/such/dir/b.exr");
        assert!(write_exr(&missing, &image).is_err());
    }
}
