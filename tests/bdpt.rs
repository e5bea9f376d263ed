//! Bidirectional path tracing against the path tracer on surface scenes:
//! the same image in expectation, every strategy (s, t) included.

mod bdpt_support;

use bdpt_support::*;

/// A small light (where next-event estimation and light tracing carry most
/// paths) and a large one (where hitting it from the camera side matters as much).
#[test]
fn diffuse_box_matches_the_path_tracer() {
    for light in [0.5, 1.8] {
        let scene = scene_from_str(&diffuse_box(6, light, DIFFUSE_SPHERE));
        let path = estimate_pixels(&scene, 8192);
        let bdpt = bdpt_pixels(&scene, 2048);
        eprintln!("path {:?} bdpt {:?}", image_mean(&path), image_mean(&bdpt));
        assert_agree(&bdpt, &path, &format!("diffuse box, light of side {light}"));
    }
}

/// A mirror and a glass sphere: paths through Dirac BSDFs, which no
/// connection can end at, weighed among the strategies that remain.
#[test]
fn specular_spheres_match_the_path_tracer() {
    let scene = scene_from_str(&diffuse_box(6, 0.8, SPECULAR_SPHERES));
    let path = estimate_pixels(&scene, 8192);
    let bdpt = bdpt_pixels(&scene, 2048);
    eprintln!("path {:?} bdpt {:?}", image_mean(&path), image_mean(&bdpt));
    assert_agree(&bdpt, &path, "specular spheres");
}
