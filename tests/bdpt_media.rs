//! Bidirectional path tracing in homogeneous media: furnaces whose every
//! pixel is known in closed form, and the path tracer's image on
//! single- and multiple-scattering scenes with suns, environments, point
//! and spot lights.

mod bdpt_support;

use bdpt_support::common::furnace_scene;
use bdpt_support::common::scene_text::SceneText;
use bdpt_support::*;

/// Albedo-1 media (isotropic and HG, thin and thick, grey and chromatic σt)
/// inside an environment of radiance 1: every pixel is 1.
#[test]
fn white_furnace_media() {
    for (sigma_t, phase, spp) in [
        ("0.3", "{ type = \"isotropic\" }", 256),
        ("8.0", "{ type = \"isotropic\" }", 64),
        ("0.3", "{ type = \"hg\", g = 0.8 }", 256),
        ("[2.0, 0.5, 6.0]", "{ type = \"hg\", g = -0.4 }", 256),
    ] {
        let medium = format!(
            "[[medium]]\ntype = \"homogeneous\"\nsigma_t = {sigma_t}\nalbedo = 1.0\nphase = {phase}\nbounds = {{ type = \"sphere\", radius = 1.0 }}\n"
        );
        let scene = scene_from_str(&furnace_scene(&medium, 1.0));
        let pixels = bdpt_pixels(&scene, spp);
        let what = format!("white furnace σt={sigma_t} phase={phase}");
        assert_pixels_equal(&pixels, [1.0; 3], &what);
    }
}

/// Media emitting σa·Le with Le the environment's radiance: every pixel is Le,
/// the medium's emission gathered by the camera subpath alone.
#[test]
fn emissive_furnace_media() {
    for (sigma_a, sigma_s, g) in [
        ("0.5", "0.5", "0.0"),
        ("[2.0, 0.1, 0.5]", "[1.0, 3.0, 0.2]", "-0.5"),
        ("3.0", "0.0", "0.3"),
    ] {
        let medium = format!(
            "[[medium]]\ntype = \"homogeneous\"\nsigma_a = {sigma_a}\nsigma_s = {sigma_s}\nemission = 0.7\nphase = {{ type = \"hg\", g = {g} }}\nbounds = {{ type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }}\ntransform = {{ rotate = [20.0, 30.0, 0.0] }}\n"
        );
        let scene = scene_from_str(&furnace_scene(&medium, 0.7));
        let pixels = bdpt_pixels(&scene, 256);
        let what = format!("emissive furnace σa={sigma_a} σs={sigma_s} g={g}");
        assert_pixels_equal(&pixels, [0.7; 3], &what);
    }
}

/// A closed room of inward emissive walls (radiance 1, albedo 0) around a
/// white sphere in a white medium: every pixel is 1, with light subpaths
/// starting on every wall and sphere emitters.
#[test]
fn emissive_room_furnace_with_a_medium() {
    let mut walls = String::new();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut center = [0.0; 3];
            let mut normal = [0.0; 3];
            center[axis] = 2.0 * sign;
            normal[axis] = -sign;
            walls += &format!(
                "[[shape]]\ntype = \"quad\"\ncenter = {center:?}\nnormal = {normal:?}\nsize = [4.0, 4.0]\nemission = 1.0\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n"
            );
        }
    }
    let text = format!(
        "[camera]\nposition = [0.3, -0.2, 1.7]\nlook_at = [0.0, 0.0, 0.0]\nfov = 70.0\nresolution = [6, 6]\n\
         [integrator]\nmax_depth = 1000\nrr_depth = 5\nseed = 7\n{walls}\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.0, -0.3, 0.0]\nradius = 0.8\nmaterial = {{ type = \"diffuse\", albedo = 1.0 }}\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [1.2, 0.9, -0.4]\nradius = 0.15\nemission = 1.0\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n\
         [[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.7\nalbedo = 1.0\nphase = {{ type = \"hg\", g = 0.5 }}\nbounds = {{ type = \"box\", min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }}\n"
    );
    let pixels = bdpt_pixels(&scene_from_str(&text), 128);
    assert_pixels_equal(&pixels, [1.0; 3], "emissive room with a medium");
}

/// The slab y ∈ [0, 1] under a delta sun, seen from above at 6×6 pixels,
/// with single scattering only or all orders, over an absorbing ground.
fn sunlit_slab(sigma_t: &str, albedo: &str, g: f32, max_scatter_depth: Option<u32>) -> String {
    SceneText::camera([0.0, 5.0, 5.0], [0.0; 3], [6, 6])
        .fov(30.0)
        .integrator(&format!(
            "max_depth = 1000\nseed = 11\n{}",
            scatter_depth(max_scatter_depth)
        ))
        .sun([-0.5, -0.866, 0.0], [3.0, 2.0, 4.0])
        .with("angular_radius = 0.0")
        .quad([0.0; 3], [0.0, 1.0, 0.0], [40.0, 40.0])
        .with("material = { type = \"diffuse\", albedo = 0.0 }")
        .medium(&format!(
            "type = \"homogeneous\"\nsigma_t = {sigma_t}\nalbedo = {albedo}\n\
             phase = {{ type = \"hg\", g = {g:?} }}\n\
             bounds = {{ type = \"box\", min = [-20.0, 0.0, -20.0], max = [20.0, 1.0, 20.0] }}"
        ))
        .build()
}

/// `max_scatter_depth = d` for `Some(d)`, nothing (all orders) for `None`.
fn scatter_depth(max_scatter_depth: Option<u32>) -> String {
    max_scatter_depth.map_or(String::new(), |d| format!("max_scatter_depth = {d}"))
}

/// The sunlit slab of the analytic suite, single and multiple scattering,
/// grey and chromatic: the path tracer's image (which matches the closed form).
#[test]
fn sunlit_slab_matches_the_path_tracer() {
    for (sigma_t, albedo, g) in [
        ("1.0", "0.9", 0.6),
        ("[0.2, 0.6, 1.5]", "[0.9, 0.7, 0.5]", 0.4),
    ] {
        for depth in [Some(1), None] {
            let scene = scene_from_str(&sunlit_slab(sigma_t, albedo, g, depth));
            let path = estimate_pixels(&scene, 2048);
            let bdpt = bdpt_pixels(&scene, 512);
            let what = format!("slab σt={sigma_t} albedo={albedo} g={g} scatter depth {depth:?}");
            assert_agree(&bdpt, &path, &what);
        }
    }
}

/// A point or spot light in a global fog over a diffuse floor, seen through
/// the fog: single scattering only (the analytic suite's quadrature scene)
/// and all orders with the floor's bounces.
fn lit_fog(light: &str, sigma_s: &str, max_scatter_depth: Option<u32>) -> String {
    SceneText::camera([0.0, 1.0, 4.0], [0.5, 0.6, 0.0], [6, 6])
        .fov(50.0)
        .integrator(&format!(
            "max_depth = 100\nseed = 13\n{}",
            scatter_depth(max_scatter_depth)
        ))
        .raw(light)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [8.0, 8.0])
        .with("material = { type = \"diffuse\", albedo = [0.7, 0.6, 0.5] }")
        .medium(&format!(
            "type = \"homogeneous\"\nsigma_a = 0.05\nsigma_s = {sigma_s}\n\
             phase = {{ type = \"hg\", g = 0.5 }}\nglobal = true"
        ))
        .build()
}

const POINT_LIGHT: &str =
    "[[light]]\ntype = \"point\"\nposition = [1.0, 1.2, 0.3]\nintensity = [10.0, 8.0, 6.0]\n";
const SPOT_LIGHT: &str = "[[light]]\ntype = \"spot\"\nposition = [1.0, 2.8, 0.3]\nlook_at = [0.6, 0.0, 0.0]\nintensity = [12.0, 8.0, 4.0]\ncone_angle = 25.0\ncone_falloff = 8.0\n";

/// Point and spot lights in fog: every strategy that can reach a delta
/// light (all but s = 0) against the path tracer with its equiangular
/// sampling. (The spot sits above the image: where a pixel holds the tip
/// of its cone, light tracing finds the 1/r² in-scattering near the tip
/// that the path tracer's rays almost never cross, and the path tracer's
/// standard error misses it.)
#[test]
fn point_and_spot_lights_in_fog_match_the_path_tracer() {
    for (name, light) in [("point", POINT_LIGHT), ("spot", SPOT_LIGHT)] {
        for (sigma_s, depth) in [("0.25", Some(1)), ("[0.3, 0.2, 0.1]", None)] {
            let scene = scene_from_str(&lit_fog(light, sigma_s, depth));
            let path = estimate_pixels(&scene, 2048);
            let bdpt = bdpt_pixels(&scene, 512);
            let what = format!("{name} light, σs={sigma_s}, scatter depth {depth:?}");
            assert_agree(&bdpt, &path, &what);
        }
    }
}
