//! The Open Job Description template jobs/render-split.yaml run end to end by
//! `openjd run` (PyPI openjd-cli, installed by .ci/run): four render tasks and
//! a merge step, whose merged.exr must equal the single render.
//!
//! Where `unshare -n` works (root on Linux) the job runs in a network
//! namespace of its own, so it provably needs no network. Without openjd the
//! test fails under CI (CI set) and says it was skipped elsewhere.

mod common;
#[path = "scale_out_support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use support::*;

/// The openjd command line: BRUME_OPENJD, `openjd`, or `python3 -m openjd`, whichever runs.
fn openjd() -> Option<Vec<String>> {
    let candidates = match std::env::var("BRUME_OPENJD") {
        Ok(program) => vec![vec![program]],
        Err(_) => vec![
            vec!["openjd".into()],
            vec!["python3".into(), "-m".into(), "openjd".into()],
        ],
    };
    candidates.into_iter().find(|c| {
        Command::new(&c[0])
            .args(&c[1..])
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// A command that runs `program` without network if this machine allows it.
fn offline(program: &[String]) -> Command {
    let unshare = Command::new("unshare")
        .args(["-n", "true"])
        .output()
        .is_ok_and(|o| o.status.success());
    if unshare {
        let mut cmd = Command::new("unshare");
        cmd.arg("-n").args(program);
        cmd
    } else {
        eprintln!(
            "note: unshare -n is not allowed here; running openjd with the machine's network"
        );
        let mut cmd = Command::new(&program[0]);
        cmd.args(&program[1..]);
        cmd
    }
}

/// Runs the template on `scene` with `tasks` tasks split by `split`; returns merged.exr.
fn run_job(scene: &Path, out: &Path, tasks: u32, split: &str) -> Option<PathBuf> {
    let Some(openjd) = openjd() else {
        let message = "openjd-cli is not installed (.ci/run installs it: pip install openjd-cli)";
        assert!(std::env::var_os("CI").is_none(), "{message}");
        eprintln!("skipped: {message}");
        return None;
    };
    let template = Path::new(env!("CARGO_MANIFEST_DIR")).join("jobs/render-split.yaml");
    let param = |k: &str, v: &str| format!("{k}={v}");
    let output = offline(&openjd)
        .arg("run")
        .arg(&template)
        .args(["-p", &param("Scene", &scene.display().to_string())])
        .args(["-p", &param("OutDir", &out.display().to_string())])
        .args(["-p", &param("Tasks", &tasks.to_string())])
        .args(["-p", &param("Split", split)])
        .args(["-p", &param("Brume", env!("CARGO_BIN_EXE_brume"))])
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "openjd run failed:\n{log}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(log.contains(&format!("merged {tasks} pieces")), "{log}");
    for i in 0..tasks {
        assert!(out.join(format!("piece-{i}.exr")).exists());
    }
    Some(out.join("merged.exr"))
}

#[test]
fn the_openjd_template_splits_samples_and_merges_to_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let out = dir.path().join("job");
    std::fs::create_dir(&out).unwrap();
    let Some(merged) = run_job(&scene, &out, 4, "samples") else {
        return;
    };
    let single = film(&render(&scene, &[], "single"));
    let merged = film(&merged);
    assert_eq!(merged.counts, single.counts);
    assert_eq!(merged.provenance, single.provenance);
    let worst = max_ulps(&beauty_means(&single), &beauty_means(&merged));
    assert!(worst <= 1, "{worst} ulps from the single render");
}

#[test]
fn the_openjd_template_splits_tiles_and_merges_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let out = dir.path().join("job");
    std::fs::create_dir(&out).unwrap();
    let Some(merged) = run_job(&scene, &out, 3, "tiles") else {
        return;
    };
    let single = film(&render(&scene, &[], "single"));
    assert_bit_identical(&single, &film(&merged));
}
