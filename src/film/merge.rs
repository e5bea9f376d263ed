//! `brume merge`: pieces of one render (crops and sample ranges) added into
//! the film of the whole render, a pure function of the films.
//!
//! Every layer's sums and counts (the beauty's and each AOV's) and the splat
//! sums are added, pieces taken in order of their first sample index (then
//! row, then column), so the result does not depend on the order the pieces
//! are named. A piece's EXR holds f32 means and exact counts (its sums are
//! mean × count), so:
//! - crops merge bit for bit: every pixel comes from one piece, whose mean
//!   is written back unchanged;
//! - sample ranges merge to within one f32 step of the single render in
//!   every channel whose samples share a sign (beauty, alpha, depth, albedo,
//!   transmittance): each piece's mean is off its exact value by at most
//!   half an f32 step, a relative 2⁻²⁴, so the count-weighted merge is off
//!   the single render's exact mean by at most a relative 2⁻²⁴, less than
//!   one f32 step, and the two round to the same f32 or to neighbours (at an
//!   exact power of two, where the step halves, two steps of the smaller).
//!   The normal's samples have both signs: there the bound is 2⁻²⁴ times the
//!   count-weighted mean of the pieces' |means|, plus one step;
//! - a splat-carrying film's pixel is its mean plus its splat sum over the
//!   samples per pixel; merging re-divides the summed splats by the merged
//!   samples per pixel, exact up to the same f32 rounding of each part.
//!
//! Refused: pieces of different scenes (scene hash), seeds, display windows,
//! render spp or layers (AOVs, splats); two pieces holding a sample of the same pixel; and a
//! pixel lacking a sample range (a missing piece). Interrupted pieces are
//! accepted and weighted by the samples they hold; the merge is then marked
//! incomplete and its `brume:samples_held` lists the samples every pixel holds.

use crate::error::{Error, Result};
use crate::film::{coalesce, format_ranges, Film, Provenance, Rect, SampleRange};
use std::path::{Path, PathBuf};

/// A merged film and what the user should know about it.
pub struct Merged {
    /// The film of the whole render.
    pub film: Film,
    /// One line per interrupted piece (and where a partial merge went).
    pub notes: Vec<String>,
    /// Where the merged EXR was written (`None` before writing, or when a
    /// partial merge could replace neither file, see `render::merge_pieces::merge_files`).
    pub written: Option<PathBuf>,
}

fn refuse(message: String) -> Error {
    Error::Merge { message }
}

/// Merges `pieces` (file name, film) into the film of the whole frame.
pub fn merge(pieces: &[(PathBuf, Film)]) -> Result<Merged> {
    let Some((first_path, first)) = pieces.first() else {
        return Err(refuse("no piece given".into()));
    };
    for (path, film) in pieces {
        if film.adaptive.is_some() {
            return Err(refuse(format!(
                "{}: an adaptive or noise-target render (brume:adaptive) holds different samples \
                 in each pixel and cannot be merged; merge uniform renders (--adaptive off)",
                path.display()
            )));
        }
        check_same_render(first_path, first, path, film)?;
    }
    check_no_overlap(pieces)?;
    check_coverage(pieces)?;
    let mut order: Vec<&(PathBuf, Film)> = pieces.iter().collect();
    order.sort_by_key(|(_, f)| (f.provenance.requested[0].start, f.window.y0, f.window.x0));
    let (w, h) = first.display;
    let mut film = Film::new(first.display, Rect::full(w, h), merged_provenance(pieces));
    let n = film.window.area();
    film.layers
        .extend(first.layers[1..].iter().map(|l| l.emptied(n)));
    if first.splats.is_some() {
        film.add_splats();
    }
    for (_, piece) in order {
        add(&mut film, piece);
    }
    let notes = pieces
        .iter()
        .filter(|(_, f)| !f.provenance.complete())
        .map(|(path, f)| {
            format!(
                "note: {} was interrupted: it holds samples {} of {}; merged with what it holds",
                path.display(),
                or_none(&f.provenance.held),
                format_ranges(&f.provenance.requested)
            )
        })
        .collect();
    Ok(Merged {
        film,
        notes,
        written: None,
    })
}

fn or_none(ranges: &[SampleRange]) -> String {
    if ranges.is_empty() {
        "none".into()
    } else {
        format_ranges(ranges)
    }
}

/// Refuses a piece of another render than the first piece's.
fn check_same_render(a_path: &Path, a: &Film, b_path: &Path, b: &Film) -> Result<()> {
    let (pa, pb) = (&a.provenance, &b.provenance);
    let differs = |what: &str, va: String, vb: String| {
        Err(refuse(format!(
            "{}: {what} {vb} differs from {}'s {va}",
            b_path.display(),
            a_path.display()
        )))
    };
    if pb.scene_hash != pa.scene_hash {
        return differs(
            "scene hash (scene file, files it reads, settings)",
            format!("{:016x}", pa.scene_hash),
            format!("{:016x}", pb.scene_hash),
        );
    }
    if pb.seed != pa.seed {
        return differs("seed", pa.seed.to_string(), pb.seed.to_string());
    }
    if b.display != a.display {
        let size = |d: (u32, u32)| format!("{}x{}", d.0, d.1);
        return differs("display window", size(a.display), size(b.display));
    }
    if pb.spp_total != pa.spp_total {
        let spp = |p: &Provenance| format!("{} spp", p.spp_total);
        return differs("render size", spp(pa), spp(pb));
    }
    let names = |f: &Film| -> Vec<String> {
        let splats = f
            .splats
            .as_ref()
            .map(|_| "splats.R,splats.G,splats.B".to_string());
        f.layers
            .iter()
            .flat_map(|l| l.channels.iter().cloned())
            .chain(splats)
            .collect()
    };
    if names(a) != names(b) {
        return differs("channels", names(a).join(","), names(b).join(","));
    }
    if pb.requested.is_empty() || pb.requested.iter().any(|r| r.end > pb.spp_total) {
        return Err(refuse(format!(
            "{}: sample range {} does not lie inside its render's 0..{}",
            b_path.display(),
            or_none(&pb.requested),
            pb.spp_total
        )));
    }
    Ok(())
}

/// Refuses two pieces that hold (or were asked for) a sample of the same pixel.
fn check_no_overlap(pieces: &[(PathBuf, Film)]) -> Result<()> {
    for (i, (a_path, a)) in pieces.iter().enumerate() {
        for (b_path, b) in &pieces[i + 1..] {
            if !a.window.overlaps(&b.window) {
                continue;
            }
            let (ra, rb) = (&a.provenance.requested, &b.provenance.requested);
            if ra.iter().any(|x| rb.iter().any(|y| x.overlaps(y))) {
                return Err(refuse(format!(
                    "{} (samples {}, pixels {}) overlaps {} (samples {}, pixels {}): \
                     a sample would be counted twice",
                    b_path.display(),
                    format_ranges(rb),
                    b.window,
                    a_path.display(),
                    format_ranges(ra),
                    a.window
                )));
            }
        }
    }
    Ok(())
}

/// Reports the first pixel (in row order) that some sample range is missing for.
fn check_coverage(pieces: &[(PathBuf, Film)]) -> Result<()> {
    let first = &pieces[0].1;
    let (w, h) = first.display;
    let spp = first.provenance.spp_total;
    let mut covered = vec![0u32; w as usize * h as usize];
    for (_, f) in pieces {
        let n: u32 = f.provenance.requested.iter().map(SampleRange::len).sum();
        for y in f.window.y0..f.window.y1 {
            let row = &mut covered[(y * w) as usize..][f.window.x0 as usize..f.window.x1 as usize];
            row.iter_mut().for_each(|c| *c += n);
        }
    }
    let short = covered.iter().filter(|c| **c < spp).count();
    let Some(at) = covered.iter().position(|c| *c < spp) else {
        return Ok(());
    };
    let (x, y) = (at as u32 % w, at as u32 / w);
    let mut have: Vec<SampleRange> = pieces
        .iter()
        .filter(|(_, f)| f.index(x, y).is_some())
        .flat_map(|(_, f)| f.provenance.requested.iter().copied())
        .collect();
    coalesce(&mut have);
    Err(refuse(format!(
        "missing piece: no piece holds samples {} of pixel {x},{y} ({short} of {} pixels lack samples)",
        format_ranges(&complement(&have, spp)),
        covered.len()
    )))
}

/// The parts of 0..spp that `have` (coalesced) leaves out.
fn complement(have: &[SampleRange], spp: u32) -> Vec<SampleRange> {
    let mut out = Vec::new();
    let mut next = 0;
    for r in have {
        if r.start > next {
            out.push(SampleRange::new(next, r.start));
        }
        next = next.max(r.end);
    }
    if next < spp {
        out.push(SampleRange::new(next, spp));
    }
    out
}

/// The merge's provenance: all samples asked for; held those no piece lost.
fn merged_provenance(pieces: &[(PathBuf, Film)]) -> Provenance {
    let p = &pieces[0].1.provenance;
    let mut lost = Vec::new();
    for (_, f) in pieces {
        for r in &f.provenance.requested {
            let mut held: Vec<SampleRange> = f.provenance.held.clone();
            held.retain(|h| h.overlaps(r));
            let missing = complement(&held, r.end);
            lost.extend(missing.into_iter().filter_map(|m| {
                let m = SampleRange::new(m.start.max(r.start), m.end);
                (!m.is_empty()).then_some(m)
            }));
        }
    }
    coalesce(&mut lost);
    Provenance {
        seed: p.seed,
        scene_hash: p.scene_hash,
        spp_total: p.spp_total,
        requested: vec![SampleRange::new(0, p.spp_total)],
        held: complement(&lost, p.spp_total),
    }
}

/// Adds `piece`'s sums and counts into `film` at the piece's pixels, and its
/// splats (which may lie outside its pixels) over the display window.
fn add(film: &mut Film, piece: &Film) {
    let win = piece.window;
    for y in win.y0..win.y1 {
        for x in win.x0..win.x1 {
            let i = film.index(x, y).expect("coverage checked");
            let j = piece.index(x, y).expect("inside the piece");
            film.counts[i] += piece.counts[j];
            film.nonfinite[i] += piece.nonfinite[j];
            for (to, from) in film.layers.iter_mut().zip(&piece.layers) {
                let k = to.channels.len();
                for c in 0..k {
                    to.sums[i * k + c] += from.sums[j * k + c];
                }
                if let (Some(to), Some(from)) = (to.counts.as_mut(), from.counts.as_ref()) {
                    to[i] += from[j];
                }
            }
        }
    }
    if let (Some(to), Some(from)) = (film.splats.as_mut(), piece.splats.as_ref()) {
        to.add_sums(from);
    }
}

#[cfg(test)]
mod tests;
