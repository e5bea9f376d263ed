//! Bidirectional path tracing in heterogeneous (VDB) media, whose free
//! flights are the path tracer's null-collision tracking and whose MIS
//! weights see the deterministic surrogate densities: the furnace's closed
//! form and the path tracer's image of a lit smoke plume.

mod bdpt_support;

use bdpt_support::common::furnace_scene;
use bdpt_support::common::scene_text::{vdb_box_medium, SceneText, VDB_BOX_FURNACES};
use bdpt_support::*;

/// Albedo-1 VDB boxes (grid and global majorants, chromatic σt) in an
/// environment of radiance 1: every pixel is 1.
#[test]
fn white_furnace_vdb() {
    for fields in VDB_BOX_FURNACES {
        let scene = scene_from_str(&furnace_scene(&vdb_box_medium(fields), 1.0));
        let pixels = bdpt_pixels(&scene, 256);
        assert_pixels_equal(&pixels, [1.0; 3], &format!("white furnace vdb {fields}"));
    }
}

/// The test plume (1.4 × 1.9 × 1.4 m of fbm smoke) over a diffuse ground,
/// lit by `lights`, its shadow rays estimated by `estimator`.
fn plume(lights: &str, density: f32, estimator: &str) -> String {
    SceneText::plume_view(6)
        .integrator(&format!(
            "max_depth = 24\nseed = 17\ntransmittance = \"{estimator}\""
        ))
        .raw(lights)
        .smoke_plume_on_ground(density)
        .build()
}

const SUN_AND_SKY: &str = "[[light]]\ntype = \"sun\"\ndirection = [-1.0, -1.1, -0.7]\nirradiance = [3.0, 2.85, 2.6]\n[[light]]\ntype = \"sky\"\nzenith = [0.25, 0.4, 0.8]\nhorizon = [0.6, 0.7, 0.8]\n";
const POINT: &str =
    "[[light]]\ntype = \"point\"\nposition = [1.2, 2.2, 1.0]\nintensity = [6.0, 5.0, 4.0]\n";

/// The plume under a sun and sky, and by a point light, thin and dense,
/// with shadow rays by closed form where possible, ratio and residual ratio tracking.
#[test]
fn lit_plume_matches_the_path_tracer() {
    for (lights, density, estimator) in [
        (SUN_AND_SKY, 10.0, "auto"),
        (POINT, 10.0, "ratio"),
        (POINT, 40.0, "residual_ratio"),
    ] {
        let scene = scene_from_str(&plume(lights, density, estimator));
        let path = estimate_pixels(&scene, 2048);
        let bdpt = bdpt_pixels(&scene, 512);
        eprintln!("path {:?} bdpt {:?}", image_mean(&path), image_mean(&bdpt));
        let what = format!("plume density {density}, {estimator} shadow rays");
        assert_agree(&bdpt, &path, &what);
    }
}
