//! Every shipped scene (`scenes/*.toml`, including ones added later) renders
//! at low resolution to an image that is finite, non-negative (above −U′ under
//! the sky as a control variate), not black, and
//! statistically consistent, per pixel and pooled, with a stored reference
//! (`tests/data/scenes/NAME.ref`: per-pixel means and standard errors of an
//! independent render with another seed and 16 times the samples); animated
//! scenes at frame 1.
//!
//! After an intended change of a scene or of the estimator's expectation,
//! regenerate the references and say why in the commit:
//!
//! ```text
//! cargo test --release --test scenes_render -- --ignored write_scene_references
//! ```

mod common;

use brume::integrator::Scene;
use brume::render::{render, RenderOptions};
use common::data::{crate_root, read_text};
use common::{assert_pixels, estimate_pixels, Estimate};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Test resolution (square, whatever the scene's aspect).
const SIDE: u32 = 8;
/// Samples per pixel of the test render.
const SPP: usize = 4096;
/// Samples per pixel of the reference render.
const REFERENCE_SPP: usize = 16 * SPP;
/// Added to the scene's seed for the reference, so the two renders are independent.
const REFERENCE_SEED_OFFSET: u64 = 0x5EED_0000;

fn shipped_scenes() -> Vec<PathBuf> {
    let dir = crate_root().join("scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no scenes in {}", dir.display());
    files
}

/// `file` at the test resolution, with the scene's seed plus `seed_offset`.
fn load(file: &Path, seed_offset: u64) -> Scene {
    let text = read_text(file);
    let mut desc =
        brume::scene::parse(&text, file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    desc.camera.resolution = [SIDE, SIDE];
    desc.integrator.seed = desc.integrator.seed.wrapping_add(seed_offset);
    // frame 1: scenes with frame patterns (animations) resolve it; stills ignore it
    brume::scene::build_frame(&desc, file, file.parent().unwrap(), Some(1))
        .map(|(scene, _)| scene)
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

fn reference_path(scene: &Path) -> PathBuf {
    let name = scene.file_stem().unwrap().to_string_lossy();
    crate_root().join(format!("tests/data/scenes/{name}.ref"))
}

/// The text form: a header line, then `r g b se_r se_g se_b` per pixel, row by row.
fn format_reference(scene: &Path, pixels: &[Estimate]) -> String {
    let name = scene.file_name().unwrap().to_string_lossy();
    let mut out = format!(
        "# brume reference of scenes/{name}: {SIDE}x{SIDE} px, {REFERENCE_SPP} spp, seed + {REFERENCE_SEED_OFFSET:#x}\n"
    );
    for p in pixels {
        let v = [p.mean, p.std_error].concat();
        let cols: Vec<String> = v.iter().map(|x| format!("{x:.9e}")).collect();
        out.push_str(&cols.join(" "));
        out.push('\n');
    }
    out
}

/// Reads means and standard errors; a missing or malformed file names its path.
fn parse_reference(path: &Path) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    if !path.is_file() {
        panic!(
            "missing reference {}: generate it with `cargo test --release --test scenes_render -- --ignored write_scene_references`",
            path.display()
        );
    }
    let (mut mean, mut se) = (Vec::new(), Vec::new());
    for (i, line) in read_text(path).lines().enumerate() {
        if line.starts_with('#') {
            continue;
        }
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|x| {
                x.parse()
                    .unwrap_or_else(|e| panic!("{}:{}: {e}", path.display(), i + 1))
            })
            .collect();
        assert_eq!(
            v.len(),
            6,
            "{}:{}: six numbers expected",
            path.display(),
            i + 1
        );
        mean.push([v[0], v[1], v[2]]);
        se.push([v[3], v[4], v[5]]);
    }
    assert_eq!(
        mean.len(),
        (SIDE * SIDE) as usize,
        "{}: pixel count",
        path.display()
    );
    (mean, se)
}

/// The render path itself (threads, film, cancellation): finite, non-negative
/// (above −U′ where the sky is a control variate), lit.
fn check_render(file: &Path, scene: &Scene) {
    let options = RenderOptions {
        spp: 4,
        time_budget: None,
        spp_is_cap: false,
        threads: None,
        progress: false,
    };
    let out = render(scene, &options, &AtomicBool::new(false));
    let name = file.display();
    assert_eq!(out.image.pixels.len(), (SIDE * SIDE) as usize, "{name}");
    assert_eq!(out.nonfinite_samples, 0, "{name}: NaN/infinite samples");
    // Under the sky as a control variate a sample can be negative (module
    // `sky_control`: a path books ahead the sky light a surface it then
    // misses would have taken): a pixel of 4 samples may dip below 0, not below −U′.
    let least = scene.sky_control.map_or(0.0, |u| -u.max_channel());
    for (i, p) in out.image.pixels.iter().enumerate() {
        assert!(p.is_finite(), "{name}: pixel {i} = {p:?}");
        assert!(p.min_channel() >= least, "{name}: pixel {i} = {p:?}");
    }
    let max = out
        .image
        .pixels
        .iter()
        .map(|p| p.max_channel())
        .fold(0.0, f32::max);
    assert!(max > 0.0, "{name}: black image");
}

#[test]
fn every_shipped_scene_matches_its_reference() {
    for file in shipped_scenes() {
        let scene = load(&file, 0);
        check_render(&file, &scene);
        let (mean, se) = parse_reference(&reference_path(&file));
        let pixels = estimate_pixels(&scene, SPP);
        assert_pixels(&pixels, &mean, &se, &file.display().to_string());
    }
}

/// Writes `tests/data/scenes/NAME.ref` for every shipped scene (see the module comment).
#[test]
#[ignore = "regenerates the stored references"]
fn write_scene_references() {
    // Only the missing ones, unless asked: a new scene must not move the others.
    let rewrite = std::env::var_os("BRUME_REWRITE_REFERENCES").is_some();
    for file in shipped_scenes() {
        if !rewrite && reference_path(&file).is_file() {
            continue;
        }
        let scene = load(&file, REFERENCE_SEED_OFFSET);
        let pixels = estimate_pixels(&scene, REFERENCE_SPP);
        let path = reference_path(&file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, format_reference(&file, &pixels))
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        println!("wrote {}", path.display());
    }
}
