//! `[integrator] type`: `brume render` refuses `"bdpt"` until its driver
//! calls the bidirectional estimator (no silent fallback to the path
//! tracer), and an unknown type is a scene error; either way one line
//! naming the file and `integrator.type`, exit code 2, outputs untouched.

use assert_cmd::Command;

const SCENE: &str = "[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [8, 8]\n[[light]]\ntype = \"point\"\nposition = [0.0, 3.0, 0.0]\nintensity = 5.0\n[[shape]]\ntype = \"sphere\"\nradius = 1.0\n";

fn render(kind: &str, extra_args: &[&str]) -> (Option<i32>, String, bool, Vec<u8>) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(
        &scene,
        format!("{SCENE}[integrator]\ntype = \"{kind}\"\nspp = 1\n"),
    )
    .unwrap();
    let (exr, png) = (dir.path().join("out.exr"), dir.path().join("out.png"));
    std::fs::write(&exr, b"precious").unwrap();
    let output = Command::cargo_bin("brume")
        .unwrap()
        .args(["render", "--quiet"])
        .arg(&scene)
        .arg("--out")
        .arg(&exr)
        .arg("--png")
        .arg(&png)
        .args(extra_args)
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
        png.exists(),
        std::fs::read(&exr).unwrap(),
    )
}

#[test]
fn bdpt_scenes_are_refused_until_the_driver_is_wired() {
    for args in [&[][..], &["--frames", "1"][..]] {
        let (code, stderr, png, exr) = render("bdpt", args);
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(stderr.contains("scene.toml: integrator.type:"), "{stderr}");
        assert!(stderr.contains("not wired"), "{stderr}");
        assert!(!png && exr == b"precious", "{args:?}: output touched");
    }
}

#[test]
fn path_renders_and_unknown_types_are_scene_errors() {
    let (code, stderr, png, _) = render("path", &[]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(png);
    let (code, stderr, png, exr) = render("metropolis", &[]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains(
            "scene.toml: integrator.type: unknown integrator `metropolis`, expected path or bdpt"
        ),
        "{stderr}"
    );
    assert!(!png && exr == b"precious");
}
