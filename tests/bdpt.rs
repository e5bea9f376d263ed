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

/// A lamp inside a glass ball above a floor: its light leaves the glass
/// once, so the light subpath's refraction weight is not cancelled by a
/// second crossing as it is for a light outside a ball. Light tracing
/// (s = 3, t = 1) and the eye path that hits the lamp through the glass
/// (s = 0, t = 4) estimate the same paths without MIS, and the whole image
/// must equal the path tracer's.
#[test]
fn a_lamp_inside_glass_matches_the_path_tracer() {
    let scene = scene_from_str(LAMP_IN_GLASS);
    let strategies = unweighted_pixels(&scene, 4096, &[(3, 1), (0, 4)]);
    let (light, eye) = (&strategies[0].1, &strategies[1].1);
    eprintln!(
        "light tracing {:?} eye {:?}",
        image_mean(light),
        image_mean(eye)
    );
    assert_agree(light, eye, "lamp in glass, s=3 t=1 against s=0 t=4");
    let path = estimate_pixels(&scene, 8192);
    let bdpt = bdpt_pixels(&scene, 2048);
    assert_agree(&bdpt, &path, "lamp in glass");
}

const LAMP_IN_GLASS: &str = r#"
[camera]
position = [2.5, 2.0, 2.5]
look_at = [0.5, 0.0, 0.5]
fov = 20.0
resolution = [6, 6]

[integrator]
max_depth = 6

[[shape]]
type = "sphere"
center = [0.0, 0.6, 0.0]
radius = 0.25
emission = [1.0, 1.0, 1.0]
material = { type = "diffuse", albedo = 0.0 }

[[shape]]
type = "sphere"
center = [0.0, 0.6, 0.0]
radius = 0.4
material = { type = "dielectric", ior = 1.5 }

[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [10.0, 10.0]
material = { type = "diffuse", albedo = [0.5, 0.5, 0.5] }
"#;
