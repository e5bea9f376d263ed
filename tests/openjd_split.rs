//! The Open Job Description template jobs/render-split.yaml run end to end by
//! `openjd run` (PyPI openjd-cli, installed by .ci/run): four render tasks and
//! a merge step, whose merged.exr must equal the single render, also when
//! the scene, output folder and brume paths hold shell syntax.
//!
//! Where `unshare -n` works (root on Linux) the job runs in a network
//! namespace of its own, so it provably needs no network. Without openjd the
//! test is skipped through tests/common/skip.rs (a failure under CI).

mod common;
#[path = "scale_out_support/mod.rs"]
mod support;

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
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

/// Runs `template` with the parameters `params` (and the variables `env`);
/// `None` after recording the skip when openjd is missing.
fn openjd_run(
    template: &Path,
    params: &[(&str, &OsStr)],
    env: &[(&str, &OsStr)],
) -> Option<Output> {
    let Some(openjd) = openjd() else {
        common::skip::skip(
            "openjd-cli is not installed (.ci/run installs it: pip install openjd-cli)",
        );
        return None;
    };
    let mut cmd = offline(&openjd);
    cmd.arg("run").arg(template);
    for (key, value) in params {
        let mut param = OsString::from(format!("{key}="));
        param.push(value);
        cmd.arg("-p").arg(param);
    }
    let output = cmd
        .envs(env.iter().copied())
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap();
    Some(output)
}

/// Runs jobs/render-split.yaml on `scene` with `tasks` tasks split by `split`,
/// brume being `brume`; `None` after recording the skip without openjd.
fn run_job(
    scene: &Path,
    out: &Path,
    tasks: u32,
    split: &str,
    brume: &Path,
    env: &[(&str, &OsStr)],
) -> Option<Output> {
    let template = Path::new(env!("CARGO_MANIFEST_DIR")).join("jobs/render-split.yaml");
    let tasks_text = tasks.to_string();
    let params: [(&str, &OsStr); 5] = [
        ("Scene", scene.as_os_str()),
        ("OutDir", out.as_os_str()),
        ("Tasks", tasks_text.as_ref()),
        ("Split", split.as_ref()),
        ("Brume", brume.as_os_str()),
    ];
    openjd_run(&template, &params, env)
}

/// Checks that the job `output` succeeded and wrote its `tasks` pieces into `out`; returns merged.exr.
fn merged(output: &Output, out: &Path, tasks: u32) -> PathBuf {
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
    out.join("merged.exr")
}

/// The brume binary this test run built.
fn brume_exe() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_brume"))
}

#[test]
fn the_openjd_template_splits_samples_and_merges_to_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let out = dir.path().join("job");
    std::fs::create_dir(&out).unwrap();
    let Some(output) = run_job(&scene, &out, 4, "samples", &brume_exe(), &[]) else {
        return;
    };
    let merged = merged(&output, &out, 4);
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
    let Some(output) = run_job(&scene, &out, 3, "tiles", &brume_exe(), &[]) else {
        return;
    };
    let merged = merged(&output, &out, 3);
    let single = film(&render(&scene, &[], "single"));
    assert_bit_identical(&single, &film(&merged));
}

/// A path component holding everything a shell would act on: spaces, single
/// and double quotes, `$` expansions, `$(...)`, backticks and `;` (after a `"`
/// that would end a quoted paste). Each command payload touches
/// `${BRUME_MARK}<kind>` if it ever runs.
const HOSTILE: &str = r#"a b 'sq' $HOME ${X:-y} $(touch "${BRUME_MARK}dollar") `touch "${BRUME_MARK}tick"` "; touch "${BRUME_MARK}semi"; " #"#;

/// The marker files any payload of `HOSTILE` created in `dir`.
fn markers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("mark-"))
        .collect()
}

/// Scene, output folder and brume executable under paths made of `HOSTILE`
/// are plain paths to the template: the job renders and merges bit-identical
/// to the single render, and no payload ran. A control template that puts the
/// same parameter into shell text (as the template once did) must run the
/// payloads, so their absence means something.
#[test]
fn hostile_paths_are_plain_paths_to_the_openjd_template() {
    let dir = tempfile::tempdir().unwrap();
    let mark = dir.path().join("mark-");
    let env: [(&str, &OsStr); 1] = [("BRUME_MARK", mark.as_os_str())];
    let base = dir.path().join(HOSTILE);
    std::fs::create_dir(&base).unwrap();
    let plain = plume_scene(&base, 0.9);
    let scene = base.join(format!("{HOSTILE}.toml"));
    std::fs::rename(&plain, &scene).unwrap();
    let out = base.join(format!("out {HOSTILE}"));
    std::fs::create_dir(&out).unwrap();
    let brume = base.join(format!("brume {HOSTILE}"));
    std::os::unix::fs::symlink(brume_exe(), &brume).unwrap();

    let control = dir.path().join("control.yaml");
    std::fs::write(&control, CONTROL_TEMPLATE).unwrap();
    let Some(output) = openjd_run(&control, &[("Scene", scene.as_os_str())], &env) else {
        return;
    };
    let mut made = markers(dir.path());
    made.sort();
    assert_eq!(
        made,
        ["mark-dollar", "mark-semi", "mark-tick"],
        "control: {output:?}"
    );
    for m in made {
        std::fs::remove_file(dir.path().join(m)).unwrap();
    }

    let Some(output) = run_job(&scene, &out, 3, "tiles", &brume, &env) else {
        return;
    };
    assert_eq!(markers(dir.path()), Vec::<String>::new(), "a payload ran");
    let merged = merged(&output, &out, 3);
    let single = film(&render(&scene, &[], "single"));
    assert_bit_identical(&single, &film(&merged));
    assert!(out.join("merged.png").is_file());
}

/// The unsafe pattern: a parameter pasted into a bash script's text.
const CONTROL_TEMPLATE: &str = r#"specificationVersion: 'jobtemplate-2023-09'
name: control
parameterDefinitions:
  - name: Scene
    type: PATH
steps:
  - name: Pasted
    script:
      actions:
        onRun:
          command: bash
          args: ["{{Task.File.Run}}"]
      embeddedFiles:
        - name: Run
          type: TEXT
          data: |
            ls -d "{{Param.Scene}}"
            exit 0
"#;
