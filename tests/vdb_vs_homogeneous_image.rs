//! A constant-density VDB medium renders the same image as the homogeneous
//! medium of the same σt: every pixel agrees within 5 combined standard
//! errors, and the image means agree within 4 pooled standard errors (which
//! a 10% change of σt fails). The whole scene sits deep inside a 128 m box
//! (the VDB `homogeneous_box.vdb` scaled up), so the VDB's filtered one-voxel
//! rim, where the two media differ, is reached only through
//! e^(-0.15·50) ≈ 6e-4 of transmittance and adds nothing measurable.

mod common;

use common::*;

fn scene(medium: &str) -> String {
    format!(
        r#"
        [camera]
        position = [64.0, 64.0, 56.0]
        look_at = [64.0, 64.0, 70.0]
        fov = 50.0
        resolution = [8, 8]
        [integrator]
        max_depth = 32
        [[light]]
        type = "point"
        position = [65.0, 66.0, 60.0]
        intensity = [10.0, 8.0, 6.0]
        [[light]]
        type = "environment"
        radiance = 0.2
        [[shape]]
        type = "quad"
        center = [64.0, 64.0, 66.0]
        normal = [0.0, 0.0, -1.0]
        size = [20.0, 20.0]
        emission = [1.0, 0.8, 0.5]
        [[shape]]
        type = "quad"
        center = [64.0, 61.0, 60.0]
        normal = [0.0, 1.0, 0.0]
        size = [40.0, 40.0]
        material = {{ type = "diffuse", albedo = 0.6 }}
        [[shape]]
        type = "sphere"
        center = [63.0, 63.0, 61.0]
        radius = 1.0
        material = {{ type = "diffuse", albedo = [0.7, 0.3, 0.2] }}
        {medium}
        "#
    )
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
