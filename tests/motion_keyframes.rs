//! Keyframed transforms (`transform = { keyframes = [...] }`) of the camera,
//! media and shapes, against closed forms averaged over the shutter.
//!
//! * a camera translating sideways past a sharp emissive edge: each pixel's
//!   value is the fraction of the shutter during which it sees the emitter,
//!   averaged over the pixel (a linear ramp, integrated in closed form);
//! * keyframes that do not move, and a still scene, are bit-identical to the
//!   same scene written without keyframes.

#[path = "common/mod.rs"]
mod common;

use brume::color::Rgb;
use brume::integrator::Scene;
use brume::render::pixel_sample;
use common::{assert_pixels, scene_from_str, Accumulator, Estimate};

/// Every sample of every pixel, in order: equal vectors mean bit-identical images.
fn samples(scene: &Scene, spp: u32) -> Vec<[u32; 3]> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            for s in 0..spp {
                let l: Rgb = pixel_sample(scene, x, y, s);
                out.push([l.r.to_bits(), l.g.to_bits(), l.b.to_bits()]);
            }
        }
    }
    out
}

/// Per-pixel estimates over `spp` samples of the render path.
fn pixel_estimates(scene: &Scene, spp: u32) -> Vec<Estimate> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let mut acc = Accumulator::default();
            for s in 0..spp {
                acc.add(pixel_sample(scene, x, y, s));
            }
            out.push(acc.estimate());
        }
    }
    out
}

/// ∫ f over [a, b] by the midpoint rule on `n` pieces (exact to ~1e-9 for the ramps here).
fn average(a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let n = 20_000;
    let h = (b - a) / n as f64;
    (0..n).map(|i| f(a + (i as f64 + 0.5) * h)).sum::<f64>() / n as f64
}

/// A 16×2 camera with a 90° horizontal fov at the origin looking down −z at
/// an emitter filling x < 0 on the plane z = −8: pixel i sees plane x in [i − 8, i − 7].
fn edge_scene(camera_extra: &str) -> String {
    format!(
        r#"
        [camera]
        position = [0.0, 0.0, 0.0]
        look_at = [0.0, 0.0, -1.0]
        fov = 90.0
        fov_axis = "x"
        resolution = [16, 2]
        {camera_extra}
        [integrator]
        max_depth = 1
        [[shape]]
        type = "quad"
        center = [-25.0, 0.0, -8.0]
        normal = [0.0, 0.0, 1.0]
        size = [50.0, 10.0]
        u_axis = [1.0, 0.0, 0.0]
        emission = 1.0
        "#
    )
}

#[test]
fn a_camera_moving_past_an_edge_gives_the_analytic_ramp() {
    // Camera x goes −2 → 2 linearly over the shutter: pixel i (plane x = s) sees
    // the emitter while cx < −s, a fraction clamp((2 − s)/4, 0, 1) of the shutter.
    let scene = scene_from_str(&edge_scene(
        "shutter = [-0.5, 0.5]\n transform = { keyframes = [\
         { time = -0.5, translate = [-2.0, 0.0, 0.0] }, { time = 0.5, translate = [2.0, 0.0, 0.0] }] }",
    ));
    assert!(scene.camera.is_moving());
    let spp = 1024;
    let pixels = pixel_estimates(&scene, spp);
    let expected: Vec<[f64; 3]> = (0..2)
        .flat_map(|_| 0..16)
        .map(|i| {
            let s0 = i as f64 - 8.0;
            let v = average(s0, s0 + 1.0, |s| ((2.0 - s) / 4.0).clamp(0.0, 1.0));
            [v; 3]
        })
        .collect();
    // The ramp is resolved: pixels 6..=9 are partly lit, not 0 or 1.
    assert!((expected[7][0] - 0.625).abs() < 1e-6, "{:?}", expected[7]);
    assert_pixels(
        &pixels,
        &expected,
        &vec![[0.0; 3]; 32],
        "moving camera edge ramp",
    );
}

#[test]
fn still_keyframes_and_a_still_camera_are_bit_identical() {
    let plain = scene_from_str(&edge_scene("shutter = [-0.5, 0.5]"));
    let keyed = scene_from_str(&edge_scene(
        "shutter = [-0.5, 0.5]\n transform = { keyframes = [\
         { time = -0.5, translate = [0.0, 0.0, 0.0] }, { time = 0.5 }] }",
    ));
    assert!(
        !keyed.camera.is_moving(),
        "keys that do not move are a still camera"
    );
    let a = samples(&plain, 8);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, samples(&keyed, 8));
}
