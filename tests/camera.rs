//! The thin-lens camera and `fov_axis` as a scene file sets them.

mod common;

use brume::render::{render, RenderOptions};
use common::SceneText;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// A sphere on a ground quad under a sky, the camera's table completed by `camera_extra`.
fn scene_text(camera_extra: &str) -> String {
    SceneText::camera([0.0, 1.0, 4.0], [0.0, 0.5, 0.0], [16, 12])
        .fov(40.0)
        .with(camera_extra)
        .light("type = \"sky\"\nzenith = [0.3, 0.5, 1.0]\nhorizon = 1.0\nground = 0.2")
        .sphere([0.0, 0.5, 0.0], 0.5)
        .shape("type = \"quad\"\nnormal = [0.0, 1.0, 0.0]\nsize = [6.0, 6.0]")
        .build()
}

fn pixels(camera_extra: &str) -> Vec<brume::math::color::Rgb> {
    let scene = common::scene_from_str(&scene_text(camera_extra));
    let options = RenderOptions {
        spp: 4,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(1),
        progress: false,
    };
    render(&scene, &options, &AtomicBool::new(false))
        .image
        .pixels
}

#[test]
fn zero_aperture_renders_the_pinhole_image_bit_for_bit() {
    let pinhole = pixels("");
    assert_eq!(
        pinhole,
        pixels("aperture_radius = 0.0\nfocus_distance = 2.0")
    );
    assert_eq!(pinhole, pixels("fov_axis = \"vertical\""));
    assert_ne!(pinhole, pixels("aperture_radius = 0.1"));
    assert_ne!(pinhole, pixels("fov_axis = \"x\""));
}

#[test]
fn bad_lens_keys_name_the_key() {
    let file = Path::new("lens.toml");
    for (extra, key) in [
        ("fov_axis = \"diagonal\"", "camera.fov_axis"),
        ("aperture_radius = -0.5", "camera.aperture_radius"),
        ("focus_distance = 0.0", "camera.focus_distance"),
        ("aperture_radius = nan", "camera.aperture_radius"),
    ] {
        let desc = brume::scene::parse(&scene_text(extra), file).unwrap();
        let err = brume::scene::build(&desc, file, Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("{extra} accepted"))
            .to_string();
        assert!(err.contains(key), "{extra}: {err}");
    }
}
