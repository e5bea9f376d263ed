//! Render-level closed forms that pin each term of the radiance estimator:
//! the MIS weights of light and BSDF/phase sampling (with the light-pick
//! probability), area-light pdfs, escaped rays, medium emission, and the
//! depth limits (`max_depth = 1` is exactly direct lighting).
//!
//! Furnace principle: in a closed scene where every emitter has radiance L and
//! reflects nothing, and every other surface and medium conserves energy
//! (albedo 1, mirrors of reflectance 1, media with σa·Le and Le = L), the
//! radiance is L everywhere, whatever the number of lights and their pick
//! probabilities. Each scene is rendered at several light counts.

mod common;

use brume::math::{Ray, Vec3};
use common::*;
use std::f64::consts::PI;

const CAMERA_INSIDE: &str = r#"
[camera]
position = [0.3, -0.2, 1.7]
look_at = [0.0, 0.0, 0.0]
fov = 70.0
resolution = [8, 8]
"#;

/// Six inward-facing emissive walls of radiance 1 (albedo 0) bounding [-2, 2]³;
/// with `split` the +y wall is made of four quads (9 lights instead of 6).
fn room(split: bool) -> String {
    let mut walls = String::new();
    let mut wall = |center: [f64; 3], normal: [f64; 3], size: f64| {
        walls += &format!(
            "[[shape]]\ntype = \"quad\"\ncenter = {center:?}\nnormal = {normal:?}\nsize = [{size:?}, {size:?}]\nemission = 1.0\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n"
        );
    };
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut center = [0.0; 3];
            let mut normal = [0.0; 3];
            center[axis] = 2.0 * sign;
            normal[axis] = -sign;
            if split && axis == 1 && sign > 0.0 {
                for (dx, dz) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
                    wall([dx, 2.0, dz], normal, 2.0);
                }
            } else {
                wall(center, normal, 4.0);
            }
        }
    }
    walls
}

const WHITE_SPHERE: &str = "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, -0.3, 0.0]\nradius = 0.8\nmaterial = { type = \"diffuse\", albedo = 1.0 }\n";

const WHITE_MEDIUM: &str = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.7\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"box\", min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }\n";

/// `count` small emissive spheres of radiance `l` that reflect nothing.
fn small_emitters(count: usize, l: f64) -> String {
    (0..count)
        .map(|i| {
            let a = i as f64 * 2.1;
            format!(
                "[[shape]]\ntype = \"sphere\"\ncenter = [{:?}, {:?}, {:?}]\nradius = 0.15\nemission = {l:?}\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n",
                1.2 * a.cos(),
                0.9,
                1.2 * a.sin() - 0.4
            )
        })
        .collect()
}

fn integrator(max_depth: u32) -> String {
    format!("[integrator]\nmax_depth = {max_depth}\nrr_depth = 5\nseed = 7\n")
}

/// A closed room of emissive walls around a white diffuse sphere, with and
/// without an albedo-1 medium, with 6 and 9 wall lights and extra small
/// emitters: every pixel is 1.
#[test]
fn emissive_room_furnace() {
    for split in [false, true] {
        for extra in [0, 3] {
            for medium in ["", WHITE_MEDIUM] {
                let text = format!(
                    "{CAMERA_INSIDE}{}{}{WHITE_SPHERE}{}{medium}",
                    integrator(1000),
                    room(split),
                    small_emitters(extra, 1.0)
                );
                let pixels = estimate_pixels(&scene_from_str(&text), 96);
                let what = format!(
                    "room split {split}, {extra} extra emitters, medium {}",
                    !medium.is_empty()
                );
                assert_pixels_equal(&pixels, [1.0; 3], &what);
            }
        }
    }
}

/// One two-sided emissive sphere of radiance 1 enclosing a white sphere (and
/// a white medium), with extra small emitters: every pixel is 1.
#[test]
fn emissive_sphere_furnace() {
    for extra in [0, 2] {
        for medium in ["", WHITE_MEDIUM] {
            let text = format!(
                "{CAMERA_INSIDE}{}[[shape]]\ntype = \"sphere\"\nradius = 4.0\nemission = 1.0\ntwo_sided = true\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n{WHITE_SPHERE}{}{medium}",
                integrator(1000),
                small_emitters(extra, 1.0)
            );
            let pixels = estimate_pixels(&scene_from_str(&text), 96);
            let what = format!(
                "enclosing sphere, {extra} extra emitters, medium {}",
                !medium.is_empty()
            );
            assert_pixels_equal(&pixels, [1.0; 3], &what);
        }
    }
}

const CAMERA_OUTSIDE: &str = r#"
[camera]
position = [0.0, 0.5, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0
resolution = [8, 8]
"#;

/// An environment of radiance 1, small emitters of radiance 1 that reflect
/// nothing and a white diffuse sphere: every pixel is 1 at any depth ≥ 1
/// (the white sphere sees radiance 1 in every direction).
///
/// 2048 samples a pixel: the light pick asks each small emitter with its
/// uniform share only (probability ≈ 0.06 beside the environment's power),
/// so about 1.7% of a pixel's samples fall near 0.53 and the rest near 1.03.
/// At 128 samples a pixel sees none of those 11% of the time, its standard
/// error then misses them, and the check is not at its α; at 2048 a pixel
/// holds about 35 and the central-limit approximation holds.
#[test]
fn environment_and_emitters_furnace() {
    for extra in [1, 4] {
        for max_depth in [1, 3] {
            let text = format!(
                "{CAMERA_OUTSIDE}{}[[light]]\ntype = \"environment\"\nradiance = 1.0\n{WHITE_SPHERE}{}",
                integrator(max_depth),
                small_emitters(extra, 1.0)
            );
            let pixels = estimate_pixels(&scene_from_str(&text), 2048);
            let what = format!("environment + {extra} emitters, max_depth {max_depth}");
            assert_pixels_equal(&pixels, [1.0; 3], &what);
        }
    }
}

/// An emissive medium (σa·Le with Le = 0.7) in an environment of 0.7, with a
/// mirror sphere and area lights of radiance 0.7 present: every pixel is 0.7.
#[test]
fn emissive_medium_furnace_with_mirrors_and_area_lights() {
    for extra in [0, 3] {
        let text = format!(
            "{CAMERA_OUTSIDE}{}[[light]]\ntype = \"environment\"\nradiance = 0.7\n\
             [[shape]]\ntype = \"sphere\"\ncenter = [0.4, -0.2, 0.3]\nradius = 0.5\nmaterial = {{ type = \"mirror\" }}\n\
             {}\
             [[medium]]\ntype = \"homogeneous\"\nsigma_a = [0.5, 1.5, 0.2]\nsigma_s = 0.6\nemission = 0.7\nphase = {{ type = \"hg\", g = 0.3 }}\n\
             bounds = {{ type = \"box\", min = [-1.5, -1.0, -1.5], max = [1.5, 1.5, 1.5] }}\n",
            integrator(1000),
            small_emitters(extra, 0.7)
        );
        let pixels = estimate_pixels(&scene_from_str(&text), 128);
        assert_pixels_equal(
            &pixels,
            [0.7; 3],
            &format!("emissive furnace, {extra} emitters"),
        );
    }
}

/// Two mirror spheres in an environment of radiance 1 (and a small emitter of
/// radiance 1 that NEE could sample but mirrors cannot use): a ray is 1 when
/// it escapes within `max_depth` reflections, else 0. The estimator is exact
/// here (no randomness reaches the result), so the expectation, traced
/// analytically in f64, must match to rounding.
#[test]
fn mirror_spheres_count_reflections_exactly() {
    let spheres = [([-0.6, 0.0, 0.0], 0.5), ([0.6, 0.1, 0.0], 0.5)];
    let mut text = format!(
        "{CAMERA_OUTSIDE}[[light]]\ntype = \"environment\"\nradiance = 1.0\n{}",
        small_emitters(1, 1.0)
    );
    for (c, r) in spheres {
        text += &format!(
            "[[shape]]\ntype = \"sphere\"\ncenter = {c:?}\nradius = {r:?}\nmaterial = {{ type = \"mirror\" }}\n"
        );
    }
    let mut seen = [0usize; 3];
    for max_depth in 0..4 {
        let scene = scene_from_str(&format!("{text}{}", integrator(max_depth)));
        for i in 0..40 {
            // Rays aimed between the spheres: some bounce from one to the other and back.
            let origin = [0.1, 0.3, 4.0];
            let target = [-0.35 + 0.7 * i as f64 / 40.0, 0.05, 0.0];
            let dir = normalize(sub(target, origin));
            let Some(expected) = trace_mirrors(&spheres, origin, dir, max_depth) else {
                continue;
            };
            seen[expected.1.min(2)] += 1;
            let ray = Ray::new(vec3(origin), vec3(dir));
            let est = estimate_ray(&scene, ray, 8, 1);
            assert!(
                (est.mean[0] - expected.0).abs() < 1e-6 && est.std_error[0] < 1e-6,
                "max_depth {max_depth}, ray {i}: {} ± {} vs {}",
                est.mean[0],
                est.std_error[0],
                expected.0
            );
        }
    }
    assert!(
        seen.iter().all(|&n| n > 0),
        "rays with 0, 1 and 2+ reflections: {seen:?}"
    );
}

/// Radiance along a ray among mirror spheres in an environment of 1 with at
/// most `max_depth` reflections, and the reflection count; `None` for rays
/// that come near a silhouette or the small emitter (kept out of the check).
fn trace_mirrors(
    spheres: &[([f64; 3], f64)],
    mut o: [f64; 3],
    mut d: [f64; 3],
    max_depth: u32,
) -> Option<(f64, usize)> {
    for bounce in 0..=max_depth as usize + 1 {
        let mut best: Option<(f64, [f64; 3], f64)> = None;
        for &(c, r) in spheres {
            let oc = sub(o, c);
            let b = dot(oc, d);
            let disc = b * b - (dot(oc, oc) - r * r);
            if disc < 0.0 {
                continue;
            }
            // Grazing hits are where f32 and f64 may disagree.
            if disc < 1e-3 * r * r {
                return None;
            }
            let t = -b - disc.sqrt();
            if t > 1e-6 && best.is_none_or(|(bt, _, _)| t < bt) {
                best = Some((t, c, r));
            }
        }
        let Some((t, c, r)) = best else {
            // Escapes: does it pass near the emitter (at y = 0.9)? Then skip the ray.
            return (d[1] <= 0.05).then_some((1.0, bounce));
        };
        if bounce == max_depth as usize {
            return Some((0.0, bounce));
        }
        let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
        let n = normalize(sub(p, c));
        let _ = r;
        let k = 2.0 * dot(d, n);
        d = normalize([d[0] - k * n[0], d[1] - k * n[1], d[2] - k * n[2]]);
        o = p;
    }
    None
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

/// A diffuse ground under an emissive ball (σa, σs, Le, no other light) at
/// `max_depth = 1`: the ground point on the axis reflects ρ/π·E with
/// E = 2π ∫₀^α Le·σa/σt·(1 − e^{−σt ℓ(γ)}) cos γ sin γ dγ, ℓ the chord,
/// sin α = R/h. The in-scattered part of the ball's own light would need a
/// second scattering event, so it is excluded; with σs = 0 (pure absorption)
/// the same holds at any depth.
#[test]
fn ground_under_emissive_ball_at_max_depth_one() {
    let (big_r, h, le, rho) = (0.5f64, 1.5f64, 2.0f64, 0.8f64);
    for (sigma_a, sigma_s, max_depth) in [(1.5f64, 0.0f64, 1u32), (1.5, 0.0, 4), (0.8, 1.2, 1)] {
        let sigma_t = sigma_a + sigma_s;
        let alpha = (big_r / h).asin();
        let integrand = |g: f64| {
            let chord = 2.0 * (big_r * big_r - h * h * g.sin().powi(2)).max(0.0).sqrt();
            le * sigma_a / sigma_t * (1.0 - (-sigma_t * chord).exp()) * g.cos() * g.sin()
        };
        let e = 2.0 * PI * brume::sampling::quadrature::gauss_legendre(integrand, 0.0, alpha, 64);
        let expected = rho / PI * e;
        let text = format!(
            "[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n{}\
             [[shape]]\ntype = \"quad\"\nnormal = [0.0, 1.0, 0.0]\nsize = [6.0, 6.0]\nmaterial = {{ type = \"diffuse\", albedo = {rho:?} }}\n\
             [[medium]]\ntype = \"homogeneous\"\nsigma_a = {sigma_a:?}\nsigma_s = {sigma_s:?}\nemission = {le:?}\n\
             bounds = {{ type = \"sphere\", center = [0.0, {h:?}, 0.0], radius = {big_r:?} }}\n",
            integrator(max_depth)
        );
        let scene = scene_from_str(&text);
        let eye = Vec3::new(0.3, 0.6, 1.0);
        let ray = Ray::new(eye, (-eye).normalize());
        let est = estimate_ray(&scene, ray, 400_000, 5);
        assert_estimate(
            &est,
            [expected; 3],
            &format!("σa {sigma_a} σs {sigma_s} max_depth {max_depth}"),
        );
    }
}

/// A disk light of radiance L and radius R facing down from height h over a
/// diffuse floor (itself a disk) of albedo ρ: with direct lighting only, the
/// floor below the light's centre sends ρ/π · E, where the irradiance of a
/// coaxial disk is E = π L R²/(R² + h²). Pins the disk's area (the light
/// pdf), its uniform area sampling and its ray test (the BSDF-sampled hits
/// MIS weighs against the light samples).
#[test]
fn a_disk_light_gives_its_closed_form_irradiance() {
    let (l, r, h, rho) = (2.0, 0.5, 1.0, 0.5);
    let text = format!(
        "{CAMERA_OUTSIDE}{}\
         [[shape]]\ntype = \"disk\"\ncenter = [0.0, {h:?}, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = {r:?}\n\
         material = {{ type = \"diffuse\", albedo = 0.0 }}\nemission = {l:?}\n\
         [[shape]]\ntype = \"disk\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nradius = 3.0\n\
         material = {{ type = \"diffuse\", albedo = {rho:?} }}\n",
        integrator(1)
    );
    let scene = scene_from_str(&text);
    // From the side, under the light, to the floor point below its centre.
    let origin = [2.0, 0.3, 0.0];
    let ray = Ray::new(vec3(origin), vec3(normalize(sub([0.0; 3], origin))));
    let est = estimate_ray(&scene, ray, 40_000, 3);
    let expected = rho * l * r * r / (r * r + h * h);
    assert_estimate(&est, [expected; 3], "floor under a disk light");
}
