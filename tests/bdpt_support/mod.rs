//! Helpers of the bidirectional tests: per-pixel estimates of the BDPT
//! image (camera estimates plus light-tracing splats, pass by pass) beside
//! the path tracer's, and their comparison at the suite's k.
#![allow(dead_code, clippy::needless_range_loop)]

#[path = "../common/mod.rs"]
pub mod common;

#[allow(unused_imports)]
pub use common::{
    assert_estimate, assert_pixels, assert_pixels_equal, assert_same, estimate_pixels, k_sigma,
    scene_from_str, Accumulator, Estimate,
};

use brume::integrator::bdpt::{strategies, BdptArena};
use brume::integrator::Scene;
use brume::math::color::Rgb;

/// Per-pixel estimates of the BDPT image over `spp` passes (sample i of
/// every pixel with the splats of those samples: i.i.d. images).
pub fn bdpt_pixels(scene: &Scene, spp: u32) -> Vec<Estimate> {
    let n = (scene.camera.width() * scene.camera.height()) as usize;
    let mut acc = vec![Accumulator::default(); n];
    let mut pass = vec![Rgb::BLACK; n];
    let mut arena = BdptArena::new();
    for i in 0..spp {
        strategies::render_pass(scene, i, &mut arena, &mut pass);
        for (a, p) in acc.iter_mut().zip(&pass) {
            a.add(*p);
        }
    }
    acc.iter().map(Accumulator::estimate).collect()
}

/// Asserts the BDPT image equals the path tracer's within their joint standard errors.
pub fn assert_agree(bdpt: &[Estimate], path: &[Estimate], what: &str) {
    let mean: Vec<[f64; 3]> = path.iter().map(|e| e.mean).collect();
    let se: Vec<[f64; 3]> = path.iter().map(|e| e.std_error).collect();
    assert_pixels(bdpt, &mean, &se, what);
}

/// Image mean of the per-pixel estimates (for messages and sanity checks).
pub fn image_mean(pixels: &[Estimate]) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in pixels {
        for c in 0..3 {
            m[c] += p.mean[c] / pixels.len() as f64;
        }
    }
    m
}

/// Per-pixel estimates, over `spp` passes, of the unweighted images of every
/// strategy (s, t) in `wanted` (a pass where a strategy found nothing adds zero).
pub fn unweighted_pixels(
    scene: &Scene,
    spp: u32,
    wanted: &[(usize, usize)],
) -> Vec<((usize, usize), Vec<Estimate>)> {
    let n = (scene.camera.width() * scene.camera.height()) as usize;
    let max_segments = wanted.iter().map(|(s, t)| s + t - 1).max().unwrap_or(0);
    let mut acc = vec![vec![Accumulator::default(); n]; wanted.len()];
    let mut arena = BdptArena::new();
    let zero = vec![Rgb::BLACK; n];
    for i in 0..spp {
        let pass = strategies::strategy_pass(scene, i, max_segments, &mut arena);
        for (k, &(s, t)) in wanted.iter().enumerate() {
            let image = pass
                .iter()
                .find(|im| im.s == s && im.t == t)
                .map_or(&zero, |im| &im.unweighted);
            for (a, p) in acc[k].iter_mut().zip(image) {
                a.add(*p);
            }
        }
    }
    wanted
        .iter()
        .zip(acc)
        .map(|(&st, a)| (st, a.iter().map(Accumulator::estimate).collect()))
        .collect()
}

/// Per-pixel estimates of the path tracer's paths of exactly `segments`
/// segments: sample by sample, the render at `max_depth = segments − 1`
/// minus the one at `segments − 2` (the same camera ray and numbers up to there).
pub fn path_tracer_length(text: impl Fn(u32) -> String, segments: u32, spp: u32) -> Vec<Estimate> {
    let long = scene_from_str(&text(segments - 1));
    let short = (segments >= 2).then(|| scene_from_str(&text(segments - 2)));
    let (w, h) = (long.camera.width(), long.camera.height());
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let mut acc = Accumulator::default();
            for s in 0..spp {
                let mut l = brume::render::pixel_sample(&long, x, y, s);
                if let Some(short) = &short {
                    l = l - brume::render::pixel_sample(short, x, y, s);
                }
                acc.add(l);
            }
            out.push(acc.estimate());
        }
    }
    out
}

/// A diffuse box (floor, back, left and ceiling walls) lit by a square area
/// light of side `light` just below its ceiling (emitting 1.5/side²), at
/// `max_depth`, with `extra` TOML appended.
pub fn diffuse_box(max_depth: u32, light: f32, extra: &str) -> String {
    let emission = 1.5 / (light * light);
    format!(
        r#"
        [camera]
        position = [0.0, 1.0, 3.4]
        look_at = [0.0, 1.0, 0.0]
        fov = 45.0
        resolution = [8, 8]
        [integrator]
        max_depth = {max_depth}
        rr_depth = 3
        seed = 3
        [[shape]]
        type = "quad"
        center = [0.0, 0.0, 0.0]
        normal = [0.0, 1.0, 0.0]
        size = [2.0, 2.0]
        material = {{ type = "diffuse", albedo = [0.8, 0.7, 0.6] }}
        [[shape]]
        type = "quad"
        center = [0.0, 1.0, -1.0]
        normal = [0.0, 0.0, 1.0]
        size = [2.0, 2.0]
        material = {{ type = "diffuse", albedo = 0.7 }}
        [[shape]]
        type = "quad"
        center = [-1.0, 1.0, 0.0]
        normal = [1.0, 0.0, 0.0]
        size = [2.0, 2.0]
        material = {{ type = "diffuse", albedo = [0.7, 0.2, 0.2] }}
        [[shape]]
        type = "quad"
        center = [0.0, 2.0, 0.0]
        normal = [0.0, -1.0, 0.0]
        size = [2.0, 2.0]
        material = {{ type = "diffuse", albedo = 0.7 }}
        [[shape]]
        type = "quad"
        center = [0.0, 1.99, 0.0]
        normal = [0.0, -1.0, 0.0]
        size = [{light:?}, {light:?}]
        emission = {emission:?}
        material = {{ type = "diffuse", albedo = 0.0 }}
        {extra}
        "#
    )
}

/// A diffuse sphere standing on the box's floor.
pub const DIFFUSE_SPHERE: &str = r#"
[[shape]]
type = "sphere"
center = [0.3, 0.4, -0.2]
radius = 0.4
material = { type = "diffuse", albedo = [0.3, 0.6, 0.9] }
"#;

/// A mirror sphere and a glass sphere in the box: caustics on the floor and walls.
pub const SPECULAR_SPHERES: &str = r#"
[[shape]]
type = "sphere"
center = [-0.4, 0.35, -0.3]
radius = 0.35
material = { type = "mirror", reflectance = [0.9, 0.9, 0.8] }
[[shape]]
type = "sphere"
center = [0.45, 0.3, 0.2]
radius = 0.3
material = { type = "dielectric", ior = 1.5 }
"#;
