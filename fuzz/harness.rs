//! The bodies of the fuzz targets, shared with `tests/fuzz_regressions.rs`
//! (both include this file by `#[path]`), so that the suite replays the
//! seeds and crash reproducers through exactly the code the fuzzers run.
//! Any `Err` is fine; a panic, an abort or a hang is a crash.
// Each fuzz target calls one of the bodies.
#![allow(dead_code)]

use brume::volume::VdbFile;
use glam::{DVec3, IVec3, Vec3};
use std::path::Path;

/// The memory limit while fuzzing image readers (256 MB): refusals by the
/// limit are exercised too, and libFuzzer's RSS limit is never the one hit.
pub const IMAGE_MEMORY_LIMIT: u64 = 256_000_000;

/// The `scene_parse` target: text → parse → build, relative paths (OBJ
/// files) resolved against `base`, an empty folder.
pub fn scene_parse(data: &[u8], base: &Path) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let file = base.join("fuzz.toml");
    if let Ok(desc) = brume::scene::parse(text, &file) {
        let _ = brume::scene::build(&desc, &file, base);
    }
}

/// The `vdb_load` target: bytes → open → load every grid → what `brume
/// info` and the renderer ask of a loaded grid.
pub fn vdb_load(data: &[u8]) {
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

/// `image_read`: the bytes as an EXR through every EXR reader (environment
/// maps and compare, textures, merge pieces) and as a PNG through the
/// texture reader, from files in the folder `dir`, under
/// [`IMAGE_MEMORY_LIMIT`].
pub fn image_read(data: &[u8], dir: &Path) {
    brume::error::limits::set_memory_limit(IMAGE_MEMORY_LIMIT);
    let exr = dir.join("fuzz.exr");
    let png = dir.join("fuzz.png");
    if std::fs::write(&exr, data).is_err() || std::fs::write(&png, data).is_err() {
        return;
    }
    let _ = brume::film::image_io::read_exr(&exr);
    let _ = brume::film::image_io::read_exr_channels(&exr);
    let _ = brume::film::image_io::read_film_exr(&exr);
    let _ = brume::film::image_io::read_png(&png);
}
