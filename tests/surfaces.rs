//! Closed-form checks of the surface path tracer.

mod common;

use brume::math::{Ray, Vec3};
use brume::render::{render, RenderOptions};
use common::*;
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

/// A closed-form furnace: a sphere of `material` in a uniform environment of
/// radiance 1, seen through a field of view of `fov` degrees.
fn furnace(material: &str, rr_depth: u32, resolution: u32, fov: f32) -> Vec<Estimate> {
    furnace_with(material, rr_depth, resolution, fov, "sobol")
}

/// [`furnace`] with pixel samples drawn by `sampler` (`integrator.sampler`).
fn furnace_with(
    material: &str,
    rr_depth: u32,
    resolution: u32,
    fov: f32,
    sampler: &str,
) -> Vec<Estimate> {
    let text = SceneText::camera([0.0, 0.0, 4.0], [0.0; 3], [resolution, resolution])
        .fov(fov)
        .integrator(&format!(
            "max_depth = 1000\nrr_depth = {rr_depth}\nsampler = \"{sampler}\""
        ))
        .environment(1.0)
        .unit_sphere(material);
    let scene = scene_from_str(&text.build());
    estimate_pixels(&scene, 256)
}

/// A white Lambertian sphere inside a uniform environment of radiance 1:
/// every bounce reflects all light, so every pixel must be exactly 1.
#[test]
fn white_furnace_sphere_in_uniform_environment() {
    let pixels = furnace("{ type = \"diffuse\", albedo = 1.0 }", 1000, 12, 35.0);
    assert_pixels_equal(&pixels, [1.0; 3], "white furnace");
}

/// The same furnace with Russian roulette from the first bounce: still 1
/// (roulette reweights, never biases).
///
/// The sphere fills every pixel (it subtends 14.5° from the camera, the
/// image's corners lie 11.3° off axis): a pixel the sphere only grazes has a
/// few dozen roulette decisions at 5 % each, and when none of them kills
/// (0.95⁶⁰ ≈ 5 %) its sample variance misses the one outcome that carries
/// the variance, so its standard error is underestimated several-fold.
#[test]
fn white_furnace_with_russian_roulette_from_the_first_bounce() {
    let pixels = furnace("{ type = \"diffuse\", albedo = 1.0 }", 0, 8, 16.0);
    assert_pixels_equal(&pixels, [1.0; 3], "furnace with roulette");
}

/// The roulette furnace with independent random numbers (`sampler =
/// "independent"`): every number of the path from the PCG stream, still 1.
#[test]
fn white_furnace_with_roulette_and_independent_samples() {
    let material = "{ type = \"diffuse\", albedo = 1.0 }";
    let pixels = furnace_with(material, 0, 8, 16.0, "independent");
    assert_pixels_equal(&pixels, [1.0; 3], "furnace with independent samples");
}

/// A perfect mirror sphere in the furnace: exactly 1 as well.
#[test]
fn white_furnace_mirror_sphere() {
    let pixels = furnace("{ type = \"mirror\", reflectance = 1.0 }", 1000, 8, 35.0);
    assert_pixels_equal(&pixels, [1.0; 3], "mirror furnace");
}

/// A diffuse plane lit by a point light: L = ρ/π · I cosθ / r², exactly.
#[test]
fn point_light_on_diffuse_plane_matches_closed_form() {
    let light = [1.0f64, 2.0, -0.5];
    let intensity = [10.0, 20.0, 5.0];
    let albedo = [0.5, 0.25, 0.8];
    let text = SceneText::camera([0.0, 5.0, 5.0], [0.0; 3], [4, 4])
        .integrator("max_depth = 1")
        .point_light(light, intensity)
        .shape(&format!(
            "type = \"quad\"\nnormal = [0.0, 1.0, 0.0]\nsize = [100.0, 100.0]\n\
             material = {{ type = \"diffuse\", albedo = {albedo:?} }}"
        ));
    let scene = scene_from_str(&text.build());
    for target in [
        [0.0f32, 0.0, 0.0],
        [3.0, 0.0, 1.0],
        [-2.0, 0.0, -4.0],
        [1.0, 0.0, -0.5],
    ] {
        let eye = Vec3::new(0.3, 3.0, 4.0);
        let p = Vec3::from_array(target);
        let ray = Ray::new(eye, (p - eye).normalize());
        let d = [
            light[0] - target[0] as f64,
            light[1],
            light[2] - target[2] as f64,
        ];
        let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let cos_theta = d[1] / r2.sqrt();
        let est = estimate_ray(&scene, ray, 4, 1);
        for c in 0..3 {
            let expected = albedo[c] / PI * intensity[c] * cos_theta / r2;
            let got = est.mean[c];
            assert!(
                (got - expected).abs() <= 1e-4 * expected,
                "target {target:?} channel {c}: {got} vs {expected}"
            );
        }
    }
}

/// The same seed gives a bit-identical image with 1 and with 2 threads.
#[test]
fn image_is_independent_of_thread_count() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.toml");
    let mut scene = brume::scene::load(&path).unwrap();
    scene.camera = brume::camera::Camera::new(
        Vec3::new(0.0, 1.0, 3.9),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        38.0,
        40,
        40,
    )
    .unwrap();
    let render_with = |threads| {
        let options = RenderOptions {
            spp: 6,
            time_budget: None,
            spp_is_cap: false,
            threads: Some(threads),
            progress: false,
        };
        render(&scene, &options, &AtomicBool::new(false))
            .image
            .pixels
    };
    let one = render_with(1);
    let two = render_with(2);
    let three = render_with(3);
    assert!(one.iter().any(|p| p.max_channel() > 0.0));
    assert!(one
        .iter()
        .zip(&two)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
    assert!(one
        .iter()
        .zip(&three)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
}
