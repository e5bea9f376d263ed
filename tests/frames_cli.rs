//! `brume render --frames`: frame patterns in VDB and output names, per-frame
//! loading, missing frames (error, hold, repeat), and `--skip-existing`.

mod common;

use assert_cmd::cargo::CommandCargoExt;
use common::SceneText;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn brume() -> Command {
    Command::cargo_bin("brume").unwrap()
}

/// A scene over the animated test plume (`plume.####.vdb`), written into `dir`.
fn scene(dir: &Path, animation: &str) -> PathBuf {
    let plume = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/anim/plume.####.vdb");
    let text = SceneText::camera([0.0, 0.6, 2.5], [0.0, 0.6, 0.0], [6, 6])
        .with("shutter = [-0.25, 0.25]")
        .integrator("spp = 2")
        .environment([0.5, 0.5, 0.5])
        .medium(&format!(
            "type = \"vdb\"\nfile = \"{}\"\ndensity_scale = 20.0\nvelocity_grid = \"vel\"",
            plume.display()
        ))
        .table("[animation]", animation)
        .build();
    let path = dir.join("anim.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn render(dir: &Path, scene: &Path, extra: &[&str]) -> Output {
    brume()
        .current_dir(dir)
        .arg("render")
        .arg(scene)
        .args(extra)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

#[test]
fn a_sequence_writes_one_image_per_frame_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path(), "");
    let o = render(dir.path(), &scene, &["--frames", "1-3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in 1..=3 {
        assert!(dir.path().join(format!("anim.{f:04}.exr")).is_file());
        assert!(dir.path().join(format!("anim.{f:04}.png")).is_file());
    }
    assert!(stderr(&o).contains("frame 2 (2/3)"), "{}", stderr(&o));
    // frames differ: the plume moves
    let a = std::fs::read(dir.path().join("anim.0001.exr")).unwrap();
    let b = std::fs::read(dir.path().join("anim.0002.exr")).unwrap();
    assert_ne!(a, b);
    // resume: complete frames are skipped, a missing one is rendered
    std::fs::remove_file(dir.path().join("anim.0002.exr")).unwrap();
    let o = render(dir.path(), &scene, &["--frames", "1-3", "--skip-existing"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("frame 1 (1/3):") && err.contains("skipped"),
        "{err}"
    );
    assert!(!err.contains("frame 2 (2/3):"), "{err}");
    assert!(dir.path().join("anim.0002.exr").is_file());
    // a custom pattern with a step
    let o = render(
        dir.path(),
        &scene,
        &[
            "--frames", "1-3:2", "--out", "x_##.exr", "--png", "x_##.png",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("x_01.exr").is_file() && dir.path().join("x_03.exr").is_file());
    assert!(!dir.path().join("x_02.exr").exists());
}

fn pixels(path: &Path) -> Vec<[u32; 3]> {
    let (_, _, px) = brume::film::image_io::read_exr(path).unwrap();
    px.iter()
        .map(|c| [c.r.to_bits(), c.g.to_bits(), c.b.to_bits()])
        .collect()
}

#[test]
fn missing_frames_error_by_default_and_hold_or_repeat_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene_path = scene(d, "");
    let o = render(d, &scene_path, &["--frames", "1-4"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("plume.0004.vdb") && err.contains("medium[0].file"),
        "{err}"
    );
    // frames finished before the error stay
    let frame = |f: i64| pixels(&d.join(format!("anim.{f:04}.exr")));
    let (f1, f2, f3) = (frame(1), frame(2), frame(3));
    assert!(f1 != f2 && f2 != f3);
    // the seed does not change with the frame, so a frame drawn from the same file is the same image
    let scene_path = scene(d, "missing_frames = \"hold\"");
    let o = render(d, &scene_path, &["--frames", "0,5", "--out", "h.####.exr"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        pixels(&d.join("h.0000.exr")),
        f1,
        "hold before the first file"
    );
    assert_eq!(
        pixels(&d.join("h.0005.exr")),
        f3,
        "hold after the last file"
    );
    let scene_path = scene(d, "missing_frames = \"repeat\"");
    let o = render(d, &scene_path, &["--frames", "5,7", "--out", "r.####.exr"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(pixels(&d.join("r.0005.exr")), f2, "repeat: 1 2 3 1 2");
    assert_eq!(pixels(&d.join("r.0007.exr")), f1, "repeat: 1 2 3 1 2 3 1");
    let scene_path = scene(d, "frame_offset = -2");
    let o = render(d, &scene_path, &["--frames", "3", "--out", "o.####.exr"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        pixels(&d.join("o.0003.exr")),
        f1,
        "frame 3 with offset -2 reads file 1"
    );
    let scene_path = scene(d, "frame_offset = 2");
    let o = render(d, &scene_path, &["--frames", "3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("plume.0005.vdb"), "{}", stderr(&o));
}

#[test]
fn bad_frame_arguments_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene(dir.path(), "");
    let o = render(dir.path(), &scene_path, &["--frames", "4-1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--frames"), "{}", stderr(&o));
    let o = render(
        dir.path(),
        &scene_path,
        &["--frames", "1-2", "--out", "same.exr"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("####"), "{}", stderr(&o));
    // a pattern without --frames
    let o = render(dir.path(), &scene_path, &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--frames"), "{}", stderr(&o));
    let bad = scene(dir.path(), "missing_frames = \"loop\"");
    let o = render(dir.path(), &bad, &["--frames", "1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("animation.missing_frames"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn keyframes_in_a_form_brume_does_not_read_are_refused_clearly() {
    let text = r#"
        [camera]
        position = [0.0, 0.0, 3.0]
        look_at = [0.0, 0.0, 0.0]
        [[shape]]
        type = "sphere"
        radius = 0.5
        transform = [{ time = 0.0, translate = [0.0, 0.0, 0.0] }, { time = 1.0, translate = [1.0, 0.0, 0.0] }]
    "#;
    let file = Path::new("keys.toml");
    let err = brume::scene::parse(text, file).unwrap_err().to_string();
    assert!(
        err.contains("shape[0].transform") && err.contains("transform = { keyframes = ["),
        "{err}"
    );
    let text = text.replace(
        "transform = [{ time = 0.0, translate = [0.0, 0.0, 0.0] }, { time = 1.0, translate = [1.0, 0.0, 0.0] }]",
        "",
    ) + "\n[[medium]]\ntype = \"homogeneous\"\nsigma_t = 1.0\nbounds = { type = \"sphere\", radius = 1.0 }\ntransform = { keyframes = [] }\n";
    let desc = brume::scene::parse(&text, file).expect("the keyframes form parses");
    let err = brume::scene::build(&desc, file, Path::new("."))
        .err()
        .expect("no keys is an error")
        .to_string();
    assert!(
        err.contains("medium[0].transform.keyframes") && err.contains("at least one key"),
        "{err}"
    );
}
