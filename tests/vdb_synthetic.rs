//! Hand-built VDB files for cases the shared files lack: root-level tiles, a
//! non-zero background, and an unsupported (frustum) transform.

use std::path::Path;

use brume::volume::{VdbFile, VolumeError};
use glam::{IVec3, Vec3};

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend((s.len() as u32).to_le_bytes());
    out.extend(s.as_bytes());
}

/// A one-grid file (format 224, no compression) whose tree is only root tiles.
fn root_tile_file(map: &str, background: f32, tiles: &[([i32; 3], f32, bool)]) -> Vec<u8> {
    let mut f = Vec::new();
    f.extend(0x5644_4220u64.to_le_bytes());
    f.extend(224u32.to_le_bytes());
    f.extend([10u32.to_le_bytes(), 0u32.to_le_bytes()].concat());
    f.push(1); // has grid offsets
    f.extend(b"00000000-0000-0000-0000-000000000000");
    f.extend(0u32.to_le_bytes()); // file metadata
    f.extend(1i32.to_le_bytes()); // grid count
    string(&mut f, "density");
    string(&mut f, "Tree_float_5_4_3");
    string(&mut f, "");
    let offsets_at = f.len();
    f.extend([0u8; 24]);
    let grid_pos = f.len();
    f.extend(0u32.to_le_bytes()); // compression
    f.extend(0u32.to_le_bytes()); // grid metadata
    string(&mut f, map);
    for v in [
        0.5f64, 0.5, 0.5, 0.5, 0.5, 0.5, 2.0, 2.0, 2.0, 4.0, 4.0, 4.0, 1.0, 1.0, 1.0,
    ] {
        f.extend(v.to_le_bytes());
    }
    f.extend(1i32.to_le_bytes()); // buffer count
    f.extend(background.to_le_bytes());
    f.extend((tiles.len() as u32).to_le_bytes());
    f.extend(0u32.to_le_bytes());
    for (o, v, active) in tiles {
        for c in o {
            f.extend(c.to_le_bytes());
        }
        f.extend(v.to_le_bytes());
        f.push(*active as u8);
    }
    let end = f.len() as i64;
    let offs = [grid_pos as i64, end, end];
    for (i, o) in offs.iter().enumerate() {
        f[offsets_at + 8 * i..offsets_at + 8 * i + 8].copy_from_slice(&o.to_le_bytes());
    }
    f
}

#[test]
fn root_tiles_and_background_are_honoured() {
    let data = root_tile_file(
        "UniformScaleMap",
        0.25,
        &[([4096, 0, 0], 2.0, true), ([-4096, 0, 0], 3.0, false)],
    );
    let file = VdbFile::from_bytes(Path::new("roots.vdb"), data).unwrap();
    let grid = file.load_float_grid("density").unwrap();
    assert_eq!(grid.background(), 0.25);
    assert_eq!(grid.value(IVec3::new(5000, 17, 4095)), 2.0);
    assert!(grid.is_active(IVec3::new(5000, 17, 4095)));
    assert_eq!(grid.value(IVec3::new(-1, 0, 0)), 3.0);
    assert!(!grid.is_active(IVec3::new(-1, 0, 0)));
    assert_eq!(grid.value(IVec3::new(0, 0, 0)), 0.25);
    assert_eq!(grid.value(IVec3::new(4096, 4096, 0)), 0.25);
    assert_eq!(grid.active_voxel_count(), 1 << 36);
    assert_eq!(grid.value_range(), (2.0, 2.0));
    assert_eq!(
        grid.index_bbox_active(),
        Some((IVec3::new(4096, 0, 0), IVec3::new(8191, 4095, 4095)))
    );
    // halfway between the background and the active tile
    assert_eq!(
        grid.trilinear_index(Vec3::new(4095.5, 10.0, 10.0)),
        0.25 + (2.0 - 0.25) * 0.5
    );
    let sizes: Vec<i32> = grid.blocks().map(|b| b.size).collect();
    assert_eq!(sizes, [4096, 4096]);
    assert_eq!(grid.transform().voxel_size(), glam::DVec3::splat(0.5));
}

#[test]
fn frustum_transform_is_unsupported_with_the_map_name() {
    let data = root_tile_file("NonlinearFrustumMap", 0.0, &[]);
    let file = VdbFile::from_bytes(Path::new("frustum.vdb"), data).unwrap();
    let err = file.load_float_grid("density").unwrap_err();
    assert!(matches!(err, VolumeError::Unsupported { .. }));
    let msg = err.to_string();
    assert!(
        msg.contains("frustum.vdb")
            && msg.contains("density")
            && msg.contains("NonlinearFrustumMap"),
        "{msg}"
    );
}

#[test]
fn misaligned_root_tile_is_an_error() {
    let data = root_tile_file("UniformScaleMap", 0.0, &[([100, 0, 0], 1.0, true)]);
    let file = VdbFile::from_bytes(Path::new("bad.vdb"), data).unwrap();
    let err = file.load_float_grid("density").unwrap_err().to_string();
    assert!(
        err.contains("bad.vdb") && err.contains("not a multiple"),
        "{err}"
    );
}
