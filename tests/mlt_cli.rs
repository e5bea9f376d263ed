//! `brume render` with `[integrator] type = "mlt"`: the summary's
//! acceptance per path length, and what it refuses in the user's words
//! (exit code 2, one line, the output left as it was).

mod common;

use common::cli::{assert_refused, assert_scene_refused, brume};

const SCENE: &str = "[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [12, 8]\n[[light]]\ntype = \"point\"\nposition = [0.0, 3.0, 1.0]\nintensity = 5.0\n[[shape]]\ntype = \"sphere\"\nradius = 1.0\n[[shape]]\ntype = \"quad\"\ncenter = [0.0, -1.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nsize = [6.0, 6.0]\n";

fn scene(integrator: &str) -> String {
    format!("{SCENE}[integrator]\nspp = 4\nmax_depth = 6\n{integrator}\n")
}

#[test]
fn the_summary_reports_acceptance_per_path_length() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, scene("type = \"mlt\"")).unwrap();
    let output = brume()
        .arg("render")
        .arg(&file)
        .arg("--out")
        .arg(dir.path().join("out.exr"))
        .arg("--png")
        .arg(dir.path().join("out.png"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("mlt: acceptance by path length (segments): 2: "),
        "{stderr}"
    );
    assert!(stderr.contains("mlt: brightness "), "{stderr}");
}

#[test]
fn bad_keys_are_scene_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (integrator, culprits) in [
        (
            "type = \"mlt\"\nsmall_step_size = 0.7",
            &["integrator.small_step_size", "(0, 0.5)", "0.7"][..],
        ),
        (
            "type = \"mlt\"\nlarge_step_probability = -0.1",
            &["integrator.large_step_probability", "[0, 1]"],
        ),
        (
            "type = \"mlt\"\nbootstrap_samples = 3",
            &["integrator.bootstrap_samples", "max_depth + 1 = 7", "got 3"],
        ),
        (
            "type = \"mlt\"\nchains = 0",
            &["integrator.chains", "at least 1"],
        ),
        (
            "type = \"mlt\"\nbootstrap_samples = 4294967295",
            &["integrator.bootstrap_samples", "68.7 GB", "memory limit"],
        ),
        (
            "type = \"sppm\"\nradius = 1e-30",
            &["integrator.radius", "1e-30"],
        ),
        (
            "type = \"sppm\"\nradius = 1e30",
            &["integrator.radius", "1e30"],
        ),
    ] {
        assert_scene_refused::<&str>(
            dir.path(),
            "scene.toml",
            &scene(integrator),
            &[],
            culprits,
            integrator,
        );
    }
}

/// Another integrator's keys are warnings, not errors: `--set
/// integrator.type=...` switches a scene between estimators and keeps them.
#[test]
fn other_integrators_keys_are_warnings() {
    let dir = tempfile::tempdir().unwrap();
    for (n, (integrator, key, kind)) in [
        (
            "type = \"bdpt\"\nchains = 4",
            "integrator.chains",
            "Metropolis",
        ),
        (
            "type = \"path\"\nsmall_step_size = 0.1",
            "integrator.small_step_size",
            "Metropolis",
        ),
        (
            "type = \"bdpt\"\nphotons = 100",
            "integrator.photons",
            "photon-mapping",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let file = dir.path().join("scene.toml");
        std::fs::write(&file, scene(integrator)).unwrap();
        let output = brume()
            .arg("render")
            .arg(&file)
            .arg("--out")
            .arg(dir.path().join(format!("out{n}.exr")))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{integrator}: {stderr}");
        assert!(
            stderr.contains(key) && stderr.contains(kind) && stderr.contains("ignored by type"),
            "{integrator}: no warning naming {key}: {stderr}"
        );
    }
}

#[test]
fn pieces_and_aovs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, scene("type = \"mlt\"")).unwrap();
    let out = dir.path().join("out.exr");
    for (args, culprits) in [
        (
            &["--crop", "0,4,0,4"][..],
            &["--crop", "mlt", "whole frame"][..],
        ),
        (&["--samples", "0..2"], &["--samples", "mlt"]),
        (
            &["--task-count", "2", "--task-index", "0"],
            &["--task-count", "mlt"],
        ),
        (&["--aovs", "depth"], &["--aovs", "mlt"]),
        (&["--max-depth", "5000"], &["--max-depth", "5000", "mlt"]),
    ] {
        std::fs::write(&out, b"precious").unwrap();
        let output = brume()
            .args(["render", "--quiet"])
            .arg(&file)
            .arg("--out")
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        assert_refused(&output, culprits, &args.join(" "));
        assert_eq!(std::fs::read(&out).unwrap(), b"precious");
    }
}
