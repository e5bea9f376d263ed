//! Separable Smith masking (`masking = "separable"`, what the Mitsuba
//! importer sets): rough conductors and dielectrics evaluate as Mitsuba 3's
//! `roughconductor` and `roughdielectric` do, and sample by their pdf.

mod analytic_support;

use analytic_support::lobes::{self, direction};
use brume::material::{ConductorFresnel, Distribution, Material, Shading};
use brume::math::color::Rgb;
use brume::math::Vec3;
use brume::sampling::chi2::Chi2Result;

/// Significance of each χ² test.
const ALPHA: f64 = 0.01;
/// 2 materials × 2 distributions × 2 angles.
const CHI2_TEST_COUNT: usize = 8;
/// Salt of the lobe-choice stream of [`lobes::chi2_of`].
const LOBE_SALT: u64 = 0x5E9A;

fn conductor(distribution: Distribution, alpha: f32) -> Material {
    Material::Conductor {
        alpha,
        fresnel: ConductorFresnel::Complex {
            eta: Rgb::splat(0.2),
            k: Rgb::splat(3.0),
        },
        distribution,
        multiscatter: false,
    }
}

fn dielectric(distribution: Distribution, alpha: f32) -> Material {
    Material::Dielectric {
        ior: 1.5,
        alpha,
        distribution,
        multiscatter: false,
    }
}

/// Mitsuba 3's f · cos θ (scalar_rgb variant, `mi.load_dict({...}).eval(ctx,
/// si, wo)`) of reflections with the view at θ 20° and 70° and the light at
/// 40° and 75°, azimuth (−0.6, 0.8): conductors of η 0.2, k 3, dielectrics
/// of index 1.5 in air.
const MITSUBA: [(bool, Distribution, f32, [f64; 2]); 4] = [
    (
        true,
        Distribution::GgxSeparable,
        0.5,
        [0.18996359407901764, 0.04503047466278076],
    ),
    (
        true,
        Distribution::BeckmannSeparable,
        0.8,
        [0.1260918527841568, 0.07286658883094788],
    ),
    (
        false,
        Distribution::GgxSeparable,
        0.6,
        [0.0068047805689275265, 0.004415084607899189],
    ),
    (
        false,
        Distribution::BeckmannSeparable,
        0.3,
        [0.016605259850621223, 3.5694422417797966e-10],
    ),
];

/// With separable masking the lobes are Mitsuba's: within 0.1 % for GGX,
/// 0.5 % for Beckmann (Mitsuba's Beckmann G1 is a rational fit good to
/// 0.35 %). Seen failing with the height-correlated G2 (by 4–23 % at 70°/75°).
#[test]
fn separable_masking_evaluates_as_mitsubas_rough_lobes() {
    for (metal, distribution, alpha, expected) in MITSUBA {
        let m = match metal {
            true => conductor(distribution, alpha),
            false => dielectric(distribution, alpha),
        };
        let tolerance = match distribution {
            Distribution::GgxSeparable => 1e-3,
            _ => 5e-3,
        };
        for ((view, light), want) in [(20.0f32, 40.0f64), (70.0, 75.0)].into_iter().zip(expected) {
            let wo = direction(view);
            let (s, c) = light.to_radians().sin_cos();
            let wi = Vec3::new((-0.6 * s) as f32, (0.8 * s) as f32, c as f32);
            let got = m.eval(&Shading::facing(Vec3::Z, wo), wo, wi).r as f64;
            assert!(
                (got / want - 1.0).abs() < tolerance,
                "{distribution:?} α {alpha} metal {metal}, θ {view}° / {light}°: {got} vs Mitsuba's {want}"
            );
        }
    }
}

/// Sampling follows the pdf (χ² through the shared harness) with the
/// separable weight.
#[test]
fn separable_lobes_sample_by_their_pdf() {
    let mut seed = 0;
    for distribution in [Distribution::GgxSeparable, Distribution::BeckmannSeparable] {
        for material in [conductor(distribution, 0.5), dielectric(distribution, 0.5)] {
            for theta in [20.0f32, 70.0] {
                seed += 1;
                let front = true;
                let r: Chi2Result =
                    lobes::chi2_of(material, direction(theta), front, (seed, LOBE_SALT));
                assert!(
                    r.passes(ALPHA, CHI2_TEST_COUNT),
                    "{distribution:?} θ {theta}: {r}"
                );
            }
        }
    }
}
