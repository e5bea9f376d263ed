//! Mitsuba's rule for the medium a ray is in (set by the last interface
//! crossed), followed for imported scenes where it differs from brume's
//! containment: transmittance along one ray through overlapping and nested
//! media against the closed form the rule defines.

mod common;

use brume::integrator::Scene;
use brume::math::{Ray, Vec3};
use common::{assert_estimate, estimate_ray};
use std::path::PathBuf;

/// Pure absorbers (albedo 0), one σt per channel each.
const MEDIA: &str = r#"
    <medium type="homogeneous" id="a"><rgb name="sigma_t" value="0.10, 0.20, 0.30"/><float name="albedo" value="0"/></medium>
    <medium type="homogeneous" id="b"><rgb name="sigma_t" value="0.25, 0.05, 0.15"/><float name="albedo" value="0"/></medium>
    <medium type="homogeneous" id="c"><rgb name="sigma_t" value="0.07, 0.11, 0.02"/><float name="albedo" value="0"/></medium>
    <medium type="homogeneous" id="d"><rgb name="sigma_t" value="0.03, 0.09, 0.13"/><float name="albedo" value="0"/></medium>"#;

/// σt of media a, b, c, d above.
const SIGMA: [[f64; 3]; 4] = [
    [0.10, 0.20, 0.30],
    [0.25, 0.05, 0.15],
    [0.07, 0.11, 0.02],
    [0.03, 0.09, 0.13],
];

/// A null-BSDF cube spanning x, y ∈ [−5, 5] and z ∈ [`z0`, `z1`], with `media` refs inside.
fn slab_cube(z0: f64, z1: f64, media: &str) -> String {
    format!(
        r#"<shape type="cube"><transform name="to_world"><scale x="5" y="5" z="{}"/><translate z="{}"/></transform>
        <bsdf type="null"/>{media}</shape>"#,
        0.5 * (z1 - z0),
        0.5 * (z0 + z1)
    )
}

/// A unit-radiance emitting rectangle at z = 10 facing the camera.
const EMITTER: &str = r#"<shape type="rectangle"><boolean name="flip_normals" value="true"/>
    <transform name="to_world"><scale value="40"/><translate z="10"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#;

/// Imports and builds `body` (with the media) behind a sensor at the origin looking along +z
/// (`sensor_medium`: the sensor's `<ref>`, or empty); `max_depth` in Mitsuba's counting.
fn load(body: &str, sensor_medium: &str, max_depth: u32) -> (tempfile::TempDir, Scene) {
    let dir = tempfile::tempdir().unwrap();
    let path: PathBuf = dir.path().join("scene.xml");
    let text = format!(
        r#"<scene version="3.0.0">{MEDIA}
        <integrator type="volpath"><integer name="max_depth" value="{max_depth}"/></integrator>
        <sensor type="perspective"><float name="fov" value="10"/>{sensor_medium}<film type="hdrfilm"><rfilter type="box"/></film></sensor>
        {body}</scene>"#
    );
    std::fs::write(&path, text).unwrap();
    let scene = brume::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        scene.interfaces.is_some(),
        "the scene should need the interface rule"
    );
    (dir, scene)
}

/// Per channel, exp(−Σ σt·d) over `(medium, distance)` pairs, times `scale`.
fn transmittance(stretches: &[(usize, f64)], scale: f64) -> [f64; 3] {
    std::array::from_fn(|c| {
        let depth: f64 = stretches.iter().map(|&(m, d)| SIGMA[m][c] * d).sum();
        scale * (-depth).exp()
    })
}

/// The radiance along the camera's axis (+z from the origin), `n` paths.
fn along_axis(scene: &Scene, n: usize) -> common::Estimate {
    estimate_ray(scene, Ray::new(Vec3::ZERO, Vec3::Z), n, 17)
}

/// Two overlapping boxes, A (a inside) over z ∈ [2, 6] and B (b inside)
/// over z ∈ [4, 9], no exterior media, the camera in vacuum. Mitsuba's
/// rule: a from 2 to 4, b from 4 (entering B) to 6, where leaving A sets
/// A's exterior, vacuum, to the emitter. (Containment would add a and b
/// over [4, 6]; a stack of entered media would keep b to 9; interior and
/// exterior swapped would give a over [6, 9], b over [9, 10].)
#[test]
fn overlapping_boxes_follow_the_last_interface_crossed() {
    let body = format!(
        "{}{}{EMITTER}",
        slab_cube(2.0, 6.0, r#"<ref name="interior" id="a"/>"#),
        slab_cube(4.0, 9.0, r#"<ref name="interior" id="b"/>"#)
    );
    let (_dir, scene) = load(&body, "", 1);
    let expected = transmittance(&[(0, 2.0), (1, 2.0)], 1.0);
    assert_estimate(
        &along_axis(&scene, 40_000),
        expected,
        "two overlapping boxes",
    );
}

/// The camera in medium a (the sensor's), a box over z ∈ [2, 5] with c
/// inside and b outside: a to 2, c to 5, then b (the box's exterior, not the
/// a around it) to the emitter at 10.
#[test]
fn a_shape_whose_exterior_differs_from_the_medium_around_it() {
    let body = format!(
        "{}{EMITTER}",
        slab_cube(
            2.0,
            5.0,
            r#"<ref name="interior" id="c"/><ref name="exterior" id="b"/>"#
        )
    );
    let (_dir, scene) = load(&body, r#"<ref id="a"/>"#, 1);
    let expected = transmittance(&[(0, 2.0), (2, 3.0), (1, 5.0)], 1.0);
    assert_estimate(&along_axis(&scene, 40_000), expected, "exterior b after c");
}

/// The camera inside a box over z ∈ [−2, 2] with d inside and c outside:
/// with the sensor in d, d to 2 then c to 10; with the sensor in no
/// medium, vacuum until the box is left, then c.
#[test]
fn a_camera_inside_a_medium_shape_is_in_the_sensors_medium() {
    let body = format!(
        "{}{EMITTER}",
        slab_cube(
            -2.0,
            2.0,
            r#"<ref name="interior" id="d"/><ref name="exterior" id="c"/>"#
        )
    );
    let (_dir, scene) = load(&body, r#"<ref id="d"/>"#, 1);
    let expected = transmittance(&[(3, 2.0), (2, 8.0)], 1.0);
    assert_estimate(&along_axis(&scene, 40_000), expected, "sensor in d");
    let (_dir, scene) = load(&body, "", 1);
    let expected = transmittance(&[(2, 8.0)], 1.0);
    assert_estimate(&along_axis(&scene, 40_000), expected, "sensor in vacuum");
}

/// A white diffuse wall at z = 10 lit by a point light at the camera,
/// through the two overlapping boxes of the first test: the camera ray
/// carries exp(−2σa − 2σb), the shadow ray back exp(−3σb − 2σa) (entering
/// B at 9, b; entering A at 6, a; leaving B at 4, vacuum).
/// L = T_camera · T_shadow · (1/π) · I / 10².
#[test]
fn shadow_rays_pass_null_interfaces_and_change_medium_there() {
    let wall = r#"<shape type="rectangle"><boolean name="flip_normals" value="true"/>
        <transform name="to_world"><scale value="40"/><translate z="10"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></shape>
        <emitter type="point"><rgb name="intensity" value="100"/></emitter>"#;
    let body = format!(
        "{}{}{wall}",
        slab_cube(2.0, 6.0, r#"<ref name="interior" id="a"/>"#),
        slab_cube(4.0, 9.0, r#"<ref name="interior" id="b"/>"#)
    );
    let (_dir, scene) = load(&body, "", 2);
    let expected = transmittance(&[(0, 4.0), (1, 5.0)], 100.0 / 100.0 / std::f64::consts::PI);
    assert_estimate(
        &along_axis(&scene, 40_000),
        expected,
        "lit through two boxes",
    );
}

/// The wall of the test above lit instead by a directional light along +z:
/// its shadow rays have no end, so they cross the boxes with their
/// direction kept. L = T_camera · T_shadow · (1/π) · E.
#[test]
fn shadow_rays_toward_a_directional_light_pass_null_interfaces() {
    let wall = r#"<shape type="rectangle"><boolean name="flip_normals" value="true"/>
        <transform name="to_world"><scale value="40"/><translate z="10"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></shape>
        <emitter type="directional"><vector name="direction" value="0, 0, 1"/><rgb name="irradiance" value="3"/></emitter>"#;
    let body = format!(
        "{}{}{wall}",
        slab_cube(2.0, 6.0, r#"<ref name="interior" id="a"/>"#),
        slab_cube(4.0, 9.0, r#"<ref name="interior" id="b"/>"#)
    );
    let (_dir, scene) = load(&body, "", 2);
    let expected = transmittance(&[(0, 4.0), (1, 5.0)], 3.0 / std::f64::consts::PI);
    assert_estimate(
        &along_axis(&scene, 40_000),
        expected,
        "lit by a directional light through two boxes",
    );
}

/// The wall of the test above lit instead by a 0.4 × 0.4 emitting square
/// at z = −0.5 facing it, through the same boxes: each shadow ray ends on
/// the emitter after four null crossings, each of which moves its origin off
/// the surface it crossed. The ray must still end short of the emitter (a
/// ray that reaches it is blocked by it, as any surface blocks): every
/// crossing re-aims the ray at the same end point.
/// L = T_camera · (1/π) ∫ L_e · T_shadow(θ) · cos² θ / r² dA over the square.
#[test]
fn shadow_rays_through_null_interfaces_still_end_short_of_an_area_light() {
    let body = format!(
        r#"{}{}
        <shape type="rectangle"><boolean name="flip_normals" value="true"/>
            <transform name="to_world"><scale value="40"/><translate z="10"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></shape>
        <shape type="rectangle">
            <transform name="to_world"><scale value="0.2"/><translate z="-0.5"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
            <emitter type="area"><rgb name="radiance" value="1000"/></emitter></shape>"#,
        slab_cube(2.0, 6.0, r#"<ref name="interior" id="a"/>"#),
        slab_cube(4.0, 9.0, r#"<ref name="interior" id="b"/>"#)
    );
    let (_dir, scene) = load(&body, "", 2);
    let camera = transmittance(&[(0, 2.0), (1, 2.0)], 1.0);
    let expected =
        std::array::from_fn(|c| camera[c] * wall_irradiance(c, 1000.0) / std::f64::consts::PI);
    assert_estimate(
        &along_axis(&scene, 40_000),
        expected,
        "lit by a square through two boxes",
    );
}

/// Irradiance in channel `c` at (0, 0, 10) from the square of side 0.4 at
/// z = −0.5 with radiance `radiance`, through the shadow ray's media (b
/// from 9 to 6, a from 6 to 4, then vacuum: leaving B sets B's exterior),
/// by a 200 × 200 midpoint rule.
fn wall_irradiance(c: usize, radiance: f64) -> f64 {
    let (n, side, h) = (200, 0.4, 10.5);
    let cell = side / n as f64;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let x = -0.5 * side + (i as f64 + 0.5) * cell;
            let y = -0.5 * side + (j as f64 + 0.5) * cell;
            let r2 = x * x + y * y + h * h;
            let cos = h / r2.sqrt();
            let depth = (SIGMA[0][c] * 2.0 + SIGMA[1][c] * 3.0) / cos;
            sum += radiance * (-depth).exp() * cos * cos / r2 * cell * cell;
        }
    }
    sum
}

/// Only the path tracer follows the rule: another integrator is refused by
/// key, in one line.
#[test]
fn other_integrators_refuse_a_scene_that_needs_the_rule() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.xml");
    let body = format!(
        r#"<scene version="3.0.0">{MEDIA}<sensor type="perspective"><film type="hdrfilm"><rfilter type="box"/></film></sensor>{}{}{EMITTER}</scene>"#,
        slab_cube(2.0, 6.0, r#"<ref name="interior" id="a"/>"#),
        slab_cube(4.0, 9.0, r#"<ref name="interior" id="b"/>"#)
    );
    std::fs::write(&path, body).unwrap();
    let mut imported = brume::scene::mitsuba::import(&path, vec![]).unwrap();
    assert!(imported.desc.interfaces.is_some());
    for kind in ["bdpt", "mlt", "sppm"] {
        imported.desc.integrator.kind = kind.into();
        imported.desc.integrator.max_depth = 8;
        let e = brume::scene::build(&imported.desc, &path, dir.path())
            .err()
            .expect("refused")
            .to_string();
        assert!(
            e.contains("integrator.type") && e.contains("interface rule") && !e.contains('\n'),
            "{kind}: {e}"
        );
    }
}

/// The test above with an index-matched dielectric box (int_ior = ext_ior)
/// instead of a null one: the medium after a scattering vertex on a
/// transition surface is the side the sampled direction leaves to.
#[test]
fn a_dielectric_interface_sets_the_medium_of_the_sampled_side() {
    let body = format!(
        r#"<shape type="cube"><transform name="to_world"><scale x="5" y="5" z="1.5"/><translate z="3.5"/></transform>
        <bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.5"/></bsdf>
        <ref name="interior" id="c"/><ref name="exterior" id="b"/></shape>{EMITTER}"#
    );
    let (_dir, scene) = load(&body, r#"<ref id="a"/>"#, 4);
    let expected = transmittance(&[(0, 2.0), (2, 3.0), (1, 5.0)], 1.0);
    assert_estimate(
        &along_axis(&scene, 40_000),
        expected,
        "glass box: c, then b",
    );
}
