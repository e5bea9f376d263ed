//! Keyframed transforms (`transform = { keyframes = [...] }`) of the camera,
//! media and shapes, against closed forms averaged over the shutter.
//!
//! * a camera translating sideways past a sharp emissive edge: each pixel's
//!   value is the fraction of the shutter during which it sees the emitter,
//!   averaged over the pixel (a linear ramp, integrated in closed form);
//! * keyframes that do not move, and a still scene, are bit-identical to the
//!   same scene written without keyframes.

#[path = "common/mod.rs"]
mod common;

use brume::integrator::Scene;
use common::{
    assert_pixels, estimate_pixels, sample_bits, scene_from_str, Accumulator, Estimate, SceneText,
};

/// ∫ f over [a, b] by the midpoint rule on `n` pieces (exact to ~1e-9 for the ramps here).
fn average(a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let n = 20_000;
    let h = (b - a) / n as f64;
    (0..n).map(|i| f(a + (i as f64 + 0.5) * h)).sum::<f64>() / n as f64
}

/// A 16×2 camera with a 90° horizontal fov at the origin looking down −z at
/// an emitter filling x < 0 on the plane z = −8: pixel i sees plane x in [i − 8, i − 7].
fn edge_scene(camera_extra: &str) -> String {
    edge_view(camera_extra)
        .quad([-25.0, 0.0, -8.0], [0.0, 0.0, 1.0], [50.0, 10.0])
        .with("u_axis = [1.0, 0.0, 0.0]\nemission = 1.0")
        .build()
}

/// The camera and integrator of [`edge_scene`], without the emitter.
fn edge_view(camera_extra: &str) -> SceneText {
    SceneText::camera([0.0; 3], [0.0, 0.0, -1.0], [16, 2])
        .fov(90.0)
        .with("fov_axis = \"x\"")
        .with(camera_extra)
        .integrator("max_depth = 1")
}

#[test]
fn a_camera_moving_past_an_edge_gives_the_analytic_ramp() {
    // Camera x goes −2 → 2 linearly over the shutter: pixel i (plane x = s) sees
    // the emitter while cx < −s, a fraction clamp((2 − s)/4, 0, 1) of the shutter.
    let scene = scene_from_str(&edge_scene(
        "shutter = [-0.5, 0.5]\n transform = { keyframes = [\
         { time = -0.5, translate = [-2.0, 0.0, 0.0] }, { time = 0.5, translate = [2.0, 0.0, 0.0] }] }",
    ));
    assert!(scene.camera.is_moving());
    let spp = 1024;
    let pixels = estimate_pixels(&scene, spp);
    let expected: Vec<[f64; 3]> = (0..2)
        .flat_map(|_| 0..16)
        .map(|i| {
            let s0 = i as f64 - 8.0;
            let v = average(s0, s0 + 1.0, |s| ((2.0 - s) / 4.0).clamp(0.0, 1.0));
            [v; 3]
        })
        .collect();
    // The ramp is resolved: pixels 6..=9 are partly lit, not 0 or 1.
    assert!((expected[7][0] - 0.625).abs() < 1e-6, "{:?}", expected[7]);
    assert_pixels(
        &pixels,
        &expected,
        &vec![[0.0; 3]; 32],
        "moving camera edge ramp",
    );
}

#[test]
fn still_keyframes_and_a_still_camera_are_bit_identical() {
    let plain = scene_from_str(&edge_scene("shutter = [-0.5, 0.5]"));
    let keyed = scene_from_str(&edge_scene(
        "shutter = [-0.5, 0.5]\n transform = { keyframes = [\
         { time = -0.5, translate = [0.0, 0.0, 0.0] }, { time = 0.5 }] }",
    ));
    assert!(
        !keyed.camera.is_moving(),
        "keys that do not move are a still camera"
    );
    let a = sample_bits(&plain, 8);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, sample_bits(&keyed, 8));
}

// --- moving shapes -------------------------------------------------------

/// Fraction of the shutter [−0.5, 0.5] during which plane point x is inside the
/// emitter of half-width 2 centred at 6t, averaged over pixel i of `edge_scene`'s camera.
fn swept_coverage(i: usize) -> f64 {
    let s0 = i as f64 - 8.0;
    average(s0, s0 + 1.0, |s| {
        ((s + 2.0).min(3.0) - (s - 2.0).max(-3.0)).max(0.0) / 6.0
    })
}

/// [`edge_scene`] with a shutter and `shape` (TOML) as the only emitter.
fn moving_emitter_scene(shape: &str) -> String {
    edge_view("shutter = [-0.5, 0.5]").raw(shape).build()
}

const SLIDE: &str = "transform = { keyframes = [{ time = -0.5, translate = [-3.0, 0.0, 0.0] }, \
                     { time = 0.5, translate = [3.0, 0.0, 0.0] }] }";

#[test]
fn a_moving_emissive_quad_and_mesh_cover_pixels_for_their_share_of_the_shutter() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("quad.obj");
    // The same 4×10 rectangle at z = −8 as two triangles, facing +z.
    std::fs::write(
        &obj,
        "v -2 -5 -8\nv 2 -5 -8\nv 2 5 -8\nv -2 5 -8\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let quad = format!(
        "[[shape]]\ntype = \"quad\"\ncenter = [0.0, 0.0, -8.0]\nnormal = [0.0, 0.0, 1.0]\n\
         size = [4.0, 10.0]\nu_axis = [1.0, 0.0, 0.0]\nemission = 1.0\n{SLIDE}"
    );
    let mesh = format!(
        "[[shape]]\ntype = \"mesh\"\nfile = \"{}\"\nemission = 1.0\n{SLIDE}",
        obj.display()
    );
    let expected: Vec<[f64; 3]> = (0..2)
        .flat_map(|_| 0..16)
        .map(|i| [swept_coverage(i); 3])
        .collect();
    assert!(
        (expected[8][0] - 2.0 / 3.0).abs() < 1e-6,
        "{:?}",
        expected[8]
    );
    for (name, shape) in [("quad", quad), ("mesh", mesh)] {
        let scene = scene_from_str(&moving_emitter_scene(&shape));
        let pixels = estimate_pixels(&scene, 1024);
        assert_pixels(
            &pixels,
            &expected,
            &vec![[0.0; 3]; 32],
            &format!("moving {name}"),
        );
    }
}

/// Irradiance at `p` (normal `n`) from a polygon of uniform radiance 1 (Lambert's formula).
fn polygon_irradiance(p: glam::DVec3, n: glam::DVec3, corners: &[glam::DVec3]) -> f64 {
    let mut sum = 0.0;
    for k in 0..corners.len() {
        let a = (corners[k] - p).normalize();
        let b = (corners[(k + 1) % corners.len()] - p).normalize();
        let c = a.cross(b);
        sum += a.dot(b).clamp(-1.0, 1.0).acos() * n.dot(c.normalize());
    }
    0.5 * sum.abs()
}

/// A diffuse floor at y = 0 lit only by `light` (TOML); one bounce.
fn floor_scene(light: &str) -> String {
    SceneText::camera([0.0, 3.0, 0.0], [0.0; 3], [4, 4])
        .with("up = [0.0, 0.0, -1.0]\nshutter = [-0.5, 0.5]")
        .integrator("max_depth = 1")
        .quad([0.0; 3], [0.0, 1.0, 0.0], [40.0, 40.0])
        .with("material = { type = \"diffuse\", albedo = 0.5 }")
        .raw(light)
        .build()
}

/// Radiance leaving floor point (x0, 0, 0) upward, averaged over the shutter.
fn floor_estimate(scene: &Scene, x0: f32, n: usize, seed: u64) -> Estimate {
    let mut acc = Accumulator::default();
    for i in 0..n {
        let mut sampler = brume::sampling::Sampler::new(seed, 0, 0, i as u64);
        let time = -0.5 + sampler.next_1d();
        let ray = brume::math::Ray {
            time,
            ..brume::math::Ray::new(brume::math::Vec3::new(x0, 0.5, 0.0), -brume::math::Vec3::Y)
        };
        acc.add(brume::integrator::li(scene, ray, &mut sampler));
    }
    acc.estimate()
}

#[test]
fn a_moving_turning_area_light_lights_the_floor_as_its_shutter_average() {
    // A 0.6×0.4 two-sided quad of radiance 4 at height 1, sliding x −1 → 1 and turning 40° about z.
    let light = "[[shape]]\ntype = \"quad\"\ncenter = [0.0, 1.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
        size = [0.6, 0.4]\nu_axis = [1.0, 0.0, 0.0]\nemission = 4.0\ntwo_sided = true\n\
        transform = { keyframes = [{ time = -0.5, translate = [-1.0, 0.0, 0.0] }, \
        { time = 0.5, translate = [1.0, 0.0, 0.0], rotate = [0.0, 0.0, 40.0] }] }";
    let scene = scene_from_str(&floor_scene(light));
    let corners_at = |t: f64| {
        let u = t + 0.5;
        let turn = glam::DQuat::from_rotation_z((40.0 * u).to_radians());
        let shift = glam::DVec3::new(-1.0 + 2.0 * u, 0.0, 0.0);
        [(-0.3, -0.2), (0.3, -0.2), (0.3, 0.2), (-0.3, 0.2)]
            .map(|(x, z)| shift + turn * glam::DVec3::new(x, 1.0, z))
    };
    for x0 in [0.0f32, 0.7, -1.3] {
        let p = glam::DVec3::new(x0 as f64, 0.0, 0.0);
        let e = brume::sampling::quadrature::gauss_legendre(
            |t| polygon_irradiance(p, glam::DVec3::Y, &corners_at(t)),
            -0.5,
            0.5,
            256,
        );
        let expected = 0.5 / std::f64::consts::PI * 4.0 * e;
        let est = floor_estimate(&scene, x0, 40_000, 3);
        common::assert_estimate(&est, [expected; 3], &format!("floor at x {x0}"));
    }
}

#[test]
fn a_moving_growing_sphere_light_lights_the_floor_as_its_shutter_average() {
    // Radius 0.2 at x = −1 growing to 0.3 at x = 1, height 1: always above the horizon.
    let light =
        "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 0.2\nemission = 4.0\n\
        transform = { keyframes = [{ time = -0.5, translate = [-1.0, 0.0, 0.0] }, \
        { time = 0.5, translate = [1.0, 0.0, 0.0], scale = 1.5 }] }";
    let scene = scene_from_str(&floor_scene(light));
    assert_floor_under_sphere_light(&scene, &[0.0, 0.8], 5, "sphere light", |t| {
        let u = t + 0.5;
        let s = 1.0 + 0.5 * u;
        // The centre is scaled about the origin too: (0, s, 0) + (−1 + 2u, 0, 0).
        (glam::DVec3::new(-1.0 + 2.0 * u, s, 0.0), 0.2 * s)
    });
}

/// Asserts the radiance leaving the floor of `floor_scene` at each x in `xs`
/// against its shutter average under a sphere light of radiance 4 whose
/// centre and radius at time t are `sphere_at(t)` (always above the
/// horizon: E = π L r²/d² · cos θ, averaged by Gauss–Legendre).
fn assert_floor_under_sphere_light(
    scene: &Scene,
    xs: &[f32],
    seed: u64,
    what: &str,
    sphere_at: impl Fn(f64) -> (glam::DVec3, f64),
) {
    for &x0 in xs {
        let e = brume::sampling::quadrature::gauss_legendre(
            |t| {
                let (c, r) = sphere_at(t);
                let d = c - glam::DVec3::new(x0 as f64, 0.0, 0.0);
                std::f64::consts::PI * (r * r / d.length_squared()) * (d.y / d.length())
            },
            -0.5,
            0.5,
            256,
        );
        let expected = 0.5 / std::f64::consts::PI * 4.0 * e;
        let est = floor_estimate(scene, x0, 40_000, seed);
        common::assert_estimate(&est, [expected; 3], &format!("{what}, floor at x {x0}"));
    }
}

/// The MIS weight of a floor ray that hits a moving sphere light must use the
/// light's cone where the light is at that time. Written at height 0.25 (a
/// cone of 2.5 sr from the floor) and keyframed up to 1.5 (0.06 sr), a light
/// weighed at its written place would give the floor's BSDF-sampled hits
/// about 0.4 of the weight they should nearly lack: ~40 % too bright.
#[test]
fn a_sphere_light_keyframed_away_from_where_it_is_written_is_weighed_where_it_is() {
    let light =
        "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.25, 0.0]\nradius = 0.2\nemission = 4.0\n\
        transform = { keyframes = [{ time = -0.5, translate = [-0.3, 1.25, 0.0] }, \
        { time = 0.5, translate = [0.3, 1.25, 0.0] }] }";
    let scene = scene_from_str(&floor_scene(light));
    assert_floor_under_sphere_light(&scene, &[0.0, 0.5], 7, "sphere light keyframed up", |t| {
        (glam::DVec3::new(0.6 * t, 1.5, 0.0), 0.2)
    });
}

#[test]
fn shapes_with_keys_that_do_not_move_render_as_a_plain_transform() {
    let light = |t: &str| {
        format!(
            "[[shape]]\ntype = \"quad\"\ncenter = [0.0, 1.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
             size = [0.6, 0.4]\nemission = 4.0\ntransform = {t}"
        )
    };
    let plain = scene_from_str(&floor_scene(&light("{ translate = [0.3, 0.0, 0.0] }")));
    let keyed = scene_from_str(&floor_scene(&light(
        "{ keyframes = [{ time = -0.5, translate = [0.3, 0.0, 0.0] }, \
           { time = 0.5, translate = [0.3, 0.0, 0.0] }] }",
    )));
    assert!(keyed.geometry.moving_shape(1).is_none());
    let a = sample_bits(&plain, 16);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, sample_bits(&keyed, 16));
}

#[test]
fn a_moving_sphere_light_samples_points_on_the_sphere_at_the_time_asked() {
    let light =
        "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 0.2\nemission = 4.0\n\
        transform = { keyframes = [{ time = -0.5, translate = [-1.0, 0.0, 0.0], scale = 0.5 }, \
        { time = 0.5, translate = [1.0, 0.0, 0.0], scale = 1.5 }] }";
    let scene = scene_from_str(&floor_scene(light));
    let p = brume::math::Vec3::new(0.3, 0.0, 0.1);
    let mut s = brume::sampling::Sampler::from_seed(7);
    for i in 0..200 {
        let t = -0.5 + i as f32 / 200.0;
        let ls = scene.lights[0]
            .sample_facing(p, None, s.next_2d(), &scene.geometry, t)
            .expect("a visible sphere");
        let u = t + 0.5;
        let scale = 0.5 + u;
        let centre = brume::math::Vec3::new(-1.0 + 2.0 * u, scale, 0.0);
        let on = p + ls.wi * ls.distance;
        let off = ((on - centre).length() - 0.2 * scale).abs();
        assert!(off < 1e-4, "time {t}: {off} off the sphere");
    }
}

#[test]
fn aovs_see_the_moving_camera_at_the_beauty_time() {
    let scene = scene_from_str(&edge_scene(
        "shutter = [-0.5, 0.5]\n transform = { keyframes = [\
         { time = -0.5, translate = [-2.0, 0.0, 0.0] }, { time = 0.5, translate = [2.0, 0.0, 0.0] }] }",
    ));
    let spp = 1024;
    let channels =
        brume::render::render_aovs(&scene, &[brume::integrator::aov::Aov::Alpha], spp, Some(1));
    let alpha = &channels[0].1;
    let n = spp as f64;
    let pixels: Vec<Estimate> = alpha
        .iter()
        .map(|&a| {
            let a = a as f64;
            Estimate {
                mean: [a; 3],
                std_error: [(a * (1.0 - a) / (n - 1.0)).sqrt(); 3],
                n: spp as usize,
            }
        })
        .collect();
    let expected: Vec<[f64; 3]> = (0..2)
        .flat_map(|_| 0..16)
        .map(|i| {
            let s0 = i as f64 - 8.0;
            [average(s0, s0 + 1.0, |s| ((2.0 - s) / 4.0).clamp(0.0, 1.0)); 3]
        })
        .collect();
    assert_pixels(
        &pixels,
        &expected,
        &vec![[0.0; 3]; 32],
        "alpha of a moving camera",
    );
}
