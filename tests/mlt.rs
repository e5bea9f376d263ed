//! Metropolis light transport (`type = "mlt"`) on closed-form scenes: the
//! image's mean luminance is the bootstrap's brightness b by construction
//! (every splat carries b/I of a state of luminance I), and b must be the
//! furnace's value within the bootstrap's standard error; the image does not
//! depend on the thread count.

mod mlt_support;

use mlt_support::*;

/// A furnace of `medium` in an environment of radiance `env`, rendered by mlt.
fn furnace(medium: &str, env: f32, max_depth: u32) -> String {
    SceneText::furnace_view(6)
        .integrator(&mlt_integrator(max_depth, 1 << 19, 3))
        .environment(env)
        .raw(medium)
        .build()
}

/// Checks image mean = b (to f32 rounding) and b = `expected` within the bootstrap's error.
fn check_brightness(text: &str, expected: f64, what: &str) {
    let scene = scene_from_str(text);
    let out = render_mlt(&scene, 4, None);
    let stats = out.mlt.as_ref().expect("an mlt render reports its chains");
    let mean = mean_luminance(&out);
    eprintln!(
        "{what}: b = {} ± {}, acceptance {:.3}",
        stats.brightness,
        stats.brightness_std_error,
        stats.acceptance()
    );
    assert!(
        (mean - stats.brightness).abs() <= 1e-5 * stats.brightness,
        "{what}: image mean {mean} is not the bootstrap's brightness {}",
        stats.brightness
    );
    assert_within(
        stats.brightness,
        stats.brightness_std_error,
        expected,
        1,
        what,
    );
    assert!(stats.acceptance() > 0.0, "{what}: no mutation accepted");
}

/// An albedo-1 isotropic medium in an environment of radiance 1: every pixel is 1
/// (paths of more than 40 scatterings in a sphere of optical radius 0.3 are negligible).
#[test]
fn white_furnace_medium() {
    let medium = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.3\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"sphere\", radius = 1.0 }\n";
    check_brightness(&furnace(medium, 1.0, 40), 1.0, "white furnace");
}

/// A medium emitting σa·Le with Le the environment's radiance: every pixel is
/// Le, the emission gathered by the k = 1 states' camera subpaths.
#[test]
fn emissive_furnace_medium() {
    let medium = "[[medium]]\ntype = \"homogeneous\"\nsigma_a = 0.5\nsigma_s = 0.5\nemission = 0.7\nphase = { type = \"isotropic\" }\nbounds = { type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }\n";
    check_brightness(&furnace(medium, 0.7, 40), 0.7, "emissive furnace");
}

/// A closed room of inward emissive walls (radiance 1, albedo 0) around a
/// white sphere in a white medium: every pixel is 1, found by every strategy.
#[test]
fn emissive_room_furnace() {
    let mut text = SceneText::camera([0.3, -0.2, 1.7], [0.0; 3], [6, 6])
        .fov(70.0)
        .integrator(&mlt_integrator(60, 1 << 20, 5));
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut center = [0.0f32; 3];
            let mut normal = [0.0f32; 3];
            center[axis] = 2.0 * sign;
            normal[axis] = -sign;
            text = text
                .quad(center, normal, [4.0, 4.0])
                .with("emission = 1.0\nmaterial = { type = \"diffuse\", albedo = 0.0 }");
        }
    }
    let text = text
        .sphere([0.0, -0.3, 0.0], 0.8)
        .with("material = { type = \"diffuse\", albedo = 1.0 }")
        .medium("type = \"homogeneous\"\nsigma_t = 0.7\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"box\", min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }")
        .build();
    check_brightness(&text, 1.0, "emissive room");
}

/// Chains are independent and add their splats in chain order: one thread
/// or two give the same image, bit for bit.
#[test]
fn the_image_does_not_depend_on_the_thread_count() {
    let medium = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 1.0\nalbedo = 0.8\nbounds = { type = \"sphere\", radius = 1.0 }\n";
    let text = SceneText::furnace_view(8)
        .integrator(&mlt_integrator(10, 4096, 9))
        .sun([0.3, -1.0, 0.2], 2.0)
        .raw(medium)
        .build();
    let scene = scene_from_str(&text);
    let one = render_mlt(&scene, 8, Some(1));
    let two = render_mlt(&scene, 8, Some(2));
    assert_eq!(one.image.pixels, two.image.pixels);
    assert!(mean_luminance(&one) > 0.0);
}
