//! `--set KEY=VALUE`: scene values from the command line, applied before
//! validation, for every TOML value type; errors name the key as written
//! and the `--set` that wrote it, in the user's words.

mod common;

use common::cli::brume;
use std::path::Path;

const SCENE: &str = r#"
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
resolution = [8, 6]

[integrator]
spp = 2

[[light]]
type = "point"
position = [0.0, 3.0, 2.0]
intensity = [10.0, 10.0, 10.0]

[[shape]]
type = "sphere"
center = [0.0, 0.5, 0.0]
radius = 0.5
material = { type = "diffuse", albedo = [0.5, 0.5, 0.5] }
"#;

fn render(dir: &Path, sets: &[&str]) -> std::process::Output {
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    let mut cmd = brume();
    cmd.current_dir(dir).args([
        "render", "s.toml", "--quiet", "--out", "o.exr", "--png", "o.png",
    ]);
    for s in sets {
        cmd.args(["--set", s]);
    }
    cmd.output().unwrap()
}

/// The "size WxH" line of `brume compare` on an image and itself.
fn size(dir: &Path) -> String {
    let out = brume()
        .current_dir(dir)
        .args(["compare", "o.exr", "o.exr"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.lines()
        .find_map(|l| l.strip_prefix("size"))
        .unwrap_or_else(|| panic!("no size line in {text}"))
        .trim()
        .to_string()
}

#[test]
fn values_of_every_type_take_effect() {
    let dir = tempfile::tempdir().unwrap();
    let out = render(
        dir.path(),
        &[
            "camera.resolution=[12, 7]",               // array
            "camera.fov=30.5",                         // float
            "integrator.spp=1",                        // integer
            "integrator.equiangular=false",            // boolean
            "integrator.type=path",                    // bare word
            "shape[0].material={ type = \"mirror\" }", // inline table
            "film.aovs=[\"depth\"]",                   // a table the scene does not have
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert_eq!(size(dir.path()), "12x7");
    // The later of two sets wins.
    let out = render(
        dir.path(),
        &["camera.resolution=[5, 5]", "camera.resolution=[9, 4]"],
    );
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(size(dir.path()), "9x4");
}

#[test]
fn errors_name_the_key_and_the_set_in_the_users_words() {
    let cases: &[(&str, &[&str])] = &[
        (
            "integrator.spp=-3",
            &["integrator.spp", "--set integrator.spp=-3"],
        ),
        ("integrator.spp=\"many\"", &["integrator.spp", "--set"]),
        (
            "camera.resolution=[1, 2, 3]",
            &["camera.resolution", "--set"],
        ),
        ("camera.fov=true", &["camera.fov", "--set"]),
        ("shape[0].radius=-1", &["shape[0].radius", "--set"]),
        ("shape[9].radius=1", &["shape[9].radius", "1 entries"]),
        ("camera.fov.x=1", &["camera.fov", "--set camera.fov.x=1"]),
        ("integrator.spp.x=1", &["integrator.spp", "not a table"]),
        (
            "integrator.type=bidirectional",
            &["integrator.type", "--set"],
        ),
    ];
    for (set, culprits) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = render(dir.path(), &[set]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--set {set}: {stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "--set {set}: one error line: {stderr}");
        for c in *culprits {
            assert!(
                errors[0].contains(c),
                "--set {set}: `{c}` missing in {}",
                errors[0]
            );
        }
        for rust in ["u32", "f32", "i64", "usize", "sequence", "map", "panicked"] {
            assert!(
                !errors[0].contains(rust),
                "--set {set}: `{rust}` in {}",
                errors[0]
            );
        }
        assert!(
            !dir.path().join("o.exr").exists(),
            "--set {set}: rendered anyway"
        );
    }
}

#[test]
fn malformed_sets_are_refused_as_arguments() {
    for set in [
        "integrator.spp",
        "=3",
        "camera..fov=1",
        "camera.fov=[1,",
        "shape[x].radius=1",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = render(dir.path(), &[set]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--set {set}: {stderr}");
        assert!(
            stderr.contains("--set"),
            "--set {set}: flag not named: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}
