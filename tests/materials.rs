//! Dielectric and GGX materials: chi-square of every lobe against its pdf,
//! energy against independent quadrature, and closed-form furnace renders.

mod analytic_support;

use analytic_support::common::{assert_pixels_equal, estimate_pixels, scene_from_str};
use analytic_support::ggx::ggx_white_albedo;
use analytic_support::lobes::{self, direction};
use analytic_support::SceneText;
use analytic_support::{assert_estimate, estimate, estimate_li, k_sigma};
use brume::material::{ConductorFresnel, Distribution, Material, Shading};
use brume::math::color::Rgb;
use brume::math::{Ray, Vec3};
use brume::sampling::chi2::Chi2Result;

const ALPHA: f64 = 0.01;
/// 3 conductor roughnesses × 3 angles + 2 dielectric roughnesses × 2 angles × 2 sides × 2 iors.
const CHI2_TEST_COUNT: usize = 9 + 16;

/// Salt of the lobe-choice stream of [`chi2_of`].
const LOBE_SALT: u64 = 0xABCD;

fn chi2_of(m: Material, wo: Vec3, front: bool, seed: u64) -> Chi2Result {
    lobes::chi2_of(m, wo, front, (seed, LOBE_SALT))
}

fn assert_chi2(name: &str, r: &Chi2Result) {
    assert!(r.passes(ALPHA, CHI2_TEST_COUNT), "{name}: {r}");
}

#[test]
fn rough_conductor_sampling_follows_its_pdf() {
    let fresnel = ConductorFresnel::Complex {
        eta: Rgb::new(0.2, 0.9, 1.1),
        k: Rgb::new(3.9, 2.4, 2.2),
    };
    for (i, alpha) in [0.1, 0.4, 1.0].into_iter().enumerate() {
        for (j, theta) in [0.0, 40.0, 80.0].into_iter().enumerate() {
            let m = Material::Conductor {
                alpha,
                fresnel,
                distribution: Distribution::Ggx,
                multiscatter: false,
            };
            let r = chi2_of(m, direction(theta), true, (10 * i + j) as u64);
            assert_chi2(&format!("conductor α {alpha} θ {theta}"), &r);
        }
    }
}

#[test]
fn rough_dielectric_sampling_follows_its_pdf_on_both_sides() {
    let mut seed = 100;
    for alpha in [0.15, 0.6] {
        for theta in [30.0, 70.0] {
            for front in [true, false] {
                for ior in [1.5, 1.1] {
                    seed += 1;
                    let m = Material::Dielectric {
                        ior,
                        alpha,
                        distribution: Distribution::Ggx,
                        multiscatter: false,
                    };
                    let wo = if front {
                        direction(theta)
                    } else {
                        -direction(theta)
                    };
                    let r = chi2_of(m, wo, front, seed);
                    assert_chi2(
                        &format!("dielectric α {alpha} θ {theta} front {front} ior {ior}"),
                        &r,
                    );
                }
            }
        }
    }
}

#[test]
fn white_rough_conductor_reflects_its_single_scattering_albedo() {
    for alpha in [0.2f64, 0.5, 1.0] {
        for theta_deg in [0.0f64, 45.0, 75.0] {
            let theta = theta_deg.to_radians();
            let reference = ggx_white_albedo(alpha, theta, 96);
            // The quadrature has converged far below the Monte Carlo error.
            assert!((reference - ggx_white_albedo(alpha, theta, 48)).abs() < 1e-5);
            assert!(
                reference <= 1.0 + 1e-6,
                "α {alpha} θ {theta_deg}: {reference}"
            );
            let m = Material::Conductor {
                alpha: alpha as f32,
                fresnel: ConductorFresnel::Schlick { f0: Rgb::WHITE },
                distribution: Distribution::Ggx,
                multiscatter: false,
            };
            let wo = direction(theta_deg as f32);
            let sp = Shading::facing(Vec3::Z, wo);
            let est = estimate(200_000, 7, |s| {
                m.sample(&sp, wo, s.next_2d(), s.next_1d())
                    .map_or(Rgb::BLACK, |b| b.weight)
            });
            assert!(
                est.mean[0] <= 1.0,
                "α {alpha} θ {theta_deg}: {}",
                est.mean[0]
            );
            assert_estimate(
                &est,
                [reference; 3],
                &format!("albedo α {alpha} θ {theta_deg}"),
            );
        }
    }
    // Rough surfaces lose energy to masking at grazing angles: the test can tell.
    assert!(ggx_white_albedo(1.0, 75f64.to_radians(), 48) < 0.9);
}

#[test]
fn rough_dielectric_conserves_energy_and_nearly_smooth_reflects_fresnel() {
    for (alpha, theta, front) in [
        (0.3f32, 20.0f32, true),
        (0.8, 60.0, true),
        (0.3, 50.0, false),
    ] {
        let m = Material::Dielectric {
            ior: 1.5,
            alpha,
            distribution: Distribution::Ggx,
            multiscatter: false,
        };
        let eta: f32 = if front { 1.5 } else { 1.0 / 1.5 };
        let wo = if front {
            direction(theta)
        } else {
            -direction(theta)
        };
        let normal = if front { Vec3::Z } else { -Vec3::Z };
        let sp = Shading::facing(normal, wo);
        // Importance transport: undo the radiance compression η² of transmission.
        let est = estimate(100_000, 11, |s| {
            m.sample(&sp, wo, s.next_2d(), s.next_1d())
                .map_or(Rgb::BLACK, |b| {
                    let through = b.wi.dot(sp.n) < 0.0;
                    b.weight * if through { eta * eta } else { 1.0 }
                })
        });
        assert!(
            est.mean[0] <= 1.0 + k_sigma(1) * est.std_error[0],
            "α {alpha} θ {theta}: {} ± {}",
            est.mean[0],
            est.std_error[0]
        );
    }
    // A nearly smooth surface reflects the Fresnel fraction.
    let m = Material::Dielectric {
        ior: 1.5,
        alpha: 0.002,
        distribution: Distribution::Ggx,
        multiscatter: false,
    };
    for theta in [0.0f32, 45.0, 80.0] {
        let wo = direction(theta);
        let sp = Shading::facing(Vec3::Z, wo);
        let est = estimate(100_000, 12, |s| {
            m.sample(&sp, wo, s.next_2d(), s.next_1d())
                .filter(|b| b.wi.z > 0.0)
                .map_or(Rgb::BLACK, |b| b.weight)
        });
        let f = brume::material::fresnel::dielectric(theta.to_radians().cos(), 1.5) as f64;
        assert!(
            // 2e-3 f: α = 0.002 is nearly, not exactly, the smooth interface.
            (est.mean[0] - f).abs() < k_sigma(3) * est.std_error[0] + 2e-3 * f,
            "θ {theta}: {} vs {f}",
            est.mean[0]
        );
    }
}

/// A sphere of `material` in a uniform environment of radiance 1.
fn furnace_scene(material: &str) -> String {
    SceneText::furnace_view(10)
        .depths(1000, 1000)
        .environment(1.0)
        .unit_sphere(material)
        .build()
}

#[test]
fn glass_sphere_furnace_renders_one_everywhere() {
    for ior in [1.5, 2.4] {
        let scene = scene_from_str(&furnace_scene(&format!(
            "{{ type = \"dielectric\", ior = {ior} }}"
        )));
        let pixels = estimate_pixels(&scene, 64);
        assert_pixels_equal(&pixels, [1.0; 3], &format!("glass furnace ior {ior}"));
    }
}

#[test]
fn radiance_inside_a_glass_furnace_is_eta_squared_times_outside() {
    // L/η² is invariant along a path through smooth interfaces, so in a
    // furnace of radiance 1 the radiance inside glass of index η is η².
    let scene = scene_from_str(&furnace_scene("{ type = \"dielectric\", ior = 1.5 }"));
    for dir in [Vec3::X, Vec3::new(0.3, -0.4, 0.5).normalize()] {
        let ray = Ray::new(Vec3::new(0.1, 0.2, 0.0), dir);
        let est = estimate_li(&scene, ray, 2000, 5);
        assert_estimate(&est, [2.25; 3], &format!("inside glass along {dir}"));
    }
}

#[test]
fn white_rough_conductor_sphere_shows_its_albedo_through_nee_and_mis() {
    // A convex sphere: every path leaves after one bounce, so the radiance
    // seen at a point is the albedo E(θo), reached by light sampling and BSDF
    // sampling combined by MIS.
    let alpha = 0.5;
    let scene = scene_from_str(&furnace_scene(&format!(
        "{{ type = \"conductor\", alpha = {alpha}, f0 = 1.0, multiscatter = false }}"
    )));
    for b in [0.0f32, 0.6, 0.9] {
        let ray = Ray::new(Vec3::new(b, 0.0, 4.0), -Vec3::Z);
        let theta_o = (b as f64).asin();
        let reference = ggx_white_albedo(alpha, theta_o, 96);
        let est = estimate_li(&scene, ray, 100_000, 21);
        assert_estimate(&est, [reference; 3], &format!("sphere at b = {b}"));
    }
}

#[test]
fn bad_material_keys_name_the_key() {
    // Without compensation any index is fine.
    let ok = "{ type = \"dielectric\", alpha = 0.3, ior = 4.0, multiscatter = false }";
    let desc = brume::scene::parse(&furnace_scene(ok), std::path::Path::new("m.toml")).unwrap();
    brume::scene::build(
        &desc,
        std::path::Path::new("m.toml"),
        std::path::Path::new("."),
    )
    .unwrap();
    let file = std::path::Path::new("mat.toml");
    for (material, key) in [
        (
            "{ type = \"dielectric\", ior = -1.0 }",
            "shape[0].material.ior",
        ),
        (
            "{ type = \"dielectric\", alpha = 0.0001 }",
            "shape[0].material.alpha",
        ),
        (
            "{ type = \"conductor\", alpha = 2.0, f0 = 0.9 }",
            "shape[0].material.alpha",
        ),
        ("{ type = \"conductor\" }", "shape[0].material"),
        ("{ type = \"conductor\", eta = 0.2 }", "shape[0].material.k"),
        (
            "{ type = \"conductor\", eta = 0.2, k = 3.0, f0 = 0.5 }",
            "shape[0].material.f0",
        ),
        ("{ type = \"conductor\", f0 = 1.5 }", "shape[0].material.f0"),
        (
            "{ type = \"conductor\", alpha = 0.3, f0 = 0.9, multiscatter = \"yes\" }",
            "shape[0].material.multiscatter: expected true or false",
        ),
        (
            "{ type = \"dielectric\", alpha = 0.3, ior = 4.0 }",
            "shape[0].material.ior: 4 is outside 1/3..3, where the energy compensation",
        ),
        (
            "{ type = \"mirror\" }\ninterior = { type = \"homogeneous\", sigma_t = 1.0 }",
            "shape[0].material: a shape with an interior needs a dielectric material",
        ),
    ] {
        let err = match brume::scene::parse(&furnace_scene(material), file) {
            Ok(desc) => brume::scene::build(&desc, file, std::path::Path::new("."))
                .err()
                .unwrap_or_else(|| panic!("{material} accepted"))
                .to_string(),
            Err(e) => e.to_string(),
        };
        assert!(err.contains(key), "{material}: {err}");
    }
}
