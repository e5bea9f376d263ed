//! The brume binary as the command-line tests run it: the command, a signal
//! sent to a running render, the checks every refusal of bad input must
//! pass (docs/robustness.md): exit code 2, one line naming the culprit, no
//! panic, no touched output; runs in a test folder with a deadline, and
//! snapshots of a folder's files to prove that none was changed.

use assert_cmd::cargo::CommandCargoExt;
use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The brume binary with no standard input and captured output.
pub fn brume() -> Command {
    let mut cmd = Command::cargo_bin("brume").unwrap();
    cmd.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    cmd
}

/// Sends `signal` (e.g. "INT") to `child` after `after`, then waits for it at most `limit`.
pub fn signal_and_wait(mut child: Child, signal: &str, after: Duration, limit: Duration) -> Output {
    std::thread::sleep(after);
    let status = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(status.success(), "kill -{signal} failed");
    let deadline = Instant::now() + limit;
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            child.kill().unwrap();
            panic!("brume did not stop within {limit:?} of SIG{signal}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Asserts `output` is a refusal of bad input: exit code 2, no panic, one
/// line on stderr naming each of `culprits` (`what` names the case). Returns the line.
pub fn assert_refused(output: &Output, culprits: &[&str], what: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(
        output.status.code(),
        Some(2),
        "{what}: exit code, stderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{what}: panicked: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "{what}: one line expected: {stderr}"
    );
    for culprit in culprits {
        assert!(
            stderr.contains(culprit),
            "{what}: '{culprit}' not named: {stderr}"
        );
    }
    stderr
}

/// Writes `text` to `dir/NAME` and renders it with `--out dir/out.exr` (an
/// image already there) and `extra` arguments: the render must be refused
/// ([`assert_refused`]) naming NAME and each of `culprits`, and leave the
/// image as it was. Returns the error line.
pub fn assert_scene_refused<S: AsRef<OsStr>>(
    dir: &Path,
    name: &str,
    text: &str,
    extra: &[S],
    culprits: &[&str],
    what: &str,
) -> String {
    let scene = dir.join(name);
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out.exr");
    std::fs::write(&out, b"precious").unwrap();
    let output = brume()
        .args(["render", "--quiet"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .args(extra)
        .output()
        .unwrap();
    let mut named = vec![name];
    named.extend(culprits);
    let line = assert_refused(&output, &named, what);
    assert_eq!(
        std::fs::read(&out).unwrap(),
        b"precious",
        "{what}: output touched"
    );
    line
}

/// What a run of brume left: exit code (`None`: killed by a signal), stderr, seconds.
#[derive(Debug)]
pub struct Outcome {
    /// The exit code.
    pub code: Option<i32>,
    /// Everything brume wrote on stderr.
    pub stderr: String,
    /// Wall-clock seconds until it ended.
    pub seconds: f64,
}

/// Runs brume in `dir` with `args`; a run that outlives `deadline` is
/// killed and fails the test (a hang must fail, never block the suite).
pub fn run_brume(dir: &Path, args: &[String], deadline: Duration) -> Outcome {
    let start = Instant::now();
    let mut child = Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > deadline {
            child.kill().unwrap();
            let out = child.wait_with_output().unwrap();
            panic!(
                "brume {args:?} did not finish within {deadline:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let out = child.wait_with_output().unwrap();
    Outcome {
        code: out.status.code(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The bytes of every regular file directly in `dir` (links, FIFOs and folders left out).
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if std::fs::symlink_metadata(&p).unwrap().is_file() {
            out.insert(p.clone(), std::fs::read(&p).unwrap());
        }
    }
    out
}
