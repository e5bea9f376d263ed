//! An imported Mitsuba 3 scene renders bit for bit like its hand-written
//! TOML twin at the same seed: the importer builds exactly the description
//! a user would write (camera, lights, materials, media), so everything
//! downstream is shared.

mod twin_support;

use twin_support::assert_twins;

/// Camera from `<lookat>` with fov along x, `<default>`s, a cube holding an
/// RGB homogeneous medium with an HG phase (σt scaled by `scale`), a quarter-turned
/// rectangle floor in `twosided`, an emissive sphere and a point light.
#[test]
fn fog_box_renders_like_its_toml_twin() {
    assert_twins("fog_box");
}

/// fov along y, an `aov` wrapper around `path` (unlimited depth), a stratified
/// sampler, a rough water sphere with fog inside (named IORs), a
/// quarter-turned, scaled rough-conductor cube by `<ref>`, a directional
/// light and an envmap turned into brume's orientation.
#[test]
fn glass_sun_renders_like_its_toml_twin() {
    assert_twins("glass_sun");
}
