//! `brume render --noise` and `--adaptive` on the command line: the summary
//! and the EXR say what the render did, `merge` refuses an adaptive film,
//! and bad values or combinations are refused naming the flag or key.

mod common;

use common::cli::{assert_refused, assert_scene_refused, brume};
use common::SceneText;
use std::path::{Path, PathBuf};

/// A small chromatic white furnace (noisy on the sphere, exact around it).
fn scene_text(integrator: &str) -> String {
    let medium = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = [2.0, 0.5, 6.0]\nalbedo = 1.0\n\
                  phase = { type = \"hg\", g = -0.4 }\nbounds = { type = \"sphere\", radius = 1.0 }\n";
    SceneText::camera([0.0, 0.0, 4.0], [0.0; 3], [12, 12])
        .fov(60.0)
        .integrator(integrator)
        .environment(1.0)
        .raw(medium)
        .build()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn render(scene: &Path, out: &Path, args: &[&str]) -> std::process::Output {
    brume()
        .arg("render")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .arg("--png")
        .arg(out.with_extension("png"))
        .args(args)
        .output()
        .unwrap()
}

/// `--noise` renders, reports its estimate within the target, writes
/// per-pixel counts that differ and `brume:adaptive`; `merge` refuses the film.
#[test]
fn a_noise_target_render_reports_and_records_itself() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "furnace.toml", &scene_text("max_depth = 1000"));
    let out = dir.path().join("a.exr");
    let output = render(&scene, &out, &["--noise", "0.05", "--spp", "2048"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("adaptive: pilot"))
        .unwrap_or_else(|| panic!("no adaptive summary: {stderr}"));
    let estimate: f64 = line
        .split("estimated relative error ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no estimate in {line}"));
    assert!(estimate <= 0.05, "{line}");
    assert!(line.contains("(target 0.05)"), "{line}");
    let film = brume::film::image_io::read_film_exr(&out).unwrap();
    let note = film.adaptive.clone().expect("brume:adaptive in the header");
    assert!(note.starts_with("adaptive; pilot"), "{note}");
    let (least, most) = (
        film.counts.iter().min().unwrap(),
        film.counts.iter().max().unwrap(),
    );
    assert!(least < most, "counts {least}..{most}");
    let merged = dir.path().join("m.exr");
    let output = brume()
        .arg("merge")
        .arg(&out)
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("brume:adaptive"), "{stderr}");
    assert!(!merged.exists());
}

/// Bad values and combinations: exit 2, one line naming the flag or the key.
#[test]
fn bad_noise_targets_and_combinations_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "s.toml", &scene_text("spp = 16"));
    let out = dir.path().join("o.exr");
    for (args, culprit) in [
        (vec!["--noise", "0"], "--noise"),
        (vec!["--noise", "1.5"], "--noise"),
        (vec!["--noise", "nan"], "--noise"),
        (vec!["--adaptive", "maybe"], "--adaptive"),
        (vec!["--noise", "0.1", "--spp", "4"], "--noise"),
        (vec!["--noise", "0.1", "--samples", "0..8"], "--noise"),
        (vec!["--adaptive", "on", "--crop", "0,4,0,4"], "--adaptive"),
    ] {
        let output = render(&path, &out, &args);
        assert_refused(&output, &[culprit], &format!("{args:?}"));
        assert!(!out.exists(), "{args:?}: wrote an image");
    }
    let bdpt = write(dir.path(), "b.toml", &scene_text("type = \"bdpt\""));
    let output = render(&bdpt, &out, &["--noise", "0.1"]);
    assert_refused(&output, &["--noise", "path"], "--noise with bdpt");
    for (integrator, culprit) in [
        ("noise = -0.5", "integrator.noise"),
        ("noise = 2.0", "integrator.noise"),
        ("adaptive = \"yes\"", "integrator.adaptive"),
        ("type = \"sppm\"\nnoise = 0.1", "integrator.noise"),
        ("spp = 4\nadaptive = true", "integrator.spp"),
    ] {
        assert_scene_refused(
            dir.path(),
            "k.toml",
            &scene_text(integrator),
            &[] as &[&str],
            &[culprit],
            integrator,
        );
    }
}

/// Without `adaptive` or `noise` the summary says what the automatic choice
/// made of its pilot; `--adaptive off`, `adaptive = false` or a noise target
/// in the scene, a piece of a split render and a render below 64 spp make no
/// automatic choice and say nothing of it.
#[test]
fn the_automatic_choice_says_what_it_chose() {
    let dir = tempfile::tempdir().unwrap();
    let spread = write(dir.path(), "spread.toml", &scene_text("max_depth = 1000"));
    let out = dir.path().join("a.exr");
    let stderr_of = |scene: &Path, args: &[&str]| {
        let output = render(scene, &out, args);
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        assert_eq!(output.status.code(), Some(0), "{stderr}");
        stderr
    };
    let stderr = stderr_of(&spread, &["--spp", "64"]);
    assert!(
        stderr.contains("adaptive (automatic): the pilot predicts"),
        "{stderr}"
    );
    assert!(stderr.contains("adaptive: pilot 4 spp"), "{stderr}");
    // The medium fills a narrow view: even noise, kept uniform.
    let even = scene_text("max_depth = 1000").replace("fov = 60.0", "fov = 8.0");
    assert_ne!(even, scene_text("max_depth = 1000"), "the fov line moved");
    let even = write(dir.path(), "even.toml", &even);
    let stderr = stderr_of(&even, &["--spp", "64"]);
    assert!(
        stderr.contains("uniform (automatic): the pilot of 4 spp"),
        "{stderr}"
    );
    for args in [
        &["--spp", "64", "--adaptive", "off"][..],
        &["--spp", "64", "--crop", "0,6,0,12"][..],
        &["--spp", "32"][..],
    ] {
        let stderr = stderr_of(&spread, args);
        assert!(!stderr.contains("automatic"), "{args:?}: {stderr}");
    }
    // The scene's own keys decide as the flags do: `adaptive = false` keeps
    // the render uniform, a noise target is adaptive by the user's choice.
    for (keys, chosen) in [
        ("max_depth = 1000\nadaptive = false", None),
        ("max_depth = 1000\nnoise = 0.05", Some("adaptive: pilot")),
    ] {
        let scene = write(dir.path(), "keys.toml", &scene_text(keys));
        let stderr = stderr_of(&scene, &["--spp", "64"]);
        assert!(!stderr.contains("automatic"), "{keys}: {stderr}");
        match chosen {
            Some(line) => assert!(stderr.contains(line), "{keys}: {stderr}"),
            None => assert!(!stderr.contains("adaptive: pilot"), "{keys}: {stderr}"),
        }
    }
}
