//! The render driver: rows in parallel (rayon), progressive passes,
//! time/spp budget, progress bar (indicatif) and film accumulation.
//!
//! Each pixel's samples are summed in sample order by the one task that owns
//! the pixel, and passes are added in pass order, so the image depends on the
//! seed only, never on the thread count or scheduling.

use crate::color::Rgb;
use crate::film::{Film, Provenance, Rect, SampleRange};
use crate::image_io::Image;
use crate::integrator::aov::{aov_sample, Aov, AovPixel};
use crate::integrator::tracking::{take_thread_stats, TrackingStats};
use crate::integrator::{li, Scene};
use crate::sampling::PixelStreams;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// How long and how to render.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel to reach (the scene's unless overridden).
    pub spp: u32,
    /// Wall-clock budget: keep adding passes until it is spent (spp is then only a cap if `spp_is_cap`).
    pub time_budget: Option<Duration>,
    /// With a time budget, stop at `spp` too.
    pub spp_is_cap: bool,
    /// Worker threads (None = all cores).
    pub threads: Option<usize>,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// What a render produced and how it went.
pub struct RenderOutput {
    /// The image (mean radiance per pixel of the data window).
    pub image: Image,
    /// The sums and counts behind the image, for EXR output and `merge`.
    pub film: Film,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Samples whose radiance was NaN or infinite and were left out.
    pub nonfinite_samples: u64,
    /// Total radiance samples taken.
    pub samples: u64,
    /// Tentative collisions of the media tracking, their null fraction and
    /// the rays ended by the cap (`tracking::MAX_TENTATIVE_COLLISIONS`).
    pub tracking: TrackingStats,
    /// Interior interval queries cut short by `geometry::closed::MAX_CROSSINGS`.
    pub truncated_interiors: u64,
}

/// Per-pixel running sums.
#[derive(Clone, Copy, Default)]
struct Pixel {
    sum: [f64; 3],
    count: u32,
    nonfinite: u32,
}

/// The most memory a render may hold at its peak (64 GiB): larger images are
/// refused before rendering on every machine, whatever the kernel would grant
/// (a reservation can succeed with overcommit and fail only when touched).
pub const MAX_PEAK_BYTES: u64 = 64 << 30;

/// Bytes a `width`×`height` render holds at its peak: sums, pass, film,
/// image, PNG bytes and the EXR channels (3 means, 8 words of sums and counts),
/// plus the passes a small image renders at once (at most `GROUP_PIXELS`).
pub fn peak_bytes(width: u32, height: u32) -> u64 {
    let per_pixel = 3 * std::mem::size_of::<Pixel>() + std::mem::size_of::<Rgb>() + 3 + 11 * 4;
    let pixels = width as u64 * height as u64;
    let group = (GROUP_PIXELS as u64).saturating_sub(pixels) * std::mem::size_of::<Pixel>() as u64;
    pixels * per_pixel as u64 + group
}

impl Pixel {
    /// Adds one radiance sample; a NaN or infinite one is only counted, so it
    /// cannot spread into the pixel (or, through filtering, its neighbours).
    fn add(&mut self, l: Rgb) {
        if l.is_finite() {
            self.sum[0] += l.r as f64;
            self.sum[1] += l.g as f64;
            self.sum[2] += l.b as f64;
            self.count += 1;
        } else {
            self.nonfinite += 1;
        }
    }

    /// Adds another pass's sums for the same pixel.
    fn merge(&mut self, other: &Pixel) {
        for c in 0..3 {
            self.sum[c] += other.sum[c];
        }
        self.count += other.count;
        self.nonfinite += other.nonfinite;
    }

    /// Mean of the finite samples (black if there were none).
    fn mean(&self) -> Rgb {
        if self.count == 0 {
            return Rgb::BLACK;
        }
        let n = self.count as f64;
        Rgb::new(
            (self.sum[0] / n) as f32,
            (self.sum[1] / n) as f32,
            (self.sum[2] / n) as f32,
        )
    }
}

/// Which part of the film a render fills: a crop and a sample range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Part {
    /// Pixels to render (the data window).
    pub crop: Rect,
    /// Sample indices to take in every pixel.
    pub samples: SampleRange,
}

impl Part {
    /// The whole frame of `scene` at `spp` samples per pixel.
    pub fn whole(scene: &Scene, spp: u32) -> Part {
        Part {
            crop: Rect::full(scene.camera.width(), scene.camera.height()),
            samples: SampleRange::new(0, spp),
        }
    }
}

/// Renders `scene`; stops early (keeping finished passes) once `cancel` is set.
pub fn render(scene: &Scene, options: &RenderOptions, cancel: &AtomicBool) -> RenderOutput {
    render_part(
        scene,
        options,
        &Part::whole(scene, options.spp),
        cancel,
        None,
    )
}

/// Called after every finished pass with the image so far (marked partial).
pub type PassObserver<'a> = &'a mut (dyn FnMut(&Image) + Send);

/// [`render`], showing the image so far to `on_pass` after every finished pass
/// (live preview, checkpoints); the result does not depend on the observer.
pub fn render_observed(
    scene: &Scene,
    options: &RenderOptions,
    cancel: &AtomicBool,
    on_pass: Option<PassObserver>,
) -> RenderOutput {
    render_part(
        scene,
        options,
        &Part::whole(scene, options.spp),
        cancel,
        on_pass,
    )
}

/// Renders sample indices `part.samples` of the pixels in `part.crop` only
/// (`options.spp` is then the spp of the whole render the part belongs to),
/// showing the image so far to `on_pass` after every finished pass.
pub fn render_part(
    scene: &Scene,
    options: &RenderOptions,
    part: &Part,
    cancel: &AtomicBool,
    on_pass: Option<PassObserver>,
) -> RenderOutput {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads.unwrap_or(0))
        .build()
        .expect("thread pool");
    let spp_total = options.spp;
    let options = RenderOptions {
        spp: part.samples.len(),
        ..options.clone()
    };
    let timed = options.time_budget.is_some();
    let mut out = pool.install(|| render_in_pool(scene, &options, part, cancel, on_pass));
    // A timed render's size is what it reached; a piece belongs to a render of `spp_total`.
    if !timed {
        let provenance = &mut out.film.provenance;
        provenance.spp_total = provenance.spp_total.max(spp_total);
    }
    out
}

fn render_in_pool(
    scene: &Scene,
    options: &RenderOptions,
    part: &Part,
    cancel: &AtomicBool,
    mut on_pass: Option<PassObserver>,
) -> RenderOutput {
    let (w, h) = (part.crop.width() as usize, part.crop.height() as usize);
    let (x0, y0, first) = (part.crop.x0, part.crop.y0, part.samples.start);
    let mut film = vec![Pixel::default(); w * h];
    let start = Instant::now();
    let pass_spp = pass_size(options);
    let bar = progress_bar(options, h as u64);
    let mut spp_done = 0u32;
    let mut partial = false;
    let mut counts_so_far = RayCounts::default();
    let mut passes: Vec<Pixel> = Vec::new();
    loop {
        let budget_left = match options.time_budget {
            // A time budget always gets its first pass: no render ends with 0 samples.
            Some(t) => {
                (spp_done == 0 || start.elapsed() < t)
                    && (!options.spp_is_cap || spp_done < options.spp)
            }
            None => spp_done < options.spp,
        };
        if !budget_left {
            break;
        }
        if cancel.load(Ordering::Relaxed) {
            partial = true;
            break;
        }
        let counts = group_counts(options, pass_spp, spp_done, on_pass.is_some(), w * h);
        passes.clear();
        passes.resize(counts.len() * w * h, Pixel::default());
        let group = Group {
            scene,
            w,
            h,
            origin: (x0, y0),
            first: first + spp_done,
            counts: &counts,
            cancel,
            bar: &bar,
        };
        let (finished, ray_counts) = group.render(&mut passes);
        counts_so_far.merge(ray_counts);
        // A pass cut short is dropped whole, so every pixel of the image has
        // exactly `spp_done` samples; a pass that finished is kept even if the
        // stop request came in just after its last row.
        for (k, pass) in passes.chunks(w * h).take(finished).enumerate() {
            for (f, p) in film.iter_mut().zip(pass) {
                f.merge(p);
            }
            spp_done += counts[k];
            if let Some(observe) = on_pass.as_mut() {
                observe(&Image {
                    width: w,
                    height: h,
                    pixels: film.par_iter().map(Pixel::mean).collect(),
                    spp: spp_done,
                    partial: true,
                });
            }
        }
        bar.set_message(format!("{spp_done} spp"));
        if finished < counts.len() {
            partial = true;
            break;
        }
    }
    bar.finish_and_clear();
    let nonfinite: u64 = film.iter().map(|p| p.nonfinite as u64).sum();
    // In parallel: after a stop request this stands between the request and the exit.
    let pixels = film.par_iter().map(Pixel::mean).collect();
    let held = SampleRange::new(first, first + spp_done);
    RenderOutput {
        image: Image {
            width: w,
            height: h,
            pixels,
            spp: spp_done,
            partial,
        },
        film: to_film(scene, part, held, partial, &film),
        elapsed: start.elapsed(),
        nonfinite_samples: nonfinite,
        samples: spp_done as u64 * (w * h) as u64,
        tracking: counts_so_far.tracking,
        truncated_interiors: counts_so_far.truncated_interiors,
    }
}

/// Pixels of pass buffers a group of passes may hold at once (32 MiB of sums).
const GROUP_PIXELS: usize = 1 << 20;

/// The spp of each pass of the next group: one pass with a time budget or an
/// observer (they look at the image after every pass), otherwise as many as
/// fit in `GROUP_PIXELS`, so that the threads meet once per group instead of
/// once per pass (each meeting idles all but the slowest thread).
fn group_counts(
    options: &RenderOptions,
    pass_spp: u32,
    spp_done: u32,
    observed: bool,
    pixels: usize,
) -> Vec<u32> {
    if options.time_budget.is_some() {
        let count = match options.spp_is_cap {
            true => pass_spp.min(options.spp - spp_done),
            false => pass_spp,
        };
        return vec![count];
    }
    let most = if observed {
        1
    } else {
        (GROUP_PIXELS / pixels.max(1)).max(1)
    };
    let mut counts = Vec::new();
    let mut done = spp_done;
    while done < options.spp && counts.len() < most {
        let count = pass_spp.min(options.spp - done);
        counts.push(count);
        done += count;
    }
    counts
}

/// One parallel job over several passes: each work item is one row of one pass.
struct Group<'a> {
    scene: &'a Scene,
    w: usize,
    h: usize,
    /// Top-left pixel of the crop.
    origin: (u32, u32),
    /// Index of the first sample of the first pass.
    first: u32,
    /// Samples of each pass.
    counts: &'a [u32],
    cancel: &'a AtomicBool,
    bar: &'a ProgressBar,
}

impl Group<'_> {
    /// Fills `passes` (one `w`×`h` buffer per pass, in pass order); returns
    /// how many leading passes finished every row, and what their rays ran into.
    fn render(&self, passes: &mut [Pixel]) -> (usize, RayCounts) {
        let rows_done: Vec<AtomicUsize> = self.counts.iter().map(|_| AtomicUsize::new(0)).collect();
        let firsts: Vec<u32> = self
            .counts
            .iter()
            .scan(self.first, |next, &c| {
                let f = *next;
                *next += c;
                Some(f)
            })
            .collect();
        let stats = passes
            .par_chunks_mut(self.w)
            // Rayon otherwise splits the rows into a few large blocks only
            // (one level per thread) and a thread that finishes its block
            // early finds nothing left to steal: the last pass of a group
            // is often shorter, so its block is cheaper (B4 at 87 spp: 1.80×
            // on two threads, 1.97× with small blocks).
            .with_max_len(4)
            .enumerate()
            .map(|(item, row)| {
                let (k, y) = (item / self.h, item % self.h);
                if self.cancel.load(Ordering::Relaxed) {
                    return RayCounts::default();
                }
                // An item runs on one thread from start to end: its counts are the thread's.
                RayCounts::take_thread();
                let (x0, y0) = self.origin;
                for (x, px) in row.iter_mut().enumerate() {
                    let (px_x, px_y) = (x0 + x as u32, y0 + y as u32);
                    match render_pixel(
                        self.scene,
                        px_x,
                        px_y,
                        firsts[k],
                        self.counts[k],
                        self.cancel,
                    ) {
                        Some(p) => *px = p,
                        // Stopped: the row is not counted, so its pass is dropped.
                        None => return RayCounts::default(),
                    }
                }
                rows_done[k].fetch_add(1, Ordering::Relaxed);
                self.bar.inc(1);
                RayCounts::take_thread()
            })
            .reduce(RayCounts::default, |mut a, b| {
                a.merge(b);
                a
            });
        let finished = rows_done
            .iter()
            .take_while(|r| r.load(Ordering::Relaxed) == self.h)
            .count();
        (finished, stats)
    }
}

/// What the rays of a render ran into, counted per thread and merged: a
/// render reports its own rays only, whatever else runs in the process.
#[derive(Clone, Copy, Default)]
struct RayCounts {
    tracking: TrackingStats,
    truncated_interiors: u64,
}

impl RayCounts {
    /// Takes (and resets) this thread's counts.
    fn take_thread() -> RayCounts {
        RayCounts {
            tracking: take_thread_stats(),
            truncated_interiors: crate::medium::interior::take_thread_truncated_queries(),
        }
    }

    fn merge(&mut self, other: RayCounts) {
        self.tracking.merge(other.tracking);
        self.truncated_interiors += other.truncated_interiors;
    }
}

/// The film of `part` holding the sums in `pixels` (samples `held` of each pixel).
fn to_film(scene: &Scene, part: &Part, held: SampleRange, partial: bool, pixels: &[Pixel]) -> Film {
    let display = (scene.camera.width(), scene.camera.height());
    // A timed render asks for what it reaches; only a stopped one falls short.
    let requested = match partial {
        true => SampleRange::new(part.samples.start, part.samples.end.max(held.end)),
        false => held,
    };
    let provenance = Provenance {
        seed: scene.settings.seed,
        scene_hash: 0,
        spp_total: requested.end,
        requested: vec![requested],
        held: if held.is_empty() { vec![] } else { vec![held] },
    };
    let mut film = Film::new(display, part.crop, provenance);
    for (i, p) in pixels.iter().enumerate() {
        film.counts[i] = p.count;
        film.nonfinite[i] = p.nonfinite;
        film.layers[0].sums[3 * i..3 * i + 3].copy_from_slice(&p.sum);
    }
    film
}

/// Samples per pass: all at once without a time budget (in chunks for progress), small passes with one.
fn pass_size(options: &RenderOptions) -> u32 {
    match options.time_budget {
        Some(_) => 4,
        None => options.spp.clamp(1, 16),
    }
}

fn progress_bar(options: &RenderOptions, rows: u64) -> ProgressBar {
    if !options.progress {
        return ProgressBar::hidden();
    }
    let bar = match options.time_budget {
        // The length of a timed render is unknown: show a spinner with rates.
        Some(_) => ProgressBar::new_spinner(),
        None => ProgressBar::new(rows * options.spp.div_ceil(pass_size(options)) as u64),
    };
    bar.set_draw_target(ProgressDrawTarget::stderr());
    let template = if options.time_budget.is_some() {
        "{spinner} {elapsed_precise} {msg}"
    } else {
        "{bar:40} {percent:>3}% {elapsed_precise} eta {eta} {msg}"
    };
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Sums `count` samples of pixel (x, y) starting at sample index `first`;
/// `None` once `cancel` is set (checked before every sample, so a stop
/// request is seen within one sample's time whatever the scene).
fn render_pixel(
    scene: &Scene,
    x: u32,
    y: u32,
    first: u32,
    count: u32,
    cancel: &AtomicBool,
) -> Option<Pixel> {
    let mut px = Pixel::default();
    let streams = scene.settings.pixel_streams(x, y);
    for s in first..first + count {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        px.add(stream_sample(scene, x, y, &streams, s));
    }
    Some(px)
}

/// Radiance of sample `s` of pixel (x, y): the same value whatever renders it.
pub fn pixel_sample(scene: &Scene, x: u32, y: u32, s: u32) -> Rgb {
    stream_sample(scene, x, y, &scene.settings.pixel_streams(x, y), s)
}

/// [`pixel_sample`] given the pixel's streams, hashed once for all its samples.
fn stream_sample(scene: &Scene, x: u32, y: u32, streams: &PixelStreams, s: u32) -> Rgb {
    let mut sampler = streams.sampler(s as u64);
    // The time sits at a reserved position of the stream: drawing it first moves no other number.
    let time = match scene.settings.shutter {
        Some(_) => scene.settings.sample_time(sampler.time_1d()),
        None => 0.0,
    };
    let ray = scene.camera.sample_ray_at(x, y, time, &mut sampler);
    li(scene, ray, &mut sampler)
}

/// Per-pixel means of `aovs` over samples `0..spp` (the beauty's camera rays,
/// the AOV streams): one named channel per entry of each `Aov::channels`.
pub fn render_aovs(
    scene: &Scene,
    aovs: &[Aov],
    spp: u32,
    threads: Option<usize>,
) -> Vec<(String, Vec<f32>)> {
    let (w, h) = (
        scene.camera.width() as usize,
        scene.camera.height() as usize,
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .expect("thread pool");
    let mut film = vec![AovPixel::default(); w * h];
    pool.install(|| {
        film.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, px) in row.iter_mut().enumerate() {
                let (x, y) = (x as u32, y as u32);
                let beauty = scene.settings.pixel_streams(x, y);
                for s in 0..spp {
                    px.add(&aov_sample(scene, x, y, &beauty, s));
                }
            }
        })
    });
    let mut out = Vec::new();
    let mut values = Vec::with_capacity(3);
    for &aov in aovs {
        let mut channels: Vec<Vec<f32>> = vec![Vec::with_capacity(w * h); aov.channels().len()];
        for px in &film {
            values.clear();
            px.value(aov, &mut values);
            for (c, v) in channels.iter_mut().zip(&values) {
                c.push(*v);
            }
        }
        for (name, data) in aov.channels().iter().zip(channels) {
            out.push((name.to_string(), data));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nonfinite_samples_are_counted_and_left_out() {
        let mut px = Pixel::default();
        for l in [
            Rgb::new(1.0, 2.0, 3.0),
            Rgb::new(f32::NAN, 0.0, 0.0),
            Rgb::new(0.0, f32::INFINITY, 0.0),
            Rgb::new(0.0, 0.0, f32::NEG_INFINITY),
            Rgb::new(3.0, 2.0, 1.0),
        ] {
            px.add(l);
        }
        assert_eq!((px.count, px.nonfinite), (2, 3));
        assert_eq!(px.mean(), Rgb::new(2.0, 2.0, 2.0));
        let mut film = Pixel::default();
        film.merge(&px);
        film.merge(&px);
        assert_eq!((film.count, film.nonfinite), (4, 6));
        assert_eq!(film.mean(), Rgb::new(2.0, 2.0, 2.0));
    }

    #[test]
    fn a_pixel_of_only_nonfinite_samples_is_black_not_nan() {
        let mut px = Pixel::default();
        px.add(Rgb::new(f32::NAN, f32::NAN, f32::NAN));
        assert_eq!(px.mean(), Rgb::BLACK);
        assert_eq!(px.nonfinite, 1);
    }
}
