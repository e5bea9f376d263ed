//! Helpers of the Metropolis tests: scenes with `type = "mlt"` and renders
//! through the library's driver, as `brume render` runs them.
#![allow(dead_code)]

#[path = "../common/mod.rs"]
pub mod common;

#[allow(unused_imports)]
pub use common::{assert_within, scene_from_str, SceneText};

use brume::integrator::Scene;
use brume::render::{render, RenderOptions, RenderOutput};
use std::sync::atomic::AtomicBool;

/// The `[integrator]` lines of a Metropolis render.
pub fn mlt_integrator(max_depth: u32, bootstrap: u32, seed: u64) -> String {
    format!(
        "type = \"mlt\"\nmax_depth = {max_depth}\nrr_depth = 100000\nbootstrap_samples = {bootstrap}\nseed = {seed}"
    )
}

/// Renders `scene` at `spp` mutations per pixel on `threads` threads.
pub fn render_mlt(scene: &Scene, spp: u32, threads: Option<usize>) -> RenderOutput {
    let options = RenderOptions {
        spp,
        time_budget: None,
        spp_is_cap: false,
        threads,
        progress: false,
    };
    render(scene, &options, &AtomicBool::new(false))
}

/// Mean luminance of an image.
pub fn mean_luminance(out: &RenderOutput) -> f64 {
    let px = &out.image.pixels;
    px.iter().map(|p| p.luminance() as f64).sum::<f64>() / px.len() as f64
}
