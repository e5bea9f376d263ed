//! Helpers shared by the integration tests: scenes from TOML text,
//! per-pixel Monte Carlo estimates, the one statistical assertion (`stats`)
//! where the test files are (`data`) and the one way to skip a test (`skip`).
#![allow(dead_code, clippy::needless_range_loop)]

use brume::integrator::tracking::{sample_free_flight, FreeFlight};
use brume::integrator::{li, Scene};
use brume::math::color::Rgb;
use brume::math::Ray;
use brume::medium::Medium;
use brume::sampling::Sampler;
use std::path::Path;

pub mod cli;
pub mod data;
pub mod k_sigma;
pub mod paths;
pub mod scene_text;
pub mod skip;
pub mod stats;

pub use scene_text::SceneText;

#[allow(unused_imports)]
pub use stats::{
    assert_estimate, assert_lower_error, assert_pixels, assert_pixels_equal, assert_same,
    assert_within, k_sigma,
};

/// Builds a scene from TOML text as if it were the file `test.toml` in the crate root.
pub fn scene_from_str(text: &str) -> Scene {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("test.toml");
    let desc = brume::scene::parse(text, &file).expect("parse");
    brume::scene::build(&desc, &file, Path::new(env!("CARGO_MANIFEST_DIR"))).expect("build")
}

/// The error building a scene from TOML text gives (as [`scene_from_str`]
/// reads it); `what` names the case where the scene is accepted instead.
#[allow(dead_code)]
pub fn build_error_from_str(text: &str, what: &str) -> String {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("test.toml");
    let desc = brume::scene::parse(text, &file).expect("parse");
    brume::scene::build(&desc, &file, Path::new(env!("CARGO_MANIFEST_DIR")))
        .err()
        .unwrap_or_else(|| panic!("{what}: accepted"))
        .to_string()
}

/// A furnace: a camera looking at `medium` (TOML) inside a uniform environment of radiance `env`.
///
/// Paths are never cut short (no depth limit or roulette in practice), so
/// the expected value of every pixel is known in closed form.
pub fn furnace_scene(medium: &str, env: f32) -> String {
    SceneText::furnace_view(6)
        .depths(100000, 100000)
        .environment(env)
        .raw(medium)
        .build()
}

/// Mean and standard error of the mean of a set of samples (per channel).
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    pub mean: [f64; 3],
    pub std_error: [f64; 3],
    pub n: usize,
}

/// Running sums from which an `Estimate` is formed.
#[derive(Clone, Copy, Default)]
pub struct Accumulator {
    sum: [f64; 3],
    sum2: [f64; 3],
    n: usize,
}

impl Accumulator {
    pub fn add(&mut self, v: Rgb) {
        for c in 0..3 {
            let x = v[c] as f64;
            self.sum[c] += x;
            self.sum2[c] += x * x;
        }
        self.n += 1;
    }

    pub fn estimate(&self) -> Estimate {
        let n = self.n as f64;
        let mut mean = [0.0; 3];
        let mut std_error = [0.0; 3];
        for c in 0..3 {
            mean[c] = self.sum[c] / n;
            let var = (self.sum2[c] / n - mean[c] * mean[c]).max(0.0) * n / (n - 1.0).max(1.0);
            std_error[c] = (var / n).sqrt();
        }
        Estimate {
            mean,
            std_error,
            n: self.n,
        }
    }
}

/// Estimates the radiance along `ray` with `n` independent paths.
pub fn estimate_ray(scene: &Scene, ray: Ray, n: usize, seed: u64) -> Estimate {
    let mut acc = Accumulator::default();
    for i in 0..n {
        let mut sampler = Sampler::new(seed, 0, 0, i as u64);
        acc.add(li(scene, ray, &mut sampler));
    }
    acc.estimate()
}

/// One free flight through `media` along `ray` up to `t_max` from unit
/// throughput: the event, the throughput after it and the radiance it gathered.
pub fn free_flight(
    media: &[Medium],
    ray: &Ray,
    t_max: f32,
    sampler: &mut Sampler,
) -> (FreeFlight, Rgb, Rgb) {
    let (mut throughput, mut radiance) = (Rgb::WHITE, Rgb::BLACK);
    let event = sample_free_flight(media, ray, t_max, &mut throughput, &mut radiance, sampler);
    (event, throughput, radiance)
}

/// Every sample of every pixel of the render path, in order, as bits: equal
/// vectors mean bit-identical images.
pub fn sample_bits(scene: &Scene, spp: u32) -> Vec<[u32; 3]> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::with_capacity((w * h * spp) as usize);
    for y in 0..h {
        for x in 0..w {
            for s in 0..spp {
                let l = brume::render::pixel_sample(scene, x, y, s);
                out.push([l.r.to_bits(), l.g.to_bits(), l.b.to_bits()]);
            }
        }
    }
    out
}

/// Per-pixel estimates of a whole image with `spp` samples each.
pub fn estimate_pixels(scene: &Scene, spp: usize) -> Vec<Estimate> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut acc = Accumulator::default();
            for s in 0..spp {
                // the render's own sample: camera ray, shutter time, path
                acc.add(brume::render::pixel_sample(scene, x, y, s as u32));
            }
            out.push(acc.estimate());
        }
    }
    out
}
