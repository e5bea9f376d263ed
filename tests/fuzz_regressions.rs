//! Replays the fuzzers' seeds and every crash they once found through the
//! same code paths as the fuzz targets (fuzz/fuzz_targets/): each input may be
//! refused with an error, none may panic.

#[path = "../fuzz/harness.rs"]
mod harness;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every file in the given folders (relative to the crate root), sorted.
fn inputs(folders: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for folder in folders {
        for entry in std::fs::read_dir(root().join(folder)).unwrap() {
            let path = entry.unwrap().path();
            let hidden = path.file_name().unwrap().to_string_lossy().starts_with('.');
            if path.is_file() && !hidden {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// Runs `body` on every input; fails naming every input that panicked.
fn replay(inputs: &[PathBuf], body: impl Fn(&[u8])) {
    assert!(!inputs.is_empty());
    let failures: Vec<String> = inputs
        .iter()
        .filter(|path| {
            let data = std::fs::read(path).unwrap();
            catch_unwind(AssertUnwindSafe(|| body(&data))).is_err()
        })
        .map(|path| path.display().to_string())
        .collect();
    assert!(failures.is_empty(), "panicked on: {failures:#?}");
}

#[test]
fn scene_seeds_and_crash_reproducers_never_panic() {
    let files = inputs(&["fuzz/seeds/scene_parse", "tests/fuzz_regressions/scene"]);
    replay(&files, |data| {
        let base = tempfile::tempdir().unwrap();
        harness::scene_parse(data, base.path());
    });
}

#[test]
fn vdb_seeds_and_crash_reproducers_never_panic() {
    let files = inputs(&["fuzz/seeds/vdb_load", "tests/fuzz_regressions/vdb"]);
    replay(&files, harness::vdb_load);
}

#[test]
fn the_shipped_scene_seeds_still_parse() {
    // Seeds that no longer parse would only exercise the error paths.
    for path in inputs(&["fuzz/seeds/scene_parse"]) {
        let text = std::fs::read_to_string(&path).unwrap();
        brume::scene::parse(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    }
}
