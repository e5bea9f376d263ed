//! The film: per-pixel f64 sums of every layer and sample counts over a data
//! window (a crop) inside the display window, with the sample range rendered.
//!
//! A film is what one `brume render` (or one piece of a split render) fills and
//! what `brume merge` adds up. Its layers are sums over the finite samples of
//! each pixel; a layer's value is its sum divided by the pixel's `count`. The
//! beauty is layer [`BEAUTY`]; more named layers (AOVs) sit beside it under
//! their own names, and the EXR writer and `merge` handle every layer alike. A
//! layer that needs another denominator than the sample count carries it as
//! one of its own channels.
//!
//! In the EXR a layer's channels are `NAME.CH` (the beauty's bare `R`, `G`,
//! `B`); a bare channel such as `A` is a channel added to the beauty layer.

pub mod compare;
pub mod denoise;
pub mod image_io;
pub mod merge;
pub mod tonemap;

use crate::film::image_io::Image;
use crate::math::color::Rgb;
use std::fmt;

/// Name of the beauty layer (its channels are written as plain R, G, B).
pub const BEAUTY: &str = "";

/// One light-tracing contribution landing on display pixel (`x`, `y`): radiance
/// summed into the film's splat layer, divided like the beauty by the samples
/// per pixel of the pass (not by the pixel's own count). Integrators that trace
/// from the lights (bidirectional, photon, Metropolis) hand these to the film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Display column.
    pub x: u32,
    /// Display row (0 at the top).
    pub y: u32,
    /// Radiance, already weighted (MIS, pdfs, importance).
    pub radiance: Rgb,
}

/// A half-open rectangle of pixels, x0..x1 by y0..y1, row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Rect {
    /// The whole `width`×`height` frame.
    pub fn full(width: u32, height: u32) -> Rect {
        Rect {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Number of pixels.
    pub fn area(&self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// True when `other` lies inside this rectangle.
    pub fn contains(&self, other: &Rect) -> bool {
        other.x0 >= self.x0 && other.x1 <= self.x1 && other.y0 >= self.y0 && other.y1 <= self.y1
    }

    /// True when the two rectangles share a pixel.
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }
}

impl fmt::Display for Rect {
    /// The `--crop` form: x0,x1,y0,y1.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// A half-open range of sample indices, start..end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct SampleRange {
    /// First sample index.
    pub start: u32,
    /// One past the last sample index.
    pub end: u32,
}

impl SampleRange {
    /// The range start..end.
    pub fn new(start: u32, end: u32) -> SampleRange {
        SampleRange { start, end }
    }

    /// Number of sample indices.
    pub fn len(&self) -> u32 {
        self.end.saturating_sub(self.start)
    }

    /// True when the range holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True when the two ranges share a sample index.
    pub fn overlaps(&self, other: &SampleRange) -> bool {
        self.start < other.end && other.start < self.end
    }
}

impl fmt::Display for SampleRange {
    /// The `--samples` form: START..END.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}..{}", self.start, self.end)
    }
}

/// Writes ranges as `0..16,32..48` (the header form).
pub fn format_ranges(ranges: &[SampleRange]) -> String {
    let parts: Vec<String> = ranges.iter().map(|r| r.to_string()).collect();
    parts.join(",")
}

/// Parses `START..END`; None unless both are integers with START < END.
pub fn parse_range(text: &str) -> Option<SampleRange> {
    let (a, b) = text.trim().split_once("..")?;
    let range = SampleRange::new(a.trim().parse().ok()?, b.trim().parse().ok()?);
    (range.start < range.end).then_some(range)
}

/// Parses the header form `0..16,32..48` (empty text: no range).
pub fn parse_ranges(text: &str) -> Option<Vec<SampleRange>> {
    if text.trim().is_empty() {
        return Some(Vec::new());
    }
    text.split(',').map(parse_range).collect()
}

/// Sorts ranges and joins the ones that touch: `16..32,0..16` → `0..32`.
pub fn coalesce(ranges: &mut Vec<SampleRange>) {
    ranges.retain(|r| !r.is_empty());
    ranges.sort();
    let mut out: Vec<SampleRange> = Vec::with_capacity(ranges.len());
    for r in ranges.drain(..) {
        match out.last_mut() {
            Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
            _ => out.push(r),
        }
    }
    *ranges = out;
}

/// One named layer: f64 sums of its channels, interleaved per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Layer name ([`BEAUTY`] for the beauty), written as the EXR channel prefix.
    pub name: String,
    /// Channel names in order, e.g. R, G, B.
    pub channels: Vec<String>,
    /// `channels.len()` sums per pixel of the data window, row-major.
    pub sums: Vec<f64>,
}

impl Layer {
    /// The EXR channel name of channel `c`: `R` for the beauty, `albedo.R` for others.
    pub fn channel_name(&self, c: usize) -> String {
        if self.name.is_empty() {
            self.channels[c].clone()
        } else {
            format!("{}.{}", self.name, self.channels[c])
        }
    }
}

/// Where a film comes from: what must agree for two films to be merged.
#[derive(Clone, Debug, PartialEq)]
pub struct Provenance {
    /// Seed of the random streams.
    pub seed: u64,
    /// Hash of the scene file, the files it read and the settings that change samples.
    pub scene_hash: u64,
    /// Samples per pixel of the whole render the film is a piece of.
    pub spp_total: u32,
    /// Sample ranges the film was asked to hold, coalesced.
    pub requested: Vec<SampleRange>,
    /// Sample ranges the film holds (less than `requested` if interrupted), coalesced.
    pub held: Vec<SampleRange>,
}

impl Provenance {
    /// True when the film holds every sample it was asked for.
    pub fn complete(&self) -> bool {
        self.held == self.requested
    }

    /// Samples held per pixel.
    pub fn spp_held(&self) -> u32 {
        self.held.iter().map(SampleRange::len).sum()
    }
}

/// Per-pixel sums and counts over a data window inside a display window.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Display window size: the full frame.
    pub display: (u32, u32),
    /// Data window: the pixels this film holds.
    pub window: Rect,
    /// Finite samples summed per pixel (the denominator of every layer).
    pub counts: Vec<u32>,
    /// NaN or infinite samples left out per pixel.
    pub nonfinite: Vec<u32>,
    /// Layers; `layers[0]` is the beauty.
    pub layers: Vec<Layer>,
    /// Seed, scene and sample ranges.
    pub provenance: Provenance,
}

impl Film {
    /// An empty film (zero sums) over `window` with a beauty layer.
    pub fn new(display: (u32, u32), window: Rect, provenance: Provenance) -> Film {
        let n = window.area();
        Film {
            display,
            window,
            counts: vec![0; n],
            nonfinite: vec![0; n],
            layers: vec![Layer {
                name: BEAUTY.into(),
                channels: vec!["R".into(), "G".into(), "B".into()],
                sums: vec![0.0; 3 * n],
            }],
            provenance,
        }
    }

    /// Adds a layer of `channels` zero sums; refuses a name already taken.
    pub fn add_layer(&mut self, name: &str, channels: &[&str]) -> Option<&mut Layer> {
        if self.layer(name).is_some() || channels.is_empty() {
            return None;
        }
        self.layers.push(Layer {
            name: name.into(),
            channels: channels.iter().map(|c| c.to_string()).collect(),
            sums: vec![0.0; channels.len() * self.window.area()],
        });
        self.layers.last_mut()
    }

    /// The layer called `name`.
    pub fn layer(&self, name: &str) -> Option<&Layer> {
        self.layers.iter().find(|l| l.name == name)
    }

    /// The layer called `name`, to accumulate into.
    pub fn layer_mut(&mut self, name: &str) -> Option<&mut Layer> {
        self.layers.iter_mut().find(|l| l.name == name)
    }

    /// Index into the per-pixel vectors of display pixel (x, y), if inside the window.
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        let w = &self.window;
        (x >= w.x0 && x < w.x1 && y >= w.y0 && y < w.y1)
            .then(|| (y - w.y0) as usize * w.width() as usize + (x - w.x0) as usize)
    }

    /// Mean of channel `c` of `layer` at pixel index `i` (0 without finite samples).
    pub fn mean(&self, layer: &Layer, i: usize, c: usize) -> f32 {
        let n = self.counts[i];
        if n == 0 {
            return 0.0;
        }
        (layer.sums[i * layer.channels.len() + c] / n as f64) as f32
    }

    /// The beauty means as an image of the data window.
    pub fn beauty_image(&self) -> Image {
        let beauty = &self.layers[0];
        let pixels = (0..self.window.area())
            .map(|i| {
                Rgb::new(
                    self.mean(beauty, i, 0),
                    self.mean(beauty, i, 1),
                    self.mean(beauty, i, 2),
                )
            })
            .collect();
        Image {
            width: self.window.width() as usize,
            height: self.window.height() as usize,
            pixels,
            spp: self.provenance.spp_held(),
            partial: !self.provenance.complete(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_format_and_coalesce() {
        assert_eq!(parse_range("16..32"), Some(SampleRange::new(16, 32)));
        assert_eq!(parse_range("32..16"), None);
        assert_eq!(parse_range("5..5"), None);
        assert_eq!(parse_range("a..4"), None);
        let mut r = parse_ranges("32..48,0..16,16..20").unwrap();
        coalesce(&mut r);
        assert_eq!(format_ranges(&r), "0..20,32..48");
        assert_eq!(parse_ranges("").unwrap(), vec![]);
        assert!(SampleRange::new(0, 16).overlaps(&SampleRange::new(15, 20)));
        assert!(!SampleRange::new(0, 16).overlaps(&SampleRange::new(16, 20)));
    }

    #[test]
    fn rects_index_and_overlap() {
        let film = Film::new(
            (8, 6),
            Rect {
                x0: 2,
                x1: 5,
                y0: 1,
                y1: 3,
            },
            Provenance {
                seed: 0,
                scene_hash: 0,
                spp_total: 1,
                requested: vec![SampleRange::new(0, 1)],
                held: vec![],
            },
        );
        assert_eq!(film.index(2, 1), Some(0));
        assert_eq!(film.index(4, 2), Some(5));
        assert_eq!(film.index(5, 2), None);
        assert_eq!(film.index(1, 1), None);
        assert!(!film.provenance.complete());
        let a = Rect::full(4, 4);
        let b = Rect {
            x0: 4,
            x1: 6,
            y0: 0,
            y1: 4,
        };
        assert!(!a.overlaps(&b));
        assert!(Rect::full(8, 8).contains(&b));
    }

    #[test]
    fn layers_have_unique_names() {
        let mut film = Film::new(
            (2, 2),
            Rect::full(2, 2),
            Provenance {
                seed: 0,
                scene_hash: 0,
                spp_total: 1,
                requested: vec![],
                held: vec![],
            },
        );
        assert!(film.add_layer("albedo", &["R", "G", "B"]).is_some());
        assert!(film.add_layer("albedo", &["R"]).is_none());
        assert!(film.add_layer(BEAUTY, &["R"]).is_none());
        assert_eq!(film.layer("albedo").unwrap().sums.len(), 12);
        assert_eq!(film.layer("albedo").unwrap().channel_name(1), "albedo.G");
        assert_eq!(film.layers[0].channel_name(2), "B");
    }
}
