//! The Beckmann microfacet distribution (Mitsuba 3's default): sampling
//! against its pdf by the χ² harness, and the single-scattering albedo of a
//! white rough conductor against a quadrature with its own D and Λ (Λ by
//! integrating the slope distribution, not brume's erf closed form).

mod analytic_support;

use analytic_support::lobes::{self, direction};
use analytic_support::{assert_estimate, estimate};
use brume::material::{ConductorFresnel, Distribution, Material, Shading};
use brume::math::color::Rgb;
use brume::math::Vec3;
use brume::sampling::chi2::Chi2Result;
use brume::sampling::quadrature::gauss_legendre;
use std::f64::consts::PI;

const ALPHA: f64 = 0.01;
/// 3 conductor roughnesses × 3 angles + 2 dielectric roughnesses × 2 angles × 2 sides.
const CHI2_TEST_COUNT: usize = 9 + 8;

/// Salt of the lobe-choice stream of [`chi2_of`].
const LOBE_SALT: u64 = 0xBECC;

fn chi2_of(m: Material, wo: Vec3, front: bool, seed: u64) -> Chi2Result {
    lobes::chi2_of(m, wo, front, (seed, LOBE_SALT))
}

fn conductor(alpha: f32, fresnel: ConductorFresnel) -> Material {
    Material::Conductor {
        alpha,
        fresnel,
        distribution: Distribution::Beckmann,
        multiscatter: false,
    }
}

#[test]
fn beckmann_conductor_sampling_follows_its_pdf() {
    let fresnel = ConductorFresnel::Complex {
        eta: Rgb::new(0.2, 0.9, 1.1),
        k: Rgb::new(3.9, 2.4, 2.2),
    };
    for (i, alpha) in [0.1, 0.4, 1.0].into_iter().enumerate() {
        for (j, theta) in [0.0, 40.0, 80.0].into_iter().enumerate() {
            let r = chi2_of(
                conductor(alpha, fresnel),
                direction(theta),
                true,
                (10 * i + j) as u64,
            );
            assert!(
                r.passes(ALPHA, CHI2_TEST_COUNT),
                "conductor α {alpha} θ {theta}: {r}"
            );
        }
    }
}

#[test]
fn beckmann_dielectric_sampling_follows_its_pdf_on_both_sides() {
    let mut seed = 200;
    for alpha in [0.15, 0.6] {
        for theta in [30.0, 70.0] {
            for front in [true, false] {
                seed += 1;
                let m = Material::Dielectric {
                    ior: 1.5,
                    alpha,
                    distribution: Distribution::Beckmann,
                    multiscatter: false,
                };
                let wo = if front {
                    direction(theta)
                } else {
                    -direction(theta)
                };
                let r = chi2_of(m, wo, front, seed);
                assert!(
                    r.passes(ALPHA, CHI2_TEST_COUNT),
                    "dielectric α {alpha} θ {theta} front {front}: {r}"
                );
            }
        }
    }
}

/// Smith's Λ from its definition: (1/cot θ) ∫_{cot θ}^∞ (q − cot θ) P2(q) dq,
/// P2 the Gaussian marginal slope density of variance α²/2.
fn lambda_by_integral(alpha: f64, cos: f64) -> f64 {
    let cot = cos / (1.0 - cos * cos).sqrt();
    let p2 = |q: f64| (-q * q / (alpha * alpha)).exp() / (alpha * PI.sqrt());
    gauss_legendre(|q| (q - cot) * p2(q), cot, cot + 12.0 * alpha, 64) / cot
}

/// White-conductor albedo ∫ D G2 / (4 cos θo) dωi by 2-D quadrature.
fn beckmann_white_albedo(alpha: f64, theta_o: f64) -> f64 {
    let a2 = alpha * alpha;
    let wo = [theta_o.sin(), 0.0, theta_o.cos()];
    let lambda_o = if theta_o == 0.0 {
        0.0
    } else {
        lambda_by_integral(alpha, wo[2])
    };
    gauss_legendre(
        |mu| {
            let lambda_i = lambda_by_integral(alpha, mu);
            gauss_legendre(
                |phi| {
                    let s = (1.0 - mu * mu).sqrt();
                    let h = [wo[0] + s * phi.cos(), s * phi.sin(), wo[2] + mu];
                    let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
                    let hz = h[2] / len;
                    let tan2 = (1.0 - hz * hz) / (hz * hz);
                    let d = (-tan2 / a2).exp() / (PI * a2 * hz.powi(4));
                    d / (1.0 + lambda_o + lambda_i) / (4.0 * wo[2])
                },
                0.0,
                2.0 * PI,
                96,
            )
        },
        0.0,
        1.0,
        96,
    )
}

#[test]
fn white_beckmann_conductor_reflects_its_single_scattering_albedo() {
    for alpha in [0.2f64, 0.5, 1.0] {
        for theta_deg in [0.0f64, 45.0, 75.0] {
            let reference = beckmann_white_albedo(alpha, theta_deg.to_radians());
            assert!(
                reference <= 1.0 + 1e-6,
                "α {alpha} θ {theta_deg}: {reference}"
            );
            let m = conductor(alpha as f32, ConductorFresnel::Schlick { f0: Rgb::WHITE });
            let wo = direction(theta_deg as f32);
            let sp = Shading::facing(Vec3::Z, wo);
            let est = estimate(200_000, 11, |s| {
                m.sample(&sp, wo, s.next_2d(), s.next_1d())
                    .map_or(Rgb::BLACK, |b| b.weight)
            });
            assert_estimate(
                &est,
                [reference; 3],
                &format!("albedo α {alpha} θ {theta_deg}"),
            );
        }
    }
    // Masking costs energy at grazing angles: the test can tell a lost G2.
    assert!(beckmann_white_albedo(1.0, 75f64.to_radians()) < 0.9);
}

/// A nearly smooth Beckmann dielectric transmits what the smooth one does:
/// the mean sample weight (reflected plus refracted, radiance form) of
/// α = 0.02 against the delta dielectric's, from outside and inside. They
/// differ only by the rough lobe's masking loss, well under 1 % at 30°;
/// a transmission lost entirely (Λ = ∞ below the surface, as once) leaves
/// only the reflected few per cent.
#[test]
fn a_nearly_smooth_beckmann_dielectric_transmits_like_the_smooth_one() {
    let albedo = |alpha: f32, wo: Vec3, seed: u64| {
        let m = Material::Dielectric {
            ior: 1.5,
            alpha,
            distribution: Distribution::Beckmann,
            multiscatter: false,
        };
        let sp = Shading::facing(Vec3::Z, wo);
        estimate(100_000, seed, |s| {
            m.sample(&sp, wo, s.next_2d(), s.next_1d())
                .map_or(Rgb::BLACK, |b| b.weight)
        })
        .mean[0]
    };
    for (wo, seed) in [(direction(30.0), 21), (-direction(30.0), 22)] {
        let (rough, smooth) = (albedo(0.02, wo, seed), albedo(0.0, wo, seed + 10));
        assert!(
            (rough - smooth).abs() < 0.01 * smooth,
            "wo {wo}: rough {rough}, smooth {smooth}"
        );
    }
}
