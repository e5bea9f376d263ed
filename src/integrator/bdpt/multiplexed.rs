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
use crate::sampling::primary::{PrimarySamples, Stream};
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
        let gathers = k == 1 && s == 0;
        let camera_limit = if gathers { usize::MAX } else { t };
        let (ctx, pixel, emission) = self.trace(scene, sampler, arena, (camera_limit, s));
        sampler.set_stream(Stream::Connection);
        let value = strategy(&ctx, &arena.light, &arena.camera, (s, t), sampler);
        finish(value, pixel, emission.filter(|_| gathers), n)
    }

    /// Every strategy of length `k` on one pair of subpaths (the state's
    /// camera and light numbers, each strategy reading the connection stream
    /// from its second number on, as [`Multiplexed::evaluate`] does):
    /// `luminance[t − 1]` becomes the luminance of the state that picks
    /// (k + 1 − t, t). Their mean is the multiplexed estimate's expectation
    /// over the strategy choice (a bidirectional sample of length k), and
    /// `state` afterwards holds every number they read: setting its first
    /// connection number into strategy t's bin gives that state exactly.
    pub fn evaluate_all(
        &self,
        scene: &Scene,
        k: usize,
        state: &mut PrimarySamples,
        arena: &mut BdptArena,
        luminance: &mut [f64],
    ) {
        let n = k + 1;
        let camera_limit = if k == 1 { usize::MAX } else { n };
        let (ctx, pixel, emission) = {
            let mut sampler = Sampler::primary(state);
            // The strategy pick, unused here: drawn first, as evaluate draws it,
            // so the state holds it for a chain to set.
            sampler.set_stream(Stream::Connection);
            sampler.next_1d();
            self.trace(scene, &mut sampler, arena, (camera_limit, k))
        };
        for (i, l) in luminance[..n].iter_mut().enumerate() {
            let (s, t) = (n - 1 - i, i + 1);
            state.seek(Stream::Connection, 1);
            let mut sampler = Sampler::primary(state);
            let value = strategy(&ctx, &arena.light, &arena.camera, (s, t), &mut sampler);
            let gathered = emission.filter(|_| k == 1 && s == 0);
            *l = match finish(value, pixel, gathered, n) {
                Some(p) if p.radiance.is_finite() => p.radiance.luminance().max(0.0) as f64,
                _ => 0.0,
            };
        }
    }

    /// The camera subpath (at most `camera_limit` vertices) and, for `s` ≥ 2,
    /// the light subpath (at most `s`) into `arena`; the context, the
    /// pixel and the medium emission the camera subpath gathered.
    fn trace<'a>(
        &self,
        scene: &'a Scene,
        sampler: &mut Sampler,
        arena: &mut BdptArena,
        (camera_limit, s): (usize, usize),
    ) -> (Context<'a>, (u32, u32), Option<Rgb>) {
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
        let cam = (&mut *camera, camera_limit);
        subpath::camera_subpath(scene, &ctx.sur, ray, sampler, cam, &mut emission);
        sampler.set_stream(Stream::Light);
        if s >= 2 {
            subpath::light_subpath(scene, &ctx.sur, &ctx.sphere, time, sampler, (light, s));
        } else {
            light.clear();
        }
        (ctx, (px, py), Some(emission))
    }
}

/// The state's path from its strategy's value: its pixel (the light-tracing
/// one, else the camera ray's), and its radiance with the `gathered` medium
/// emission, times the `n` strategies it was picked among.
fn finish(
    value: Option<(Option<(u32, u32)>, Rgb)>,
    (px, py): (u32, u32),
    gathered: Option<Rgb>,
    n: usize,
) -> Option<PathSample> {
    let (x, y, c) = match value {
        Some((Some((x, y)), c)) => (x, y, c),
        Some((None, c)) => (px, py, c),
        None => (px, py, Rgb::BLACK),
    };
    let radiance = (c + gathered.unwrap_or(Rgb::BLACK)) * n as f32;
    (!radiance.is_black() || !radiance.is_finite()).then_some(PathSample { x, y, radiance })
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// A lamp in a glass ball over a diffuse floor, a mirror wall, fog
    /// everywhere: surface, medium, Dirac and light-tracing strategies all apply.
    const GLASS_FOG: &str = r#"
[camera]
position = [0.0, 1.0, 3.4]
look_at = [0.0, 0.8, 0.0]
fov = 45.0
resolution = [8, 8]
[integrator]
max_depth = 6
[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [4.0, 4.0]
material = { type = "diffuse", albedo = 0.8 }
[[shape]]
type = "quad"
center = [-1.0, 1.0, 0.0]
normal = [1.0, 0.0, 0.0]
size = [4.0, 4.0]
material = { type = "mirror", reflectance = 0.9 }
[[shape]]
type = "sphere"
center = [0.3, 1.0, 0.0]
radius = 0.4
material = { type = "dielectric", ior = 1.5 }
[[shape]]
type = "sphere"
center = [0.3, 1.0, 0.0]
radius = 0.2
emission = 5.0
material = { type = "diffuse", albedo = 0.0 }
[[light]]
type = "point"
position = [0.5, 1.9, 1.0]
intensity = 2.0
[[medium]]
type = "homogeneous"
sigma_a = 0.05
sigma_s = 0.5
phase = { type = "hg", g = 0.3 }
global = true
"#;

    fn luminance(p: Option<PathSample>) -> f64 {
        match p {
            Some(p) if p.radiance.is_finite() => p.radiance.luminance().max(0.0) as f64,
            _ => 0.0,
        }
    }

    /// evaluate_all's luminance t − 1 is, bit for bit, what evaluate gives the
    /// same numbers with the first connection number in strategy t's bin: the
    /// bootstrap's weights are the luminances of the states chains start from.
    #[test]
    fn every_strategy_is_the_state_that_picks_it() {
        let file = Path::new("multiplexed.toml");
        let desc = crate::scene::parse(GLASS_FOG, file).expect("parse");
        let scene = crate::scene::build(&desc, file, Path::new(".")).expect("build");
        let mux = Multiplexed::new(&scene);
        let mut arena = BdptArena::new();
        let mut all = [0.0; 8];
        let mut positive = [0usize; 8];
        for key in 0..400u64 {
            for k in 1..=Multiplexed::max_length(&scene) {
                let mut state = PrimarySamples::new(key, 0.01, 0.3);
                mux.evaluate_all(&scene, k, &mut state, &mut arena, &mut all);
                for (i, &l) in all[..=k].iter().enumerate() {
                    let mut one = state.clone();
                    one.set(Stream::Connection, 0, (i as f32 + 0.5) / (k + 1) as f32);
                    one.rewind();
                    let path = mux.evaluate(&scene, k, &mut Sampler::primary(&mut one), &mut arena);
                    assert_eq!(luminance(path), l, "key {key}, length {k}, t = {}", i + 1);
                    positive[i] += usize::from(l > 0.0);
                }
            }
        }
        // Every t up to the longest length found light somewhere: the check was not vacuous.
        assert!(positive[..7].iter().all(|&p| p > 0), "{positive:?}");
    }
}
