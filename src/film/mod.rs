//! The film: what one `brume render` (or one piece of a split render) fills in
//! one pass over the samples and what `brume merge` adds up.
//!
//! Over a data window (a crop) inside the display window it holds, per pixel,
//! the f64 sums of the beauty's finite samples and of their squares, the
//! counts of finite and left-out samples, one layer of sums per AOV (each
//! with its own per-pixel count: the samples whose AOVs were finite, or for
//! the depth the samples that met a first vertex), and — when the integrator
//! traces from the lights — the splat sums over the whole display window.
//!
//! A layer's value is its sum over its count; the beauty's pixel adds the
//! splat sum over the samples per pixel the film holds (see [`Film::pixel`]).
//! The renderer fills a film through `render`; the EXR form is in
//! `image_io::film_exr`.

pub mod aov;
pub mod compare;
pub mod denoise;
pub mod frame_pattern;
pub mod image_io;
pub mod merge;
pub mod output_safety;
pub mod tonemap;
use crate::film::aov::Aov;
use crate::film::image_io::{Image, NamedChannel};
use crate::math::color::Rgb;
use rayon::prelude::*;

mod pixel;
mod range;
pub mod runs;
mod splat;

pub use pixel::{variance_of_mean, PixelSums};
pub use range::{
    coalesce, format_ranges, parse_range, parse_ranges, Provenance, Rect, SampleRange,
};
pub use splat::{Splat, Splats};

/// Name of the beauty layer (its channels are written as plain R, G, B).
pub const BEAUTY: &str = "";

/// One layer: f64 sums of its channels, interleaved per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// [`BEAUTY`] for the beauty, else the AOV's name (`alpha`, `depth`, ...).
    pub name: String,
    /// Its EXR channel names in order, e.g. `R`, `G`, `B` or `normal.X`, ...
    pub channels: Vec<String>,
    /// `channels.len()` sums per pixel of the data window, row-major.
    pub sums: Vec<f64>,
    /// The layer's own per-pixel denominators; None: the film's `counts`.
    pub counts: Option<Vec<u32>>,
    /// The value of a pixel without samples (+∞ for the depth, else 0).
    pub empty: f32,
}

impl Layer {
    /// The EXR channel name of channel `c`.
    pub fn channel_name(&self, c: usize) -> String {
        self.channels[c].clone()
    }

    /// The empty layer of `aov` over `n` pixels.
    pub fn for_aov(aov: Aov, n: usize) -> Layer {
        let channels = aov.channels();
        Layer {
            name: aov.name().into(),
            channels: channels.iter().map(|c| c.to_string()).collect(),
            sums: vec![0.0; channels.len() * n],
            counts: Some(vec![0; n]),
            empty: aov.empty_value(),
        }
    }

    /// The AOV this layer holds (None for the beauty).
    pub fn aov(&self) -> Option<Aov> {
        Aov::from_name(&self.name)
    }

    /// The same layer with zero sums and counts over `n` pixels.
    pub fn emptied(&self, n: usize) -> Layer {
        Layer {
            name: self.name.clone(),
            channels: self.channels.clone(),
            sums: vec![0.0; self.channels.len() * n],
            counts: self.counts.as_ref().map(|_| vec![0; n]),
            empty: self.empty,
        }
    }
}

/// Per-pixel sums and counts over a data window inside a display window.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Display window size: the full frame.
    pub display: (u32, u32),
    /// Data window: the pixels this film holds.
    pub window: Rect,
    /// Finite beauty samples summed per pixel (the beauty's denominator).
    pub counts: Vec<u32>,
    /// NaN or infinite beauty samples left out per pixel.
    pub nonfinite: Vec<u32>,
    /// Sums of the squared beauty samples, 3 per pixel, for the per-pixel
    /// variance; a render keeps them, a film read from an EXR has none.
    pub squares: Option<Vec<f64>>,
    /// Layers; `layers[0]` is the beauty, then one per AOV.
    pub layers: Vec<Layer>,
    /// Splat sums over the display window, when the integrator splats.
    pub splats: Option<Splats>,
    /// Seed, scene and sample ranges.
    pub provenance: Provenance,
    /// A piloted render's note (`brume:adaptive`): its pixels hold different
    /// sample counts, so `merge` refuses it. None for a uniform render.
    pub adaptive: Option<String>,
}

impl Film {
    /// An empty film (zero sums) over `window` with a beauty layer only.
    pub fn new(display: (u32, u32), window: Rect, provenance: Provenance) -> Film {
        let n = window.area();
        Film {
            display,
            window,
            counts: vec![0; n],
            nonfinite: vec![0; n],
            squares: None,
            layers: vec![Layer {
                name: BEAUTY.into(),
                channels: vec!["R".into(), "G".into(), "B".into()],
                sums: vec![0.0; 3 * n],
                counts: None,
                empty: 0.0,
            }],
            splats: None,
            provenance,
            adaptive: None,
        }
    }

    /// Adds the layer of `aov`; refuses one already there.
    pub fn add_aov(&mut self, aov: Aov) -> Option<&mut Layer> {
        if self.layer(aov.name()).is_some() {
            return None;
        }
        self.layers.push(Layer::for_aov(aov, self.window.area()));
        self.layers.last_mut()
    }

    /// Adds the splat sums over the display window.
    pub fn add_splats(&mut self) {
        self.splats = Some(Splats::new(self.display.0, self.display.1));
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

    /// Display pixel of index `i` of the data window.
    pub fn position(&self, i: usize) -> (u32, u32) {
        let w = self.window.width() as usize;
        (
            self.window.x0 + (i % w) as u32,
            self.window.y0 + (i / w) as u32,
        )
    }

    /// The denominator of `layer` at pixel index `i`.
    pub fn count(&self, layer: &Layer, i: usize) -> u32 {
        match &layer.counts {
            Some(counts) => counts[i],
            None => self.counts[i],
        }
    }

    /// Mean of channel `c` of `layer` at pixel index `i` (the layer's empty
    /// value without samples); the beauty's mean leaves the splats out.
    pub fn mean(&self, layer: &Layer, i: usize, c: usize) -> f32 {
        let n = self.count(layer, i);
        if n == 0 {
            return layer.empty;
        }
        (layer.sums[i * layer.channels.len() + c] / n as f64) as f32
    }

    /// The means of every channel of `layer`, one vector per channel, equal
    /// to [`Film::mean`] pixel by pixel. One parallel pass over the pixels
    /// reads each pixel's sums and count once: after a stop with AOVs at
    /// 4096² this stands between the request and the exit (a pass per
    /// channel, striding over the sums, was a third of that time).
    pub fn layer_means(&self, layer: &Layer) -> Vec<Vec<f32>> {
        /// Pixels per task.
        const CHUNK: usize = 1 << 14;
        let k = layer.channels.len();
        let n = self.window.area();
        let counts = layer.counts.as_deref().unwrap_or(&self.counts);
        let mut outs = vec![vec![0.0f32; n]; k];
        let mut tasks: Vec<Vec<&mut [f32]>> = (0..n.div_ceil(CHUNK)).map(|_| Vec::new()).collect();
        for out in outs.iter_mut() {
            for (t, chunk) in out.chunks_mut(CHUNK).enumerate() {
                tasks[t].push(chunk);
            }
        }
        tasks
            .into_par_iter()
            .enumerate()
            .for_each(|(t, mut chunks)| {
                let first = t * CHUNK;
                for j in 0..chunks[0].len() {
                    let i = first + j;
                    let sums = &layer.sums[i * k..(i + 1) * k];
                    for (c, chunk) in chunks.iter_mut().enumerate() {
                        chunk[j] = match counts[i] {
                            0 => layer.empty,
                            m => (sums[c] / m as f64) as f32,
                        };
                    }
                }
            });
        outs
    }

    /// The splat part of pixel index `i`: its splat sums over the samples
    /// per pixel held (0 without splats).
    pub fn splat_value(&self, i: usize) -> [f64; 3] {
        match &self.splats {
            None => [0.0; 3],
            Some(s) => {
                let (x, y) = self.position(i);
                let spp = self.provenance.spp_held().max(1) as f64;
                s.at(x, y).map(|v| v / spp)
            }
        }
    }

    /// The beauty of pixel index `i`: the mean of its finite samples plus
    /// its splat sum over the samples per pixel held, rounded once to f32.
    pub fn pixel(&self, i: usize) -> Rgb {
        let n = self.counts[i];
        let sums = &self.layers[0].sums[3 * i..3 * i + 3];
        let mut v = self.splat_value(i);
        if n > 0 {
            for c in 0..3 {
                v[c] += sums[c] / n as f64;
            }
        }
        Rgb::new(v[0] as f32, v[1] as f32, v[2] as f32)
    }

    /// Variance of the beauty mean of channel `c` at pixel index `i`, from
    /// the squared samples (None without them or below two samples).
    pub fn variance(&self, i: usize, c: usize) -> Option<f64> {
        let squares = self.squares.as_ref()?;
        variance_of_mean(
            self.layers[0].sums[3 * i + c],
            squares[3 * i + c],
            self.counts[i],
        )
    }

    /// The beauty of the data window as an image.
    pub fn beauty_image(&self) -> Image {
        Image {
            width: self.window.width() as usize,
            height: self.window.height() as usize,
            // In parallel: after a stop request this stands between the request and the exit.
            pixels: (0..self.window.area())
                .into_par_iter()
                .map(|i| self.pixel(i))
                .collect(),
            spp: self.provenance.spp_held(),
            partial: !self.provenance.complete(),
        }
    }

    /// The image of a film that holds no sample yet: black, like its
    /// [`Film::beauty_image`], without reading the film.
    pub fn black_image(&self) -> Image {
        Image {
            width: self.window.width() as usize,
            height: self.window.height() as usize,
            pixels: (0..self.window.area())
                .into_par_iter()
                .map(|_| Rgb::default())
                .collect(),
            spp: 0,
            partial: true,
        }
    }

    /// The means of the AOV layers, one named channel each (EXR names).
    pub fn aov_channels(&self) -> Vec<NamedChannel> {
        let mut out = Vec::new();
        for layer in &self.layers[1..] {
            for c in 0..layer.channels.len() {
                let values = (0..self.window.area())
                    .map(|i| self.mean(layer, i, c))
                    .collect();
                out.push((layer.channels[c].clone(), values));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
