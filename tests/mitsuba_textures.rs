//! `<texture type="checkerboard">` and `<texture type="bitmap">` as a diffuse
//! reflectance: each imported scene renders bit for bit like its TOML twin,
//! whose uv_scale carries the shape's (u, v) convention (README.md, "Mitsuba 3 scenes").

mod twin_support;

use brume::math::{Ray, Vec2, Vec3};

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

/// Spheres: Mitsuba's (φ/2π, θ/π) about the local Z axis, brume's sphere
/// with its pole at local −Z and its seam at local X (a checkerboard
/// scaled by to_uv on a scaled sphere, a repeating bitmap on a sphere with
/// a centre and radius).
#[test]
fn textured_spheres_render_like_their_toml_twin() {
    assert_twins("textured_spheres");
}

/// An imported sphere under a rotation: the (u, v) brume computes where a
/// ray hits it are Mitsuba's, u = φ / 2π (φ from local X toward local Y,
/// in [0, 2π)) and v = θ / π (θ from local Z) of the hit point taken back
/// through to_world, written here from Mitsuba's documented parametrization.
#[test]
fn a_turned_spheres_texture_coordinates_are_mitsubas() {
    let scene = checkered(
        r#"<shape type="sphere"><transform name="to_world"><scale value="1.5"/>
            <rotate x="0.48" y="0.6" z="0.64" angle="40"/><translate x="0.3" y="-0.2" z="0.1"/></transform>"#,
    );
    let center = glam::DVec3::new(0.3, -0.2, 0.1);
    let rotation =
        glam::DMat3::from_axis_angle(glam::DVec3::new(0.48, 0.6, 0.64), 40f64.to_radians());
    for k in 0..50 {
        // Directions spread over the sphere (a Fibonacci spiral).
        let z = 1.0 - (k as f64 + 0.5) / 25.0;
        let phi = k as f64 * 2.399963;
        let d = glam::DVec3::new(
            (1.0 - z * z).sqrt() * phi.cos(),
            (1.0 - z * z).sqrt() * phi.sin(),
            z,
        );
        let origin = center + 10.0 * d;
        let (p, uv) = hit_uv(&scene, Ray::new(origin.as_vec3(), -d.as_vec3()));
        let local = rotation.transpose() * ((p.as_dvec3() - center) / 1.5);
        let u = local.y.atan2(local.x).rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU;
        let v = local.z.clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
        let du = (uv.x as f64 - u).abs();
        assert!(
            du.min(1.0 - du) < 1e-4 && (uv.y as f64 - v).abs() < 1e-4,
            "direction {d:?}: brume's ({}, {}) vs Mitsuba's ({u}, {v})",
            uv.x,
            uv.y
        );
    }
}

/// Texture coordinates that need an offset: a clamped bitmap on a rectangle
/// (Mitsuba's rows run down, so v ↦ 1 − v), a mirrored bitmap under a
/// to_uv that scales and translates, a nearest-filtered bitmap shifted in u.
#[test]
fn textures_with_offsets_mirroring_and_nearest_render_like_their_toml_twin() {
    assert_twins("textured_offsets");
}

/// Rays at a turned, stretched cube, with the (u, v) Mitsuba 3's
/// scalar_rgb variant reports where each meets it (`scene.ray_intersect(ray).uv`
/// for a cube of to_world translate (0.2, −0.1, 0.3) · rotate (0.6, 0, 0.8) by 25° ·
/// scale (1.5, 0.8, 1.2)): origin, direction, Mitsuba's (u, v).
const MITSUBA_CUBE_HITS: [([f32; 3], [f32; 3], [f32; 2]); 6] = [
    (
        [-2.997084, -5.435259, -0.720327],
        [0.511428, 0.844603, 0.158391],
        [0.51233, 0.19091],
    ),
    (
        [-2.224368, -3.876584, 3.831105],
        [0.453979, 0.644668, -0.615067],
        [0.14561, 0.22139],
    ),
    (
        [-2.658224, 4.952688, 0.944681],
        [0.510794, -0.852874, -0.108144],
        [0.50214, 0.54462],
    ),
    (
        [-3.468827, -2.611001, -3.964737],
        [0.588616, 0.456465, 0.667211],
        [0.76503, 0.08770],
    ),
    (
        [1.740649, 2.76374, -5.21664],
        [-0.217230, -0.440070, 0.871292],
        [0.40890, 0.69216],
    ),
    (
        [-5.83464, -0.181824, 0.018772],
        [0.999440, -0.016037, 0.029366],
        [0.71310, 0.42757],
    ),
];

/// An imported cube is brume's box with `face_uv = "mitsuba"`: where a ray
/// meets it, brume's (u, v) is Mitsuba's (u, 1 − v) on all six faces (the
/// importer's texture mapping flips v back). Seen failing with brume's own
/// face layout.
#[test]
fn an_imported_cubes_face_coordinates_are_mitsubas() {
    let scene = checkered(
        r#"<shape type="cube"><transform name="to_world"><scale x="1.5" y="0.8" z="1.2"/>
            <rotate x="0.6" z="0.8" angle="25"/><translate x="0.2" y="-0.1" z="0.3"/></transform>"#,
    );
    for (origin, direction, [u, v]) in MITSUBA_CUBE_HITS {
        let ray = Ray::new(Vec3::from_array(origin), Vec3::from_array(direction));
        let (_, uv) = hit_uv(&scene, ray);
        assert!(
            (uv.x - u).abs() < 1e-4 && (uv.y - (1.0 - v)).abs() < 1e-4,
            "ray from {origin:?}: brume's ({}, {}) vs Mitsuba's (u, 1 − v) = ({u}, {})",
            uv.x,
            uv.y,
            1.0 - v
        );
    }
}

/// An imported scene of one shape (`shape`: its opening tag and transform)
/// with a checkerboard diffuse reflectance.
fn checkered(shape: &str) -> brume::integrator::Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.xml");
    let text = format!(
        r#"<scene version="3.0.0"><sensor type="perspective"/>{shape}
        <bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf></shape></scene>"#
    );
    std::fs::write(&path, text).unwrap();
    brume::scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Where `ray` first meets the scene, and brume's (u, v) there.
fn hit_uv(scene: &brume::integrator::Scene, ray: Ray) -> (Vec3, Vec2) {
    let hit = scene
        .geometry
        .intersect(&ray, f32::INFINITY)
        .expect("the ray meets the shape");
    (hit.p, scene.geometry.uv(hit.primitive, hit.st, hit.p))
}
