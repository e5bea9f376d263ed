//! Media moved by keyframed transforms, against closed forms over the shutter.
//!
//! * a homogeneous box translating and turning, and a sphere translating:
//!   the transmittance along a ray averaged over the shutter equals the 1-D
//!   quadrature over the shutter of exp(−σt·chord(t)), the chord of the ray
//!   through the medium placed at time t (closed form per time);
//! * a grid box translating at constant velocity by keyframes equals the
//!   same box moved by a constant velocity grid (the Eulerian motion blur on
//!   main), and both equal the quadrature;
//! * the majorant of a keyframed grid (translating, turning, scaling) bounds
//!   σt at every point of random rays at random times;
//! * keys that do not move build the same medium as a plain transform (bit-identical images).

#[path = "analytic_support/mod.rs"]
mod analytic_support;
#[path = "voxel_box_support/mod.rs"]
mod voxel_box_support;

use std::sync::Arc;

use analytic_support::common::scene_from_str;
use analytic_support::{assert_estimate, assert_same, estimate, SceneText};
use brume::integrator::tracking::{medium_transmittance, TransmittanceEstimator};
use brume::math::keyframes::{Key, Keyframes};
use brume::math::{Quat, Ray, Vec3};
use brume::medium::{GridMedium, Medium};
use brume::render::pixel_sample;
use brume::sampling::quadrature::gauss_legendre;
use brume::sampling::Sampler;
use glam::{DQuat, DVec3, IVec3};
use voxel_box_support::*;

const SHUTTER: [f32; 2] = [-0.5, 0.5];
const SIGMA_T: f64 = 1.5;

/// A homogeneous medium in `bounds` moved by the keyframes `keys`, under a uniform sky.
fn medium_scene(bounds: &str, keys: &str) -> String {
    SceneText::camera([0.0, 0.0, 5.0], [0.0; 3], [4, 4])
        .with("shutter = [-0.5, 0.5]")
        .environment(1.0)
        .medium(&format!(
            "type = \"homogeneous\"\nsigma_t = {SIGMA_T:?}\nalbedo = 0.5\nbounds = {bounds}\ntransform = {keys}"
        ))
        .build()
}

/// Slab chord of the ray (o, d) through the box [lo, hi] (f64).
fn box_chord(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    let inv = d.recip();
    let (ta, tb) = ((lo - o) * inv, (hi - o) * inv);
    let near = ta.min(tb).max_element().max(0.0);
    let far = ta.max(tb).min_element();
    (far - near).max(0.0)
}

/// Checks the shutter-averaged transmittance of `medium` along `rays` against
/// the quadrature of exp(−σt·chord(ray, t)).
fn check_rays(medium: &Medium, rays: &[(Vec3, Vec3)], chord: impl Fn(DVec3, DVec3, f64) -> f64) {
    for (i, &(o, d)) in rays.iter().enumerate() {
        let d = d.normalize();
        let (od, dd) = (o.as_dvec3(), d.as_dvec3());
        let (a, b) = (SHUTTER[0] as f64, SHUTTER[1] as f64);
        let expected =
            gauss_legendre(|t| (-SIGMA_T * chord(od, dd, t)).exp(), a, b, 2048) / (b - a);
        assert!(
            expected > 0.05 && expected < 0.95,
            "ray {i} must cross the medium: {expected}"
        );
        for estimator in [
            TransmittanceEstimator::Auto,
            TransmittanceEstimator::Ratio,
            TransmittanceEstimator::Delta,
        ] {
            let est = estimate(40_000, 17 + i as u64, |s: &mut Sampler| {
                let time = SHUTTER[0] + (SHUTTER[1] - SHUTTER[0]) * s.next_1d();
                let ray = Ray {
                    time,
                    ..Ray::new(o, d)
                };
                medium_transmittance(medium, &ray, 20.0, estimator, s)
            });
            assert_estimate(&est, [expected; 3], &format!("ray {i} {estimator:?}"));
        }
    }
}

#[test]
fn a_translating_turning_box_transmits_the_shutter_average_of_its_chords() {
    // x from −1 to 1 and a turn of 60° about y over the shutter.
    let scene = scene_from_str(&medium_scene(
        "{ type = \"box\", min = [-0.5, -0.5, -0.5], max = [0.5, 0.5, 0.5] }",
        "{ keyframes = [{ time = -0.5, translate = [-1.0, 0.0, 0.0] }, \
           { time = 0.5, translate = [1.0, 0.0, 0.0], rotate = [0.0, 60.0, 0.0] }] }",
    ));
    assert!(matches!(scene.media[0], Medium::Moving(_)));
    let chord = |o: DVec3, d: DVec3, t: f64| {
        let u = t + 0.5;
        let translate = DVec3::new(-1.0 + 2.0 * u, 0.0, 0.0);
        let turn = DQuat::from_rotation_y((60.0 * u).to_radians()).inverse();
        let (lo, hi) = (DVec3::splat(-0.5), DVec3::splat(0.5));
        box_chord(turn * (o - translate), turn * d, lo, hi)
    };
    let rays = [
        (Vec3::new(-3.0, 0.1, -2.0), Vec3::new(1.0, 0.0, 0.7)),
        (Vec3::new(0.0, -0.2, 3.0), Vec3::new(0.05, 0.0, -1.0)),
        (Vec3::new(-4.0, 0.3, 0.2), Vec3::new(1.0, 0.0, 0.0)),
    ];
    check_rays(&scene.media[0], &rays, chord);
}

#[test]
fn a_translating_sphere_transmits_the_shutter_average_of_its_chords() {
    let scene = scene_from_str(&medium_scene(
        "{ type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 0.6 }",
        "{ keyframes = [{ time = -0.5, translate = [0.0, -1.0, 0.0] }, \
           { time = 0.5, translate = [0.0, 1.0, 0.0] }] }",
    ));
    let chord = |o: DVec3, d: DVec3, t: f64| {
        let c = DVec3::new(0.0, 2.0 * t, 0.0);
        let oc = c - o;
        let along = oc.dot(d);
        let perp2 = (oc - d * along).length_squared();
        let half = (0.36 - perp2).max(0.0).sqrt();
        ((along + half).max(0.0) - (along - half).max(0.0)).max(0.0)
    };
    let rays = [
        (Vec3::new(0.0, 0.2, 3.0), Vec3::new(0.0, 0.0, -1.0)),
        (Vec3::new(-3.0, -0.4, 0.1), Vec3::new(1.0, 0.1, 0.0)),
    ];
    check_rays(&scene.media[0], &rays, chord);
}

// --- a grid box: keyframes against the velocity grid ---------------------

fn key(time: f32, translate: Vec3, rotation: Quat, scale: f32) -> Key {
    Key {
        time,
        translate,
        rotation,
        scale: Vec3::splat(scale),
    }
}

#[test]
fn a_keyframed_grid_box_equals_the_velocity_grid_box_and_the_quadrature() {
    // 9.6 m/s is 0.4 m (4 voxels) per frame: over [0, 0.5] the box moves 2 voxels in +x.
    let v = Vec3::new(9.6, 0.0, 0.0);
    let shutter = [0.0f32, 0.5];
    let density = dense(IVec3::ZERO, IVec3::splat(8), 1.0);
    let eulerian = Medium::Grid(Arc::new(GridMedium::new_moving(
        density.clone(),
        params(4),
        Some(constant_velocity(v, shutter)),
    )));
    let keys = Keyframes::new(&[
        key(0.0, Vec3::ZERO, Quat::IDENTITY, 1.0),
        key(0.5, v * (0.5 / FPS), Quat::IDENTITY, 1.0),
    ]);
    let keyed = Medium::Grid(Arc::new(GridMedium::new(density, params(4)))).moved_by(keys);
    let v_index = (v.x / FPS / H) as f64;
    let tau_across = (SIGMA * H * 8.0) as f64;
    for qx in [8.5f32, 7.5, 3.0] {
        let closed = |t: f64| (-tau_across * profile(qx as f64 - v_index * t)).exp();
        let expected = gauss_legendre(closed, 0.0, 0.5, 64) / 0.5;
        let run = |medium: &Medium| {
            estimate(40_000, 11, |s: &mut Sampler| {
                let time = shutter[0] + (shutter[1] - shutter[0]) * s.next_1d();
                let ray = ray_at(qx, time);
                medium_transmittance(medium, &ray, 3.0, TransmittanceEstimator::Ratio, s)
            })
        };
        let (a, b) = (run(&keyed), run(&eulerian));
        assert_estimate(&a, [expected; 3], &format!("keyframed qx {qx}"));
        assert_same(&a, &b, &format!("keyframed vs velocity grid qx {qx}"));
    }
}

#[test]
fn the_keyframed_majorant_bounds_every_point_at_every_time() {
    let grid = GridMedium::new(half_dense(), params(2));
    let keys = Keyframes::new(&[
        key(-0.5, Vec3::new(-0.5, 0.0, 0.0), Quat::IDENTITY, 1.0),
        key(
            0.0,
            Vec3::new(0.2, 0.3, 0.0),
            Quat::from_rotation_z(0.8),
            1.5,
        ),
        key(
            0.5,
            Vec3::new(0.6, -0.2, 0.4),
            Quat::from_rotation_y(-0.7),
            0.7,
        ),
    ]);
    let medium = Medium::Grid(Arc::new(grid)).moved_by(keys);
    let (mut n, mut over, mut inside) = (0u64, 0u64, 0u64);
    for i in 0..3000u64 {
        let mut s = Sampler::new(21, 0, 0, i);
        let centre = Vec3::new(0.8, 0.4, 0.4);
        let o = centre + (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5) * 6.0;
        let target = centre + (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5) * 2.0;
        let time = SHUTTER[0] + (SHUTTER[1] - SHUTTER[0]) * s.next_1d();
        let ray = Ray {
            time,
            ..Ray::new(o, (target - o).normalize())
        };
        let segments: Vec<_> = medium.majorants(&ray, f32::INFINITY).collect();
        for _ in 0..64 {
            let t = 8.0 * s.next_1d();
            let maj = segments
                .iter()
                .find(|g| g.t0 <= t && t < g.t1)
                .map_or(0.0, |g| g.majorant_at(t));
            let sigma_t = medium.sigma_t_at(ray.at(t), time).max_channel();
            n += 1;
            inside += (sigma_t > 0.0) as u64;
            over += (sigma_t > maj) as u64;
        }
    }
    assert!(inside > 10_000, "{inside} of {n} points in the medium");
    assert_eq!(over, 0, "{n} checks");
}

#[test]
fn keys_that_do_not_move_render_as_a_plain_transform() {
    let bounds = "{ type = \"box\", min = [-0.5, -0.5, -0.5], max = [0.5, 0.5, 0.5] }";
    let plain = scene_from_str(&medium_scene(
        bounds,
        "{ translate = [0.2, 0.0, 0.0], rotate = [0.0, 30.0, 0.0] }",
    ));
    let keyed = scene_from_str(&medium_scene(
        bounds,
        "{ keyframes = [{ time = -0.5, translate = [0.2, 0.0, 0.0], rotate = [0.0, 30.0, 0.0] }, \
           { time = 0.5, translate = [0.2, 0.0, 0.0], rotate = [0.0, 30.0, 0.0] }] }",
    ));
    assert!(matches!(keyed.media[0], Medium::Homogeneous(_)));
    let bits = |scene: &brume::integrator::Scene| {
        let mut out = Vec::new();
        for p in 0..16u32 {
            for s in 0..4 {
                let l = pixel_sample(scene, p % 4, p / 4, s);
                out.push([l.r.to_bits(), l.g.to_bits(), l.b.to_bits()]);
            }
        }
        out
    };
    let a = bits(&plain);
    assert!(a.iter().any(|s| s != &[0, 0, 0]));
    assert_eq!(a, bits(&keyed));
}
