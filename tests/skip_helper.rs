//! The skip mechanism of tests/common/skip.rs, run through this test binary
//! itself: a probe test that skips is run in a child process under each
//! environment, and its exit status, stderr and the skip list are checked.

mod common;

use common::skip::{LATER_VAR, LIST_VAR};
use std::path::Path;
use std::process::Output;

/// Skips with a known reason; run only by `skips_fail_under_ci_and_are_listed_elsewhere`.
#[test]
#[ignore = "a probe, run in a child process by skips_fail_under_ci_and_are_listed_elsewhere"]
fn probe_that_skips() {
    common::skip::skip("the probe's reason");
}

/// Runs the probe alone with `env` set, the skip list at `list`.
fn run_probe(list: &Path, env: &[(&str, &str)], threads: &str) -> Output {
    std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--ignored",
            "--exact",
            "probe_that_skips",
            "--nocapture",
            "--test-threads",
        ])
        .arg(threads)
        .env_remove("CI")
        .env_remove(LATER_VAR)
        .env(LIST_VAR, list)
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

fn listed(list: &Path) -> Vec<String> {
    std::fs::read_to_string(list)
        .unwrap_or_default()
        .lines()
        .map(String::from)
        .collect()
}

const LINE: &str = "SKIPPED skip_helper::probe_that_skips: the probe's reason";

#[test]
fn skips_fail_under_ci_and_are_listed_elsewhere() {
    let dir = tempfile::tempdir().unwrap();
    let list = dir.path().join("skipped.txt");
    // Outside CI (unset, empty, 0, false): the test passes, says so on stderr
    // and appends its line; with one test thread too (the name must not be lost).
    let outside: [&[(&str, &str)]; 4] = [&[], &[("CI", "")], &[("CI", "0")], &[("CI", "false")]];
    for (i, env) in outside.iter().enumerate() {
        let threads = if i % 2 == 0 { "2" } else { "1" };
        let out = run_probe(&list, env, threads);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{env:?}: {out:?}");
        assert!(stderr.contains(LINE), "{env:?}: {stderr}");
        assert_eq!(listed(&list), vec![LINE; i + 1], "{env:?}");
    }
    // Under CI: the test fails naming itself and the reason; nothing is listed.
    std::fs::remove_file(&list).unwrap();
    for ci in ["true", "1", "yes"] {
        let out = run_probe(&list, &[("CI", ci)], "2");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "CI={ci}: {out:?}");
        assert!(
            stderr.contains(
                "skip_helper::probe_that_skips cannot run its subject under CI: the probe's reason"
            ),
            "CI={ci}: {stderr}"
        );
        assert!(!list.exists(), "CI={ci} listed a skip");
    }
    // A test file that CI runs in a later step is recorded, not failed; another is not.
    let later = run_probe(
        &list,
        &[("CI", "true"), (LATER_VAR, "denoise, skip_helper")],
        "2",
    );
    assert!(later.status.success(), "{later:?}");
    assert_eq!(listed(&list), vec![LINE]);
    let other = run_probe(&list, &[("CI", "true"), (LATER_VAR, "skip")], "2");
    assert!(!other.status.success(), "{other:?}");
    // An unwritable list is a failure, not a silent skip.
    let out = run_probe(&dir.path().join("no/such/folder/list.txt"), &[], "2");
    assert!(!out.status.success(), "{out:?}");
}
