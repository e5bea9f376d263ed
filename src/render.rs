//! The render driver: row bands in parallel (rayon), progressive passes,
//! time/spp budget, progress bar (indicatif) and film accumulation.
//!
//! Each pixel's samples are summed in sample order by the one task that owns
//! the pixel, and passes are added in pass order, so the image depends on the
//! seed only, never on the thread count or scheduling.

use crate::color::Rgb;
use crate::image_io::Image;
use crate::integrator::{li, Scene};
use crate::sampling::Sampler;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Rows per parallel work item.
const BAND_ROWS: usize = 4;

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
    /// The image (mean radiance per pixel).
    pub image: Image,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Samples whose radiance was NaN or infinite and were left out.
    pub nonfinite_samples: u64,
    /// Total radiance samples taken.
    pub samples: u64,
}

/// Per-pixel running sums.
#[derive(Clone, Copy, Default)]
struct Pixel {
    sum: [f64; 3],
    count: u32,
    nonfinite: u32,
}

/// Renders `scene`; stops early (keeping finished passes) once `cancel` is set.
pub fn render(scene: &Scene, options: &RenderOptions, cancel: &AtomicBool) -> RenderOutput {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads.unwrap_or(0))
        .build()
        .expect("thread pool");
    pool.install(|| render_in_pool(scene, options, cancel))
}

fn render_in_pool(scene: &Scene, options: &RenderOptions, cancel: &AtomicBool) -> RenderOutput {
    let (w, h) = (
        scene.camera.width() as usize,
        scene.camera.height() as usize,
    );
    let mut film = vec![Pixel::default(); w * h];
    let start = Instant::now();
    let pass_spp = pass_size(options);
    let bands = h.div_ceil(BAND_ROWS) as u64;
    let bar = progress_bar(options, bands);
    let mut spp_done = 0u32;
    let mut partial = false;
    loop {
        let budget_left = match options.time_budget {
            Some(t) => start.elapsed() < t && (!options.spp_is_cap || spp_done < options.spp),
            None => spp_done < options.spp,
        };
        if !budget_left {
            break;
        }
        let count = match options.time_budget {
            Some(_) if !options.spp_is_cap => pass_spp,
            _ => pass_spp.min(options.spp - spp_done),
        };
        let mut pass = vec![Pixel::default(); w * h];
        pass.par_chunks_mut(w * BAND_ROWS)
            .enumerate()
            .for_each(|(band, rows)| {
                if cancel.load(Ordering::Relaxed) {
                    return;
                }
                for (i, px) in rows.iter_mut().enumerate() {
                    let (x, y) = ((i % w) as u32, (band * BAND_ROWS + i / w) as u32);
                    *px = render_pixel(scene, x, y, spp_done, count);
                }
                bar.inc(1);
            });
        if cancel.load(Ordering::Relaxed) {
            partial = true;
            break;
        }
        for (f, p) in film.iter_mut().zip(&pass) {
            for c in 0..3 {
                f.sum[c] += p.sum[c];
            }
            f.count += p.count;
            f.nonfinite += p.nonfinite;
        }
        spp_done += count;
        bar.set_message(format!("{spp_done} spp"));
    }
    bar.finish_and_clear();
    let nonfinite: u64 = film.iter().map(|p| p.nonfinite as u64).sum();
    let pixels = film
        .iter()
        .map(|p| {
            if p.count == 0 {
                Rgb::BLACK
            } else {
                let n = p.count as f64;
                Rgb::new(
                    (p.sum[0] / n) as f32,
                    (p.sum[1] / n) as f32,
                    (p.sum[2] / n) as f32,
                )
            }
        })
        .collect();
    RenderOutput {
        image: Image {
            width: w,
            height: h,
            pixels,
            spp: spp_done,
            partial,
        },
        elapsed: start.elapsed(),
        nonfinite_samples: nonfinite,
        samples: spp_done as u64 * (w * h) as u64,
    }
}

/// Samples per pass: all at once without a time budget (in chunks for progress), small passes with one.
fn pass_size(options: &RenderOptions) -> u32 {
    match options.time_budget {
        Some(_) => 4,
        None => options.spp.clamp(1, 16),
    }
}

fn progress_bar(options: &RenderOptions, bands: u64) -> ProgressBar {
    if !options.progress {
        return ProgressBar::hidden();
    }
    let bar = match options.time_budget {
        // The length of a timed render is unknown: show a spinner with rates.
        Some(_) => ProgressBar::new_spinner(),
        None => ProgressBar::new(bands * options.spp.div_ceil(pass_size(options)) as u64),
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

/// Sums `count` samples of pixel (x, y) starting at sample index `first`.
fn render_pixel(scene: &Scene, x: u32, y: u32, first: u32, count: u32) -> Pixel {
    let mut px = Pixel::default();
    for s in first..first + count {
        let mut sampler = Sampler::new(scene.settings.seed, x, y, s as u64);
        let ray = scene.camera.generate_ray(x, y, sampler.next_2d());
        let l = li(scene, ray, &mut sampler);
        if l.is_finite() {
            px.sum[0] += l.r as f64;
            px.sum[1] += l.g as f64;
            px.sum[2] += l.b as f64;
            px.count += 1;
        } else {
            px.nonfinite += 1;
        }
    }
    px
}
