//! What the render driver (module `render`) asks of an integrator: the
//! radiance of one camera sample, and the light-traced contributions
//! (splats) that sample lands elsewhere. It lives beside the integrators so
//! that they implement it without importing the driver.

use crate::film::Splat;
use crate::integrator::{li, Scene};
use crate::math::color::Rgb;
use crate::sampling::PixelStreams;
use std::sync::atomic::AtomicBool;

/// A camera-sample estimator the driver runs for every (pixel, sample index).
///
/// The driver calls [`Estimator::sample`] for samples `s` of pixel (`x`, `y`)
/// in sample order, on one thread per pixel and pass, with an arena that the
/// thread reuses (never one per sample) and a splat buffer that belongs to the
/// work unit (one row of one pass) and is added to the film in a fixed order,
/// so the image depends on the seed only. A bidirectional integrator's
/// `fn(scene, x, y, s, &mut Arena, &mut Vec<Splat>) -> Rgb` fits by ignoring
/// `streams` (or using them: they are `scene.settings.pixel_streams(x, y)`).
pub trait Estimator: Sync {
    /// Scratch memory reused across samples (subpath vertices, ...).
    type Arena: Send;

    /// A fresh arena; made a few times per thread, never per sample.
    fn arena(&self) -> Self::Arena;

    /// True when `sample` may push splats: the film then keeps splat sums
    /// over the display window, divided by the samples per pixel of the render.
    fn splats(&self) -> bool;

    /// `Some(n)` for an estimator whose samples depend on work shared by all
    /// pixels (a photon pass): passes then hold `n` sample indices and
    /// [`Estimator::prepare`] runs before each. `None` (the default): any.
    fn pass_samples(&self) -> Option<u32> {
        None
    }

    /// Prepares sample index `s` of every pixel before any pixel takes it
    /// (called only when [`Estimator::pass_samples`] is `Some`); the pass is
    /// rendered only when it is [`Prepared::Ready`].
    fn prepare(&self, _scene: &Scene, _s: u32, _cancel: &AtomicBool) -> Prepared {
        Prepared::Ready
    }

    /// The radiance of sample `s` of pixel (`x`, `y`) (NaN or infinite
    /// values are counted and left out by the film); pushes any splats.
    fn sample(
        &self,
        scene: &Scene,
        pixel: (u32, u32),
        streams: &PixelStreams,
        s: u32,
        arena: &mut Self::Arena,
        splats: &mut Vec<Splat>,
    ) -> Rgb;
}

/// How the preparation of a pass ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Prepared {
    /// The pass may be rendered.
    Ready,
    /// `cancel` stopped it.
    Stopped,
    /// It cannot be done: the scene key to blame and why, in the user's words.
    Refused {
        /// The scene key, e.g. `integrator.photons`.
        key: &'static str,
        /// What went wrong and how to get past it.
        message: String,
    },
}

/// The unidirectional volumetric path tracer (`integrator::li`): no splats.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathTracer;

impl Estimator for PathTracer {
    type Arena = ();

    fn arena(&self) {}

    fn splats(&self) -> bool {
        false
    }

    #[inline]
    fn sample(
        &self,
        scene: &Scene,
        (x, y): (u32, u32),
        streams: &PixelStreams,
        s: u32,
        _arena: &mut (),
        _splats: &mut Vec<Splat>,
    ) -> Rgb {
        stream_sample(scene, x, y, streams, s)
    }
}

/// Radiance of sample `s` of pixel (x, y): the same value whatever renders it.
pub fn pixel_sample(scene: &Scene, x: u32, y: u32, s: u32) -> Rgb {
    stream_sample(scene, x, y, &scene.settings.pixel_streams(x, y), s)
}

/// [`pixel_sample`] given the pixel's streams, hashed once for all its samples.
#[inline]
pub fn stream_sample(scene: &Scene, x: u32, y: u32, streams: &PixelStreams, s: u32) -> Rgb {
    let mut sampler = streams.sampler(s as u64);
    // The time sits at a reserved position of the stream: drawing it first moves no other number.
    let time = match scene.settings.shutter {
        Some(_) => scene.settings.sample_time(sampler.time_1d()),
        None => 0.0,
    };
    let ray = scene.camera.sample_ray_at(x, y, time, &mut sampler);
    li(scene, ray, &mut sampler)
}
