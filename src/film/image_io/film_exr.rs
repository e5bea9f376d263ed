//! A film as an EXR: the data window is the film's crop, the display window
//! the full frame, as OpenEXR intends, so pieces line up in any EXR tool.
//!
//! The image channels are what a viewer shows and nothing else: `R`, `G`,
//! `B` (the beauty, splats included), `A` with the alpha AOV and `NAME.CH`
//! for the other AOVs, as f32 means. What `merge` needs besides the means is
//! in the header (see [`write_film_exr`]): the provenance and the per-pixel
//! counts, run-length encoded (`film::runs`), which turn each mean back into
//! its sum. A film with splats carries a second part, `splats`, over the
//! whole display window: its splat sums over the samples per pixel held.
//!
//! A mean is an f32, so the sum read back is the mean times the count, not
//! the f64 sum the render held: merging sample ranges is exact up to that
//! rounding (see `merge`); a crop's pixels come back bit for bit.

use crate::error::{Error, Result};
use crate::film::aov::Aov;
use crate::film::runs::{decode_runs, encode_runs};
use crate::film::{format_ranges, parse_ranges, Film, Provenance, Rect};
use crate::math::color::Rgb;
use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::prelude::{
    AnyChannel, AnyChannels, FlatSamples, Image as ExrImage, ImageAttributes, Layer as ExrLayer,
    LayerAttributes, SmallVec, Vec2, WritableImage,
};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::Path;

/// Name of the part holding the splats.
const SPLATS: &str = "splats";

type Channels = SmallVec<[AnyChannel<FlatSamples>; 4]>;

/// Writes `film` atomically, with its provenance and counts in the header.
pub fn write_film_exr(path: &Path, film: &Film) -> Result<()> {
    write_film_exr_with(path, film, &[])
}

/// [`write_film_exr`] plus `extra` f32 channels derived from the film (the
/// denoised beauty: one value per pixel of the data window), which `merge`
/// does not read.
///
/// Header: `brume:spp`, `brume:complete`, `brume:samples`,
/// `brume:samples_held`, `brume:spp_total`, `brume:seed`, `brume:scene_hash`,
/// `brume:layers` (the AOV names, comma-separated), `brume:count` and
/// `brume:nonfinite` (the beauty's finite and left-out samples per pixel),
/// `brume:count.NAME` (each AOV's), `brume:version`, and for a piloted
/// render `brume:adaptive` (its pilot, counts and estimated error).
pub fn write_film_exr_with(path: &Path, film: &Film, extra: &[super::NamedChannel]) -> Result<()> {
    write_film(path, film, (None, !film.provenance.complete()), extra)
}

/// [`write_film_exr_with`] given the film's beauty image already computed
/// (`Film::beauty_image`), so that a stopped render does not compute its
/// pixels twice on the way to the exit. A stopped render's image (marked
/// partial) gets the fast encoding even when the film is complete: a timed
/// render asks for what it reached, so its film is complete after a stop.
pub fn write_film_exr_beauty(
    path: &Path,
    film: &Film,
    beauty: &super::Image,
    extra: &[super::NamedChannel],
) -> Result<()> {
    let fast = beauty.partial || !film.provenance.complete();
    write_film(path, film, (Some(&beauty.pixels), fast), extra)
}

/// Writes `film` with its `beauty` if computed, in the fast encoding if `fast`.
fn write_film(
    path: &Path,
    film: &Film,
    (beauty, fast): (Option<&[Rgb]>, bool),
    extra: &[super::NamedChannel],
) -> Result<()> {
    let w = &film.window;
    let sizes = extra.iter().map(|(name, v)| (name.as_str(), v.len()));
    let beauty_size = beauty.map(|b| ("R, G, B", b.len()));
    if let Some((name, _)) = sizes.chain(beauty_size).find(|&(_, n)| n != w.area()) {
        return Err(super::output_error(
            path,
            format!("channel {name} does not match the image size"),
        ));
    }
    let mut channels = image_channels(film, beauty);
    for (name, values) in extra {
        channels.push(AnyChannel::new(
            name.as_str(),
            FlatSamples::F32(values.clone()),
        ));
    }
    let mut attributes = LayerAttributes::named("");
    // A file of several parts must name each one; a lone part stays unnamed.
    attributes.layer_name = film.splats.is_some().then(|| Text::from("rgb"));
    attributes.layer_position = Vec2(w.x0 as i32, w.y0 as i32);
    insert_header(&mut attributes.other, film);
    let mut layers = vec![ExrLayer::new(
        (w.width() as usize, w.height() as usize),
        attributes,
        super::exr_encoding(fast),
        AnyChannels::sort(channels),
    )];
    layers.extend(splat_part(film, fast));
    let display = IntegerBounds::new((0, 0), (film.display.0 as usize, film.display.1 as usize));
    let image = ExrImage::from_layers(ImageAttributes::new(display), layers);
    super::write_atomically(path, |tmp| {
        image.write().to_file(tmp).map_err(|e| e.to_string())
    })
}

/// The f32 means of every layer: the beauty (with its splats; `beauty` if
/// given, else computed) and the AOVs.
fn image_channels(film: &Film, beauty: Option<&[Rgb]>) -> Channels {
    let n = film.window.area();
    // In parallel: after a stop request this stands between the request and the exit.
    let computed: Vec<Rgb>;
    let pixels = match beauty {
        Some(pixels) => pixels,
        None => {
            computed = (0..n).into_par_iter().map(|i| film.pixel(i)).collect();
            &computed
        }
    };
    let mut out = Channels::new();
    for c in 0..3 {
        let values = pixels.par_iter().map(|p| p[c]).collect();
        out.push(AnyChannel::new(
            film.layers[0].channels[c].as_str(),
            FlatSamples::F32(values),
        ));
    }
    for layer in &film.layers[1..] {
        for (name, values) in layer.channels.iter().zip(film.layer_means(layer)) {
            out.push(AnyChannel::new(name.as_str(), FlatSamples::F32(values)));
        }
    }
    out
}

/// The `splats` part: the splat sums over the samples per pixel held, on
/// the whole display window.
fn splat_part(film: &Film, fast: bool) -> Option<ExrLayer<AnyChannels<FlatSamples>>> {
    let splats = film.splats.as_ref()?;
    let spp = film.provenance.spp_held().max(1) as f64;
    let mut channels = Channels::new();
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        let values = splats
            .sums
            .iter()
            .skip(c)
            .step_by(3)
            .map(|s| (s / spp) as f32)
            .collect();
        channels.push(AnyChannel::new(name, FlatSamples::F32(values)));
    }
    let mut attributes = LayerAttributes::named(SPLATS);
    attributes.layer_position = Vec2(0, 0);
    Some(ExrLayer::new(
        (film.display.0 as usize, film.display.1 as usize),
        attributes,
        super::exr_encoding(fast),
        AnyChannels::sort(channels),
    ))
}

/// The `brume:*` header attributes of `film`.
fn insert_header(other: &mut HashMap<Text, AttributeValue>, film: &Film) {
    let p = &film.provenance;
    let int = |v: u32| AttributeValue::I32(v.min(i32::MAX as u32) as i32);
    let text = |s: String| AttributeValue::Text(Text::from(s.as_str()));
    let aovs: Vec<&str> = film.layers[1..].iter().map(|l| l.name.as_str()).collect();
    let mut entries = vec![
        ("brume:spp".to_string(), int(p.spp_held())),
        ("brume:complete".into(), int(p.complete() as u32)),
        ("brume:samples".into(), text(format_ranges(&p.requested))),
        ("brume:samples_held".into(), text(format_ranges(&p.held))),
        ("brume:spp_total".into(), int(p.spp_total)),
        ("brume:seed".into(), text(p.seed.to_string())),
        (
            "brume:scene_hash".into(),
            text(format!("{:016x}", p.scene_hash)),
        ),
        ("brume:layers".into(), text(aovs.join(","))),
        ("brume:count".into(), text(encode_runs(&film.counts))),
        ("brume:nonfinite".into(), text(encode_runs(&film.nonfinite))),
        (
            "brume:version".into(),
            text(env!("CARGO_PKG_VERSION").to_string()),
        ),
    ];
    if let Some(note) = &film.adaptive {
        entries.push(("brume:adaptive".into(), text(note.clone())));
    }
    for layer in &film.layers[1..] {
        if let Some(counts) = &layer.counts {
            entries.push((
                format!("brume:count.{}", layer.name),
                text(encode_runs(counts)),
            ));
        }
    }
    for (key, value) in entries {
        other.insert(Text::from(key.as_str()), value);
    }
}

/// Reads a film written by [`write_film_exr`]; any other EXR is refused by name.
pub fn read_film_exr(path: &Path) -> Result<Film> {
    let bad = |message: String| Error::Input {
        path: path.to_path_buf(),
        message,
    };
    super::check_input(path, "EXR")?;
    super::header::check_exr(path, super::header::Keep::AllChannels)?;
    let image = exr::prelude::read_all_flat_layers_from_file(path)
        .map_err(|e| bad(format!("cannot read EXR: {e}")))?;
    let main = image
        .layer_data
        .first()
        .ok_or_else(|| bad("the EXR holds no image".into()))?;
    let header = Header {
        layer: &main.attributes.other,
        shared: &image.attributes.other,
    };
    let provenance = header.provenance().map_err(&bad)?;
    let (display, window) = windows(
        image.attributes.display_window,
        main.attributes.layer_position,
        main.size,
    )
    .map_err(&bad)?;
    let mut film = Film::new(display, window, provenance);
    film.adaptive = header.text("brume:adaptive").ok();
    read_counts(&mut film, &header).map_err(&bad)?;
    let splat_part = image.layer_data.iter().find(|l| {
        l.attributes
            .layer_name
            .as_ref()
            .is_some_and(|n| n.eq(SPLATS))
    });
    let splat_image = match splat_part {
        Some(part) => Some(read_splats(&mut film, part).map_err(&bad)?),
        None => None,
    };
    read_means(&mut film, &main.channel_data.list, splat_image.as_deref()).map_err(&bad)?;
    Ok(film)
}

type Found<T> = std::result::Result<T, String>;

/// The display size and the data window, checked against each other.
fn windows(display: IntegerBounds, pos: Vec2<i32>, size: Vec2<usize>) -> Found<((u32, u32), Rect)> {
    if display.position != Vec2(0, 0) || pos.0 < 0 || pos.1 < 0 {
        return Err("the display window must start at pixel 0,0".into());
    }
    // Scenes are at most 32768 pixels a side; a larger window is a damaged header.
    if display.size.0 > 32768 || display.size.1 > 32768 {
        return Err(format!(
            "display window {}x{} is larger than brume renders (32768 a side)",
            display.size.0, display.size.1
        ));
    }
    let display = (display.size.0 as u32, display.size.1 as u32);
    let window = Rect {
        x0: pos.0 as u32,
        x1: pos.0 as u32 + size.0 as u32,
        y0: pos.1 as u32,
        y1: pos.1 as u32 + size.1 as u32,
    };
    if !Rect::full(display.0, display.1).contains(&window) {
        return Err(format!(
            "data window {window} lies outside the display window"
        ));
    }
    Ok((display, window))
}

/// The per-pixel counts of the beauty and of every AOV layer named in the header.
fn read_counts(film: &mut Film, header: &Header) -> Found<()> {
    let n = film.window.area();
    film.counts = header.runs("brume:count", n)?;
    film.nonfinite = header.runs("brume:nonfinite", n)?;
    let names = header.text("brume:layers")?;
    for name in names.split(',').filter(|s| !s.is_empty()) {
        let aov = Aov::from_name(name)
            .ok_or_else(|| format!("brume:layers names an unknown layer `{name}`"))?;
        let counts = header.runs(&format!("brume:count.{name}"), n)?;
        let layer = film
            .add_aov(aov)
            .ok_or_else(|| format!("brume:layers names `{name}` twice"))?;
        layer.counts = Some(counts);
    }
    Ok(())
}

/// The splat sums from the `splats` part; returns its values (the splat
/// part of each display pixel).
fn read_splats(film: &mut Film, part: &ExrLayer<AnyChannels<FlatSamples>>) -> Found<Vec<[f32; 3]>> {
    let (w, h) = film.display;
    if part.attributes.layer_position != Vec2(0, 0) || part.size != Vec2(w as usize, h as usize) {
        return Err(format!(
            "the {SPLATS} part does not cover the display window {w}x{h}"
        ));
    }
    let list = &part.channel_data.list;
    let rgb = [f32s(list, "R")?, f32s(list, "G")?, f32s(list, "B")?];
    let spp = film.provenance.spp_held().max(1) as f64;
    film.add_splats();
    let splats = film.splats.as_mut().expect("just added");
    let mut values = Vec::with_capacity(rgb[0].len());
    for (i, sums) in splats.sums.chunks_mut(3).enumerate() {
        let v = [rgb[0][i], rgb[1][i], rgb[2][i]];
        for c in 0..3 {
            sums[c] = v[c] as f64 * spp;
        }
        values.push(v);
    }
    Ok(values)
}

/// Every layer's sums from its means and counts (the beauty's mean is its
/// pixel less its splat part).
fn read_means(
    film: &mut Film,
    list: &[AnyChannel<FlatSamples>],
    splats: Option<&[[f32; 3]]>,
) -> Found<()> {
    let n = film.window.area();
    let beauty_counts = film.counts.clone();
    let positions: Vec<(u32, u32)> = (0..n).map(|i| film.position(i)).collect();
    let display_width = film.display.0 as usize;
    for layer in film.layers.iter_mut() {
        let k = layer.channels.len();
        for c in 0..k {
            let means = f32s(list, &layer.channels[c])?;
            for i in 0..n {
                let count = layer.counts.as_ref().map_or(beauty_counts[i], |v| v[i]);
                let mut mean = means[i] as f64;
                if let (true, Some(s)) = (layer.name.is_empty(), splats) {
                    let (x, y) = positions[i];
                    mean -= s[y as usize * display_width + x as usize][c] as f64;
                }
                // A pixel without samples holds the layer's empty value (+∞ for the depth).
                layer.sums[i * k + c] = if count == 0 { 0.0 } else { mean * count as f64 };
            }
        }
    }
    Ok(())
}

/// The f32 values of channel `name`.
fn f32s<'a>(list: &'a [AnyChannel<FlatSamples>], name: &str) -> Found<&'a [f32]> {
    let channel = list
        .iter()
        .find(|c| c.name.eq(name))
        .ok_or_else(|| format!("not a brume film: no channel {name}"))?;
    match &channel.sample_data {
        FlatSamples::F32(v) => Ok(v),
        _ => Err(format!("channel {name} is not 32-bit float")),
    }
}

/// The custom attributes of a file (readers file them per layer or shared).
struct Header<'a> {
    layer: &'a HashMap<Text, AttributeValue>,
    shared: &'a HashMap<Text, AttributeValue>,
}

impl Header<'_> {
    fn get(&self, key: &str) -> Found<&AttributeValue> {
        let k = Text::from(key);
        self.layer
            .get(&k)
            .or_else(|| self.shared.get(&k))
            .ok_or_else(|| {
                format!(
                    "not a brume film: the header has no {key} (write pieces with brume render)"
                )
            })
    }

    fn text(&self, key: &str) -> Found<String> {
        match self.get(key)? {
            AttributeValue::Text(t) => Ok(t.to_string()),
            _ => Err(format!("header attribute {key} is not text")),
        }
    }

    fn int(&self, key: &str) -> Found<u32> {
        match self.get(key)? {
            AttributeValue::I32(v) if *v >= 0 => Ok(*v as u32),
            _ => Err(format!("header attribute {key} is not a count")),
        }
    }

    fn ranges(&self, key: &str) -> Found<Vec<crate::film::SampleRange>> {
        let text = self.text(key)?;
        parse_ranges(&text)
            .ok_or_else(|| format!("header attribute {key} = `{text}` is not START..END"))
    }

    /// The `n` per-pixel counts of attribute `key`.
    fn runs(&self, key: &str, n: usize) -> Found<Vec<u32>> {
        decode_runs(&self.text(key)?, n).map_err(|e| format!("header attribute {key}: {e}"))
    }

    fn provenance(&self) -> Found<Provenance> {
        let seed = self.text("brume:seed")?;
        let hash = self.text("brume:scene_hash")?;
        Ok(Provenance {
            seed: seed
                .parse()
                .map_err(|_| format!("brume:seed = `{seed}` is not a number"))?,
            scene_hash: u64::from_str_radix(&hash, 16)
                .map_err(|_| format!("brume:scene_hash = `{hash}` is not hexadecimal"))?,
            spp_total: self.int("brume:spp_total")?,
            requested: self.ranges("brume:samples")?,
            held: self.ranges("brume:samples_held")?,
        })
    }
}

#[cfg(test)]
#[path = "film_exr_tests.rs"]
mod tests;
