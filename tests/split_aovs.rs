//! Split renders carry their AOVs: pieces rendered with `[film] aovs` (or
//! `--aovs`) merge with `brume merge` into the AOVs of the single render —
//! crops bit for bit, sample ranges within the bound stated in src/merge.rs —
//! and an EXR holds only image channels (R, G, B, A and the AOV layers),
//! its merge bookkeeping in the header.

mod common;
#[path = "scale_out_support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use support::*;

/// Every AOV, as `[film] aovs` lists them.
const AOVS: &str = r#"aovs = ["alpha", "depth", "normal", "albedo", "transmittance"]"#;

/// The plume scene of the scale-out tests with every AOV in its `[film]` table.
fn aov_scene(dir: &Path) -> PathBuf {
    let scene = plume_scene(dir, 0.9);
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, format!("{text}\n[film]\n{AOVS}\n")).unwrap();
    scene
}

/// The channels of an EXR by name, sorted.
fn channels(path: &Path) -> Vec<(String, Vec<f32>)> {
    let mut c = brume::film::image_io::read_exr_channels(path).unwrap().2;
    c.sort_by(|a, b| a.0.cmp(&b.0));
    c
}

fn names(channels: &[(String, Vec<f32>)]) -> Vec<&str> {
    channels.iter().map(|(n, _)| n.as_str()).collect()
}

const ALL_CHANNELS: [&str; 14] = [
    "A",
    "B",
    "G",
    "R",
    "albedo.B",
    "albedo.G",
    "albedo.R",
    "depth.Z",
    "normal.X",
    "normal.Y",
    "normal.Z",
    "transmittance.B",
    "transmittance.G",
    "transmittance.R",
];

/// Four crops (the error for AOVs on split renders is gone: the scene's
/// `[film] aovs` is accepted) merge to every channel of the single render
/// bit for bit, and every layer's counts come back exactly.
#[test]
fn crops_with_aovs_merge_bit_identical_to_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = aov_scene(dir.path());
    let full = render(&scene, &[], "full");
    let crops = ["13,32,9,24", "0,13,0,9", "13,32,0,9", "0,13,9,24"];
    let pieces: Vec<PathBuf> = crops
        .iter()
        .enumerate()
        .map(|(i, c)| render(&scene, &["--crop", c], &format!("c{i}")))
        .collect();
    let merged = merge(dir.path(), &pieces);
    let (a, b) = (channels(&full), channels(&merged));
    assert_eq!(names(&a), ALL_CHANNELS);
    assert_eq!(names(&a), names(&b));
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert!(bits(x) == bits(y), "channel {name} differs");
    }
    let (single, merged) = (film(&full), film(&merged));
    for (l, m) in single.layers.iter().zip(&merged.layers) {
        assert_eq!((&l.name, &l.counts), (&m.name, &m.counts));
    }
    // The AOVs carry information: the plume covers part of the ground.
    let t = &a.iter().find(|(n, _)| n == "transmittance.R").unwrap().1;
    assert!(t.iter().any(|&v| v < 0.5) && t.iter().any(|&v| v > 0.99));
}

/// Four sample ranges: every channel whose samples share a sign is within
/// one f32 step of the single render; the normal within 2⁻²⁴ times the
/// largest piece's |mean| plus one step; the counts are exact.
#[test]
fn sample_ranges_with_aovs_merge_within_the_stated_bound() {
    let dir = tempfile::tempdir().unwrap();
    let scene = aov_scene(dir.path());
    let full = render(&scene, &[], "full");
    let pieces: Vec<PathBuf> = ["0..5", "5..30", "30..47", "47..64"]
        .iter()
        .enumerate()
        .map(|(i, r)| render(&scene, &["--samples", r], &format!("p{i}")))
        .collect();
    let merged = merge(dir.path(), &pieces);
    let (a, b) = (channels(&full), channels(&merged));
    assert_eq!(names(&b), ALL_CHANNELS);
    let piece_channels: Vec<_> = pieces.iter().map(|p| channels(p)).collect();
    for (k, ((name, x), (_, y))) in a.iter().zip(&b).enumerate() {
        if !name.starts_with("normal.") {
            let worst = max_ulps(x, y);
            assert!(worst <= 1, "channel {name}: {worst} ulps");
            continue;
        }
        for i in 0..x.len() {
            let largest = piece_channels
                .iter()
                .map(|p| p[k].1[i].abs())
                .fold(0.0f32, f32::max);
            let step = f32::EPSILON * x[i].abs().max(f32::MIN_POSITIVE);
            let bound = 2f32.powi(-24) * largest + step;
            assert!(
                (x[i] - y[i]).abs() <= bound,
                "{name} pixel {i}: {} vs {}",
                x[i],
                y[i]
            );
        }
    }
    let (single, merged) = (film(&full), film(&merged));
    assert_eq!(merged.counts, single.counts);
    for (l, m) in single.layers.iter().zip(&merged.layers) {
        assert_eq!(l.counts, m.counts, "layer {}", l.name);
    }
}

/// A plain render's EXR holds R, G, B only (with `--aovs`, those and the
/// AOV layers), no bookkeeping channel; it still merges, to itself.
#[test]
fn a_plain_render_holds_only_image_channels_and_still_merges() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let plain = render(&scene, &["--spp", "8"], "plain");
    assert_eq!(names(&channels(&plain)), ["B", "G", "R"]);
    let with = render(&scene, &["--spp", "8", "--aovs", "depth,alpha"], "with");
    assert_eq!(names(&channels(&with)), ["A", "B", "G", "R", "depth.Z"]);
    for exr in [plain, with] {
        let merged = merge(dir.path(), std::slice::from_ref(&exr));
        assert_eq!(channels(&merged), channels(&exr));
        assert_bit_identical(&film(&exr), &film(&merged));
    }
}

/// Pieces with different AOV lists are refused with the channels of each.
#[test]
fn pieces_with_other_aovs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let a = render(&scene, &["--samples", "0..32", "--aovs", "alpha"], "a");
    let b = render(&scene, &["--samples", "32..64", "--aovs", "depth"], "b");
    let output = brume()
        .arg("merge")
        .args([&a, &b])
        .arg("-o")
        .arg(dir.path().join("m.exr"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("channels R,G,B,depth.Z differs from") && stderr.contains("R,G,B,A"),
        "{stderr}"
    );
    assert!(!dir.path().join("m.exr").exists());
}

/// Without the `denoise` feature, `brume merge --denoise` says so before
/// reading anything (exit 2, one line); tests/denoise.rs covers the feature.
#[cfg(not(feature = "denoise"))]
#[test]
fn merge_denoise_without_the_feature_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let output = brume()
        .args(["merge", "nothing.exr", "--denoise", "-o"])
        .arg(dir.path().join("m.exr"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("--denoise") && stderr.contains("without the `denoise` feature"),
        "{stderr}"
    );
}
