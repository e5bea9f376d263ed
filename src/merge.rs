//! `brume merge`: pieces of one render (crops and sample ranges) added into
//! the film of the whole render, a pure function of the films.
//!
//! Every pixel's f64 sums and counts are added, pieces taken in order of their
//! first sample index (then row, then column), so the result does not depend
//! on the order the pieces are named. A crop piece holds exactly the sums the
//! full render holds for its pixels, so crops merge bit for bit. Sample-range
//! pieces add the same f64 samples grouped differently: the merged f64 mean
//! differs from the single render's by f64 rounding (a relative 2⁻⁵³ per
//! addition), so the f32 pixel equals the single render's or is its f32
//! neighbour (at most 1 ulp apart), and then only when the exact mean falls
//! within f64 rounding of an f32 rounding boundary.
//!
//! Refused: pieces of different scenes (scene hash), seeds, display windows,
//! render spp or layers; two pieces holding a sample of the same pixel; and a
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
    /// One line per interrupted piece.
    pub notes: Vec<String>,
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
        check_same_render(first_path, first, path, film)?;
    }
    check_no_overlap(pieces)?;
    check_coverage(pieces)?;
    let mut order: Vec<&(PathBuf, Film)> = pieces.iter().collect();
    order.sort_by_key(|(_, f)| (f.provenance.requested[0].start, f.window.y0, f.window.x0));
    let (w, h) = first.display;
    let mut film = Film::new(first.display, Rect::full(w, h), merged_provenance(pieces));
    for layer in &first.layers[1..] {
        let channels: Vec<&str> = layer.channels.iter().map(String::as_str).collect();
        film.add_layer(&layer.name, &channels);
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
    Ok(Merged { film, notes })
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
        f.layers
            .iter()
            .flat_map(|l| (0..l.channels.len()).map(|c| l.channel_name(c)))
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

/// Adds `piece`'s sums and counts into `film` at the piece's pixels.
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
            }
        }
    }
}

/// Refuses a merge whose film (the first piece's display window) is over
/// the memory limit: the pieces' headers declare it, not their pixels.
fn check_merged_size(pieces: &[(PathBuf, Film)]) -> Result<()> {
    let Some((path, first)) = pieces.first() else {
        return Ok(());
    };
    let (w, h) = first.display;
    let channels: usize = first.layers.iter().map(|l| l.channels.len()).sum();
    // Coverage, counts and non-finite counts (u32 each), and an f64 sum per channel.
    let bytes = w as u128 * h as u128 * (12 + 8 * channels as u128);
    crate::limits::check(bytes).map_err(|refusal| {
        refuse(format!(
            "{} declares a {w}x{h} image, whose merged film needs {}, {refusal}",
            path.display(),
            crate::limits::format_bytes(bytes)
        ))
    })
}

/// Reads the pieces, merges them and writes the merged film to `out` (and a PNG preview to `png`).
pub fn merge_files(pieces: &[PathBuf], out: &Path, png: Option<&Path>) -> Result<Merged> {
    crate::image_io::check_writable(out)?;
    if let Some(png) = png {
        crate::image_io::check_writable(png)?;
    }
    if let Some(absent) = pieces.iter().find(|p| !p.exists()) {
        return Err(refuse(format!(
            "missing piece: {} does not exist",
            absent.display()
        )));
    }
    let mut seen = std::collections::HashSet::new();
    for p in pieces {
        if !seen.insert(p.canonicalize().unwrap_or_else(|_| p.clone())) {
            return Err(refuse(format!("{} is named twice", p.display())));
        }
    }
    let films = pieces
        .iter()
        .map(|p| Ok((p.clone(), crate::image_io::read_film_exr(p)?)))
        .collect::<Result<Vec<_>>>()?;
    check_merged_size(&films)?;
    let merged = merge(&films)?;
    crate::image_io::write_film_exr(out, &merged.film)?;
    if let Some(png) = png {
        crate::image_io::write_png(png, &merged.film.beauty_image(), 0.0)?;
    }
    Ok(merged)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn piece(window: Rect, requested: SampleRange, held: SampleRange, value: f64) -> Film {
        let provenance = Provenance {
            seed: 1,
            scene_hash: 2,
            spp_total: 8,
            requested: vec![requested],
            held: if held.is_empty() { vec![] } else { vec![held] },
        };
        let mut film = Film::new((4, 2), window, provenance);
        film.counts.fill(held.len());
        film.layers[0].sums.fill(value * held.len() as f64);
        film
    }

    fn named(films: Vec<Film>) -> Vec<(PathBuf, Film)> {
        films
            .into_iter()
            .enumerate()
            .map(|(i, f)| (PathBuf::from(format!("p{i}.exr")), f))
            .collect()
    }

    const FULL: Rect = Rect {
        x0: 0,
        x1: 4,
        y0: 0,
        y1: 2,
    };
    const R: fn(u32, u32) -> SampleRange = SampleRange::new;

    #[test]
    fn sample_ranges_are_weighted_by_their_counts() {
        // An interrupted piece holding 2 samples of mean 4 and a whole piece of
        // 4 samples of mean 1: mean (8 + 4) / 6 = 2, not the (4 + 1) / 2 of the means.
        let pieces = named(vec![
            piece(FULL, R(0, 4), R(0, 2), 4.0),
            piece(FULL, R(4, 8), R(4, 8), 1.0),
        ]);
        let merged = merge(&pieces).unwrap();
        let beauty = &merged.film.layers[0];
        assert_eq!(merged.film.mean(beauty, 5, 1), 2.0);
        assert_eq!(merged.film.counts[5], 6);
        assert_eq!(merged.notes.len(), 1);
        assert!(merged.notes[0].contains("p0.exr") && merged.notes[0].contains("0..2 of 0..4"));
        assert_eq!(merged.film.provenance.held, vec![R(0, 2), R(4, 8)]);
        assert!(!merged.film.provenance.complete());
    }

    #[test]
    fn crops_are_placed_in_the_display_window() {
        let left = Rect {
            x0: 0,
            x1: 1,
            y0: 0,
            y1: 2,
        };
        let right = Rect {
            x0: 1,
            x1: 4,
            y0: 0,
            y1: 2,
        };
        let pieces = named(vec![
            piece(right, R(0, 8), R(0, 8), 3.0),
            piece(left, R(0, 8), R(0, 8), 5.0),
        ]);
        let merged = merge(&pieces).unwrap();
        let film = &merged.film;
        let means: Vec<f32> = (0..8).map(|i| film.mean(&film.layers[0], i, 0)).collect();
        assert_eq!(means, [5.0, 3.0, 3.0, 3.0, 5.0, 3.0, 3.0, 3.0]);
        assert!(film.provenance.complete() && merged.notes.is_empty());
    }

    #[test]
    fn refusals_say_what_differs() {
        let err = |films: Vec<Film>| merge(&named(films)).err().unwrap().to_string();
        let a = piece(FULL, R(0, 4), R(0, 4), 1.0);
        let overlap = err(vec![a.clone(), piece(FULL, R(3, 8), R(3, 8), 1.0)]);
        assert!(
            overlap.contains("p1.exr (samples 3..8") && overlap.contains("overlaps p0.exr"),
            "{overlap}"
        );
        let missing = err(vec![a.clone(), piece(FULL, R(4, 6), R(4, 6), 1.0)]);
        assert!(
            missing.contains("missing piece: no piece holds samples 6..8 of pixel 0,0"),
            "{missing}"
        );
        let mut other_seed = piece(FULL, R(4, 8), R(4, 8), 1.0);
        other_seed.provenance.seed = 9;
        assert!(err(vec![a.clone(), other_seed]).contains("p1.exr: seed 9 differs from p0.exr's 1"));
        let mut other_scene = piece(FULL, R(4, 8), R(4, 8), 1.0);
        other_scene.provenance.scene_hash = 3;
        assert!(err(vec![a.clone(), other_scene]).contains("scene hash"));
        let mut other_size = piece(FULL, R(4, 8), R(4, 8), 1.0);
        other_size.display = (5, 2);
        assert!(err(vec![a, other_size]).contains("display window 5x2 differs from p0.exr's 4x2"));
    }

    #[test]
    fn a_crop_gap_is_reported_with_its_pixel() {
        let top = Rect {
            x0: 0,
            x1: 4,
            y0: 0,
            y1: 1,
        };
        let e = merge(&named(vec![piece(top, R(0, 8), R(0, 8), 1.0)]))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("samples 0..8 of pixel 0,1 (4 of 8 pixels"),
            "{e}"
        );
    }
}
