//! Equiangular sampling combined with free flight by MIS: the same answer
//! with and without it, and a lower variance with it near point lights.

mod common;

use brume::math::{Ray, Vec3};
use common::*;

/// A scattering sphere of medium lit by `light` (TOML) and a dim sky.
fn scene_text(equiangular: bool, max_scatter: &str, light: &str) -> String {
    SceneText::view([0.0, 0.0, 4.0], [0.0; 3])
        .integrator(&format!("max_depth = 1000\nequiangular = {equiangular}"))
        .with(max_scatter)
        .raw(light)
        .environment(0.1)
        .medium(
            "type = \"homogeneous\"\nsigma_a = 0.05\nsigma_s = [0.2, 0.3, 0.4]\n\
             phase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"sphere\", radius = 3.0 }",
        )
        .build()
}

const POINT: &str = "[[light]]\ntype = \"point\"\nposition = [0.0, 0.3, 0.0]\nintensity = 1.0\n";
const SPOT: &str = "[[light]]\ntype = \"spot\"\nposition = [0.0, 0.3, 0.0]\nlook_at = [0.0, -1.0, 0.0]\nintensity = 2.0\ncone_angle = 60.0\n";

/// Same expectation with and without equiangular sampling (single and multiple
/// scattering, point and spot lights); the difference is within 4 combined
/// standard errors, and equiangular sampling lowers the standard error.
#[test]
fn equiangular_and_free_flight_agree_and_equiangular_lowers_variance() {
    let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    for light in [POINT, SPOT] {
        for max_scatter in ["max_scatter_depth = 1", ""] {
            let without = estimate_ray(
                &scene_from_str(&scene_text(false, max_scatter, light)),
                ray,
                100_000,
                3,
            );
            let with = estimate_ray(
                &scene_from_str(&scene_text(true, max_scatter, light)),
                ray,
                100_000,
                4,
            );
            assert_same(&without, &with, max_scatter);
            assert_lower_error(&with, &without, 0.8, max_scatter);
        }
    }
}

/// A point light a hundred-thousandth below a ceiling: the shadow rays of
/// both strategies must stop short of the light, not reach the ceiling
/// behind it, so the two agree (with the equiangular connection running on
/// past the light by 10⁻⁴ of its length, its samples would all be blocked).
#[test]
fn a_point_light_just_below_a_ceiling_lights_the_medium_alike_either_way() {
    let light = format!(
        "{POINT}[[shape]]\ntype = \"quad\"\ncenter = [0.0, 0.30001, 0.0]\nnormal = [0.0, -1.0, 0.0]\nsize = [0.5, 0.5]\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n"
    );
    let max_scatter = "max_scatter_depth = 1";
    let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    let without = estimate_ray(
        &scene_from_str(&scene_text(false, max_scatter, &light)),
        ray,
        100_000,
        5,
    );
    let with = estimate_ray(
        &scene_from_str(&scene_text(true, max_scatter, &light)),
        ray,
        100_000,
        6,
    );
    assert_same(&without, &with, "point light under a ceiling");
}
