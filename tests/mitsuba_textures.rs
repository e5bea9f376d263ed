//! `<texture type="checkerboard">` and `<texture type="bitmap">` as a diffuse
//! reflectance: each imported scene renders bit for bit like its TOML twin,
//! whose uv_scale carries the shape's (u, v) convention (README.md, "Mitsuba 3 scenes").

mod twin_support;

use twin_support::assert_twins;

/// Rectangles: Mitsuba's v matches brume's quad (a repeating bitmap, to_uv
/// scale), or runs against it (flip_normals, a mirroring to_world).
#[test]
fn textured_rectangles_render_like_their_toml_twin() {
    assert_twins("textured_rectangles");
}

/// OBJ quads: Mitsuba flips v by default (a clamped bitmap, a checkerboard
/// whose v offset is whole periods) and not with flip_tex_coords = false.
#[test]
fn textured_obj_renders_like_its_toml_twin() {
    assert_twins("textured_obj");
}

/// PLY quads: uv as stored (a repeating bitmap scaled by to_uv, Mitsuba's
/// default checkerboard).
#[test]
fn textured_ply_renders_like_its_toml_twin() {
    assert_twins("textured_ply");
}

/// Disks: (r, φ/2π) in both, φ turned by flip_normals (a repeating bitmap,
/// a checkerboard and a clamped bitmap on flipped disks).
#[test]
fn textured_disks_render_like_their_toml_twin() {
    assert_twins("textured_disks");
}
