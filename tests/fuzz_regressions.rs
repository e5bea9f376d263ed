//! Replays the fuzzers' seeds and every crash they once found through the
//! same code paths as the fuzz targets (fuzz/fuzz_targets/): each input may be
//! refused with an error, none may panic.

use brume::volume::VdbFile;
use glam::{DVec3, IVec3, Vec3};
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

/// The `scene_parse` target: text → parse → build against an empty folder.
fn scene_parse(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let base = tempfile::tempdir().unwrap();
    let file = base.path().join("fuzz.toml");
    if let Ok(desc) = brume::scene::parse(text, &file) {
        let _ = brume::scene::build(&desc, &file, base.path());
    }
}

/// The `vdb_load` target: bytes → open → load every grid → lookups.
fn vdb_load(data: &[u8]) {
    let Ok(file) = VdbFile::from_bytes(Path::new("fuzz.vdb"), data.to_vec()) else {
        return;
    };
    let _ = file.grids();
    for name in file.grid_names() {
        let Ok(grid) = file.load_float_grid(&name) else {
            continue;
        };
        let _ = (grid.active_voxel_count(), grid.value_range());
        let _ = (grid.sum_active_values(), grid.memory_bytes());
        let _ = grid.blocks().count();
        let (lo, hi) = grid
            .index_bbox_active()
            .unwrap_or((IVec3::ZERO, IVec3::ONE));
        let mid = (lo.as_dvec3() + hi.as_dvec3()) * 0.5;
        for p in [
            lo.as_dvec3(),
            hi.as_dvec3(),
            mid,
            mid + 0.37,
            DVec3::splat(-1e9),
        ] {
            let _ = grid.trilinear_index_f64(p);
            let _ = grid.trilinear_index(p.as_vec3());
            let _ = grid.nearest_index(p);
            let w = grid.transform().index_to_world(p);
            let _ = grid.trilinear_world(w);
            let _ = grid.transform().world_to_index(w);
        }
        let _ = grid.trilinear_index(Vec3::NAN);
        let _ = (grid.value(lo), grid.is_active(hi), grid.value(IVec3::MAX));
    }
}

#[test]
fn scene_seeds_and_crash_reproducers_never_panic() {
    let files = inputs(&["fuzz/seeds/scene_parse", "tests/fuzz_regressions/scene"]);
    replay(&files, scene_parse);
}

#[test]
fn vdb_seeds_and_crash_reproducers_never_panic() {
    let files = inputs(&["fuzz/seeds/vdb_load", "tests/fuzz_regressions/vdb"]);
    replay(&files, vdb_load);
}

#[test]
fn the_shipped_scene_seeds_still_parse() {
    // Seeds that no longer parse would only exercise the error paths.
    for path in inputs(&["fuzz/seeds/scene_parse"]) {
        let text = std::fs::read_to_string(&path).unwrap();
        brume::scene::parse(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    }
}
