//! Helpers of the analytic-media suite: Monte Carlo estimates of one
//! quantity and their comparison with a closed form.
#![allow(dead_code, clippy::needless_range_loop)]

#[path = "../common/mod.rs"]
pub mod common;
pub mod ggx;
pub mod lobes;

#[allow(unused_imports)]
pub use common::{
    assert_estimate, assert_same, assert_within, free_flight, k_sigma, scene_from_str, Accumulator,
    Estimate, SceneText,
};

use brume::integrator::li;
use brume::integrator::Scene;
use brume::math::color::Rgb;
use brume::math::Ray;
use brume::sampling::Sampler;

/// Mean and standard error of `n` independent draws of `f`, each with its own stream.
pub fn estimate(n: usize, seed: u64, mut f: impl FnMut(&mut Sampler) -> Rgb) -> Estimate {
    let mut acc = Accumulator::default();
    for i in 0..n {
        let mut sampler = Sampler::new(seed, 0, 0, i as u64);
        acc.add(f(&mut sampler));
    }
    acc.estimate()
}

/// Radiance estimate along `ray` through `li`.
pub fn estimate_li(scene: &Scene, ray: Ray, n: usize, seed: u64) -> Estimate {
    estimate(n, seed, |s| li(scene, ray, s))
}

/// Henyey–Greenstein in f64 for cos θ between propagation directions.
pub fn hg(g: f64, cos_theta: f64) -> f64 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * denom * denom.sqrt())
}

/// Per-channel f64 array of an RGB triple.
pub fn rgb64(c: [f32; 3]) -> [f64; 3] {
    [c[0] as f64, c[1] as f64, c[2] as f64]
}

/// Applies `f` to each channel.
pub fn per_channel(f: impl Fn(usize) -> f64) -> [f64; 3] {
    [f(0), f(1), f(2)]
}

/// A TOML array literal of three numbers.
pub fn toml3(c: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", c[0], c[1], c[2])
}
