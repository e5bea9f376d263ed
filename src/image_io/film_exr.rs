//! A film as one multi-layer EXR: the data window is the film's crop, the
//! display window the full frame, as OpenEXR intends, so pieces line up in any
//! EXR tool.
//!
//! Channels, all in one part:
//! - `R`, `G`, `B` (and `NAME.CH` for every other layer): f32 means, what a
//!   viewer shows;
//! - `brume.f64hi.CH` / `brume.f64lo.CH`: the upper and lower 32 bits of each
//!   layer channel's f64 sum (u32 channels, so the sums come back bit for bit);
//! - `brume.count` / `brume.nonfinite`: finite and left-out samples per pixel.
//!
//! Header (see [`write_film_exr`]): `brume:spp`, `brume:complete`,
//! `brume:samples`, `brume:samples_held`, `brume:spp_total`, `brume:seed`,
//! `brume:scene_hash`, `brume:layers`, `brume:version`.

use crate::error::{Error, Result};
use crate::film::{format_ranges, parse_ranges, Film, Layer, Provenance, Rect};
use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::prelude::{
    AnyChannel, AnyChannels, FlatSamples, Image as ExrImage, Layer as ExrLayer, LayerAttributes,
    SmallVec, Vec2, WritableImage,
};
use std::collections::HashMap;
use std::path::Path;

const HI: &str = "brume.f64hi.";
const LO: &str = "brume.f64lo.";
const COUNT: &str = "brume.count";
const NONFINITE: &str = "brume.nonfinite";

/// Writes `film` atomically, with its provenance in the header.
pub fn write_film_exr(path: &Path, film: &Film) -> Result<()> {
    write_film_exr_with(path, film, &[])
}

/// [`write_film_exr`] plus `extra` f32 channels (AOVs: means only, one value
/// per pixel of the data window), which `merge` does not read.
pub fn write_film_exr_with(path: &Path, film: &Film, extra: &[super::NamedChannel]) -> Result<()> {
    let w = &film.window;
    if let Some((name, _)) = extra.iter().find(|(_, v)| v.len() != w.area()) {
        return Err(super::output_error(
            path,
            format!("channel {name} does not match the image size"),
        ));
    }
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for layer in &film.layers {
        push_layer_channels(&mut channels, film, layer);
    }
    for (name, values) in extra {
        channels.push(AnyChannel::new(
            name.as_str(),
            FlatSamples::F32(values.clone()),
        ));
    }
    channels.push(AnyChannel::new(
        COUNT,
        FlatSamples::U32(film.counts.clone()),
    ));
    channels.push(AnyChannel::new(
        NONFINITE,
        FlatSamples::U32(film.nonfinite.clone()),
    ));
    let mut attributes = LayerAttributes::named("");
    attributes.layer_name = None;
    attributes.layer_position = Vec2(w.x0 as i32, w.y0 as i32);
    insert_header(&mut attributes.other, film);
    let layer = ExrLayer::new(
        (w.width() as usize, w.height() as usize),
        attributes,
        super::exr_encoding(!film.provenance.complete()),
        AnyChannels::sort(channels),
    );
    let mut image = ExrImage::from_layer(layer);
    image.attributes.display_window =
        IntegerBounds::new((0, 0), (film.display.0 as usize, film.display.1 as usize));
    super::write_atomically(path, |tmp| {
        image.write().to_file(tmp).map_err(|e| e.to_string())
    })
}

/// The mean channel and the two halves of the f64 sum of every channel of `layer`.
fn push_layer_channels(
    out: &mut SmallVec<[AnyChannel<FlatSamples>; 4]>,
    film: &Film,
    layer: &Layer,
) {
    let n = film.window.area();
    let k = layer.channels.len();
    for c in 0..k {
        let name = layer.channel_name(c);
        let means = (0..n).map(|i| film.mean(layer, i, c)).collect();
        let bits: Vec<u64> = (0..n).map(|i| layer.sums[i * k + c].to_bits()).collect();
        out.push(AnyChannel::new(name.as_str(), FlatSamples::F32(means)));
        let hi = bits.iter().map(|b| (b >> 32) as u32).collect();
        let lo = bits.iter().map(|b| *b as u32).collect();
        out.push(AnyChannel::new(
            format!("{HI}{name}").as_str(),
            FlatSamples::U32(hi),
        ));
        out.push(AnyChannel::new(
            format!("{LO}{name}").as_str(),
            FlatSamples::U32(lo),
        ));
    }
}

/// The `brume:*` header attributes of `film`.
fn insert_header(other: &mut HashMap<Text, AttributeValue>, film: &Film) {
    let p = &film.provenance;
    let int = |v: u32| AttributeValue::I32(v.min(i32::MAX as u32) as i32);
    let text = |s: String| AttributeValue::Text(Text::from(s.as_str()));
    let layers: Vec<String> = film
        .layers
        .iter()
        .map(|l| format!("{}:{}", l.name, l.channels.join(",")))
        .collect();
    let entries = [
        ("brume:spp", int(p.spp_held())),
        ("brume:complete", int(p.complete() as u32)),
        ("brume:samples", text(format_ranges(&p.requested))),
        ("brume:samples_held", text(format_ranges(&p.held))),
        ("brume:spp_total", int(p.spp_total)),
        ("brume:seed", text(p.seed.to_string())),
        ("brume:scene_hash", text(format!("{:016x}", p.scene_hash))),
        ("brume:layers", text(layers.join(";"))),
        ("brume:version", text(env!("CARGO_PKG_VERSION").to_string())),
    ];
    for (key, value) in entries {
        other.insert(Text::from(key), value);
    }
}

/// Reads a film written by [`write_film_exr`]; any other EXR is refused by name.
pub fn read_film_exr(path: &Path) -> Result<Film> {
    let bad = |message: String| Error::Input {
        path: path.to_path_buf(),
        message,
    };
    let image = exr::prelude::read_first_flat_layer_from_file(path)
        .map_err(|e| bad(format!("cannot read EXR: {e}")))?;
    let header = Header {
        layer: &image.layer_data.attributes.other,
        shared: &image.attributes.other,
    };
    let provenance = header.provenance().map_err(&bad)?;
    let display = image.attributes.display_window;
    let pos = image.layer_data.attributes.layer_position;
    let size = image.layer_data.size;
    if display.position != Vec2(0, 0) || pos.0 < 0 || pos.1 < 0 {
        return Err(bad("the display window must start at pixel 0,0".into()));
    }
    // Scenes are at most 32768 pixels a side; a larger window is a damaged header.
    if display.size.0 > 32768 || display.size.1 > 32768 {
        return Err(bad(format!(
            "display window {}x{} is larger than brume renders (32768 a side)",
            display.size.0, display.size.1
        )));
    }
    let display = (display.size.0 as u32, display.size.1 as u32);
    let window = Rect {
        x0: pos.0 as u32,
        x1: pos.0 as u32 + size.0 as u32,
        y0: pos.1 as u32,
        y1: pos.1 as u32 + size.1 as u32,
    };
    if !Rect::full(display.0, display.1).contains(&window) {
        return Err(bad(format!(
            "data window {window} lies outside the display window"
        )));
    }
    let mut film = Film::new(display, window, provenance);
    let channels = Channels(&image.layer_data.channel_data.list);
    film.counts = channels.u32(COUNT).map_err(&bad)?;
    film.nonfinite = channels.u32(NONFINITE).map_err(&bad)?;
    film.layers = header
        .layer_list()
        .map_err(&bad)?
        .into_iter()
        .map(|(name, chans)| channels.layer(name, chans, window.area()))
        .collect::<std::result::Result<_, _>>()
        .map_err(&bad)?;
    if film.layers.first().is_none_or(|l| !l.name.is_empty()) {
        return Err(bad("brume:layers does not start with the beauty".into()));
    }
    Ok(film)
}

/// The custom attributes of a file (readers file them per layer or shared).
struct Header<'a> {
    layer: &'a HashMap<Text, AttributeValue>,
    shared: &'a HashMap<Text, AttributeValue>,
}

type Found<T> = std::result::Result<T, String>;

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

    /// `:R,G,B;albedo:R,G,B` → [("", [R, G, B]), ("albedo", [R, G, B])].
    fn layer_list(&self) -> Found<Vec<(String, Vec<String>)>> {
        let text = self.text("brume:layers")?;
        text.split(';')
            .map(|entry| {
                let (name, chans) = entry
                    .split_once(':')
                    .ok_or_else(|| format!("brume:layers entry `{entry}` is not NAME:CHANNELS"))?;
                Ok((name.into(), chans.split(',').map(String::from).collect()))
            })
            .collect()
    }
}

/// The channel list of the file.
struct Channels<'a>(&'a [AnyChannel<FlatSamples>]);

impl Channels<'_> {
    fn u32(&self, name: &str) -> Found<Vec<u32>> {
        let channel = self
            .0
            .iter()
            .find(|c| c.name == *name)
            .ok_or_else(|| format!("not a brume film: no channel {name}"))?;
        match &channel.sample_data {
            FlatSamples::U32(v) => Ok(v.clone()),
            _ => Err(format!("channel {name} is not u32")),
        }
    }

    /// A layer's f64 sums put together from their two u32 halves.
    fn layer(&self, name: String, channels: Vec<String>, n: usize) -> Found<Layer> {
        let mut layer = Layer {
            name,
            channels,
            sums: Vec::new(),
        };
        let k = layer.channels.len();
        layer.sums = vec![0.0; n * k];
        for c in 0..k {
            let full = layer.channel_name(c);
            let hi = self.u32(&format!("{HI}{full}"))?;
            let lo = self.u32(&format!("{LO}{full}"))?;
            for i in 0..n {
                let bits = ((hi[i] as u64) << 32) | lo[i] as u64;
                layer.sums[i * k + c] = f64::from_bits(bits);
            }
        }
        Ok(layer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::SampleRange;

    fn piece() -> Film {
        let provenance = Provenance {
            seed: u64::MAX - 3,
            scene_hash: 0xfeed_beef_0123_4567,
            spp_total: 64,
            requested: vec![SampleRange::new(16, 32)],
            held: vec![SampleRange::new(16, 24)],
        };
        let window = Rect {
            x0: 2,
            x1: 5,
            y0: 1,
            y1: 3,
        };
        let mut film = Film::new((7, 4), window, provenance);
        for i in 0..6 {
            film.counts[i] = 8 - i as u32 % 2;
            film.nonfinite[i] = i as u32 % 2;
            for c in 0..3 {
                // Sums that f32 cannot hold: the round trip must keep every bit.
                film.layers[0].sums[3 * i + c] = 1.0 / 3.0 + i as f64 * 1e-12 + c as f64;
            }
        }
        let albedo = film.add_layer("albedo", &["R", "G", "B"]).unwrap();
        albedo
            .sums
            .iter_mut()
            .enumerate()
            .for_each(|(i, s)| *s = 0.1 * i as f64);
        film
    }

    #[test]
    fn a_film_round_trips_bit_for_bit_with_its_windows_and_header() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("piece.exr");
        let film = piece();
        write_film_exr(&path, &film).unwrap();
        let back = read_film_exr(&path).unwrap();
        assert_eq!(back, film);
        // Viewers and the RGB reader see the means of the data window.
        let (w, h, pixels) = super::super::read_exr(&path).unwrap();
        assert_eq!((w, h), (3, 2));
        assert_eq!(pixels, film.beauty_image().pixels);
    }

    #[test]
    fn an_exr_without_brume_header_is_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plain.exr");
        let image = super::super::Image {
            width: 2,
            height: 2,
            pixels: vec![crate::color::Rgb::BLACK; 4],
            spp: 1,
            partial: false,
        };
        super::super::write_exr(&path, &image).unwrap();
        let err = read_film_exr(&path).unwrap_err().to_string();
        assert!(
            err.contains("plain.exr") && err.contains("not a brume film"),
            "{err}"
        );
    }
}
