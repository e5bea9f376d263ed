//! Whole-image renders of the bidirectional estimator for validation: the
//! image (camera estimates plus light-tracing splats), one sample pass at a
//! time, and each strategy (s, t) alone, weighted and unweighted, the
//! images `--debug-strategies DIR` writes (as pbrt does).
//!
//! Sample pass `i` draws sample `i` of every pixel: its image is the camera
//! estimates plus every splat of those samples (a pass is one sample per
//! pixel, so nothing is divided). Passes are independent, identically
//! distributed images whose mean is the render, which is what per-pixel
//! standard errors need, splats included.

use super::{run, BdptArena, Event};
use crate::integrator::Scene;
use crate::math::color::Rgb;

mod parallel;
pub use parallel::render_strategies;

/// One pass over the image: sample `index` of every pixel, its splats added
/// where they land. `image` holds width × height pixels, row-major; it is
/// overwritten.
pub fn render_pass(scene: &Scene, index: u32, arena: &mut BdptArena, image: &mut [Rgb]) {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    assert_eq!(image.len(), (w * h) as usize, "image size");
    image.fill(Rgb::BLACK);
    for y in 0..h {
        for x in 0..w {
            let streams = scene.settings.pixel_streams(x, y);
            let mut splats = std::mem::take(&mut arena.splat_buffer);
            splats.clear();
            let l = super::sample_with_streams(scene, x, y, &streams, index, arena, &mut splats);
            image[(y * w + x) as usize] += l;
            // The film leaves non-finite splats out: so does this image.
            for sp in splats.iter().filter(|sp| sp.radiance.is_finite()) {
                image[(sp.y * w + sp.x) as usize] += sp.radiance;
            }
            arena.splat_buffer = splats;
        }
    }
}

/// The images of one strategy (s, t): what it adds to the render, and what
/// it alone estimates (all paths of its length, s + t − 1 segments).
#[derive(Clone, Debug)]
pub struct StrategyImage {
    /// Light subpath vertices.
    pub s: usize,
    /// Camera subpath vertices.
    pub t: usize,
    /// Per-pixel mean of the MIS-weighted contributions (row-major).
    pub weighted: Vec<Rgb>,
    /// Per-pixel mean of the unweighted contributions.
    pub unweighted: Vec<Rgb>,
}

/// The strategy images of pass `index` alone (sample `index` of every pixel),
/// sorted by (segments, s) as [`render_strategies`] sorts them.
pub fn strategy_pass(
    scene: &Scene,
    index: u32,
    max_segments: usize,
    arena: &mut BdptArena,
) -> Vec<StrategyImage> {
    let mut out = Vec::new();
    add_strategy_pass(scene, index, max_segments, arena, &mut out);
    out.sort_by_key(|im| (im.s + im.t, im.s));
    out
}

/// Adds every contribution of pass `index` to its strategy's images in `out`.
fn add_strategy_pass(
    scene: &Scene,
    index: u32,
    max_segments: usize,
    arena: &mut BdptArena,
    out: &mut Vec<StrategyImage>,
) {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let n = (w * h) as usize;
    for y in 0..h {
        for x in 0..w {
            let streams = scene.settings.pixel_streams(x, y);
            let mut record = |event: Event| {
                let (s, t, px, py, c) = match event {
                    Event::Camera { s, t, c } => (s, t, x, y, c),
                    Event::Splat { s, x, y, c } => (s, 1, x, y, c),
                };
                if s + t - 1 > max_segments || !c.weighted.is_finite() {
                    return;
                }
                let i = match out.iter().position(|im| im.s == s && im.t == t) {
                    Some(i) => i,
                    None => {
                        out.push(StrategyImage {
                            s,
                            t,
                            weighted: vec![Rgb::BLACK; n],
                            unweighted: vec![Rgb::BLACK; n],
                        });
                        out.len() - 1
                    }
                };
                let p = (py * w + px) as usize;
                out[i].weighted[p] += c.weighted;
                out[i].unweighted[p] += c.unweighted;
            };
            run(scene, x, y, &streams, index, arena, &mut record);
        }
    }
}
