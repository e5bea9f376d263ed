//! Scale-out through the command line: pieces rendered with --samples, --crop
//! and --task-index/--task-count (or JOB_COMPLETION_INDEX) merge with
//! `brume merge` into the single render; every refusal exits 2 with one line.
//!
//! The bound for sample ranges (stated in README "Rendering on many machines"
//! and src/film/merge.rs): a piece's EXR holds f32 means and exact counts, so each
//! piece's sum is off by at most a relative 2⁻²⁴ and each merged f32 pixel is
//! equal to the single render's or 1 ulp apart.

mod common;
#[path = "scale_out_support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use support::*;

/// The four pieces `--samples` ranges, deliberately not aligned to passes of 16.
const RANGES: [&str; 4] = ["0..5", "5..30", "30..47", "47..64"];

#[test]
fn four_sample_ranges_merge_to_the_single_render_within_one_f32_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let full = render(&scene, &["--spp", "64"], "full");
    let pieces: Vec<PathBuf> = RANGES
        .iter()
        .enumerate()
        .map(|(i, r)| render(&scene, &["--spp", "64", "--samples", r], &format!("p{i}")))
        .collect();
    let merged = merge(dir.path(), &pieces);
    let (single, merged) = (film(&full), film(&merged));
    assert_eq!(merged.counts, single.counts);
    assert!(merged.provenance.complete());
    assert_eq!(merged.provenance.held, single.provenance.held);
    let worst = max_ulps(&beauty_means(&single), &beauty_means(&merged));
    assert!(
        worst <= 1,
        "a merged pixel is {worst} f32 ulps from the single render"
    );
    // The sums read back (f32 mean × count) agree to the f32 rounding of
    // the means: a relative 2⁻²⁴ on each side.
    for (a, b) in single.layers[0].sums.iter().zip(&merged.layers[0].sums) {
        assert!(
            (a - b).abs() <= 2.0 * 2f64.powi(-24) * a.abs(),
            "{a} vs {b}"
        );
    }
    let lit = beauty_means(&single).iter().filter(|v| **v > 0.0).count();
    assert!(
        lit > 100,
        "the scene must not be black ({lit} lit channels)"
    );
}

#[test]
fn four_task_shares_of_samples_equal_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let full = render(&scene, &[], "full");
    let pieces: Vec<PathBuf> = (0..4)
        .map(|i| {
            let index = i.to_string();
            let args = ["--task-count", "4", "--task-index", &index];
            render(&scene, &args, &format!("t{i}"))
        })
        .collect();
    for (i, piece) in pieces.iter().enumerate() {
        let f = film(piece);
        let share = 16 * i as u32..16 * (i as u32 + 1);
        assert_eq!(
            f.provenance.requested[0].start..f.provenance.requested[0].end,
            share
        );
    }
    let merged = film(&merge(dir.path(), &pieces));
    let worst = max_ulps(&beauty_means(&film(&full)), &beauty_means(&merged));
    assert!(worst <= 1, "{worst} ulps");
}

#[test]
fn four_crops_merge_bit_identical_to_the_full_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let full = render(&scene, &[], "full");
    // Quadrants of unequal sizes, named out of order.
    let crops = ["13,32,9,24", "0,13,0,9", "13,32,0,9", "0,13,9,24"];
    let pieces: Vec<PathBuf> = crops
        .iter()
        .enumerate()
        .map(|(i, c)| render(&scene, &["--crop", c], &format!("c{i}")))
        .collect();
    let piece = film(&pieces[0]);
    assert_eq!(piece.display, (32, 24));
    assert_eq!(piece.window.to_string(), "13,32,9,24");
    let merged = merge(dir.path(), &pieces);
    assert_bit_identical(&film(&full), &film(&merged));
    // Viewers see the same pixels too.
    let (_, _, a) = brume::film::image_io::read_exr(&full).unwrap();
    let (_, _, b) = brume::film::image_io::read_exr(&merged).unwrap();
    assert!(a
        .iter()
        .zip(&b)
        .all(|(p, q)| p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits)));
}

#[test]
fn tiles_from_job_completion_index_merge_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let full = render(&scene, &[], "full");
    let pieces: Vec<PathBuf> = (0..4)
        .map(|i| {
            let out = dir.path().join(format!("k{i}.exr"));
            let output = brume()
                .env("JOB_COMPLETION_INDEX", i.to_string())
                .args(["render", "--quiet", "--task-count", "4", "--split", "tiles"])
                .arg(&scene)
                .arg("--out")
                .arg(&out)
                .arg("--png")
                .arg(out.with_extension("png"))
                .output()
                .unwrap();
            assert!(
                output.status.success(),
                "{}",
                String::from_utf8_lossy(&output.stderr)
            );
            out
        })
        .collect();
    assert_eq!(film(&pieces[1]).window.to_string(), "0,32,6,12");
    assert_bit_identical(&film(&full), &film(&merge(dir.path(), &pieces)));
}

#[test]
fn an_interrupted_piece_is_merged_by_the_samples_it_holds() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let spp = ["--spp", "1000000"];
    let first = render(
        &scene,
        &[&spp[..], &["--samples", "0..16"]].concat(),
        "first",
    );
    let rest = dir.path().join("rest.exr");
    let child = brume()
        .args(["render", "--quiet", "--threads", "2", "--adaptive", "off"])
        .arg(&scene)
        .args(spp)
        .args(["--samples", "16..1000000", "--out"])
        .arg(&rest)
        .arg("--png")
        .arg(dir.path().join("rest.png"))
        .spawn()
        .unwrap();
    let output = interrupt_after(child, std::time::Duration::from_millis(1500));
    assert_eq!(
        output.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let held = film(&rest).provenance.held;
    assert_eq!(held.len(), 1);
    let end = held[0].end;
    assert!(
        held[0].start == 16 && end > 16,
        "no pass finished: {held:?}"
    );
    assert!(!film(&rest).provenance.complete());

    let out = dir.path().join("merged.exr");
    let output = brume()
        .arg("merge")
        .arg(&first)
        .arg(&rest)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let note = format!(
        "{} was interrupted: it holds samples 16..{end} of 16..1000000",
        rest.display()
    );
    assert!(stderr.contains(&note), "{stderr}");
    let merged = film(&out);
    assert_eq!(
        merged.provenance.held,
        vec![brume::film::SampleRange::new(0, end)]
    );
    assert!(!merged.provenance.complete());
    // The merge holds samples 0..end: the render asked for exactly those.
    let single = render(&scene, &["--spp", &end.to_string()], "single");
    let single = film(&single);
    assert_eq!(merged.counts, single.counts);
    let worst = max_ulps(&beauty_means(&single), &beauty_means(&merged));
    assert!(worst <= 1, "{worst} ulps");
}

fn refusal(dir: &Path, pieces: &[PathBuf]) -> String {
    let output = brume()
        .arg("merge")
        .args(pieces)
        .arg("-o")
        .arg(dir.join("refused.exr"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line expected: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(!dir.join("refused.exr").exists());
    stderr
}

#[test]
fn merge_refuses_overlap_other_scenes_seeds_and_missing_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let piece = |args: &[&str], name: &str| render(&scene, args, name);
    let a = piece(&["--samples", "0..32"], "a");
    let b = piece(&["--samples", "16..64"], "b");
    let c = piece(&["--samples", "32..48"], "c");
    let d = piece(&["--samples", "32..64", "--seed", "7"], "d");
    let e = piece(&["--samples", "32..64", "--max-depth", "3"], "e");
    let name = |p: &PathBuf| p.display().to_string();

    let overlap = refusal(dir.path(), &[a.clone(), b.clone()]);
    assert!(
        overlap.contains(&format!("{} (samples 16..64", name(&b))),
        "{overlap}"
    );
    assert!(
        overlap.contains(&format!("overlaps {} (samples 0..32", name(&a))),
        "{overlap}"
    );

    let missing = refusal(dir.path(), &[a.clone(), c.clone()]);
    assert!(
        missing.contains("missing piece: no piece holds samples 48..64 of pixel 0,0"),
        "{missing}"
    );

    let absent = refusal(dir.path(), &[a.clone(), dir.path().join("c2.exr")]);
    assert!(
        absent.contains("missing piece: ") && absent.contains("c2.exr does not exist"),
        "{absent}"
    );

    let twice = refusal(dir.path(), &[a.clone(), c.clone(), c.clone()]);
    assert!(
        twice.contains(&format!("{} is named twice", name(&c))),
        "{twice}"
    );

    let seed = refusal(dir.path(), &[a.clone(), d]);
    assert!(
        seed.contains("seed 7 differs from") && seed.contains("'s 0"),
        "{seed}"
    );

    // Settings given on the command line are part of the scene hash.
    let depth = refusal(dir.path(), &[a.clone(), e]);
    assert!(depth.contains("scene hash"), "{depth}");

    let other_dir = dir.path().join("other");
    std::fs::create_dir(&other_dir).unwrap();
    let other = plume_scene(&other_dir, 0.5);
    let f = render(&other, &["--samples", "32..64"], "f");
    let scene_hash = refusal(dir.path(), &[a.clone(), f]);
    assert!(scene_hash.contains("scene hash"), "{scene_hash}");

    let junk = dir.path().join("junk.exr");
    std::fs::write(&junk, b"not an EXR at all").unwrap();
    let damaged = refusal(dir.path(), &[a.clone(), junk]);
    assert!(
        damaged.contains("junk.exr: is text, not an EXR image"),
        "{damaged}"
    );
    // Named by what it is, in the user's words, not the EXR reader's.
    let png = dir.path().join("preview.exr");
    std::fs::write(&png, b"\x89PNG\r\n\x1a\n0000").unwrap();
    let png_refusal = refusal(dir.path(), &[a.clone(), png]);
    assert!(
        png_refusal.contains("preview.exr: is a PNG image, not an EXR image"),
        "{png_refusal}"
    );
    let cut = dir.path().join("cut.exr");
    std::fs::write(&cut, [0x76, 0x2f, 0x31, 0x01, 2, 0]).unwrap();
    let cut_refusal = refusal(dir.path(), &[a.clone(), cut]);
    assert!(
        cut_refusal.contains("cut.exr: cannot read EXR"),
        "{cut_refusal}"
    );

    let plain = dir.path().join("plain.exr");
    brume::film::image_io::write_exr(&plain, &film(&a).beauty_image()).unwrap();
    let not_film = refusal(dir.path(), &[a, plain]);
    assert!(
        not_film.contains("plain.exr: not a brume film"),
        "{not_film}"
    );
}

#[test]
fn the_scene_hash_covers_the_volume_bytes_but_not_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let settings = brume::scene::load(&scene).unwrap().settings;
    let hash = || brume::render::provenance::scene_hash(&scene, &settings).unwrap();
    let before = hash();
    // The same files elsewhere: the same hash (farm machines mount scenes anywhere).
    let moved = dir.path().join("moved");
    std::fs::create_dir(&moved).unwrap();
    let moved_scene = plume_scene(&moved, 0.9);
    assert_eq!(
        brume::render::provenance::scene_hash(&moved_scene, &settings).unwrap(),
        before
    );
    // One byte of the volume changed: another hash.
    let vdb = dir.path().join("plume.vdb");
    let mut bytes = std::fs::read(&vdb).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 1;
    std::fs::write(&vdb, bytes).unwrap();
    assert_ne!(hash(), before);
}

#[test]
fn piece_options_are_checked_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    for (args, flag) in [
        (&["--crop", "0,33,0,24"][..], "--crop"),
        (&["--crop", "5,5,0,24"][..], "--crop"),
        (&["--samples", "0..65"][..], "--samples"),
        (&["--samples", "9..3"][..], "--samples"),
        (
            &["--task-count", "4", "--task-index", "4"][..],
            "--task-index",
        ),
        (
            &["--task-count", "65", "--task-index", "0"][..],
            "--task-count",
        ),
        (&["--task-count", "4"][..], "--task-count"),
        (&["--samples", "0..8", "--time", "1"][..], "--time"),
    ] {
        let output = brume()
            .env_remove("JOB_COMPLETION_INDEX")
            .args(["render", "--quiet"])
            .arg(&scene)
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(flag), "{args:?}: {stderr}");
        assert!(!dir.path().join("scene.exr").exists());
    }
}

#[test]
fn a_timed_render_is_a_whole_render_of_the_samples_it_reached() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plume_scene(dir.path(), 0.9);
    let timed = render(&scene, &["--time", "0.3", "--spp", "1000000"], "timed");
    let p = film(&timed).provenance;
    assert!(p.complete(), "{p:?}");
    assert_eq!(p.spp_total, p.held[0].end, "{p:?}");
    let merged = film(&merge(dir.path(), std::slice::from_ref(&timed)));
    assert_bit_identical(&film(&timed), &merged);
}
