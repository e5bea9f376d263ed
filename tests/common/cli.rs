//! Running the `brume` binary in a test folder with a deadline, and
//! snapshots of a folder's files to prove that none was changed.

use assert_cmd::cargo::CommandCargoExt;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

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
