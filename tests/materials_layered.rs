//! Plastic (a diffuse base under a smooth dielectric coating, Mitsuba's
//! model) and the thin dielectric sheet: albedos against closed forms whose
//! Fresnel terms and diffuse Fresnel reflectances are computed here in f64,
//! independently of brume's.

mod analytic_support;

use analytic_support::common::{assert_pixels_equal, estimate_pixels};
use analytic_support::lobes::{build_error, directional_albedo as albedo};
use analytic_support::{assert_estimate, estimate, scene_from_str};
use brume::material::layered::{diffuse_fresnel, Plastic};
use brume::material::{Distribution, Material, Shading};
use brume::math::color::Rgb;
use brume::math::Vec3;
use brume::sampling::quadrature::gauss_legendre;

/// Unpolarized Fresnel reflectance, `eta` = far side over near side.
fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// 2 ∫ F μ dμ by a fine plain quadrature (no split at the critical angle).
fn fdr(eta: f64) -> f64 {
    2.0 * gauss_legendre(|mu| fresnel(mu, eta) * mu, 0.0, 1.0, 4000)
}

fn direction(theta_deg: f64) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin() as f32, 0.0, t.cos() as f32)
}

fn plastic(diffuse: Rgb, specular: Rgb, ior: f32, nonlinear: bool) -> Material {
    Material::Plastic(Plastic {
        diffuse,
        specular,
        ior,
        fdr_int: diffuse_fresnel(1.0 / ior),
        nonlinear,
        alpha: 0.0,
        distribution: Distribution::Ggx,
        tables: None,
    })
}

#[test]
fn diffuse_fresnel_matches_quadrature_on_both_sides() {
    for eta in [1.1f64, 1.33, 1.5, 2.4] {
        for e in [eta, 1.0 / eta] {
            let ours = diffuse_fresnel(e as f32) as f64;
            assert!((ours - fdr(e)).abs() < 2e-4, "η {e}: {ours} vs {}", fdr(e));
        }
        // Reciprocity, what makes a white plastic conserve energy.
        let (int, ext) = (fdr(1.0 / eta), fdr(eta));
        assert!((eta * eta * (1.0 - int) - (1.0 - ext)).abs() < 1e-3);
    }
}

#[test]
fn white_plastic_reflects_everything() {
    let mut seed = 1;
    for nonlinear in [false, true] {
        for ior in [1.3f32, 1.5, 2.0] {
            for theta in [0.0, 50.0, 85.0] {
                seed += 1;
                let m = plastic(Rgb::WHITE, Rgb::WHITE, ior, nonlinear);
                let est = albedo(m, direction(theta), seed);
                assert_estimate(
                    &est,
                    [1.0; 3],
                    &format!("η {ior} θ {theta} nonlinear {nonlinear}"),
                );
            }
        }
    }
}

#[test]
fn coloured_plastic_albedo_matches_its_closed_form() {
    // F(θo)·s + (1 − F(θo)) ρ' (1 − F_dr,ext) / η², ρ' with or without the series.
    let (rho, s, eta) = ([0.2f64, 0.5, 0.9], 0.7f64, 1.5f64);
    let (fdr_int, fdr_ext) = (fdr(1.0 / eta), fdr(eta));
    let mut seed = 40;
    for nonlinear in [false, true] {
        for theta in [0.0f64, 60.0, 80.0] {
            seed += 1;
            let f_o = fresnel(theta.to_radians().cos(), eta);
            let expected = rho.map(|r| {
                let r_eff = if nonlinear {
                    r / (1.0 - fdr_int * r)
                } else {
                    r / (1.0 - fdr_int)
                };
                f_o * s + (1.0 - f_o) * r_eff * (1.0 - fdr_ext) / (eta * eta)
            });
            let m = plastic(
                Rgb::new(0.2, 0.5, 0.9),
                Rgb::splat(0.7),
                eta as f32,
                nonlinear,
            );
            let est = albedo(m, direction(theta), seed);
            assert_estimate(&est, expected, &format!("θ {theta} nonlinear {nonlinear}"));
        }
    }
}

#[test]
fn plastic_diffuse_samples_match_eval_and_pdf() {
    let m = plastic(Rgb::new(0.3, 0.6, 0.8), Rgb::splat(0.9), 1.4, true);
    let wo = direction(35.0);
    let sp = Shading::facing(Vec3::Z, wo);
    let mut s = brume::sampling::Sampler::from_seed(5);
    let (mut delta, mut diffuse) = (0, 0);
    for _ in 0..5000 {
        let Some(b) = m.sample(&sp, wo, s.next_2d(), s.next_1d()) else {
            continue;
        };
        if b.is_delta {
            delta += 1;
            assert!((b.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-5);
            continue;
        }
        diffuse += 1;
        let pdf = m.pdf(&sp, wo, b.wi);
        assert!((pdf - b.pdf).abs() < 1e-4 * pdf, "{pdf} vs {}", b.pdf);
        let w = m.eval(&sp, wo, b.wi) / pdf;
        assert!((w - b.weight).max_channel().abs() < 1e-4);
    }
    assert!(
        delta > 0 && diffuse > 0,
        "{delta} specular, {diffuse} diffuse"
    );
}

#[test]
fn thin_sheet_reflects_the_series_of_its_two_faces_and_transmits_straight() {
    let mut seed = 70;
    for ior in [1.33f32, 1.5, 2.4] {
        for theta in [0.0f64, 45.0, 80.0] {
            seed += 1;
            let m = Material::ThinDielectric { ior };
            let wo = direction(theta);
            let sp = Shading::facing(Vec3::Z, wo);
            // R + T R T + T R³ T + …, summed term by term.
            let r = fresnel(theta.to_radians().cos(), ior as f64);
            let t = 1.0 - r;
            let series = r + (0..60).map(|k| t * t * r.powi(2 * k + 1)).sum::<f64>();
            let refl = estimate(100_000, seed, |s| {
                let b = m.sample(&sp, wo, s.next_2d(), s.next_1d()).unwrap();
                assert!(b.is_delta);
                if b.wi.z > 0.0 {
                    b.weight
                } else {
                    // Straight through: the direction is unbent.
                    assert!((b.wi + wo).length() < 1e-6);
                    Rgb::BLACK
                }
            });
            assert_estimate(&refl, [series; 3], &format!("η {ior} θ {theta} reflected"));
            let all = estimate(20_000, seed, |s| {
                m.sample(&sp, wo, s.next_2d(), s.next_1d()).unwrap().weight
            });
            assert_eq!(all.mean, [1.0; 3], "a white sheet loses or gains light");
        }
    }
}

#[test]
fn thin_sheet_and_white_plastic_spheres_in_a_furnace_render_one() {
    for material in [
        r#"{ type = "thin_dielectric", ior = 1.5 }"#,
        r#"{ type = "plastic", diffuse = 1.0, specular = 1.0, ior = 1.5, nonlinear = true }"#,
    ] {
        let scene = scene_from_str(&format!(
            r#"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
resolution = [4, 4]
[integrator]
spp = 256
max_depth = 64
[[shape]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = {material}
[[light]]
type = "environment"
radiance = 1.0
"#
        ));
        let pixels = estimate_pixels(&scene, 256);
        assert_pixels_equal(&pixels, [1.0; 3], material);
    }
}

#[test]
fn bad_keys_of_the_new_materials_name_the_key() {
    let sphere = |material: &str, integrator: &str| {
        analytic_support::SceneText::furnace_view(4)
            .environment(1.0)
            .unit_sphere(material)
            .integrator(&format!("type = \"{integrator}\""))
            .build()
    };
    for (material, integrator, want) in [
        (
            r#"{ type = "conductor", alpha = 0.3, f0 = 0.9, distribution = "beckmann" }"#,
            "path",
            "shape[0].material.multiscatter: energy compensation is tabulated for GGX only",
        ),
        (
            r#"{ type = "dielectric", alpha = 0.3, masking = "separable" }"#,
            "path",
            "shape[0].material.multiscatter: energy compensation is tabulated for correlated masking only",
        ),
        (
            r#"{ type = "conductor", alpha = 0.3, f0 = 0.9, masking = "uncorrelated" }"#,
            "path",
            "shape[0].material.masking",
        ),
        (
            r#"{ type = "dielectric", alpha = 0.3, distribution = "phong" }"#,
            "path",
            "shape[0].material.distribution",
        ),
        (
            r#"{ type = "plastic", diffuse = 1.5 }"#,
            "path",
            "shape[0].material.diffuse",
        ),
        (
            r#"{ type = "plastic", specular = -1.0 }"#,
            "path",
            "shape[0].material.specular",
        ),
        (
            r#"{ type = "thin_dielectric", ior = 0.0 }"#,
            "path",
            "shape[0].material.ior",
        ),
        (
            r#"{ type = "plastic" }"#,
            "bdpt",
            "shape[0].material: `plastic` is supported by the path tracer only",
        ),
        (
            r#"{ type = "thin_dielectric" }"#,
            "sppm",
            "shape[0].material: `thin_dielectric` is supported by the path tracer only",
        ),
    ] {
        let err = build_error(&sphere(material, integrator));
        assert!(err.contains(want), "{material}: want `{want}`, got `{err}`");
        assert!(!err.contains('\n'), "{err}");
    }
}

/// Normal-incidence transmittance 1 − R of a thin sheet of index 1.5, with
/// R = 2R₀ / (1 + R₀) for the two interfaces and their inner reflections.
fn sheet_transmittance() -> f64 {
    let r0 = ((1.5f64 - 1.0) / (1.5 + 1.0)).powi(2);
    1.0 - 2.0 * r0 / (1.0 + r0)
}

/// A 4×4 view down −z at a 2 m thin sheet (index 1.5) at z = `sheet_z`, a
/// 2 m quad at z = 0 behind it with the keys `behind`, and `rest`.
fn through_a_sheet(
    fov: f32,
    max_depth: u32,
    sheet_z: f32,
    behind: &str,
    rest: &str,
) -> brume::integrator::Scene {
    let quad = |z: f32| {
        format!("[[shape]]\ntype = \"quad\"\ncenter = [0.0, 0.0, {z:?}]\nnormal = [0.0, 0.0, 1.0]\nsize = [2.0, 2.0]\n")
    };
    scene_from_str(&format!(
        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = {fov:?}\nresolution = [4, 4]\n\
         [integrator]\nmax_depth = {max_depth}\n{}material = {{ type = \"thin_dielectric\", ior = 1.5 }}\n{}{behind}\n{rest}",
        quad(sheet_z),
        quad(0.0),
    ))
}

/// The straight transmission through a thin sheet is not a scattering event
/// (Mitsuba's volpath counts it as index-matched): at `max_depth = 0` the eye
/// still sees an emitter behind the sheet, dimmed by the sheet's 1 − R.
/// Counted as an event, it was black.
#[test]
fn a_thin_sheets_transmission_is_no_scattering_event() {
    let scene = through_a_sheet(1.0, 0, 1.0, "emission = 2.0", "");
    let pixels = estimate_pixels(&scene, 4096);
    assert_pixels_equal(
        &pixels,
        [2.0 * sheet_transmittance(); 3],
        "an emitter behind a thin sheet, max_depth 0",
    );
}

/// ... and a depth limit still lets the path scatter behind the sheet: at
/// `max_depth = 1` a diffuse wall seen through a sheet is lit by a point
/// light in front of it, (1 − R)·ρ/π·I/d². Counted as an event, the
/// crossing would use up the path's only scattering event and leave it black.
#[test]
fn a_wall_behind_a_thin_sheet_is_lit_at_max_depth_one() {
    let light = "[[light]]\ntype = \"point\"\nposition = [0.0, 0.0, 1.0]\nintensity = 3.0\n";
    let wall = r#"material = { type = "diffuse", albedo = 0.5 }"#;
    let scene = through_a_sheet(0.1, 1, 2.0, wall, light);
    let lit = sheet_transmittance() * 0.5 / std::f64::consts::PI * 3.0;
    let pixels = estimate_pixels(&scene, 4096);
    assert_pixels_equal(&pixels, [lit; 3], "a wall behind a thin sheet, max_depth 1");
}
