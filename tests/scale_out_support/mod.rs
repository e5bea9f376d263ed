//! Helpers shared by the scale-out tests: a small smoke scene, running brume,
//! reading films and comparing them.
#![allow(dead_code)]

use crate::common::cli::signal_and_wait;
use crate::common::SceneText;
use brume::film::Film;
use std::path::{Path, PathBuf};
use std::process::{Child, Output};
use std::time::Duration;

pub use crate::common::cli::brume;

/// `dir/scene.toml`: the repository's smoke plume (copied to `dir/plume.vdb`)
/// over a ground plane, 32×24 pixels, 64 spp, with smoke albedo `albedo`.
pub fn plume_scene(dir: &Path, albedo: f32) -> PathBuf {
    let vdb = Path::new(env!("CARGO_MANIFEST_DIR")).join("volumes/smoke_plume.vdb");
    std::fs::copy(vdb, dir.join("plume.vdb")).unwrap();
    let text = SceneText::camera([0.0, 1.1, 4.6], [0.0, 0.85, 0.0], [32, 24])
        .fov(40.0)
        .integrator("spp = 64\nmax_depth = 8")
        .sun([-1.0, -1.1, -0.7], [3.0, 2.85, 2.6])
        .light("type = \"sky\"\nzenith = [0.25, 0.4, 0.8]\nhorizon = [0.6, 0.7, 0.8]\nground = [0.1, 0.1, 0.1]")
        .quad([0.0; 3], [0.0, 1.0, 0.0], [40.0, 40.0])
        .medium(&format!(
            "type = \"vdb\"\nfile = \"plume.vdb\"\ngrid = \"density\"\ndensity_scale = 20.0\n\
             albedo = {albedo:?}\ntransform = {{ translate = [-1.02, 0.0, -1.0] }}"
        ))
        .build();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    scene
}

/// Renders `scene` with `args` to `NAME.exr` beside it; returns the EXR path.
/// Whole renders are uniform (`--adaptive off`): the pieces they are
/// compared with hold the same samples in every pixel.
pub fn render(scene: &Path, args: &[&str], name: &str) -> PathBuf {
    let dir = scene.parent().unwrap();
    let out = dir.join(format!("{name}.exr"));
    let output = brume()
        .env_remove("JOB_COMPLETION_INDEX")
        .args(["render", "--quiet", "--threads", "2", "--adaptive", "off"])
        .arg(scene)
        .args(args)
        .arg("--out")
        .arg(&out)
        .arg("--png")
        .arg(dir.join(format!("{name}.png")))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "render {args:?}: {stderr}");
    out
}

/// Sends SIGINT to `child` after `after`, then waits for it at most 60 s.
pub fn interrupt_after(child: Child, after: Duration) -> Output {
    signal_and_wait(child, "INT", after, Duration::from_secs(60))
}

/// Merges `pieces` into `dir/merged.exr` with `brume merge`; returns its path.
pub fn merge(dir: &Path, pieces: &[PathBuf]) -> PathBuf {
    let out = dir.join("merged.exr");
    let output = brume()
        .arg("merge")
        .args(pieces)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "merge: {stderr}");
    out
}

/// The film in an EXR written by brume.
pub fn film(path: &Path) -> Film {
    brume::film::image_io::read_film_exr(path).unwrap()
}

/// Every beauty channel mean of `film` as f32, in pixel order.
pub fn beauty_means(film: &Film) -> Vec<f32> {
    let beauty = &film.layers[0];
    (0..film.window.area())
        .flat_map(|i| (0..3).map(move |c| (i, c)))
        .map(|(i, c)| film.mean(beauty, i, c))
        .collect()
}

/// Distance in units in the last place between two finite f32 values.
pub fn ulps(a: f32, b: f32) -> u32 {
    // Map the floats onto the integers in order (negative values mirrored).
    let key = |v: f32| {
        let bits = v.to_bits() as i32;
        if bits < 0 {
            i32::MIN - bits
        } else {
            bits
        }
    };
    (key(a) as i64 - key(b) as i64).unsigned_abs() as u32
}

/// The largest per-channel ulp distance between two images of the same size.
pub fn max_ulps(a: &[f32], b: &[f32]) -> u32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| ulps(*x, *y))
        .max()
        .unwrap_or(0)
}

/// Asserts two films hold the same windows, counts and the same f64 sums bit for bit.
pub fn assert_bit_identical(single: &Film, merged: &Film) {
    assert_eq!(
        (merged.display, merged.window),
        (single.display, single.window)
    );
    assert_eq!(merged.counts, single.counts);
    assert_eq!(merged.nonfinite, single.nonfinite);
    assert_eq!(merged.provenance, single.provenance);
    let bits = |f: &Film| -> Vec<u64> { f.layers[0].sums.iter().map(|s| s.to_bits()).collect() };
    assert!(
        bits(merged) == bits(single),
        "the merged sums differ from the full render's"
    );
    let mean_bits =
        |f: &Film| -> Vec<u32> { beauty_means(f).iter().map(|v| v.to_bits()).collect() };
    assert!(mean_bits(merged) == mean_bits(single));
}
