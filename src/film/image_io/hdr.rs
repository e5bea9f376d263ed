//! Radiance `.hdr` (RGBE) images: the text header, then scanlines stored flat
//! (4 bytes a pixel) or run-length encoded per component (the "new" RLE of
//! Radiance 2). Only the standard orientation `-Y height +X width` (rows top
//! to bottom, pixels left to right) and `FORMAT=32-bit_rle_rgbe` are read;
//! anything else is refused by name. `EXPOSURE` and `COLORCORR` lines are
//! ignored, as most renderers do (Mitsuba among them).
//!
//! The declared size is checked against the file's length before a pixel is
//! allocated, as for EXR and PNG (see `header`): an RLE scanline of width w
//! takes at least 4 + 8⌈w/127⌉ bytes, a flat one 4w.

use crate::error::limits::{self, format_bytes};
use crate::error::{Error, Result};
use crate::math::color::Rgb;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// Longest header brume reads (real headers are a few hundred bytes).
const MAX_HEADER: usize = 64 * 1024;
/// Longest run one RLE byte pair can describe.
const MAX_RUN: u128 = 127;

fn input(path: &Path, message: String) -> Error {
    Error::Input {
        path: path.to_path_buf(),
        message: format!("cannot read Radiance HDR: {message}"),
    }
}

/// Reads the header lines up to the blank line, then the resolution line: (width, height, bytes read).
fn read_header(r: &mut impl BufRead) -> std::result::Result<(usize, usize, usize), String> {
    let mut consumed = 0;
    let mut line = Vec::new();
    let mut next_line = |r: &mut dyn BufRead, consumed: &mut usize| {
        line.clear();
        let n = r
            .take((MAX_HEADER - *consumed) as u64)
            .read_until(b'\n', &mut line)
            .map_err(|e| e.to_string())?;
        *consumed += n;
        if n == 0 || line.last() != Some(&b'\n') {
            return Err(if *consumed >= MAX_HEADER {
                format!("the header is longer than {MAX_HEADER} bytes")
            } else {
                "the file ends inside its header".to_string()
            });
        }
        Ok(String::from_utf8_lossy(&line[..line.len() - 1]).into_owned())
    };
    let magic = next_line(r, &mut consumed)?;
    if !(magic.starts_with("#?RADIANCE") || magic.starts_with("#?RGBE")) {
        return Err("it does not start with #?RADIANCE or #?RGBE".into());
    }
    loop {
        let l = next_line(r, &mut consumed)?;
        if l.trim().is_empty() {
            break;
        }
        if let Some(format) = l.strip_prefix("FORMAT=") {
            if format.trim() != "32-bit_rle_rgbe" {
                return Err(format!(
                    "FORMAT={} is not supported (only 32-bit_rle_rgbe)",
                    format.trim()
                ));
            }
        }
    }
    let res = next_line(r, &mut consumed)?;
    let (w, h) = parse_resolution(&res)?;
    Ok((w, h, consumed))
}

/// `-Y height +X width`, the only orientation brume reads.
fn parse_resolution(line: &str) -> std::result::Result<(usize, usize), String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let number = |s: &str| s.parse::<usize>().ok().filter(|&n| n > 0);
    match words.as_slice() {
        ["-Y", h, "+X", w] => match (number(w), number(h)) {
            (Some(w), Some(h)) => Ok((w, h)),
            _ => Err(format!("bad resolution line `{line}`")),
        },
        [a, _, b, _] if a.len() == 2 && b.len() == 2 => Err(format!(
            "orientation `{line}` is not supported (only `-Y height +X width`, rows from the top)"
        )),
        _ => Err(format!("bad resolution line `{line}`")),
    }
}

/// The least bytes of pixel data `w` × `h` can be stored in.
fn least_data(w: u128, h: u128) -> u128 {
    let scanline = if (8..=0x7fff).contains(&w) {
        (4 * w).min(4 + 8 * w.div_ceil(MAX_RUN))
    } else {
        4 * w
    };
    h * scanline
}

/// One RGBE pixel as linear radiance (Radiance's `colr_color`: the middle of the bin).
#[inline]
pub fn rgbe_to_rgb(p: [u8; 4]) -> Rgb {
    if p[3] == 0 {
        return Rgb::BLACK;
    }
    let f = (p[3] as f32 - 136.0).exp2();
    Rgb::new(
        (p[0] as f32 + 0.5) * f,
        (p[1] as f32 + 0.5) * f,
        (p[2] as f32 + 0.5) * f,
    )
}

/// Reads one run-length-encoded scanline (its 4-byte header already read)
/// into `row`, one component at a time.
fn read_rle_scanline(r: &mut impl Read, row: &mut [[u8; 4]]) -> std::result::Result<(), String> {
    let width = row.len();
    for c in 0..4 {
        let mut x = 0;
        while x < width {
            let mut pair = [0u8; 2];
            r.read_exact(&mut pair[..1]).map_err(|_| truncated())?;
            let (count, literal) = if pair[0] > 128 {
                ((pair[0] - 128) as usize, false)
            } else {
                (pair[0] as usize, true)
            };
            if count == 0 || x + count > width {
                return Err("a run-length-encoded scanline overruns its width".into());
            }
            if literal {
                let mut bytes = [0u8; 128];
                r.read_exact(&mut bytes[..count]).map_err(|_| truncated())?;
                for (i, &b) in bytes[..count].iter().enumerate() {
                    row[x + i][c] = b;
                }
            } else {
                r.read_exact(&mut pair[1..]).map_err(|_| truncated())?;
                row[x..x + count].iter_mut().for_each(|p| p[c] = pair[1]);
            }
            x += count;
        }
    }
    Ok(())
}

fn truncated() -> String {
    "the file ends inside its pixels (truncated)".into()
}

/// Reads a flat scanline whose first pixel is `first`.
fn read_flat_scanline(
    r: &mut impl Read,
    first: [u8; 4],
    row: &mut [[u8; 4]],
) -> std::result::Result<(), String> {
    row[0] = first;
    for p in row[1..].iter_mut() {
        r.read_exact(p).map_err(|_| truncated())?;
    }
    if row.iter().any(|p| p[..3] == [1, 1, 1]) {
        return Err(
            "uses the old (Radiance 1) run-length encoding, which brume does not read".into(),
        );
    }
    Ok(())
}

/// Reads a Radiance `.hdr` image: width, height and row-major pixels, row 0 at the top.
pub fn read_hdr(path: &Path) -> Result<(usize, usize, Vec<Rgb>)> {
    super::check_input(path, "Radiance HDR")?;
    let fail = |m: String| input(path, m);
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    let file_len = file.metadata().map_err(|e| fail(e.to_string()))?.len() as u128;
    let mut r = BufReader::new(file);
    let (w, h, header_len) = read_header(&mut r).map_err(fail)?;
    let (w128, h128) = (w as u128, h as u128);
    let describe = format!(
        "declares {w}x{h} pixels ({} decoded)",
        format_bytes(w128 * h128 * 12)
    );
    let least = header_len as u128 + least_data(w128, h128);
    if file_len < least {
        let packing = if (8..=0x7fff).contains(&w) {
            format!(
                "run-length encoding packs at most {MAX_RUN} pixels of a component into 2 bytes"
            )
        } else {
            "scanlines of this width are stored flat, 4 bytes a pixel".to_string()
        };
        return Err(fail(format!(
            "{describe} but the file is {}: {packing}, so they need at least {}; the file is truncated or damaged",
            format_bytes(file_len),
            format_bytes(least)
        )));
    }
    limits::check(w128 * h128 * 12).map_err(|refusal| fail(format!("{describe}, {refusal}")))?;
    let mut pixels = Vec::with_capacity(w * h);
    let mut row = vec![[0u8; 4]; w];
    for _ in 0..h {
        let mut head = [0u8; 4];
        r.read_exact(&mut head).map_err(|_| fail(truncated()))?;
        let rle = head[0] == 2 && head[1] == 2 && head[2] & 0x80 == 0 && (8..=0x7fff).contains(&w);
        if rle {
            let declared = (head[2] as usize) << 8 | head[3] as usize;
            if declared != w {
                return Err(fail(format!(
                    "a scanline declares width {declared} in an image of width {w}"
                )));
            }
            read_rle_scanline(&mut r, &mut row).map_err(fail)?;
        } else {
            read_flat_scanline(&mut r, head, &mut row).map_err(fail)?;
        }
        pixels.extend(row.iter().map(|&p| rgbe_to_rgb(p)));
    }
    Ok((w, h, pixels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_lines() {
        assert_eq!(parse_resolution("-Y 3 +X 5"), Ok((5, 3)));
        let e = parse_resolution("+Y 3 +X 5").unwrap_err();
        assert!(
            e.contains("orientation `+Y 3 +X 5` is not supported"),
            "{e}"
        );
        assert!(parse_resolution("-Y 0 +X 5").is_err());
        assert!(parse_resolution("-Y x +X 5").is_err());
    }

    #[test]
    fn rgbe_decodes_to_the_middle_of_its_bin() {
        // 1.0 is stored as mantissa 128, exponent 129: (128 + 0.5) / 128.
        let c = rgbe_to_rgb([128, 64, 0, 129]);
        assert_eq!(c.r, 128.5 / 128.0);
        assert_eq!(c.g, 64.5 / 128.0);
        assert_eq!(rgbe_to_rgb([200, 3, 9, 0]), Rgb::BLACK);
    }

    #[test]
    fn least_data_of_rle_and_flat_widths() {
        // Too narrow or too wide for RLE: flat.
        assert_eq!(least_data(4, 2), 32);
        assert_eq!(least_data(40_000, 1), 160_000);
        // 1000 pixels: 4 + 8·8 bytes a scanline at best.
        assert_eq!(least_data(1000, 10), 680);
    }
}
