//! Damaged VDB files through the command line (`brume info`): every case
//! exits with code 2 and one `error:` line naming the file and the culprit,
//! never a panic, an abort or an out-of-memory kill.

mod common;

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn small_vdb() -> PathBuf {
    common::data::test_volume("homogeneous_box_tiles.vdb")
}

/// Runs `brume info` on `path`; returns (exit code, stderr).
fn info(path: &Path) -> (Option<i32>, String) {
    let output = Command::cargo_bin("brume")
        .unwrap()
        .arg("info")
        .arg(path)
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// Asserts the one-line, exit-code-2 error naming `name` and `culprit`.
fn assert_bad(path: &Path, name: &str, culprit: &str, what: &str) {
    let (code, stderr) = info(path);
    assert_eq!(code, Some(2), "{what}: exit code, stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: panicked: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "{what}: one line expected: {stderr}"
    );
    assert!(stderr.starts_with("error: "), "{what}: {stderr}");
    assert!(stderr.contains(name), "{what}: file not named: {stderr}");
    assert!(
        stderr.contains(culprit),
        "{what}: '{culprit}' not named: {stderr}"
    );
}

/// Lengths 0..64, the last 64, and an even stride through the rest (≥ 500 in all).
fn prefix_lengths(len: usize) -> Vec<usize> {
    let mut lengths: Vec<usize> = (0..64.min(len)).collect();
    let stride = (len / 500).max(1);
    lengths.extend((64..len.saturating_sub(64)).step_by(stride));
    lengths.extend(len.saturating_sub(64)..len);
    lengths.dedup();
    lengths
}

#[test]
fn every_sampled_prefix_of_a_small_vdb_is_refused_by_brume_info() {
    let data = std::fs::read(small_vdb()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.vdb");
    std::fs::write(&whole, &data).unwrap();
    assert_eq!(info(&whole).0, Some(0), "the whole file must load");
    let lengths = prefix_lengths(data.len());
    assert!(lengths.len() >= 500, "{} lengths", lengths.len());
    // Two workers: each runs the binary on its share of the prefixes.
    std::thread::scope(|s| {
        for part in lengths.chunks(lengths.len().div_ceil(2)) {
            let (data, dir) = (&data, dir.path());
            s.spawn(move || {
                for &len in part {
                    let path = dir.join(format!("prefix_{len}.vdb"));
                    std::fs::write(&path, &data[..len]).unwrap();
                    let name = format!("prefix_{len}.vdb");
                    assert_bad(&path, &name, "not a readable OpenVDB file", &name);
                    std::fs::remove_file(&path).unwrap();
                }
            });
        }
    });
}

/// A small deterministic generator (xorshift64*), so failures replay.
fn random_bytes(n: usize, mut state: u64) -> Vec<u8> {
    (0..n)
        .map(|_| {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            (state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 56) as u8
        })
        .collect()
}

/// The small file with `patch` applied to its bytes.
fn patched(patch: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    let mut data = std::fs::read(small_vdb()).unwrap();
    patch(&mut data);
    data
}

fn put(data: &mut [u8], at: usize, bytes: &[u8]) {
    data[at..at + bytes.len()].copy_from_slice(bytes);
}

// Byte offsets in homogeneous_box_tiles.vdb (format 224, one grid 'density').
const VERSION: usize = 8;
const GRID_COUNT: usize = 61;
const NAME_LEN: usize = 65;
const GRID_OFFSETS: usize = 100;
const COMPRESSION: usize = 124;

/// (name, file bytes, text the error must contain).
fn cases() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    vec![
        ("empty", Vec::new(), "magic"),
        (
            "random bytes",
            random_bytes(4096, 0x9E37_79B9),
            "not a readable",
        ),
        ("text", b"hello, I am not a volume\n".to_vec(), "magic"),
        (
            "a scene file",
            b"[camera]\nposition = [0.0, 1.0, 4.0]\n".to_vec(),
            "magic",
        ),
        ("magic only", patched(|d| d.truncate(8)), "truncated"),
        ("header only", patched(|d| d.truncate(57)), "truncated"),
        ("wrong magic", patched(|d| d[0] ^= 0xff), "magic"),
        (
            "file version too old",
            patched(|d| put(d, VERSION, &1u32.to_le_bytes())),
            "version",
        ),
        (
            "huge grid count",
            patched(|d| put(d, GRID_COUNT, &i32::MAX.to_le_bytes())),
            "grid list",
        ),
        (
            "negative grid count",
            patched(|d| put(d, GRID_COUNT, &(-5i32).to_le_bytes())),
            "grid",
        ),
        (
            "huge grid name length",
            patched(|d| put(d, NAME_LEN, &u32::MAX.to_le_bytes())),
            "string length 4294967295",
        ),
        (
            "grid offsets past the end",
            patched(|d| put(d, GRID_OFFSETS + 16, &i64::MAX.to_le_bytes())),
            "past the end",
        ),
        (
            "grid offsets out of order",
            patched(|d| put(d, GRID_OFFSETS + 16, &110i64.to_le_bytes())),
            "out of order",
        ),
        (
            "negative grid offset",
            patched(|d| put(d, GRID_OFFSETS, &(-1i64).to_le_bytes())),
            "density",
        ),
        (
            "unknown compression flags",
            patched(|d| put(d, COMPRESSION, &0xff00u32.to_le_bytes())),
            "density",
        ),
        (
            "scrambled tree",
            patched(|d| (3000..3200).for_each(|i| d[i] ^= 0x5a)),
            "grid 'density': corrupt data",
        ),
        (
            "scrambled leaf data",
            patched(|d| {
                let n = d.len();
                (n - 2000..n - 1500).for_each(|i| d[i] = !d[i])
            }),
            "grid 'density'",
        ),
    ]
}

#[test]
fn every_bad_vdb_gives_one_clear_error_line_and_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let cases = cases();
    assert!(cases.len() >= 10);
    for (i, (what, bytes, culprit)) in cases.into_iter().enumerate() {
        let name = format!("bad{i}.vdb");
        let path = dir.path().join(&name);
        std::fs::write(&path, bytes).unwrap();
        assert_bad(&path, &name, culprit, what);
    }
}

#[test]
fn missing_file_and_folder_are_refused_with_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no_such.vdb");
    assert_bad(&missing, "no_such.vdb", "cannot read file", "missing file");
    let folder = dir.path().join("folder.vdb");
    std::fs::create_dir(&folder).unwrap();
    assert_bad(&folder, "folder.vdb", "cannot read file", "folder");
}
