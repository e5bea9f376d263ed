//! `render --denoise` (cargo feature `denoise`, Intel Open Image Denoise):
//! the denoised layer is closer to a converged reference than the noisy beauty.
//!
//! Built without the feature, each test here is recorded as skipped by name
//! (tests/common/skip.rs); `.ci/run` runs them in a step with the feature.
#![cfg_attr(not(feature = "denoise"), allow(dead_code, unused_imports))]

mod common;

use brume::image_io::read_exr_channels;

/// A lit sphere on a plane, 64×48 pixels.
const SCENE: &str = r#"
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
fov = 40.0
resolution = [64, 48]
[[light]]
type = "sun"
direction = [-1.0, -2.0, -0.5]
irradiance = 3.0
[[light]]
type = "environment"
radiance = [0.2, 0.25, 0.35]
[[shape]]
type = "sphere"
center = [0.0, 0.6, 0.0]
radius = 0.6
material = { type = "diffuse", albedo = [0.8, 0.4, 0.2] }
[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [20.0, 20.0]
material = { type = "diffuse", albedo = 0.6 }
"#;

fn rgb(channels: &[(String, Vec<f32>)], prefix: &str) -> Vec<f32> {
    let get = |c: &str| {
        &channels
            .iter()
            .find(|(n, _)| n == &format!("{prefix}{c}"))
            .unwrap()
            .1
    };
    let (r, g, b) = (get("R"), get("G"), get("B"));
    (0..r.len()).flat_map(|i| [r[i], g[i], b[i]]).collect()
}

fn rmse(a: &[f32], b: &[f32]) -> f64 {
    let se: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (*x as f64 - *y as f64).powi(2))
        .sum();
    (se / a.len() as f64).sqrt()
}

#[cfg(feature = "denoise")]
#[test]
fn the_denoised_layer_is_closer_to_the_reference_than_the_beauty() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ball.toml"), SCENE).unwrap();
    let render = |spp: &str, out: &str, denoise: bool| {
        let mut cmd = assert_cmd::Command::cargo_bin("brume").unwrap();
        cmd.current_dir(dir.path()).args([
            "render",
            "ball.toml",
            "--quiet",
            "--spp",
            spp,
            "--out",
            out,
        ]);
        if denoise {
            cmd.arg("--denoise");
        }
        cmd.assert().success();
        read_exr_channels(&dir.path().join(out)).unwrap().2
    };
    let noisy = render("4", "noisy.exr", true);
    let reference = render("1024", "reference.exr", false);
    let names: Vec<&str> = noisy.iter().map(|(n, _)| n.as_str()).collect();
    for c in [
        "denoised.R",
        "denoised.G",
        "denoised.B",
        "albedo.R",
        "normal.Z",
    ] {
        assert!(names.contains(&c), "{c} missing from {names:?}");
    }
    let truth = rgb(&reference, "");
    let before = rmse(&rgb(&noisy, ""), &truth);
    let after = rmse(&rgb(&noisy, "denoised."), &truth);
    eprintln!("rmse against 1024 spp: noisy 4 spp {before:.5}, denoised {after:.5}");
    assert!(after < 0.5 * before, "denoised {after} vs noisy {before}");
}

/// Without the feature, every test of this file (found in its own source,
/// so a new one cannot be forgotten) is recorded as skipped by name.
#[cfg(not(feature = "denoise"))]
#[test]
fn denoise_tests_need_the_denoise_feature() {
    let source = include_str!("denoise.rs");
    let lines: Vec<&str> = source.lines().collect();
    let gated: Vec<&str> = lines
        .windows(3)
        .filter(|w| w[0] == "#[cfg(feature = \"denoise\")]" && w[1] == "#[test]")
        .filter_map(|w| w[2].strip_prefix("fn ")?.split('(').next())
        .collect();
    assert!(
        !gated.is_empty(),
        "no feature-gated test found in denoise.rs"
    );
    for name in gated {
        common::skip::skip_named(
            &format!("denoise::{name}"),
            "built without --features denoise (Open Image Denoise: .ci/install-oidn.sh, README)",
        );
    }
}
