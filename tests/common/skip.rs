//! The one way a test says it cannot run its subject (a missing tool, data
//! folder or cargo feature). Cargo hides the output of passing tests, so a
//! skip is never only a message:
//!
//! - under CI (`CI` set to anything but empty, `0` or `false`) it fails the
//!   test, naming the test and the reason: CI installs what the tests need;
//! - elsewhere it prints `SKIPPED <test>: <reason>` on stderr and appends that
//!   line to the skip list, `BRUME_SKIPPED_TESTS` or else
//!   `target/skipped-tests.txt`, which `.ci/run` empties before and prints
//!   after the tests (README, "Tests").
//!
//! A test whose subject `.ci/run` runs in a later step of its own (the
//! `denoise` feature's tests, built with other features) is named in
//! `BRUME_TESTED_IN_LATER_STEP` (test file names, comma-separated): its skip in
//! the earlier step is recorded, not failed, and the later step must run it.

use std::io::Write;
use std::path::PathBuf;

/// The variable naming the skip list file.
pub const LIST_VAR: &str = "BRUME_SKIPPED_TESTS";
/// The variable naming test files that `.ci/run` runs in a later step.
pub const LATER_VAR: &str = "BRUME_TESTED_IN_LATER_STEP";

/// True when the tests run under CI.
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| !matches!(v.trim(), "" | "0" | "false"))
}

/// The skip list: `BRUME_SKIPPED_TESTS`, or `skipped-tests.txt` in the target folder.
pub fn list_path() -> PathBuf {
    match std::env::var_os(LIST_VAR) {
        Some(path) if !path.is_empty() => PathBuf::from(path),
        // CARGO_TARGET_TMPDIR is <target>/tmp
        _ => PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .parent()
            .expect("the target folder")
            .join("skipped-tests.txt"),
    }
}

/// `<test file>::<test>` for the running test (libtest names its thread after the test).
pub fn current_test() -> String {
    let thread = std::thread::current();
    let name = thread.name().unwrap_or("?");
    format!("{}::{}", env!("CARGO_CRATE_NAME"), name)
}

/// The running test cannot run its subject because of `reason`: fails under
/// CI, records `SKIPPED <test>: <reason>` elsewhere. Callers return after it.
pub fn skip(reason: &str) {
    skip_named(&current_test(), reason);
}

/// As `skip`, for the part `part` of the running test (the rest did run).
pub fn skip_part(part: &str, reason: &str) {
    skip_named(&format!("{} ({part})", current_test()), reason);
}

/// As `skip`, for the test named `test` in full (`<test file>::<name>`).
pub fn skip_named(test: &str, reason: &str) {
    let file = test.split("::").next().unwrap_or(test);
    let later = std::env::var(LATER_VAR).is_ok_and(|v| v.split(',').any(|f| f.trim() == file));
    assert!(
        !under_ci() || later,
        "{test} cannot run its subject under CI: {reason} (CI must install what the tests need)"
    );
    let line = format!("SKIPPED {test}: {reason}");
    eprintln!("{line}");
    let path = list_path();
    let recorded = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&path)
        // one write per line: appends from parallel tests do not interleave
        .and_then(|mut f| f.write_all(format!("{line}\n").as_bytes()));
    if let Err(e) = recorded {
        panic!(
            "{line}, and it could not be recorded in {}: {e}",
            path.display()
        );
    }
}
