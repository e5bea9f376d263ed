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
use analytic_support::{scene_from_str, SceneText};

fn with_shutter(scene: &str, shutter: &str) -> String {
    scene.replace("[camera]", &format!("[camera]\nshutter = {shutter}"))
}

/// A sphere and a homogeneous box under a sun and an environment.
fn static_scene() -> String {
    SceneText::camera([0.0, 0.5, 4.0], [0.0, 0.3, 0.0], [8, 6])
        .sun([-0.3, -1.0, -0.2], [3.0, 3.0, 3.0])
        .environment([0.2, 0.3, 0.4])
        .sphere([0.3, 0.3, 0.0], 0.4)
        .medium(
            "type = \"homogeneous\"\nsigma_a = [0.1, 0.1, 0.1]\nsigma_s = [0.4, 0.5, 0.6]\n\
             bounds = { type = \"box\", min = [-1.0, 0.0, -1.0], max = [1.0, 1.0, 1.0] }",
        )
        .build()
}

#[test]
fn a_scene_without_motion_renders_bit_identically_with_a_shutter() {
    let still = scene_from_str(&static_scene());
    let blurred = scene_from_str(&with_shutter(&static_scene(), "[-0.5, 0.5]"));
    assert_eq!(blurred.settings.shutter, Some([-0.5, 0.5]));
    let a = sample_bits(&still, 4);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, sample_bits(&blurred, 4));
}

const PLUME: &str = "tests/data/anim/plume.0001.vdb";

/// The animated test plume under a sun, its medium table completed by `extra_medium`.
fn plume_scene(extra_medium: &str, shutter: Option<&str>) -> String {
    let camera_shutter = shutter.map_or(String::new(), |s| format!("shutter = {s}"));
    SceneText::camera([0.0, 0.6, 2.5], [0.0, 0.6, 0.0], [8, 8])
        .fov(40.0)
        .with(&camera_shutter)
        .sun([-0.5, -1.0, -0.3], [4.0, 4.0, 4.0])
        .environment([0.1, 0.1, 0.1])
        .medium(&format!(
            "type = \"vdb\"\nfile = \"{PLUME}\"\ndensity_scale = 30.0\nalbedo = [0.9, 0.9, 0.9]"
        ))
        .with(extra_medium)
        .build()
}

#[test]
fn a_vdb_with_zero_velocity_renders_bit_identically_with_a_shutter() {
    let zero = scene_from_str(&plume_scene(
        "velocity_grid = \"vel\"\nvelocity_scale = 0.0",
        Some("[-0.5, 0.5]"),
    ));
    let brume::medium::Medium::Grid(m) = &zero.media[0] else {
        panic!("grid medium")
    };
    assert!(m.is_moving(), "the motion path must be the one tested");
    // Moving media always take null collisions (exact voxel walks need a straight
    // lookup line) over cells chosen for that: compare with the still medium
    // tracked the same way, over the same cells.
    let cell = m.majorant_grid().cell_size().x;
    let mut still = scene_from_str(&plume_scene(&format!("majorant_cell = {cell}"), None));
    if let brume::medium::Medium::Grid(g) = &still.media[0] {
        let mut g = (**g).clone();
        g.set_exact_voxels(brume::medium::ExactVoxels::Never);
        still.media[0] = brume::medium::Medium::Grid(std::sync::Arc::new(g));
    }
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
