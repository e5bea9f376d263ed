//! `brume merge` on files: the output-safety rule, the pieces read back as
//! films, `film::merge` on them, the merged film written (as a partial image
//! when some piece was interrupted), optionally denoised.

use crate::error::{Error, Result};
use crate::film::merge::{merge, Merged};
use crate::film::output_safety::{identity, place_partial, Placement, Plan};
use crate::film::{denoise, image_io, Film};
use std::path::{Path, PathBuf};

/// Reads the pieces, merges them and writes the merged film to `out` (and a
/// PNG preview to `png`). The output-safety rule is checked first: no
/// output may be a piece or the other output. A merge of interrupted pieces
/// is a partial image and follows `output_safety::place_partial`; the
/// returned `written` says where the EXR went (`None`: not written). With
/// `denoise`, adds the denoised beauty, guided by the merged albedo and
/// normal layers (see `denoise::denoise_film`).
pub fn merge_files(
    pieces: &[PathBuf],
    out: &Path,
    png: Option<&Path>,
    denoise: bool,
) -> Result<Merged> {
    if denoise && !denoise::AVAILABLE {
        return Err(denoise_error(denoise::UNAVAILABLE.into()));
    }
    let mut plan = Plan::new("merge");
    for p in pieces {
        plan.input("piece", p);
    }
    plan.image_output("-o", out, None);
    if let Some(png) = png {
        plan.image_output("--png", png, None);
    }
    plan.check()?;
    check_pieces(pieces)?;
    let films = pieces
        .iter()
        .map(|p| Ok((p.clone(), image_io::read_film_exr(p)?)))
        .collect::<Result<Vec<_>>>()?;
    check_merged_size(&films)?;
    let mut merged = merge(&films)?;
    let extra = match denoise {
        true => denoise::denoise_film(&merged.film).map_err(denoise_error)?,
        false => Vec::new(),
    };
    let place = match merged.film.provenance.complete() {
        true => Placement::requested(out, png),
        false => place_partial(out, png, merged.film.provenance.spp_held()),
    };
    if let Some(exr) = &place.exr {
        image_io::write_film_exr_with(exr, &merged.film, &extra)?;
    }
    if let Some(png) = &place.png {
        image_io::write_png(png, &merged.film.beauty_image(), 0.0)?;
    }
    merged
        .notes
        .extend(place.note().map(|n| format!("note: {n}")));
    merged.written = place.exr;
    Ok(merged)
}

/// Refuses a merge whose film (the first piece's display window) is over
/// the memory limit: the pieces' headers declare it, not their pixels.
fn check_merged_size(pieces: &[(PathBuf, Film)]) -> Result<()> {
    let Some((path, first)) = pieces.first() else {
        return Ok(());
    };
    let (w, h) = first.display;
    // Per pixel: coverage, counts and non-finite counts (u32 each), an f64
    // sum per channel and a u32 count per layer with its own, f64 RGB splats.
    let layers: u128 = first
        .layers
        .iter()
        .map(|l| 8 * l.channels.len() as u128 + 4 * l.counts.is_some() as u128)
        .sum();
    let splats = 24 * first.splats.is_some() as u128;
    let bytes = w as u128 * h as u128 * (12 + layers + splats);
    crate::error::limits::check(bytes).map_err(|refusal| Error::Merge {
        message: format!(
            "{} declares a {w}x{h} image, whose merged film needs {}, {refusal}",
            path.display(),
            crate::error::limits::format_bytes(bytes)
        ),
    })
}

fn denoise_error(message: String) -> Error {
    Error::Argument {
        argument: "--denoise".into(),
        message,
    }
}

/// Refuses, before reading any, a piece that is missing, not a regular file
/// or named twice (also through another spelling, a link or a hard link).
fn check_pieces(pieces: &[PathBuf]) -> Result<()> {
    for p in pieces {
        if !p.exists() {
            return Err(Error::Merge {
                message: format!("missing piece: {} does not exist", p.display()),
            });
        }
        if let Err(problem) = crate::error::regular_file(p) {
            return Err(Error::Merge {
                message: format!("piece {}: {problem}", p.display()),
            });
        }
    }
    let mut seen = std::collections::HashSet::new();
    for p in pieces {
        if !seen.insert(identity(p)) {
            return Err(Error::Merge {
                message: format!("{} is named twice", p.display()),
            });
        }
    }
    Ok(())
}
