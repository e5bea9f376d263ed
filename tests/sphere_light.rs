//! Direct lighting from a sphere light onto a diffuse plane against its closed
//! form and 2-D quadrature, from the axis to below the horizon.
//!
//! A point of a Lambertian plane of albedo ρ under a sphere light of radiance L
//! seen under the half-angle α (sin α = r/d) reflects ρ/π·E with
//! E = L ∫cone max(0, n·ω) dω. When the whole sphere is above the horizon, at
//! elevation e of its centre, E = π L sin²α sin e (on the axis π L r²/d²).

mod common;

use brume::math::{Ray, Vec3};
use brume::sampling::quadrature::gauss_legendre;
use common::*;
use std::f64::consts::PI;

const ALBEDO: f64 = 0.5;
const RADIANCE: f64 = 3.0;

/// Irradiance on the plane y = 0 (normal +y) from a sphere of radiance L at
/// elevation `e` (radians) and distance `d` with half-angle `asin(r/d)`, by 2-D
/// Gauss–Legendre quadrature over the cone of directions it subtends.
fn irradiance_quadrature(e: f64, d: f64, r: f64) -> f64 {
    let alpha = (r / d).asin();
    let (c, s) = (e.cos(), e.sin());
    // Cone axis toward the centre, e1 in the vertical plane through it, e2 horizontal.
    let axis = [c, s, 0.0];
    let e1 = [-s, c, 0.0];
    let cos_n = |gamma: f64, phi: f64| -> f64 {
        let (sg, cg) = gamma.sin_cos();
        (cg * axis[1] + sg * phi.cos() * e1[1]).max(0.0)
    };
    let over_phi = |gamma: f64| gauss_legendre(|phi| cos_n(gamma, phi), 0.0, 2.0 * PI, 64);
    RADIANCE * gauss_legendre(|g| over_phi(g) * g.sin(), 0.0, alpha, 64)
}

/// Ground quad around `p`, sphere light at elevation `e`, distance `d`, radius `r` from it.
fn scene_text(p: Vec3, e: f64, d: f64, r: f64, medium: bool) -> String {
    let c = [
        p.x as f64 + d * e.cos(),
        p.y as f64 + d * e.sin(),
        p.z as f64,
    ];
    let medium = if medium {
        // A clear medium: transmittance 1, but shadow rays take the media path.
        "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.0\nglobal = true\n"
    } else {
        ""
    };
    SceneText::view([0.0, 1.0, 5.0], [0.0; 3])
        .integrator("max_depth = 1")
        .quad(p.to_array(), [0.0, 1.0, 0.0], [1.0, 1.0])
        .with(&format!(
            "material = {{ type = \"diffuse\", albedo = {ALBEDO} }}"
        ))
        .sphere(c, r)
        .with(&format!(
            "emission = {RADIANCE}\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}"
        ))
        .raw(medium)
        .build()
}

/// Radiance of the plane point `p` seen from above at max_depth 1: ρ/π·E.
fn check(p: Vec3, e_deg: f64, d: f64, r: f64, expected_e: f64, medium: bool) {
    let e = e_deg.to_radians();
    let scene = scene_from_str(&scene_text(p, e, d, r, medium));
    let eye = p + Vec3::new(-0.2, 1.0, 0.4);
    let ray = Ray::new(eye, (p - eye).normalize());
    let est = estimate_ray(&scene, ray, 1_000_000, 11);
    let expected = ALBEDO / PI * expected_e;
    eprintln!(
        "p = {p}, elevation {e_deg}°, d = {d}, r = {r}, medium {medium}: {:.6} ± {:.6} vs {expected:.6} ({:+.2}%)",
        est.mean[0],
        est.std_error[0],
        100.0 * (est.mean[0] / expected - 1.0)
    );
    assert_estimate(
        &est,
        [expected; 3],
        &format!("p = {p}, elevation {e_deg}°, d = {d}, r = {r}, medium {medium}"),
    );
}

/// The quadrature reproduces the closed form where the sphere is above the horizon.
#[test]
fn quadrature_matches_closed_form_above_horizon() {
    for (e_deg, d, r) in [
        (90.0f64, 2.0f64, 0.2f64),
        (45.0, 3.0, 0.5),
        (12.0, 2.0, 0.2),
    ] {
        let closed = PI * RADIANCE * (r / d).powi(2) * e_deg.to_radians().sin();
        let quad = irradiance_quadrature(e_deg.to_radians(), d, r);
        assert!(
            (quad / closed - 1.0).abs() < 1e-9,
            "{e_deg}°: {quad} vs {closed}"
        );
    }
}

/// On the axis and at 45°: E = π L sin²α sin e, at receivers near and far from the origin
/// (the surface offset of shadow rays grows with the coordinates), with and without media.
#[test]
fn sphere_light_irradiance_matches_closed_form() {
    for p in [Vec3::ZERO, Vec3::new(4.0, 0.0, -3.0)] {
        for (e_deg, d, r) in [
            (90.0f64, 2.0f64, 0.2f64),
            (45.0, 3.0, 0.5),
            (12.0, 2.0, 0.2),
        ] {
            let closed = PI * RADIANCE * (r / d).powi(2) * e_deg.to_radians().sin();
            for medium in [false, true] {
                check(p, e_deg, d, r, closed, medium);
            }
        }
    }
}

/// Toward grazing and partly below the horizon, against the quadrature.
#[test]
fn sphere_light_irradiance_matches_quadrature_at_grazing_angles() {
    for p in [Vec3::ZERO, Vec3::new(4.0, 0.0, -3.0)] {
        for (e_deg, d, r) in [(6.0f64, 2.0f64, 0.3f64), (0.0, 2.0, 0.3), (-4.0, 2.0, 0.3)] {
            let quad = irradiance_quadrature(e_deg.to_radians(), d, r);
            check(p, e_deg, d, r, quad, false);
        }
    }
}
