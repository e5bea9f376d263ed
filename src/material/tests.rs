//! Unit tests of the BSDFs: sampling agrees with eval and pdf.

use super::*;
use crate::math::Vec2;
use crate::sampling::Sampler;

/// Checks weight = eval / pdf and pdf consistency for sampled directions.
fn check_consistency(m: Material) {
    let normal = Vec3::new(0.2, 0.9, -0.1).normalize();
    for wo in [
        Vec3::new(-0.5, 0.7, 0.3).normalize(),
        Vec3::new(0.5, -0.7, 0.1).normalize(),
        Vec3::new(0.9, 0.1, 0.2).normalize(),
    ] {
        check_consistency_from(m, Shading::facing(normal, wo), wo);
    }
}

fn check_consistency_from(m: Material, sp: Shading, wo: Vec3) {
    let mut s = Sampler::from_seed(9);
    for _ in 0..2000 {
        if let Some(bs) = m.sample(&sp, wo, s.next_2d(), s.next_1d()) {
            let pdf = m.pdf(&sp, wo, bs.wi);
            assert!(
                (pdf - bs.pdf).abs() <= 1e-3 * pdf.max(1.0),
                "{m:?} wo {wo}: {pdf} vs {} for {}",
                bs.pdf,
                sp.n.dot(bs.wi)
            );
            let expected = m.eval(&sp, wo, bs.wi) / bs.pdf;
            assert!(
                (expected - bs.weight).max_channel().abs()
                    < 1e-3 * bs.weight.max_channel().max(1.0),
                "{m:?}: {expected:?} vs {:?}",
                bs.weight
            );
        }
    }
}

#[test]
fn sampling_matches_eval_and_pdf() {
    check_consistency(Material::Diffuse {
        albedo: Rgb::new(0.2, 0.5, 0.9),
    });
    for exponent in [0.0, 1.0, 10.0, 200.0] {
        check_consistency(Material::Phong {
            albedo: Rgb::splat(0.8),
            exponent,
        });
    }
    for (distribution, multiscatter) in [
        (Distribution::Ggx, false),
        (Distribution::Ggx, true),
        (Distribution::Beckmann, false),
        (Distribution::GgxSeparable, false),
        (Distribution::BeckmannSeparable, false),
    ] {
        for alpha in [0.01, 0.1, 0.4, 1.0] {
            check_consistency(Material::Conductor {
                alpha,
                fresnel: ConductorFresnel::Complex {
                    eta: Rgb::new(0.2, 0.9, 1.1),
                    k: Rgb::new(3.9, 2.4, 2.2),
                },
                distribution,
                multiscatter,
            });
            for ior in [1.5, 1.1, 2.4] {
                check_consistency(Material::Dielectric {
                    ior,
                    alpha,
                    distribution,
                    multiscatter,
                });
            }
        }
    }
}

#[test]
fn phong_albedo_at_normal_incidence_is_its_albedo() {
    // ∫ f cosθ dω by Monte Carlo over the lobe sampler: the weight's mean.
    let m = Material::Phong {
        albedo: Rgb::WHITE,
        exponent: 20.0,
    };
    let mut s = Sampler::from_seed(2);
    let n = 200_000;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let w = m
            .sample(
                &Shading::facing(Vec3::Z, Vec3::Z),
                Vec3::Z,
                s.next_2d(),
                0.0,
            )
            .map_or(0.0, |b| b.weight.r as f64);
        sum += w;
        sum2 += w * w;
    }
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    // One check at the suite's k (tests/common/k_sigma.rs).
    let k = crate::suite_k::k_sigma(1);
    assert!((mean - 1.0).abs() < k * se + 1e-6, "{mean} ± {se}");
}

#[test]
fn mirror_reflects() {
    let m = Material::Mirror {
        reflectance: Rgb::WHITE,
    };
    let wo = Vec3::new(1.0, 1.0, 0.0).normalize();
    let bs = m
        .sample(&Shading::facing(Vec3::Y, wo), wo, Vec2::ZERO, 0.0)
        .unwrap();
    assert!((bs.wi - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    assert!(bs.is_delta);
}
