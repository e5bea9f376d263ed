//! One bidirectional strategy as the contribution function of a multiplexed
//! Metropolis state (Hachisuka, Pantaleoni and Jensen 2014): a path length
//! of `k` segments is fixed per chain, the connection stream's first number
//! picks the strategy (s, t) with s + t = k + 1 uniformly among the k + 1,
//! and the state's value is that strategy's MIS-weighted contribution over
//! the probability of picking it. Summed over strategies and lengths, the
//! expectation is the bidirectional image, which is the path tracer's.
//!
//! Only the prefixes the strategy joins are traced (t camera vertices, s light
//! vertices), so a state costs one strategy, not all of them. The camera
//! subpath's medium emission, which no strategy weighs, belongs to the k = 1
//! states that pick s = 0: their camera subpath is traced whole.

use super::media::Surrogate;
use super::vertex::Vertex;
use super::weights::Context;
use super::{allowed, connect, scene_sphere, subpath, BdptArena};
use crate::integrator::Scene;
use crate::light::SceneSphere;
use crate::math::color::Rgb;
use crate::sampling::primary::Stream;
use crate::sampling::Sampler;

/// A state's path: the display pixel it lands on and its radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSample {
    /// Display column.
    pub x: u32,
    /// Display row.
    pub y: u32,
    /// Radiance over the strategy's selection probability (MIS-weighted).
    pub radiance: Rgb,
}

/// What every state of one scene shares.
#[derive(Clone, Copy, Debug)]
pub struct Multiplexed {
    sphere: SceneSphere,
}

impl Multiplexed {
    /// The shared parts of `scene`'s states.
    pub fn new(scene: &Scene) -> Multiplexed {
        Multiplexed {
            sphere: scene_sphere(scene),
        }
    }

    /// Longest path length, in segments, that `scene` allows (`max_depth` + 1).
    pub fn max_length(scene: &Scene) -> usize {
        (scene.settings.max_depth as usize).saturating_add(1)
    }

    /// The path of length `k` segments that `sampler`'s numbers make, or None
    /// when the picked strategy does not apply (its value is then zero).
    pub fn evaluate(
        &self,
        scene: &Scene,
        k: usize,
        sampler: &mut Sampler,
        arena: &mut BdptArena,
    ) -> Option<PathSample> {
        let n = k + 1;
        sampler.set_stream(Stream::Connection);
        let t = 1 + ((sampler.next_1d() * n as f32) as usize).min(n - 1);
        let s = n - t;
        sampler.set_stream(Stream::Camera);
        let time = match scene.settings.shutter {
            Some(_) => scene.settings.sample_time(sampler.next_1d()),
            None => 0.0,
        };
        let (w, h) = (scene.camera.width(), scene.camera.height());
        let u = sampler.next_2d();
        let px = ((u.x * w as f32) as u32).min(w - 1);
        let py = ((u.y * h as f32) as u32).min(h - 1);
        let ray = scene.camera.sample_ray_at(px, py, time, sampler);
        let ctx = Context {
            scene,
            sur: Surrogate::new(scene, time),
            sphere: self.sphere,
            time,
        };
        let BdptArena { camera, light, .. } = arena;
        let mut emission = Rgb::BLACK;
        let gathers = k == 1 && s == 0;
        let camera_limit = if gathers { usize::MAX } else { t };
        let cam = (&mut *camera, camera_limit);
        subpath::camera_subpath(scene, &ctx.sur, ray, sampler, cam, &mut emission);
        sampler.set_stream(Stream::Light);
        if s >= 2 {
            subpath::light_subpath(scene, &ctx.sur, &ctx.sphere, time, sampler, (light, s));
        } else {
            light.clear();
        }
        sampler.set_stream(Stream::Connection);
        let scale = n as f32;
        let value = strategy(&ctx, light, camera, (s, t), sampler);
        let (x, y, c) = match value {
            Some((Some((x, y)), c)) => (x, y, c),
            Some((None, c)) => (px, py, c),
            None => (px, py, Rgb::BLACK),
        };
        let radiance = (c + if gathers { emission } else { Rgb::BLACK }) * scale;
        (!radiance.is_black() || !radiance.is_finite()).then_some(PathSample { x, y, radiance })
    }
}

/// The weighted contribution of strategy (s, t) and, for light tracing
/// (t = 1), the pixel it lands on; None when the strategy does not apply.
fn strategy(
    ctx: &Context,
    light: &[Vertex],
    camera: &[Vertex],
    (s, t): (usize, usize),
    sampler: &mut Sampler,
) -> Option<(Option<(u32, u32)>, Rgb)> {
    let scene = ctx.scene;
    if t > camera.len() || (s >= 2 && s > light.len()) {
        return None;
    }
    if !allowed(scene, light, camera, s, t) {
        return None;
    }
    if t == 1 {
        let (raster, c) = connect::light_trace(ctx, &light[..s], sampler)?;
        return Some((Some((raster.x as u32, raster.y as u32)), c.weighted));
    }
    let c = match s {
        0 => connect::emission(ctx, &camera[..t]),
        1 => connect::next_event(ctx, &camera[..t], sampler),
        _ => connect::connect(ctx, &light[..s], &camera[..t], sampler),
    };
    Some((None, c.weighted))
}
