//! Energy-compensated rough materials (Kulla & Conty 2017, `multiscatter`):
//! the compensation returns exactly the energy the albedo table says the
//! single-scattering lobe loses, white furnaces stay at 1, the table agrees
//! with independent estimates, the compensated sampling follows its pdf
//! (chi-square) and the compensated BSDFs are reciprocal.

mod analytic_support;

use analytic_support::common::scene_from_str;
use analytic_support::ggx::ggx_white_albedo;
use analytic_support::{
    assert_estimate, assert_same, assert_within, estimate, estimate_li, k_sigma, Estimate,
    SceneText,
};
use brume::material::albedo::{self, Side};
use brume::material::albedo_estimate::{CONDUCTOR_STRATA, DIELECTRIC_STRATA};
use brume::material::{ConductorFresnel, Distribution, Material, Shading};
use brume::math::color::Rgb;
use brume::math::{Ray, Vec3};
use brume::sampling::chi2::SphereChi2;
use brume::sampling::Sampler;
use std::cell::RefCell;

const IOR: f32 = 1.5;

fn direction(theta_deg: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin(), 0.0, t.cos())
}

fn white_conductor(alpha: f32, multiscatter: bool) -> Material {
    Material::Conductor {
        alpha,
        fresnel: ConductorFresnel::Schlick { f0: Rgb::WHITE },
        distribution: Distribution::Ggx,
        multiscatter,
    }
}

fn glass(alpha: f32, multiscatter: bool) -> Material {
    Material::Dielectric {
        ior: IOR,
        alpha,
        distribution: Distribution::Ggx,
        multiscatter,
    }
}

/// The energy `m` sends on from the direction at `theta_deg` on the side
/// `front` of a surface with normal +z (transmission counted without the
/// radiance scaling by η²), from `n` samples of its sampler.
fn energy(m: Material, theta_deg: f32, front: bool, n: usize, seed: u64) -> Estimate {
    let normal = if front { Vec3::Z } else { -Vec3::Z };
    let wo = direction(theta_deg);
    let sp = Shading::facing(normal, wo);
    let eta = match m {
        Material::Dielectric { ior, .. } if front => ior,
        Material::Dielectric { ior, .. } => 1.0 / ior,
        _ => 1.0,
    };
    estimate(n, seed, |s| {
        m.sample(&sp, wo, s.next_2d(), s.next_1d())
            .map_or(Rgb::BLACK, |b| {
                let through = b.wi.dot(sp.n) < 0.0;
                b.weight * if through { eta * eta } else { 1.0 }
            })
    })
}

/// An estimate shifted by a constant per channel.
fn minus(e: Estimate, c: [f64; 3]) -> Estimate {
    Estimate {
        mean: [e.mean[0] - c[0], e.mean[1] - c[1], e.mean[2] - c[2]],
        ..e
    }
}

/// The table's albedo of the single-scattering lobe of `m` at `theta_deg` on side `front`.
fn table_albedo(m: Material, theta_deg: f32, front: bool) -> f64 {
    let mu = theta_deg.to_radians().cos();
    match m {
        Material::Conductor { alpha, .. } => albedo::conductor(mu, alpha) as f64,
        Material::Dielectric { alpha, .. } => {
            let side = if front { Side::Enter } else { Side::Leave };
            albedo::dielectric(side, IOR, mu, alpha) as f64
        }
        _ => unreachable!(),
    }
}

/// With compensation, each lobe sends on what the single-scattering lobe
/// does plus the energy the table says it loses, 1 − E(μo); off the grid
/// nodes too (α 0.63, 0.37; θ 50°), so interpolation is covered.
#[test]
fn compensation_returns_exactly_the_energy_the_table_misses() {
    let mut seed = 0;
    for alpha in [0.2f32, 0.37, 0.5, 0.63, 1.0] {
        for theta in [10.0f32, 50.0, 80.0] {
            let cases = [
                (
                    white_conductor(alpha, false),
                    white_conductor(alpha, true),
                    true,
                ),
                (glass(alpha, false), glass(alpha, true), true),
                (glass(alpha, false), glass(alpha, true), false),
            ];
            for (single, compensated, front) in cases {
                seed += 2;
                let what = format!("{compensated:?} θ {theta} front {front}");
                let ss = energy(single, theta, front, 100_000, seed);
                let ms = energy(compensated, theta, front, 100_000, seed + 1);
                let loss = 1.0 - table_albedo(single, theta, front);
                assert_same(&minus(ms, [loss; 3]), &ss, &what);
                let k = k_sigma(1);
                assert!(
                    ms.mean[0] + k * ms.std_error[0] >= 0.98,
                    "{what}: {} ± {}",
                    ms.mean[0],
                    ms.std_error[0]
                );
            }
        }
    }
}

/// A coloured conductor's compensation is tinted by F_avg² E_avg / (1 −
/// F_avg (1 − E_avg)), with Schlick's F_avg = F0 + (1 − F0)/21.
#[test]
fn coloured_conductor_compensation_has_the_fresnel_tint() {
    let f0 = [0.9f64, 0.5, 0.1];
    let fresnel = ConductorFresnel::Schlick {
        f0: Rgb::new(f0[0] as f32, f0[1] as f32, f0[2] as f32),
    };
    let mut seed = 300;
    for alpha in [0.3f32, 0.8] {
        for theta in [20.0f32, 70.0] {
            let m = |multiscatter| Material::Conductor {
                alpha,
                fresnel,
                distribution: Distribution::Ggx,
                multiscatter,
            };
            seed += 2;
            let ss = energy(m(false), theta, true, 100_000, seed);
            let ms = energy(m(true), theta, true, 100_000, seed + 1);
            let loss = 1.0 - table_albedo(m(false), theta, true);
            let e_avg = albedo::conductor_average(alpha) as f64;
            let tint = f0.map(|f0| {
                let f_avg = f0 + (1.0 - f0) / 21.0;
                f_avg * f_avg * e_avg / (1.0 - f_avg * (1.0 - e_avg))
            });
            let added = tint.map(|t| t * loss);
            assert_same(&minus(ms, added), &ss, &format!("α {alpha} θ {theta}"));
        }
    }
}

/// The table's nodes: the conductor's against an independent quadrature,
/// the dielectric's against independent plain Monte Carlo estimates, within
/// the table's own standard error (its jittered strata have at most the
/// variance of as many independent samples) and the estimate's.
#[test]
fn table_nodes_match_independent_estimates_of_the_single_scattering_albedo() {
    let node_theta = |i: usize| albedo::mu_node(i).acos().to_degrees();
    for (i, j) in [(31, 6), (20, 15), (8, 31), (3, 22)] {
        let (theta, alpha) = (node_theta(i), albedo::alpha_node(j));
        let table = table_albedo(white_conductor(alpha, false), theta, true);
        let reference = ggx_white_albedo(alpha as f64, (theta as f64).to_radians(), 96);
        let e = energy(
            white_conductor(alpha, false),
            theta,
            true,
            20_000,
            90 + i as u64,
        );
        let table_se = e.std_error[0] * (e.n as f64).sqrt() / CONDUCTOR_STRATA as f64;
        assert_within(
            table,
            table_se,
            reference,
            1,
            &format!("conductor α {alpha} θ {theta}"),
        );
        for front in [true, false] {
            let m = glass(alpha, false);
            let table = table_albedo(m, theta, front);
            let e = energy(m, theta, front, 100_000, 70 + i as u64);
            let table_se = e.std_error[0] * (e.n as f64).sqrt() / DIELECTRIC_STRATA as f64;
            let se = e.std_error[0].hypot(table_se);
            let what = format!("glass η {IOR} α {alpha} θ {theta} front {front}");
            assert_within(e.mean[0], se, table, 1, &what);
        }
    }
}

/// A unit sphere of `material` in a uniform environment of radiance 1, seen along +z.
fn furnace(material: &str) -> brume::integrator::Scene {
    scene_from_str(
        &SceneText::furnace_view(8)
            .depths(1000, 1000)
            .environment(1.0)
            .unit_sphere(material)
            .build(),
    )
}

fn ray_at(b: f32) -> Ray {
    Ray::new(Vec3::new(b, 0.0, 4.0), -Vec3::Z)
}

/// A convex white conductor: every path leaves after one bounce, so the
/// radiance seen is the lobe's albedo at θo, E(μo) without compensation and
/// E(μo) + 1 − E_table(μo) (≈ 1) with it, through light and BSDF sampling.
#[test]
fn white_rough_conductor_furnace_sphere() {
    for alpha in [0.2f32, 0.5, 1.0] {
        let text = |ms: bool| {
            format!("{{ type = \"conductor\", alpha = {alpha}, f0 = 1.0, multiscatter = {ms} }}")
        };
        let (single, compensated) = (furnace(&text(false)), furnace(&text(true)));
        for b in [0.0f32, 0.6, 0.9] {
            let theta = b.asin().to_degrees();
            let e = ggx_white_albedo(alpha as f64, b.asin() as f64, 96);
            let table = table_albedo(white_conductor(alpha, true), theta, true);
            let what = format!("α {alpha} b {b}");
            let est = estimate_li(&single, ray_at(b), 40_000, 31);
            assert_estimate(&est, [e; 3], &format!("single scattering {what}"));
            let est = estimate_li(&compensated, ray_at(b), 40_000, 32);
            let want = e + 1.0 - table;
            assert!(want >= 0.98, "{what}: {want}");
            assert_estimate(&est, [want; 3], &format!("compensated {what}"));
        }
    }
}

/// Rough glass: paths bounce inside, so the furnace tests the compensation
/// of both sides together; without it the sphere visibly darkens.
#[test]
fn rough_glass_furnace_sphere_keeps_its_energy_with_compensation() {
    let k = k_sigma(1);
    for alpha in [0.2f32, 0.5, 1.0] {
        let text = |ms: bool| {
            format!(
                "{{ type = \"dielectric\", ior = {IOR}, alpha = {alpha}, multiscatter = {ms} }}"
            )
        };
        let (single, compensated) = (furnace(&text(false)), furnace(&text(true)));
        for b in [0.0f32, 0.5, 0.85] {
            let what = format!("rough glass α {alpha} b {b}");
            let on = estimate_li(&compensated, ray_at(b), 20_000, 41);
            let (m, se) = (on.mean[0], on.std_error[0]);
            eprintln!("{what}: compensated {m:.4} ± {se:.4}");
            assert!(
                m + k * se >= 0.98 && m - k * se <= 1.02,
                "{what}: {m} ± {se}"
            );
            let off = estimate_li(&single, ray_at(b), 20_000, 42);
            let (m, se) = (off.mean[0], off.std_error[0]);
            eprintln!("{what}: single scattering {m:.4} ± {se:.4}");
            if alpha >= 0.5 {
                assert!(m + k * se < 0.98, "{what}: loses no energy? {m} ± {se}");
            }
        }
    }
}

/// Chi-square of the compensated sampling against its pdf.
#[test]
fn compensated_sampling_follows_its_pdf() {
    let cases = [
        (white_conductor(0.3, true), 0.0f32, true),
        (white_conductor(1.0, true), 60.0, true),
        (
            Material::Conductor {
                alpha: 0.7,
                fresnel: ConductorFresnel::Complex {
                    eta: Rgb::new(0.2, 0.9, 1.1),
                    k: Rgb::new(3.9, 2.4, 2.2),
                },
                distribution: Distribution::Ggx,
                multiscatter: true,
            },
            85.0,
            true,
        ),
        (glass(0.3, true), 30.0, true),
        (glass(0.9, true), 75.0, true),
        (glass(0.3, true), 30.0, false),
        (glass(0.9, true), 75.0, false),
    ];
    for (seed, (m, theta, front)) in cases.into_iter().enumerate() {
        let normal = if front { Vec3::Z } else { -Vec3::Z };
        let wo = direction(theta) * if front { 1.0 } else { -1.0 };
        let sp = Shading::facing(normal, wo);
        let lobe = RefCell::new(Sampler::from_seed(seed as u64 ^ 0x5EED));
        let mut test = SphereChi2::new(200_000, 500 + seed as u64);
        test.cos_theta_bins = 20;
        let r = test.run(
            |u| {
                let u_lobe = lobe.borrow_mut().next_1d();
                m.sample(&sp, wo, u, u_lobe).map(|s| s.wi)
            },
            |d| m.pdf(&sp, wo, d),
        );
        assert!(
            r.passes(0.01, cases.len()),
            "{m:?} θ {theta} front {front}: {r}"
        );
    }
}

/// f(wo, wi) / η_wo² = f(wi, wo) / η_wi² (Veach's reciprocity of the
/// radiance BSDF), for the compensated conductor and dielectric.
#[test]
fn compensated_bsdfs_are_reciprocal() {
    let normal = Vec3::new(0.1, 0.3, 1.0).normalize();
    let mut s = Sampler::from_seed(77);
    for m in [
        white_conductor(0.6, true),
        glass(0.4, true),
        glass(0.9, true),
    ] {
        let mut checked = 0;
        for _ in 0..5000 {
            let wo = brume::sampling::warp::square_to_uniform_sphere(s.next_2d());
            let wi = brume::sampling::warp::square_to_uniform_sphere(s.next_2d());
            let index = |w: Vec3| match m {
                Material::Dielectric { .. } if w.dot(normal) < 0.0 => IOR,
                _ => 1.0,
            };
            let f = |a: Vec3, b: Vec3| {
                let v = m.eval(&Shading::facing(normal, a), a, b);
                v.r / b.dot(normal).abs() / (index(a) * index(a))
            };
            let (forward, backward) = (f(wo, wi), f(wi, wo));
            if forward == 0.0 && backward == 0.0 {
                continue;
            }
            let scale = forward.abs().max(backward.abs());
            assert!(
                (forward - backward).abs() <= 2e-3 * scale,
                "{m:?}: {forward} vs {backward} for {wo} {wi}"
            );
            checked += 1;
        }
        assert!(checked > 1000, "{m:?}: {checked}");
    }
}
