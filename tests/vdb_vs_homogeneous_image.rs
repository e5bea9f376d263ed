//! A constant-density VDB medium renders the same image as the homogeneous
//! medium of the same σt: every pixel agrees within 5 combined standard
//! errors, and the image means agree within 4 pooled standard errors (which
//! a 10% change of σt fails). The whole scene sits deep inside a 128 m box
//! (the VDB `homogeneous_box.vdb` scaled up), so the VDB's filtered one-voxel
//! rim, where the two media differ, is reached only through
//! e^(-0.15·50) ≈ 6e-4 of transmittance and adds nothing measurable.

mod common;

use common::*;

/// A lit room deep inside the 128 m box: a point light, a sky, an emissive
/// wall, a floor and a red ball, with `medium` (TOML) around them.
fn scene(medium: &str) -> String {
    SceneText::camera([64.0, 64.0, 56.0], [64.0, 64.0, 70.0], [8, 8])
        .fov(50.0)
        .integrator("max_depth = 32")
        .point_light([65.0, 66.0, 60.0], [10.0, 8.0, 6.0])
        .environment(0.2)
        .quad([64.0, 64.0, 66.0], [0.0, 0.0, -1.0], [20.0, 20.0])
        .with("emission = [1.0, 0.8, 0.5]")
        .quad([64.0, 61.0, 60.0], [0.0, 1.0, 0.0], [40.0, 40.0])
        .with("material = { type = \"diffuse\", albedo = 0.6 }")
        .sphere([63.0, 63.0, 61.0], 1.0)
        .with("material = { type = \"diffuse\", albedo = [0.7, 0.3, 0.2] }")
        .raw(medium)
        .build()
}

#[test]
fn constant_vdb_box_renders_like_the_homogeneous_medium() {
    let vdb = scene(
        r#"[[medium]]
        type = "vdb"
        file = "tests/data/volumes/homogeneous_box.vdb"
        density_scale = 0.15
        albedo = 0.5
        phase = { type = "hg", g = 0.5 }
        transform = { scale = 128.0 }"#,
    );
    let homogeneous = scene(
        r#"[[medium]]
        type = "homogeneous"
        sigma_t = 0.15
        albedo = 0.5
        phase = { type = "hg", g = 0.5 }
        bounds = { type = "box", min = [-2.0, -2.0, -2.0], max = [126.0, 126.0, 126.0] }"#,
    );
    let a = estimate_pixels(&scene_from_str(&vdb), 4096);
    let b = estimate_pixels(&scene_from_str(&homogeneous), 4096);
    // per pixel and pooled (far more sensitive), each error combined with the other image's
    let b_mean: Vec<[f64; 3]> = b.iter().map(|p| p.mean).collect();
    let b_se: Vec<[f64; 3]> = b.iter().map(|p| p.std_error).collect();
    assert_pixels(&a, &b_mean, &b_se, "VDB vs homogeneous");
    let brightest = b_mean.iter().flatten().fold(0.0f64, |m, &v| m.max(v));
    assert!(brightest > 0.01, "the image is lit: {brightest}");
}
