//! Bidirectional path tracing with surface and medium vertices (Veach and
//! Guibas 1995; Veach 1997, ch. 10, MIS ch. 9).
//!
//! Each camera sample traces a camera subpath from the lens and a light
//! subpath from a light picked by power, both with the path tracer's own
//! free flights, BSDF/phase sampling and Russian roulette, at one time in
//! the shutter. Every pair of prefixes (s light vertices, t camera vertices)
//! makes a path: s = 0 when the camera subpath meets a light, s = 1 by
//! next-event estimation from a camera vertex, t = 1 by connecting a light
//! vertex to the lens (light tracing: the radiance is splatted onto the
//! pixel it images to), and s, t ≥ 2 by joining the two subpaths with a
//! shadow ray whose transmittance any unbiased estimator gives. The
//! strategies are combined by the power heuristic over all of them (module
//! `mis`), with deterministic surrogate free-flight densities in media
//! (module `media`): agreeing with the path tracer in expectation is by
//! construction, everywhere both can sample.
//!
//! The path set is the path tracer's: at most `max_depth` scattering
//! vertices, at most `max_scatter_depth` medium ones, and when a path has
//! that many, the last (nearest the light) is a medium vertex — the path
//! tracer gathers only emission after its last allowed medium event.
//! Emissive media are gathered by the camera subpath's free flights exactly
//! as the path tracer gathers them (no light subpath starts in a medium, so
//! that strategy is the only one and needs no weight). Equiangular sampling
//! (`integrator.equiangular`) is a path-tracer strategy and plays no part.
//!
//! A light subpath is traced per camera sample, so t = 1 splats, like the
//! camera estimates, are divided by the samples per pixel.

mod connect;
mod estimator;
mod media;
mod mis;
pub mod multiplexed;
pub mod strategies;
mod subpath;
mod vertex;
mod weights;
#[cfg(test)]
mod weights_tests;

use crate::film::Splat;
use crate::integrator::Scene;
use crate::light::SceneSphere;
use crate::math::color::Rgb;
use crate::sampling::PixelStreams;
use connect::Contribution;
pub use estimator::Bdpt;
use media::Surrogate;
use vertex::{Kind, Vertex};
use weights::Context;

pub(crate) use vertex::{Kind as VertexKind, Vertex as SubpathVertex};

/// Traces one light subpath from a light picked by power at `time`, with
/// the walk bidirectional sampling uses (the path tracer's tracking,
/// adjoint BSDF sampling, roulette), into `path` (`path[0]` on the light):
/// the photons of photon mapping.
pub(crate) fn trace_light_subpath(
    scene: &Scene,
    sphere: &SceneSphere,
    time: f32,
    sampler: &mut crate::sampling::Sampler,
    path: &mut Vec<Vertex>,
) {
    let sur = Surrogate::new(scene, time);
    subpath::light_subpath(scene, &sur, sphere, time, sampler, (path, usize::MAX));
}

/// Per-thread storage of the subpaths, reused from sample to sample (no allocation per path).
#[derive(Debug, Default)]
pub struct BdptArena {
    camera: Vec<Vertex>,
    light: Vec<Vertex>,
    /// Reusable splat storage for whole-image renders (module `strategies`).
    splat_buffer: Vec<Splat>,
}

impl BdptArena {
    /// An empty arena; its vertex storage grows to the longest subpath met.
    pub fn new() -> BdptArena {
        BdptArena::default()
    }
}

/// The camera-side radiance of sample `s` of pixel (`x`, `y`); light-tracing
/// contributions go to `splats`, each to be divided, like the returned value,
/// by the samples per pixel (a NaN or infinite one too: the film counts it
/// and leaves it out, as it does the camera estimates).
pub fn sample(
    scene: &Scene,
    x: u32,
    y: u32,
    s: u32,
    arena: &mut BdptArena,
    splats: &mut Vec<Splat>,
) -> Rgb {
    let streams = scene.settings.pixel_streams(x, y);
    sample_with_streams(scene, x, y, &streams, s, arena, splats)
}

/// [`sample`] given the pixel's random streams (hashed once for all its samples).
pub fn sample_with_streams(
    scene: &Scene,
    x: u32,
    y: u32,
    streams: &PixelStreams,
    s: u32,
    arena: &mut BdptArena,
    splats: &mut Vec<Splat>,
) -> Rgb {
    run(
        scene,
        x,
        y,
        streams,
        s,
        arena,
        &mut |event: Event| match event {
            Event::Camera { .. } => {}
            Event::Splat { x, y, c, .. } => splats.push(Splat {
                x,
                y,
                radiance: c.weighted,
            }),
        },
    )
}

/// One strategy's contribution as a sample reports it (for the per-strategy images).
#[derive(Clone, Copy, Debug)]
enum Event {
    /// A strategy with t ≥ 2, for the sample's own pixel.
    Camera { s: usize, t: usize, c: Contribution },
    /// A light-tracing (t = 1) contribution landing on pixel (x, y).
    Splat {
        s: usize,
        x: u32,
        y: u32,
        c: Contribution,
    },
}

/// The sphere lights at infinity start their rays around: the one the light
/// pick weighs them over (shapes, the camera, point and spot lights).
pub(crate) fn scene_sphere(scene: &Scene) -> SceneSphere {
    let mut bounds = scene
        .geometry
        .bounds()
        .include(scene.camera.view_at(0.0).position);
    for light in &scene.lights {
        if let Some(p) = light.point_position() {
            bounds = bounds.include(p);
        }
    }
    let radius = 0.5 * (bounds.max - bounds.min).length();
    let (center, radius) = if radius.is_finite() && radius > 0.0 {
        (bounds.center(), radius)
    } else {
        (scene.camera.view_at(0.0).position, 1.0)
    };
    // A margin keeps the disk off the surfaces on the sphere itself.
    SceneSphere {
        center,
        radius: radius * 1.01,
    }
}

/// Traces both subpaths of one camera sample and evaluates every strategy,
/// reporting each to `report`; returns the sum of the weighted t ≥ 2 ones
/// and the medium emission the camera subpath gathered.
fn run(
    scene: &Scene,
    x: u32,
    y: u32,
    streams: &PixelStreams,
    sample_index: u32,
    arena: &mut BdptArena,
    report: &mut dyn FnMut(Event),
) -> Rgb {
    let mut sampler = streams.sampler(sample_index as u64);
    // The time sits at a reserved position of the stream, as in the path tracer.
    let time = match scene.settings.shutter {
        Some(_) => scene.settings.sample_time(sampler.time_1d()),
        None => 0.0,
    };
    let ray = scene.camera.sample_ray_at(x, y, time, &mut sampler);
    let ctx = Context {
        scene,
        sur: Surrogate::new(scene, time),
        sphere: scene_sphere(scene),
        time,
    };
    let mut radiance = Rgb::BLACK;
    let BdptArena { camera, light, .. } = arena;
    let full = usize::MAX;
    subpath::camera_subpath(
        scene,
        &ctx.sur,
        ray,
        &mut sampler,
        (camera, full),
        &mut radiance,
    );
    subpath::light_subpath(
        scene,
        &ctx.sur,
        &ctx.sphere,
        time,
        &mut sampler,
        (light, full),
    );
    radiance += evaluate_strategies(
        &ctx,
        (light.as_slice(), camera.as_slice()),
        &mut sampler,
        report,
    );
    radiance
}

/// Evaluates every allowed strategy (s, t) of the traced subpaths, reporting
/// each (t = 1 as a splat) to `report`; returns the sum of the weighted t ≥ 2 ones.
fn evaluate_strategies(
    ctx: &Context,
    (light, camera): (&[Vertex], &[Vertex]),
    sampler: &mut crate::sampling::Sampler,
    report: &mut dyn FnMut(Event),
) -> Rgb {
    let mut radiance = Rgb::BLACK;
    for t in 1..=camera.len() {
        for s in 0..=light.len().max(1) {
            if !allowed(ctx.scene, light, camera, s, t) {
                continue;
            }
            if t == 1 {
                let Some((raster, c)) = connect::light_trace(ctx, &light[..s], sampler) else {
                    continue;
                };
                let (px, py) = (raster.x as u32, raster.y as u32);
                report(Event::Splat { s, x: px, y: py, c });
                continue;
            }
            let c = match s {
                0 => connect::emission(ctx, &camera[..t]),
                1 => connect::next_event(ctx, &camera[..t], sampler),
                _ => connect::connect(ctx, &light[..s], &camera[..t], sampler),
            };
            radiance += c.weighted;
            report(Event::Camera { s, t, c });
        }
    }
    radiance
}

/// True for a positive number (false for zero, negatives and NaN).
#[inline]
fn positive(x: f32) -> bool {
    x > 0.0
}

/// True when strategy (s, t) is traced for these subpaths: both endpoints
/// can be joined, and the path is in the path tracer's set (depth limits).
fn allowed(scene: &Scene, light: &[Vertex], camera: &[Vertex], s: usize, t: usize) -> bool {
    let settings = &scene.settings;
    let k = s + t - 1;
    if k < 1 || (s == 1 && t == 1) || k - 1 > settings.max_depth as usize {
        return false;
    }
    let ends_ok = match (s, t) {
        (0, _) => matches!(
            camera[t - 1].kind,
            Kind::Surface { .. } | Kind::Escaped { .. }
        ),
        (_, 1) => s >= 2 && light[s - 1].scatters() && light[s - 1].connectable(),
        (1, _) => camera[t - 1].scatters() && camera[t - 1].connectable(),
        _ => {
            let (y, z) = (&light[s - 1], &camera[t - 1]);
            y.scatters() && y.connectable() && z.scatters() && z.connectable()
        }
    };
    if !ends_ok {
        return false;
    }
    // The light vertex next-event estimation samples (s = 1) is never in a medium.
    let light_media = if s >= 2 { light[s - 1].media } else { 0 };
    let media = (camera[t - 1].media + light_media) as usize;
    let limit = settings.max_scatter_depth as usize;
    if media > limit {
        return false;
    }
    if media == limit && k >= 2 {
        // The path tracer scatters no more after its last allowed medium event.
        let x1 = match s {
            0 => &camera[t - 2],
            1 => &camera[t - 1],
            _ => &light[1],
        };
        return matches!(x1.kind, Kind::Medium { .. });
    }
    true
}
