//! Renders a Mitsuba XML scene and its hand-written TOML twin and compares
//! their bits (shared by the twin tests: tests/mitsuba_twins.rs, tests/mitsuba_bsdfs.rs).
#![allow(dead_code)]

use brume::math::color::Rgb;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A file of tests/data/mitsuba.
pub fn data(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba")
        .join(name);
    assert!(path.is_file(), "missing test file {}", path.display());
    path
}

/// The pixels of `scene` rendered on 2 threads, with its seed changed by `seed_offset`.
pub fn render(scene: &Path, seed_offset: u64) -> Vec<Rgb> {
    let mut loaded = brume::scene::load_with_inputs(scene)
        .unwrap_or_else(|e| panic!("{}: {e}", scene.display()));
    loaded.scene.settings.seed += seed_offset;
    // Uniform renders: a spread one takes pixels past the scene's spp, to
    // samples whose rounding the twins do not share (glass_sun: one pixel).
    loaded.scene.settings.adaptive.auto = false;
    let options = brume::render::RenderOptions {
        spp: loaded.scene.settings.spp,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(2),
        progress: false,
    };
    brume::render::render(&loaded.scene, &options, &AtomicBool::new(false))
        .image
        .pixels
}

/// Every pixel as its f32 bits.
pub fn bits(pixels: &[Rgb]) -> Vec<[u32; 3]> {
    pixels
        .iter()
        .map(|p| [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()])
        .collect()
}

/// Renders `stem`.xml and `stem`.toml and compares every pixel's bits; a
/// third render at another seed must differ (the comparison can fail).
pub fn assert_twins(stem: &str) {
    let xml = render(&data(&format!("{stem}.xml")), 0);
    let toml = render(&data(&format!("{stem}.toml")), 0);
    assert!(
        xml.iter().any(|p| p.max_channel() > 0.0),
        "{stem}: the imported render is black"
    );
    let (a, b) = (bits(&xml), bits(&toml));
    let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(
        differing,
        0,
        "{stem}: {differing} of {} pixels differ between the XML and its TOML twin",
        a.len()
    );
    let reseeded = bits(&render(&data(&format!("{stem}.xml")), 1));
    assert_ne!(a, reseeded, "{stem}: another seed renders the same bits");
}
