//! The render driver: rows in parallel (rayon), progressive passes,
//! time/spp budget, progress bar (indicatif), and the one film every pass
//! adds to: beauty, AOVs and splats together.
//!
//! Each pixel's samples are summed in sample order by the one task that owns
//! the pixel (its AOVs from the same camera samples, beside the beauty),
//! passes are added to the film in pass order and splats in work-unit order,
//! so the image depends on the seed only, never on the thread count or
//! scheduling.

pub mod adaptive;
pub mod checkpoint;
pub mod class_plans;
pub mod cli_values;
pub mod display;

mod group;
mod guided;
pub mod merge_pieces;
mod mlt;
mod piloted;
pub mod provenance;
mod run;
pub mod slab_bake;
pub mod split;

pub use crate::integrator::estimator::{pixel_sample, Estimator, PathTracer};

use crate::film::image_io::{Image, NamedChannel};
use crate::film::{Film, PixelSums, Provenance, Rect, SampleRange};
use crate::integrator::aov::{Aov, AovPixel};
use crate::integrator::bdpt::Bdpt;
use crate::integrator::guiding::GuidedPathTracer;
use crate::integrator::tracking::TrackingStats;
use crate::integrator::{IntegratorKind, Scene};
use crate::math::color::Rgb;
use run::{Run, GROUP_BYTES};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

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
    /// The image (the film's beauty per pixel of the data window).
    pub image: Image,
    /// The sums and counts behind the image (beauty, AOVs, splats), for
    /// the EXR and `merge`.
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
    /// A Metropolis render's bootstrap and acceptance rates (None for the other integrators).
    pub mlt: Option<crate::integrator::mlt::MltStats>,
    /// A piloted render's sample counts and estimated error (None for uniform renders).
    pub noise: Option<adaptive::NoiseReport>,
    /// What the automatic choice made of its pilot (None when adaptive or
    /// noise was asked for, or no pilot could be taken).
    pub auto: Option<adaptive::AutoChoice>,
    /// Why the estimator refused a pass, when it did: the render stopped
    /// there (the image holds the passes before it, marked partial).
    pub refused: Option<Refused>,
}

/// A pass the estimator could not do (e.g. photons over the memory limit).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Refused {
    /// The scene key to blame, e.g. `integrator.photons`.
    pub key: &'static str,
    /// What went wrong and how to get past it.
    pub message: String,
}

/// Bytes of the film per pixel: beauty sums and squares, finite and left-out counts.
const FILM_PIXEL_BYTES: usize = 6 * 8 + 2 * 4;

/// Bytes a `width`×`height` render holds at its peak without AOVs or splats
/// (see [`film_peak_bytes`]).
pub fn peak_bytes(width: u32, height: u32) -> u64 {
    film_peak_bytes(width, height, &[], false)
}

/// Bytes a `width`×`height` render with `aovs` (and splats) holds at its
/// peak: the film, one pass of sums (or a group of passes of a small image,
/// up to `GROUP_BYTES`), the image, the PNG bytes and the EXR channels.
pub fn film_peak_bytes(width: u32, height: u32, aovs: &[Aov], splats: bool) -> u64 {
    let aov_channels: usize = aovs.iter().map(|a| a.channels().len()).sum();
    let pass = pass_pixel_bytes(!aovs.is_empty());
    let film = FILM_PIXEL_BYTES + aov_channels * 8 + aovs.len() * 4;
    let outputs = std::mem::size_of::<Rgb>() + 3 + (3 + aov_channels) * 4;
    let pixels = width as u64 * height as u64;
    let group = (GROUP_BYTES / pass) as u64;
    let group = group.saturating_sub(pixels) * pass as u64;
    // The film's and the pass's splat sums over the display window.
    let splat = if splats { 2 * 3 * 8 * pixels } else { 0 };
    pixels * (film + pass + outputs) as u64 + group + splat
}

/// Bytes of the pass buffers per pixel.
fn pass_pixel_bytes(aovs: bool) -> usize {
    let aov = if aovs {
        std::mem::size_of::<AovPixel>()
    } else {
        0
    };
    std::mem::size_of::<PixelSums>() + aov
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
/// with the scene's integrator (`[integrator] type`) and AOVs, showing the
/// image so far to `on_pass` after every finished pass. Metropolis renders
/// (`type = "mlt"`) take the whole frame only, and no AOVs.
pub fn render_part(
    scene: &Scene,
    options: &RenderOptions,
    part: &Part,
    cancel: &AtomicBool,
    on_pass: Option<PassObserver>,
) -> RenderOutput {
    // Chosen once per render: the driver is generic over the estimator, no dyn per sample.
    match scene.settings.integrator {
        IntegratorKind::Path if scene.settings.guiding => {
            render_guided(scene, options, part, cancel, on_pass)
        }
        IntegratorKind::Path => {
            render_part_with(scene, &PathTracer, options, part, cancel, on_pass)
        }
        IntegratorKind::Bdpt => render_part_with(scene, &Bdpt, options, part, cancel, on_pass),
        IntegratorKind::Sppm => {
            let sppm = crate::integrator::sppm::Sppm::new(scene);
            render_part_with(scene, &sppm, options, part, cancel, on_pass)
        }
        IntegratorKind::Mlt(settings) => {
            // Chains splat anywhere: the command line refuses pieces of split renders.
            assert!(
                *part == Part::whole(scene, options.spp),
                "mlt renders whole frames only"
            );
            mlt::render(scene, &settings, options, cancel, on_pass)
        }
    }
}

/// A path guide trained for `scene` in the current rayon pool (what a
/// guided render samples from), `None` when `cancel` stopped the training.
pub fn train_guide(
    scene: &Scene,
    cancel: &AtomicBool,
) -> Option<crate::integrator::guiding::Guide> {
    guided::train(scene, cancel)
}

/// [`render_part`] of the path tracer with path guiding: the guide is
/// trained first (its time taken from a time budget), then the image's
/// samples are taken with it. A render cancelled while training has no samples.
fn render_guided(
    scene: &Scene,
    options: &RenderOptions,
    part: &Part,
    cancel: &AtomicBool,
    on_pass: Option<PassObserver>,
) -> RenderOutput {
    let start = std::time::Instant::now();
    let guide = thread_pool(options).install(|| guided::train(scene, cancel));
    let mut options = options.clone();
    if let Some(t) = options.time_budget.as_mut() {
        *t = t.saturating_sub(start.elapsed());
    }
    let guide = guide.unwrap_or_default();
    let estimator = GuidedPathTracer { guide: &guide };
    let mut out = render_part_with(scene, &estimator, &options, part, cancel, on_pass);
    out.elapsed = start.elapsed();
    out
}

/// [`render_part`] with another estimator: the driver entry point of every
/// integrator, splatting or not.
pub fn render_part_with<E: Estimator>(
    scene: &Scene,
    estimator: &E,
    options: &RenderOptions,
    part: &Part,
    cancel: &AtomicBool,
    on_pass: Option<PassObserver>,
) -> RenderOutput {
    let job = Job {
        scene,
        estimator,
        part,
        aovs: &scene.aovs,
    };
    job.render(options, cancel, on_pass)
}

/// Per-pixel means of `aovs` over samples `0..spp` of the whole frame, one
/// named channel per entry of each `Aov::channels`: a render of the film
/// with these AOVs (the beauty comes along in the same pass).
pub fn render_aovs(
    scene: &Scene,
    aovs: &[Aov],
    spp: u32,
    threads: Option<usize>,
) -> Vec<NamedChannel> {
    let options = RenderOptions {
        spp,
        time_budget: None,
        spp_is_cap: false,
        threads,
        progress: false,
    };
    let job = Job {
        scene,
        estimator: &PathTracer,
        part: &Part::whole(scene, spp),
        aovs,
    };
    job.render(&options, &AtomicBool::new(false), None)
        .film
        .aov_channels()
}

/// What to render: the scene, by which estimator, which part, which AOVs.
struct Job<'a, E> {
    scene: &'a Scene,
    estimator: &'a E,
    part: &'a Part,
    aovs: &'a [Aov],
}

/// The pool a render runs in: `options.threads` threads (0: one per core).
fn thread_pool(options: &RenderOptions) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads.unwrap_or(0))
        .build()
        .expect("thread pool")
}

impl<E: Estimator> Job<'_, E> {
    /// Renders in a pool of `options.threads` threads.
    fn render(
        &self,
        options: &RenderOptions,
        cancel: &AtomicBool,
        on_pass: Option<PassObserver>,
    ) -> RenderOutput {
        let pool = thread_pool(options);
        let spp_total = options.spp;
        let options = RenderOptions {
            spp: self.part.samples.len(),
            ..options.clone()
        };
        let timed = options.time_budget.is_some();
        let mut out = pool.install(|| {
            let mut run = Run::new(self, &options, cancel);
            run.passes(on_pass);
            run.finish()
        });
        // A timed render's size is what it reached; a piece belongs to a render of `spp_total`.
        if !timed {
            let provenance = &mut out.film.provenance;
            provenance.spp_total = provenance.spp_total.max(spp_total);
        }
        out
    }

    /// The empty film of the part, with the AOV layers and splat sums it needs.
    fn new_film(&self) -> Film {
        let (scene, part) = (self.scene, self.part);
        let display = (scene.camera.width(), scene.camera.height());
        let provenance = Provenance {
            seed: scene.settings.seed,
            scene_hash: 0,
            spp_total: part.samples.end,
            requested: vec![part.samples],
            held: vec![],
        };
        let mut film = Film::new(display, part.crop, provenance);
        film.squares = Some(vec![0.0; 3 * part.crop.area()]);
        for &aov in self.aovs {
            film.add_aov(aov);
        }
        if self.estimator.splats() {
            film.add_splats();
        }
        film
    }
}
