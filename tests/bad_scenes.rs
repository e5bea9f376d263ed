//! Bad scene input: every case exits with code 2, prints one error line that
//! names the file and the culprit, never panics, and leaves outputs alone.

mod common;

use common::cli::{assert_scene_refused, brume};
use std::ffi::OsStr;
use std::path::Path;

const CAMERA: &str =
    "[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [8, 8]\n";
const LIGHT: &str = "[[light]]\ntype = \"point\"\nposition = [0.0, 3.0, 0.0]\nintensity = 5.0\n";

/// (name, scene text, text the error must contain).
fn cases() -> Vec<(&'static str, String, &'static str)> {
    let with = |extra: &str| format!("{CAMERA}{LIGHT}{extra}");
    vec![
        ("malformed toml", "[camera\nposition = [".into(), "line 1"),
        ("not toml at all", "\u{0}\u{1}binary".into(), "line"),
        ("missing camera", LIGHT.into(), "camera"),
        ("unknown top-level key", format!("{CAMERA}{LIGHT}colour = 1\n"), "colour"),
        ("unknown camera key", format!("{CAMERA}aperture = 2.0\n{LIGHT}"), "aperture"),
        ("camera position wrong type", "[camera]\nposition = \"here\"\nlook_at = [0.0,0.0,0.0]\n".into(), "camera.position"),
        ("camera position too short", "[camera]\nposition = [1.0]\nlook_at = [0.0,0.0,0.0]\n".into(), "camera.position"),
        ("look_at equals position", format!("[camera]\nposition = [1.0,1.0,1.0]\nlook_at = [1.0,1.0,1.0]\n{LIGHT}"), "camera.look_at"),
        ("up parallel to view", format!("[camera]\nposition = [0.0,0.0,0.0]\nlook_at = [0.0,5.0,0.0]\n{LIGHT}"), "camera.up"),
        ("zero resolution", format!("[camera]\nposition = [0.0,0.0,1.0]\nlook_at = [0.0,0.0,0.0]\nresolution = [0, 8]\n{LIGHT}"), "camera.resolution"),
        ("negative resolution", format!("[camera]\nposition = [0.0,0.0,1.0]\nlook_at = [0.0,0.0,0.0]\nresolution = [-4, 8]\n{LIGHT}"), "camera.resolution"),
        ("fov out of range", format!("[camera]\nposition = [0.0,0.0,1.0]\nlook_at = [0.0,0.0,0.0]\nfov = 190.0\n{LIGHT}"), "camera.fov"),
        ("nan fov", format!("[camera]\nposition = [0.0,0.0,1.0]\nlook_at = [0.0,0.0,0.0]\nfov = nan\n{LIGHT}"), "camera.fov"),
        ("zero spp", with("[integrator]\nspp = 0\n"), "integrator.spp"),
        ("unknown integrator key", with("[integrator]\nsamples = 4\n"), "samples"),
        ("unknown sampler", with("[integrator]\nsampler = \"halton\"\n"), "integrator.sampler: unknown sampler `halton`, expected sobol or independent"),
        ("empty scene", CAMERA.into(), "empty"),
        ("unknown light type", format!("{CAMERA}[[light]]\ntype = \"laser\"\n"), "laser"),
        ("light missing intensity", format!("{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0,0.0,0.0]\n"), "intensity"),
        ("negative intensity", format!("{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0,0.0,0.0]\nintensity = -1.0\n"), "light[0].intensity"),
        ("nan intensity channel", format!("{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0,0.0,0.0]\nintensity = [1.0, nan, 1.0]\n"), "light[0].intensity[1]"),
        ("infinite position", format!("{CAMERA}[[light]]\ntype = \"point\"\nposition = [inf,0.0,0.0]\nintensity = 1.0\n"), "light[0].position[0]"),
        ("colour with four channels", format!("{CAMERA}[[light]]\ntype = \"environment\"\nradiance = [1.0, 1.0, 1.0, 1.0]\n"), "radiance"),
        ("zero sun direction", format!("{CAMERA}[[light]]\ntype = \"sun\"\ndirection = [0.0,0.0,0.0]\nirradiance = 1.0\n"), "light[0].direction"),
        ("two environments", format!("{CAMERA}[[light]]\ntype = \"environment\"\nradiance = 1.0\n[[light]]\ntype = \"sky\"\nzenith = 1.0\nhorizon = 1.0\n"), "light[1]"),
        ("spot aimed at itself", format!("{CAMERA}[[light]]\ntype = \"spot\"\nposition = [0.0,1.0,0.0]\nlook_at = [0.0,1.0,0.0]\nintensity = 1.0\n"), "light[0].look_at"),
        ("unknown shape type", with("[[shape]]\ntype = \"torus\"\n"), "torus"),
        ("negative radius", with("[[shape]]\ntype = \"sphere\"\nradius = -1.0\n"), "shape[0].radius"),
        ("missing radius", with("[[shape]]\ntype = \"sphere\"\n"), "shape[0].radius"),
        ("radius on a quad", with("[[shape]]\ntype = \"quad\"\nnormal = [0.0,1.0,0.0]\nsize = [1.0,1.0]\nradius = 2.0\n"), "shape[0].radius"),
        ("quad size wrong length", with("[[shape]]\ntype = \"quad\"\nnormal = [0.0,1.0,0.0]\nsize = [1.0]\n"), "shape[0].size"),
        ("zero quad normal", with("[[shape]]\ntype = \"quad\"\nnormal = [0.0,0.0,0.0]\nsize = [1.0,1.0]\n"), "shape[0].normal"),
        ("albedo above one", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\nmaterial = { type = \"diffuse\", albedo = 1.5 }\n"), "shape[0].material.albedo"),
        ("negative albedo", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\nmaterial = { type = \"diffuse\", albedo = [0.5, -0.1, 0.5] }\n"), "shape[0].material.albedo"),
        ("unknown material key", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\nmaterial = { type = \"diffuse\", albedo = 0.5, roughness = 0.1 }\n"), "roughness"),
        ("unknown material type", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\nmaterial = { type = \"velvet\" }\n"), "velvet"),
        ("negative phong exponent", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\nmaterial = { type = \"phong\", albedo = 0.5, exponent = -3.0 }\n"), "shape[0].material.exponent"),
        ("negative emission", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\nemission = -2.0\n"), "shape[0].emission"),
        ("missing obj", with("[[shape]]\ntype = \"mesh\"\nfile = \"no_such_mesh.obj\"\n"), "no_such_mesh.obj"),
        ("zero scale", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\ntransform = { scale = 0.0 }\n"), "shape[0].transform.scale"),
        ("non-uniform sphere scale", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\ntransform = { scale = [1.0, 2.0, 1.0] }\n"), "shape[0].transform.scale"),
        ("disk without a normal", with("[[shape]]\ntype = \"disk\"\nradius = 1.0\n"), "shape[0].normal"),
        ("size on a disk", with("[[shape]]\ntype = \"disk\"\nnormal = [0.0,1.0,0.0]\nradius = 1.0\nsize = [1.0,1.0]\n"), "shape[0].size"),
        ("disk u_axis along its normal", with("[[shape]]\ntype = \"disk\"\nnormal = [0.0,1.0,0.0]\nradius = 1.0\nu_axis = [0.0,2.0,0.0]\n"), "shape[0].u_axis"),
        ("non-uniform disk scale", with("[[shape]]\ntype = \"disk\"\nnormal = [0.0,1.0,0.0]\nradius = 1.0\ntransform = { scale = [1.0, 1.0, 2.0] }\n"), "a disk needs a uniform scale"),
        ("interior in a disk", with("[[shape]]\ntype = \"disk\"\nnormal = [0.0,1.0,0.0]\nradius = 1.0\ninterior = { type = \"homogeneous\", sigma_a = 1.0, sigma_s = 0.0 }\n"), "a disk encloses no volume"),
        ("unknown transform key", with("[[shape]]\ntype = \"sphere\"\nradius = 1.0\ntransform = { shear = 1.0 }\n"), "shear"),
    ]
}

#[test]
fn every_bad_scene_gives_one_clear_error_line_and_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let cases = cases();
    assert!(cases.len() >= 30);
    let out_png = dir.path().join("out.png");
    let png = [OsStr::new("--png"), out_png.as_os_str()];
    for (i, (name, text, culprit)) in cases.iter().enumerate() {
        let file = format!("case{i}.toml");
        assert_scene_refused(dir.path(), &file, text, &png, &[*culprit], name);
        assert!(!out_png.exists(), "{name}: png written");
    }
}

fn tiny_scene(dir: &Path) -> std::path::PathBuf {
    let scene = dir.join("tiny.toml");
    std::fs::write(
        &scene,
        format!("{CAMERA}{LIGHT}[[shape]]\ntype = \"sphere\"\nradius = 1.0\n"),
    )
    .unwrap();
    scene
}

#[test]
fn unwritable_output_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let scene = tiny_scene(dir.path());
    let output = brume()
        .args(["render", "--quiet"])
        .arg(&scene)
        .arg("--out")
        .arg(dir.path().join("missing_folder/out.exr"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("missing_folder/out.exr"), "{stderr}");
}

#[test]
fn bad_command_line_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = tiny_scene(dir.path());
    for (flag, value) in [
        ("--spp", "0"),
        ("--threads", "0"),
        ("--time", "-1"),
        ("--time", "nan"),
    ] {
        let output = brume()
            .current_dir(dir.path())
            .args(["render", "--quiet"])
            .arg(&scene)
            .args([flag, value])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{flag} {value}: {stderr}");
        assert!(stderr.contains(flag), "{flag}: {stderr}");
    }
}

#[test]
fn a_good_scene_renders_and_writes_both_files() {
    let dir = tempfile::tempdir().unwrap();
    let scene = tiny_scene(dir.path());
    let output = brume()
        .current_dir(dir.path())
        .args(["render", "--quiet", "--spp", "2"])
        .arg(&scene)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let (w, h, pixels) = brume::film::image_io::read_exr(&dir.path().join("tiny.exr")).unwrap();
    assert_eq!((w, h), (8, 8));
    assert!(pixels.iter().any(|p| p.max_channel() > 0.0));
    assert!(dir.path().join("tiny.png").exists());

    // `--debug-pixel` replays exactly the samples the render took for that pixel.
    let output = brume()
        .current_dir(dir.path())
        .args(["render", "--spp", "2", "--debug-pixel", "3,4"])
        .arg(&scene)
        .output()
        .unwrap();
    assert!(output.status.success());
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("mean radiance"))
        .expect("mean line");
    let replayed: Vec<f32> = line
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    let rendered = pixels[4 * w + 3].to_array();
    for c in 0..3 {
        assert!(
            (replayed[c] - rendered[c]).abs() <= 1e-5 + 1e-4 * rendered[c].abs(),
            "{stdout} vs {rendered:?}"
        );
    }
}
