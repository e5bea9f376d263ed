//! Every key of the scene schema, given a value of the wrong type, is refused
//! in the user's words: no Rust or serde type names (`u32`, `f32`, `i64`,
//! `sequence`, `map`, `struct KeyframeDesc`, ...), the key named, and what to
//! write instead.
//!
//! The keys are not listed by hand: the schema is crawled through the parser
//! itself (`schema_support`), down to texture tables and keyframes, so a key
//! added to the schema is swept without touching this file.

#[path = "schema_support/mod.rs"]
mod schema_support;

use schema_support::{crawl, wrong_values};

#[test]
fn every_key_of_the_schema_refuses_wrong_types_in_the_users_words() {
    let crawl = crawl();
    // The crawl must have reached the depths of the schema, or it proves nothing.
    for deep in [
        "integrator.spp",
        "camera.resolution",
        "animation.frame_offset",
        "animation.missing_frames",
        "film.aovs",
        "light[0].intensity",
        "shape[0].material.albedo.uv_scale",
        "shape[0].transform.keyframes[0].time",
        "shape[0].interior.phase.g_forward",
        "medium[0].velocity_scale",
        "medium[0].bounds.radius",
    ] {
        assert!(
            crawl.leaves.contains(deep),
            "the crawl missed {deep}; it found {:?}",
            crawl.leaves
        );
    }
    assert!(crawl.leaves.len() > 150, "{} leaves", crawl.leaves.len());
    eprintln!(
        "swept {} keys in {} tables with {} wrong values each",
        crawl.leaves.len(),
        crawl.tables,
        wrong_values().len()
    );
}
