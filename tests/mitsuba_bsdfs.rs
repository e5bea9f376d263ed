//! The Mitsuba BSDFs, shapes and emitters that map to brume features added
//! for them (Beckmann roughness, ...): each imported scene renders bit for
//! bit like its hand-written TOML twin, so the TOML keys are first-class.

mod twin_support;

use twin_support::assert_twins;

/// A `roughconductor` naming no distribution (Mitsuba's default Beckmann)
/// and a Beckmann `roughdielectric` given `alpha_u` = `alpha_v`.
#[test]
fn beckmann_rough_bsdfs_render_like_their_toml_twin() {
    assert_twins("rough_beckmann");
}

/// `plastic` (nonlinear, tinted specular; and all defaults but ext_ior) and
/// a `thindielectric` rectangle.
#[test]
fn plastic_and_thin_dielectric_render_like_their_toml_twin() {
    assert_twins("plastic_pane");
}

/// A `spot` whose `beam_width` is inside its `cutoff_angle`: Mitsuba's edge,
/// linear in angle, is brume's `cone_edge = "linear"`.
#[test]
fn soft_spot_renders_like_its_toml_twin() {
    assert_twins("soft_spot");
}

/// `disk` shapes (a floor, a ceiling light, a light turned over by
/// `flip_normals`) and `flip_normals` on spheres: two-sided diffuse
/// (unchanged) and glass (its relative index inverted).
#[test]
fn disks_and_flipped_shapes_render_like_their_toml_twin() {
    assert_twins("disks_flipped");
}
