//! Plastic with a rough coating (Mitsuba's `roughplastic`): sampling against
//! its combined pdf by the χ² harness, the white furnace bound, and the
//! smooth coating as the limit of a small α.

mod analytic_support;

use analytic_support::lobes::{self, direction};
use analytic_support::{assert_estimate, estimate, Estimate};
use brume::material::layered::{diffuse_fresnel, Plastic};
use brume::material::{Distribution, Material, Shading};
use brume::math::color::Rgb;
use brume::math::Vec3;
use brume::sampling::chi2::Chi2Result;

const ALPHA: f64 = 0.01;
/// 2 distributions × 2 roughnesses × 2 angles.
const CHI2_TEST_COUNT: usize = 8;
/// Salt of the lobe-choice stream of [`lobes::chi2_of`].
const LOBE_SALT: u64 = 0x9A57;

fn rough_plastic(diffuse: Rgb, ior: f32, nonlinear: bool, alpha: f32, d: Distribution) -> Material {
    Material::Plastic(Plastic {
        diffuse,
        specular: Rgb::WHITE,
        ior,
        fdr_int: diffuse_fresnel(1.0 / ior),
        nonlinear,
        alpha,
        distribution: d,
    })
}

/// Mean `f cos / pdf` over the sampler from `wo` (the directional albedo).
fn albedo(m: Material, wo: Vec3, seed: u64) -> Estimate {
    let sp = Shading::facing(Vec3::Z, wo);
    estimate(200_000, seed, |s| {
        m.sample(&sp, wo, s.next_2d(), s.next_1d())
            .map_or(Rgb::BLACK, |b| b.weight)
    })
}

#[test]
fn rough_plastic_sampling_follows_its_combined_pdf() {
    let base = Rgb::new(0.3, 0.6, 0.8);
    let mut seed = 0;
    for d in [Distribution::Beckmann, Distribution::Ggx] {
        for alpha in [0.1f32, 0.5] {
            for theta in [0.0f32, 60.0] {
                seed += 1;
                let m = rough_plastic(base, 1.5, false, alpha, d);
                let r: Chi2Result = lobes::chi2_of(m, direction(theta), true, (seed, LOBE_SALT));
                assert!(
                    r.passes(ALPHA, CHI2_TEST_COUNT),
                    "{d:?} α {alpha} θ {theta}: {r}"
                );
            }
        }
    }
}
