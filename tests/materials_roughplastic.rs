//! Plastic with a rough coating (Mitsuba's `roughplastic`): sampling against
//! its combined pdf by the χ² harness, the white furnace bound, and the
//! smooth coating as the limit of a small α.

mod analytic_support;

use analytic_support::common::stats::tolerance;
use analytic_support::lobes::{self, build_error, direction, directional_albedo as albedo};
use analytic_support::{assert_same, k_sigma};
use brume::material::layered::{diffuse_fresnel, Plastic};
use brume::material::{Distribution, Material};
use brume::math::color::Rgb;
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

/// White bases: 2 distributions × 3 roughnesses × 3 angles × 2 `nonlinear`.
const WHITE_FAMILY: usize = 36 * 3;

#[test]
fn a_white_rough_plastic_reflects_at_most_everything() {
    // The diffuse share alone is exactly 1 − F(θo) for a white base (the
    // smooth plastic's identity η²(1 − F_dr,int) = 1 − F_dr,ext); the rough
    // specular lobe must not add more than the F(θo) it leaves.
    let k = k_sigma(WHITE_FAMILY);
    let mut seed = 100;
    for d in [Distribution::Beckmann, Distribution::Ggx] {
        for alpha in [0.05f32, 0.3, 0.8] {
            for theta in [0.0f32, 50.0, 85.0] {
                for nonlinear in [false, true] {
                    seed += 1;
                    let m = rough_plastic(Rgb::WHITE, 1.5, nonlinear, alpha, d);
                    let est = albedo(m, direction(theta), seed);
                    for c in 0..3 {
                        let (mean, se) = (est.mean[c], est.std_error[c]);
                        assert!(
                            mean - 1.0 <= tolerance(se, 1.0, k),
                            "{d:?} α {alpha} θ {theta} nonlinear {nonlinear}: albedo {mean} ± {se} exceeds 1"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_small_alpha_coating_reflects_like_the_smooth_one() {
    // At α = 0.002 the microfacet lobe is all but the mirror: the albedo of
    // a coloured rough plastic equals the smooth plastic's.
    let base = Rgb::new(0.2, 0.5, 0.9);
    let mut seed = 300;
    for d in [Distribution::Beckmann, Distribution::Ggx] {
        for theta in [0.0f32, 60.0, 80.0] {
            seed += 1;
            let rough = albedo(
                rough_plastic(base, 1.5, true, 0.002, d),
                direction(theta),
                seed,
            );
            let smooth = albedo(
                rough_plastic(base, 1.5, true, 0.0, d),
                direction(theta),
                seed + 50,
            );
            assert_same(&rough, &smooth, &format!("{d:?} θ {theta}"));
        }
    }
}

#[test]
fn a_bad_roughness_and_other_estimators_are_refused_by_key() {
    let sphere = |material: &str, integrator: &str| {
        analytic_support::SceneText::furnace_view(4)
            .environment(1.0)
            .unit_sphere(material)
            .integrator(&format!("type = \"{integrator}\""))
            .build()
    };
    let rough = r#"{ type = "plastic", alpha = 0.2, distribution = "beckmann" }"#;
    let only_path = "shape[0].material: `plastic` is supported by the path tracer only";
    for (material, integrator, want) in [
        (
            r#"{ type = "plastic", alpha = 1.5 }"#,
            "path",
            "shape[0].material.alpha: must be 0 (smooth) or between",
        ),
        (
            r#"{ type = "plastic", alpha = 0.2, distribution = "phong" }"#,
            "path",
            "shape[0].material.distribution",
        ),
        (rough, "bdpt", only_path),
        (rough, "mlt", only_path),
        (rough, "sppm", only_path),
    ] {
        let err = build_error(&sphere(material, integrator));
        assert!(err.contains(want), "{material}: want `{want}`, got `{err}`");
        assert!(!err.contains('\n'), "{err}");
    }
    // The same rough plastic builds under the path tracer.
    let desc = brume::scene::parse(&sphere(rough, "path"), std::path::Path::new("m.toml")).unwrap();
    assert!(brume::scene::build(
        &desc,
        std::path::Path::new("m.toml"),
        std::path::Path::new(".")
    )
    .is_ok());
}
