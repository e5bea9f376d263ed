//! Every shipped scene (`scenes/*.toml`, including ones added later) loads and
//! renders at 24×24 pixels and 4 spp to an image that is finite, non-negative
//! and not black; animated scenes at frame 1.

use brume::render::{render, RenderOptions};
use std::path::Path;
use std::sync::atomic::AtomicBool;

#[test]
fn every_shipped_scene_renders() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenes folder")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no scenes in {}", dir.display());
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let mut desc =
            brume::scene::parse(&text, &file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        desc.camera.resolution = [24, 24];
        desc.integrator.spp = 4;
        // frame 1: scenes with frame patterns (animations) resolve it; stills ignore it
        let scene = brume::scene::build_frame(&desc, &file, file.parent().unwrap(), Some(1))
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let options = RenderOptions {
            spp: 4,
            time_budget: None,
            spp_is_cap: false,
            threads: None,
            progress: false,
        };
        let out = render(&scene, &options, &AtomicBool::new(false));
        let name = file.display();
        assert_eq!(out.image.pixels.len(), 24 * 24, "{name}");
        assert_eq!(out.nonfinite_samples, 0, "{name}: NaN/infinite samples");
        for (i, p) in out.image.pixels.iter().enumerate() {
            assert!(p.is_finite(), "{name}: pixel {i} = {p:?}");
            assert!(p.min_channel() >= 0.0, "{name}: pixel {i} = {p:?}");
        }
        let max = out
            .image
            .pixels
            .iter()
            .map(|p| p.max_channel())
            .fold(0.0, f32::max);
        assert!(max > 0.0, "{name}: black image");
    }
}
