//! Chi-square tests of light sampling from a receiver against the density MIS
//! uses for the same light (`Light::escaped_pdf_facing`): environments seen
//! from a surface (cosine-weighted about its normal) and from a medium point
//! (uniform over the sphere).
//!
//! Family-wise level ALPHA, Šidák-corrected for CHI2_TEST_COUNT accepting
//! tests; fixed seeds.

use brume::geometry::Geometry;
use brume::light::{Environment, Light};
use brume::math::color::Rgb;
use brume::math::Vec3;
use brume::sampling::chi2::{Chi2Result, SphereChi2};

const ALPHA: f64 = 0.01;
/// Constant and sky environments, each from two surface normals and from a medium point.
const CHI2_TEST_COUNT: usize = 6;
const SAMPLES: usize = 100_000;

fn assert_passes(name: &str, result: &Chi2Result) {
    assert!(result.passes(ALPHA, CHI2_TEST_COUNT), "{name}: {result}");
    assert_eq!(result.invalid_count, 0, "{name}: {result}");
}

fn environments() -> [(&'static str, Light); 2] {
    [
        (
            "constant",
            Light::Environment(Environment::Constant {
                radiance: Rgb::new(0.35, 0.5, 0.8),
            }),
        ),
        (
            "sky",
            Light::Environment(Environment::Sky {
                zenith: Rgb::new(0.2, 0.4, 1.0),
                horizon: Rgb::new(0.9, 0.9, 0.8),
                ground: Rgb::splat(0.1),
                up: Vec3::Y,
            }),
        ),
    ]
}

/// `sample_facing` from a receiver with `normal` against `escaped_pdf_facing`.
fn run(light: &Light, normal: Option<Vec3>, seed: u64) -> Chi2Result {
    let geometry = Geometry::new(Vec::new());
    let p = Vec3::new(0.3, 1.0, -2.0);
    SphereChi2::new(SAMPLES, seed).run(
        |u| {
            light
                .sample_facing(p, normal, u, &geometry, 0.0)
                .map(|s| s.wi)
        },
        |d| light.escaped_pdf_facing(d, normal),
    )
}

#[test]
fn environments_from_surfaces_follow_their_cosine_density() {
    // The chi-square bins are in world cos θ about +z: an oblique normal and one along −z.
    let normals = [Vec3::new(0.3, -0.5, 0.8).normalize(), -Vec3::Z];
    for (k, (name, light)) in environments().iter().enumerate() {
        for (j, n) in normals.iter().enumerate() {
            let result = run(light, Some(*n), 10 + 2 * k as u64 + j as u64);
            assert_passes(
                &format!("{name} environment from a surface facing {n}"),
                &result,
            );
        }
    }
}

#[test]
fn environments_from_medium_points_are_uniform() {
    for (k, (name, light)) in environments().iter().enumerate() {
        let result = run(light, None, 20 + k as u64);
        assert_passes(&format!("{name} environment from a medium point"), &result);
    }
}

/// The harness tells the cosine density from the uniform ones it replaced.
#[test]
fn a_uniform_density_is_rejected_for_surface_samples() {
    let (_, light) = &environments()[0];
    let n = Vec3::new(0.3, -0.5, 0.8).normalize();
    let geometry = Geometry::new(Vec::new());
    let hemisphere = SphereChi2::new(SAMPLES, 30).run(
        |u| {
            light
                .sample_facing(Vec3::ZERO, Some(n), u, &geometry, 0.0)
                .map(|s| s.wi)
        },
        |d| {
            if d.dot(n) > 0.0 {
                0.5 * std::f32::consts::FRAC_1_PI
            } else {
                0.0
            }
        },
    );
    assert!(hemisphere.p_value < 1e-12, "{hemisphere}");
}

/// Each sample's own weight integrates the constant sky over the hemisphere
/// exactly: E = ∫ L cos θ dω = π L, whatever the direction drawn.
#[test]
fn surface_samples_weigh_to_the_cosine_irradiance() {
    let radiance = Rgb::new(0.35, 0.5, 0.8);
    let light = Light::Environment(Environment::Constant { radiance });
    let geometry = Geometry::new(Vec::new());
    let n = Vec3::new(-0.2, 0.9, 0.1).normalize();
    let mut s = brume::sampling::Sampler::from_seed(40);
    for _ in 0..1000 {
        let ls = light
            .sample_facing(Vec3::ZERO, Some(n), s.next_2d(), &geometry, 0.0)
            .expect("a direction above the surface");
        let e = ls.radiance.g * n.dot(ls.wi) / ls.pdf;
        assert!(
            (e - std::f32::consts::PI * radiance.g).abs() < 1e-3,
            "weight {e} for {:?}",
            ls.wi
        );
    }
}
