//! Analytic-media suite, radiance without scattering: emission–absorption
//! (the Koschmieder form) and a lit surface seen through an absorber.

mod analytic_support;

use analytic_support::*;
use brume::math::{Ray, Vec3};
use std::f64::consts::PI;

const N: usize = 20_000;

/// An absorbing, emitting slab z ∈ [0, d] (σs = 0) in front of a background of
/// radiance L_bg, given either by an emissive quad at z = -1 or by the environment.
fn koschmieder_scene(
    sigma_a: [f64; 3],
    le: [f64; 3],
    l_bg: [f64; 3],
    d: f64,
    quad: bool,
) -> String {
    let scene = SceneText::view([0.0, 0.0, 10.0], [0.0; 3]).integrator("max_depth = 16");
    let scene = if quad {
        scene
            .quad([0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [100.0, 100.0])
            .with(&format!(
                "emission = {l_bg:?}\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}"
            ))
    } else {
        scene.environment(l_bg)
    };
    scene
        .medium(&format!(
            "type = \"homogeneous\"\nsigma_a = {sigma_a:?}\nsigma_s = 0.0\nemission = {le:?}\n\
             bounds = {{ type = \"box\", min = [-20.0, -20.0, 0.0], max = [20.0, 20.0, {d:?}] }}"
        ))
        .build()
}

/// σa, Le, L_bg, slab thickness d, view angle θ from the slab normal (degrees).
type KoschmiederCase = ([f64; 3], [f64; 3], [f64; 3], f64, f64);

/// A camera ray crossing the slab at angle θ from its normal sees
/// L = L_bg e^(-σa ℓ) + Le (1 - e^(-σa ℓ)), ℓ = d / cos θ, per channel,
/// with the background an emissive quad or the environment.
#[test]
fn emission_absorption_slab_koschmieder() {
    // (σa, Le, L_bg, d, θ in degrees)
    let cases: [KoschmiederCase; 4] = [
        ([0.5; 3], [2.0; 3], [0.3; 3], 2.0, 0.0),
        ([0.1, 1.0, 3.0], [1.0, 0.5, 2.0], [0.2, 0.8, 0.4], 1.5, 30.0),
        ([4.0; 3], [1.5; 3], [5.0; 3], 2.0, 10.0),
        (
            [0.05, 0.02, 0.3],
            [0.0, 3.0, 1.0],
            [1.0, 1.0, 0.0],
            0.7,
            55.0,
        ),
    ];
    for (k, (sigma_a, le, l_bg, d, theta)) in cases.into_iter().enumerate() {
        let (sin, cos) = (theta as f32).to_radians().sin_cos();
        let dir = Vec3::new(sin, 0.0, -cos);
        // Start above the slab; the ray reaches z = 0 at x = 0.3, y = 0.2.
        let ray = Ray::new(Vec3::new(0.3, 0.2, 0.0) - dir * (d as f32 + 2.0) / cos, dir);
        let length = d / (theta.to_radians().cos());
        let expected = per_channel(|c| {
            let t = (-sigma_a[c] * length).exp();
            l_bg[c] * t + le[c] * (1.0 - t)
        });
        for quad in [true, false] {
            let scene = scene_from_str(&koschmieder_scene(sigma_a, le, l_bg, d, quad));
            let est = estimate_li(&scene, ray, N, 10 + k as u64);
            let bg = if quad { "quad" } else { "environment" };
            assert_estimate(
                &est,
                expected,
                &format!(
                    "Koschmieder σa={sigma_a:?} Le={le:?} L_bg={l_bg:?} d={d} θ={theta}° ({bg})"
                ),
            );
        }
    }
}

/// An emitting absorber filling all space, seen along a ray that escapes to
/// infinity: the Koschmieder form with d = ∞, L = Le, per channel.
/// (Regression: global media were skipped along escaping rays, giving 0.)
#[test]
fn emission_absorption_to_infinity() {
    let text = SceneText::view([0.0, 0.0, 5.0], [0.0; 3])
        .environment(7.0)
        .medium(
            "type = \"homogeneous\"\nsigma_a = [0.2, 0.5, 0.8]\nemission = [1.0, 2.0, 3.0]\nglobal = true",
        );
    let scene = scene_from_str(&text.build());
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.6, -0.8));
    let est = estimate_li(&scene, ray, N, 30);
    assert_estimate(
        &est,
        [1.0, 2.0, 3.0],
        "global emitting absorber to infinity",
    );
}

/// A diffuse ground (albedo ρ) in a global pure absorber, lit by a point light
/// of intensity I at distance r, seen from a camera at distance d_cam:
/// L = ρ/π · I cos θ / r² · e^(-σa r) · e^(-σa d_cam), exactly: nothing else
/// contributes (σs = 0, no other surface), whatever max_depth allows.
///
/// Depth semantics (see `li`): max_depth = 1 is direct light only, the camera
/// ray's hit being the first vertex; a medium scattering event would also count.
#[test]
fn lit_ground_through_an_absorber() {
    let rho = [0.6, 0.5, 0.4];
    let intensity = [5.0, 6.0, 7.0];
    let light = Vec3::new(0.5, 2.0, 0.3);
    let eye = Vec3::new(-1.0, 1.5, 2.0);
    let ground = Vec3::new(0.2, 0.0, -0.1);
    for (k, (sigma_a, max_depth)) in [([0.2; 3], 1), ([0.1, 0.3, 0.6], 1), ([0.1, 0.3, 0.6], 8)]
        .into_iter()
        .enumerate()
    {
        let text = SceneText::view([0.0, 2.0, 5.0], [0.0; 3])
            .integrator(&format!("max_depth = {max_depth}"))
            .point_light(light.to_array(), intensity)
            .quad([0.0; 3], [0.0, 1.0, 0.0], [50.0, 50.0])
            .with(&format!(
                "material = {{ type = \"diffuse\", albedo = {rho:?} }}"
            ))
            .medium(&format!(
                "type = \"homogeneous\"\nsigma_a = {sigma_a:?}\nglobal = true"
            ));
        let scene = scene_from_str(&text.build());
        let to_light = (light - ground).as_dvec3();
        let r = to_light.length();
        let cos_theta = to_light.y / r;
        let d_cam = (ground - eye).as_dvec3().length();
        let expected = per_channel(|c| {
            rho[c] / PI * intensity[c] * cos_theta / (r * r) * (-sigma_a[c] * (r + d_cam)).exp()
        });
        let ray = Ray::new(eye, (ground - eye).normalize());
        let est = estimate_li(&scene, ray, N, 40 + k as u64);
        assert_estimate(
            &est,
            expected,
            &format!("ground through absorber σa={sigma_a:?}, max_depth={max_depth}"),
        );
    }
}
