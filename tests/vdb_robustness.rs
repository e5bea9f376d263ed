//! Damaged VDB files give `Err(VolumeError)` with a message naming the file,
//! never a panic or an abort: truncated copies of every committed file (and of
//! the third-party ones when `BRUME_REAL_VOLUMES` is set), random bytes,
//! flipped bytes, and headers and nodes that claim huge sizes.

mod common;

use std::path::{Path, PathBuf};

use brume::volume::{info_report, VdbFile};
use common::data::{
    read_bytes, read_text, real_volumes_for_part, shipped_volume, shipped_volumes_dir, test_volume,
    test_volumes_dir, vdb_files,
};

/// Every committed `.vdb` file, plus the third-party ones if their folder is set.
fn all_files() -> Vec<PathBuf> {
    let mut out = vdb_files(&test_volumes_dir());
    out.extend(vdb_files(&shipped_volumes_dir()));
    if let Some(dir) = real_volumes_for_part() {
        out.extend(vdb_files(&dir));
    }
    out
}

/// A small deterministic generator (xorshift64*), so failures replay.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Opens the bytes and loads every grid; Ok only if everything loaded.
fn load_all(name: &str, data: Vec<u8>) -> Result<(), String> {
    let label = Path::new(name);
    let file = VdbFile::from_bytes(label, data).map_err(|e| e.to_string())?;
    for g in file.grid_names() {
        file.load_float_grid(&g).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Loads a damaged copy that must fail; checks the message names the file.
fn expect_error(name: &str, data: Vec<u8>, what: &str) {
    match load_all(name, data) {
        Ok(()) => panic!("{name}: {what}: loaded without error"),
        Err(msg) => assert!(
            msg.contains(name),
            "{what}: message does not name the file: {msg}"
        ),
    }
}

fn read(path: &Path) -> (String, Vec<u8>) {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    (name, read_bytes(path))
}

#[test]
fn every_prefix_of_small_files_is_an_error() {
    for file in ["homogeneous_box_tiles.vdb", "homogeneous_box.vdb"] {
        let (name, data) = read(&test_volume(file));
        assert!(load_all(&name, data.clone()).is_ok());
        for len in 0..data.len() {
            expect_error(&name, data[..len].to_vec(), &format!("prefix {len}"));
        }
    }
}

#[test]
fn truncated_copies_of_every_file_are_errors() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for path in all_files() {
        let (name, data) = read(&path);
        let n = data.len();
        // the whole header and grid list, then a sample across the data
        let mut lengths: Vec<usize> = (0..n.min(400)).collect();
        lengths.extend((1..300).map(|i| i * n / 300));
        lengths.extend((0..300).map(|_| rng.below(n)));
        lengths.extend([n - 1, n - 2, n - 8, n / 2 + 1]);
        for len in lengths {
            expect_error(&name, data[..len].to_vec(), &format!("prefix {len}"));
        }
    }
}

#[test]
fn random_bytes_are_errors() {
    let mut rng = Rng(42);
    let (_, real) = read(&shipped_volume("smoke_plume.vdb"));
    for i in 0..300 {
        let len = rng.below(4096);
        let mut data: Vec<u8> = (0..len).map(|_| rng.next() as u8).collect();
        if i % 2 == 1 {
            // a valid header start, so parsing goes further into garbage
            let keep = rng.below(200).min(data.len());
            data[..keep].copy_from_slice(&real[..keep]);
        }
        expect_error("random.vdb", data, &format!("random buffer {i}"));
    }
}

#[test]
fn flipped_bytes_never_panic() {
    let mut rng = Rng(7);
    for path in all_files() {
        let (name, data) = read(&path);
        for _ in 0..150 {
            let mut copy = data.clone();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(copy.len());
                copy[at] ^= 1 << rng.below(8);
            }
            // a flipped value byte may still load; anything else must be a clean error
            if let Err(msg) = load_all(&name, copy) {
                assert!(msg.contains(&name), "{msg}");
            }
        }
    }
}

fn put(data: &mut [u8], at: usize, bytes: &[u8]) {
    data[at..at + bytes.len()].copy_from_slice(bytes);
}

fn find(data: &[u8], needle: &[u8]) -> usize {
    data.windows(needle.len())
        .position(|w| w == needle)
        .unwrap()
}

#[test]
fn huge_claimed_sizes_are_errors() {
    let (name, data) = read(&test_volume("homogeneous_box_tiles.vdb"));
    // header: magic 8, version 4, library 8, offsets flag 1, uuid 36, then metadata count
    let mut d = data.clone();
    put(&mut d, 57, &u32::MAX.to_le_bytes());
    expect_error(&name, d, "metadata count");
    let mut d = data.clone();
    put(&mut d, 0, b"XBDV");
    expect_error(&name, d, "bad magic");
    // root: after the map name and its 5 vectors, buffer count, background, tiles, children
    let root = find(&data, b"UniformScaleMap") + 15 + 120 + 8;
    for (at, what) in [(root, "root tile count"), (root + 4, "root child count")] {
        let mut d = data.clone();
        put(&mut d, at, &u32::MAX.to_le_bytes());
        expect_error(&name, d, what);
    }
    // grid type string of the first descriptor claims 4 GiB
    let mut d = data.clone();
    let ty = find(&data, b"Tree_float_5_4_3") - 4;
    put(&mut d, ty, &u32::MAX.to_le_bytes());
    expect_error(&name, d, "grid type length");
}

#[test]
fn huge_compressed_chunk_sizes_are_errors() {
    let path = shipped_volume("smoke_plume.vdb");
    let (name, data) = read(&path);
    let side: serde_json::Value =
        serde_json::from_str(&read_text(&path.with_extension("vdb.json"))).unwrap();
    let grids = side["file_header"]["grids"].as_array().unwrap();
    let block_pos = grids[0]["block_pos"].as_u64().unwrap() as usize;
    // first leaf buffer: value mask (64 bytes), compression byte, then the chunk size
    let meta = data[block_pos + 64];
    assert!(matches!(meta, 0 | 1 | 6), "unexpected node metadata {meta}");
    let size_at = block_pos + 65;
    for claim in [i64::MAX, i64::MIN, -(1 << 40), 1 << 40] {
        let mut d = data.clone();
        put(&mut d, size_at, &claim.to_le_bytes());
        expect_error(&name, d, &format!("chunk size {claim}"));
    }
    // the blosc frame inside the chunk claims a huge uncompressed size
    let mut d = data.clone();
    put(&mut d, size_at + 8 + 4, &u32::MAX.to_le_bytes());
    expect_error(&name, d, "blosc nbytes");
}

#[test]
fn unsupported_value_type_names_grid_and_type_and_other_grids_load() {
    let (name, mut data) = read(&shipped_volume("smoke_plume.vdb"));
    // turn the second grid ('temperature') into an int32 grid: same length type name
    let first = find(&data, b"Tree_float_5_4_3");
    let second = first + 16 + find(&data[first + 16..], b"Tree_float_5_4_3");
    put(&mut data, second, b"Tree_int32_5_4_3");
    let dir = tempfile::tempdir().unwrap();
    let patched = dir.path().join(&name);
    std::fs::write(&patched, &data).unwrap();
    let report = info_report(&patched, false).unwrap();
    assert!(
        report.contains("int32") && report.contains("not loadable"),
        "{report}"
    );
    assert!(report.contains("active voxels: 147323"), "{report}");
    let file = VdbFile::from_bytes(Path::new(&name), data).unwrap();
    let grids = file.grids();
    let vec_grid = grids.iter().find(|g| g.value_type == "int32").unwrap();
    let err = file
        .load_float_grid(&vec_grid.name)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(&name) && err.contains(&vec_grid.name) && err.contains("int32"),
        "{err}"
    );
    let other = grids.iter().find(|g| g.value_type == "float").unwrap();
    assert!(file.load_float_grid(&other.name).is_ok());
}
