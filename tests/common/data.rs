//! Where the integration tests find their files: the OpenVDB test volumes
//! committed in `tests/data/volumes/`, the volumes shipped with the scenes in
//! `volumes/`, and the opt-in third-party volumes of `BRUME_REAL_VOLUMES`.
//! A missing file is a panic naming its full path, never a bare `NotFound`.

use std::path::{Path, PathBuf};

/// The environment variable naming the folder of the third-party volumes.
pub const REAL_VOLUMES_VAR: &str = "BRUME_REAL_VOLUMES";

/// The crate root (where `Cargo.toml` is).
pub fn crate_root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The folder of the committed OpenVDB test volumes.
pub fn test_volumes_dir() -> PathBuf {
    crate_root().join("tests/data/volumes")
}

/// The folder of the volumes shipped with the scenes.
pub fn shipped_volumes_dir() -> PathBuf {
    crate_root().join("volumes")
}

/// A committed test volume; panics naming its path if it is missing.
pub fn test_volume(name: &str) -> PathBuf {
    existing(test_volumes_dir().join(name))
}

/// A volume shipped with the scenes; panics naming its path if it is missing.
pub fn shipped_volume(name: &str) -> PathBuf {
    existing(shipped_volumes_dir().join(name))
}

/// `path`, after checking that it is a file (a panic naming it otherwise).
pub fn existing(path: PathBuf) -> PathBuf {
    assert!(
        path.is_file(),
        "missing test file {} (tests/data/README.md says where it comes from)",
        path.display()
    );
    path
}

/// The bytes of `path`; a panic naming the path on any error.
pub fn read_bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("cannot read test file {}: {e}", path.display()))
}

/// The text of `path`; a panic naming the path on any error.
pub fn read_text(path: &Path) -> String {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read test file {}: {e}", path.display()))
}

/// The folder of third-party volumes named by `BRUME_REAL_VOLUMES`, or `None`
/// after the running test is recorded as skipped (`skip`: a failure under CI).
/// A set variable that names no folder is an error, so a typo cannot skip
/// the tests.
pub fn real_volumes() -> Option<PathBuf> {
    real_volumes_or(super::skip::skip)
}

/// As `real_volumes`, for a test whose committed-file part runs anyway: only
/// its third-party part is recorded as skipped.
pub fn real_volumes_for_part() -> Option<PathBuf> {
    real_volumes_or(|reason| super::skip::skip_part("third-party part", reason))
}

fn real_volumes_or(skip: impl FnOnce(&str)) -> Option<PathBuf> {
    match std::env::var_os(REAL_VOLUMES_VAR) {
        Some(dir) if !dir.is_empty() => {
            let dir = PathBuf::from(dir);
            assert!(
                dir.is_dir(),
                "{REAL_VOLUMES_VAR}={} is not a folder",
                dir.display()
            );
            Some(dir)
        }
        _ => {
            skip(&format!(
                "{REAL_VOLUMES_VAR} is not set (the third-party volumes: README, set-up)"
            ));
            None
        }
    }
}

/// Every `.vdb` file in `dir`, sorted; a panic naming `dir` if it cannot be read.
pub fn vdb_files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list test folder {}: {e}", dir.display()))
        .map(|e| e.expect("folder entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "vdb"))
        .collect();
    out.sort();
    out
}

/// Every `.vdb` in `dir` with an OpenVDB sidecar `X.vdb.json`, sorted.
pub fn vdb_files_with_sidecars(dir: &Path) -> Vec<PathBuf> {
    vdb_files(dir)
        .into_iter()
        .filter(|p| p.with_extension("vdb.json").exists())
        .collect()
}
