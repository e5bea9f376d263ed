//! Height fog against closed forms computed here in f64: optical depth and
//! transmittance along vertical, oblique and horizontal rays, the distribution
//! of free-flight distances (the tracker's closed-form inversion of the
//! exponential majorant), overlapping fogs, emission–absorption radiance,
//! and the scene entry's errors.
//!
//! Statistical checks use k standard errors with fixed seeds; chi-square tests
//! run at family-wise level ALPHA, Šidák-corrected over CHI2_TEST_COUNT.

mod common;

use brume::error::Error;
use brume::integrator::tracking::{medium_transmittance, FreeFlight, TransmittanceEstimator};
use brume::math::color::Rgb;
use brume::math::{Affine3A, Ray, Vec3};
use brume::medium::{HeightFog, HomogeneousMedium, Medium, PhaseFunction, Region};
use brume::sampling::chi2::IntervalChi2;
use brume::sampling::Sampler;
use common::*;
use std::path::Path;

const ALPHA: f64 = 0.01;
const CHI2_TEST_COUNT: usize = 4;

fn fog(sigma_a: Rgb, sigma_s: Rgb, h0: f32, scale: f32) -> HeightFog {
    HeightFog {
        sigma_a,
        sigma_s,
        emission: Rgb::BLACK,
        phase: PhaseFunction::Isotropic,
        up: Vec3::Y,
        height: h0,
        scale_height: scale,
    }
}

/// ∫0^t σ0·exp(-(y0 + s·dy - h0)/H) ds in f64, written out independently of the crate.
fn tau(sigma0: f64, y0: f64, dy: f64, h0: f64, scale: f64, t: f64) -> f64 {
    let base = (-(y0 - h0) / scale).exp();
    if dy == 0.0 {
        sigma0 * base * t
    } else {
        sigma0 * base * scale / dy * (1.0 - (-dy * t / scale).exp())
    }
}

/// Rays (origin height, unit direction) covering vertical up/down, oblique and horizontal.
fn rays() -> Vec<(&'static str, f32, Vec3)> {
    vec![
        ("vertical up", -5.0, Vec3::Y),
        ("vertical down", 30.0, Vec3::NEG_Y),
        ("oblique up", 1.0, Vec3::new(0.8, 0.6, 0.0)),
        (
            "oblique down",
            25.0,
            Vec3::new(0.6, -0.3, 0.742_462_1).normalize(),
        ),
        ("grazing", 3.0, Vec3::new(1.0, 1e-4, 0.0).normalize()),
        ("horizontal", 3.0, Vec3::X),
    ]
}

/// `n` tracked transmittance estimates along `ray` to `t_max` from one stream of `seed`.
fn tracked(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    estimator: TransmittanceEstimator,
    seed: u64,
    n: usize,
) -> Estimate {
    let mut acc = Accumulator::default();
    let mut sampler = Sampler::from_seed(seed);
    for _ in 0..n {
        acc.add(medium_transmittance(
            medium,
            ray,
            t_max,
            estimator,
            &mut sampler,
        ));
    }
    acc.estimate()
}

#[test]
fn optical_depth_and_transmittance_match_closed_form() {
    let (h0, scale) = (2.0f32, 8.0f32);
    let sigma_a = Rgb::new(0.01, 0.02, 0.0);
    let sigma_s = Rgb::new(0.04, 0.08, 0.3);
    let medium = Medium::HeightFog(fog(sigma_a, sigma_s, h0, scale));
    let sigma_t = sigma_a + sigma_s;
    let mut sampler = Sampler::from_seed(1);
    for (name, y0, d) in rays() {
        let ray = Ray::new(Vec3::new(4.0, y0, -1.0), d);
        for (t0, t1) in [(0.0, 5.0), (0.0, 30.0), (3.0, 60.0)] {
            let got = medium.optical_depth(&ray, t0, t1).expect("closed form");
            let tr = medium_transmittance(
                &medium,
                &Ray::new(ray.at(t0), d),
                t1 - t0,
                TransmittanceEstimator::Auto,
                &mut sampler,
            );
            for c in 0..3 {
                let f = |t| tau(sigma_t[c] as f64, y0 as f64, d.y as f64, h0 as f64, 8.0, t);
                let want = f(t1 as f64) - f(t0 as f64);
                assert!(
                    (got[c] as f64 - want).abs() <= 1e-4 * want + 1e-9,
                    "{name} [{t0}, {t1}] channel {c}: {} vs {want}",
                    got[c]
                );
                let want_tr = (-want).exp();
                assert!(
                    (tr[c] as f64 - want_tr).abs() <= 1e-4 * want_tr + 1e-7,
                    "{name} transmittance channel {c}: {} vs {want_tr}",
                    tr[c]
                );
            }
        }
    }
}

/// ∫0^t σ0·ρ(x(s)) ds in f64 for the truncated density of the module doc:
/// ρ = 0 more than 40 scale heights above h0, e^x in between, e^30 more than
/// 30 scale heights below. Split at the crossings, each piece classified by
/// its midpoint.
fn truncated_tau(sigma0: f64, y0: f64, dy: f64, h0: f64, scale: f64, t: f64) -> f64 {
    let x = |s: f64| -(y0 + s * dy - h0) / scale;
    let mut cuts = vec![0.0, t];
    if dy != 0.0 {
        for y in [h0 + 40.0 * scale, h0 - 30.0 * scale] {
            let s = (y - y0) / dy;
            if s > 0.0 && s < t {
                cuts.push(s);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    let piece = |p: f64, q: f64| {
        let mid = x(0.5 * (p + q));
        if mid < -40.0 {
            0.0
        } else if mid > 30.0 {
            30f64.exp() * (q - p)
        } else if dy == 0.0 {
            mid.exp() * (q - p)
        } else {
            // d/ds e^x(s) = -(dy/H)·e^x(s)
            scale / dy * (x(p).exp() - x(q).exp())
        }
    };
    sigma0 * cuts.windows(2).map(|w| piece(w[0], w[1])).sum::<f64>()
}

/// Rays through the heights where the density is truncated (40 scale heights
/// above h0 it ends, 30 below it stops growing): closed-form optical depth and
/// ratio and residual ratio tracked transmittance against the truncated density. σt0 is tiny so
/// that the capped density e^30·σt0 is of order 1 per metre. The horizontal
/// rays have a direction with y = -0.0, whose slope is +0.0.
#[test]
fn rays_through_the_truncation_heights_match_the_truncated_closed_form() {
    let (h0, scale) = (0.0f32, 1.0f32);
    let sigma_a = Rgb::new(4e-15, 1e-14, 0.0);
    let sigma_s = Rgb::new(1e-14, 1e-14, 3e-14);
    let medium = Medium::HeightFog(fog(sigma_a, sigma_s, h0, scale));
    let sigma_t = sigma_a + sigma_s;
    let cases = [
        // (name, origin height, direction, t_max)
        (
            "up from below the bottom to above the top",
            -35.0f32,
            Vec3::Y,
            80.0f32,
        ),
        (
            "oblique down from above the top",
            45.0,
            Vec3::new(0.6, -0.8, 0.0),
            110.0,
        ),
        (
            "oblique up from the bottom",
            -31.0,
            Vec3::new(0.0, 0.6, 0.8),
            100.0,
        ),
        (
            "horizontal below the bottom",
            -32.0,
            Vec3::new(-0.6, -0.0, -0.8),
            4.0,
        ),
        (
            "horizontal in the slab",
            -28.0,
            Vec3::new(-0.6, -0.0, -0.8),
            4.0,
        ),
        (
            "horizontal above the top",
            41.0,
            Vec3::new(-0.6, -0.0, -0.8),
            4.0,
        ),
    ];
    for (i, (name, y0, d, t_max)) in cases.into_iter().enumerate() {
        let ray = Ray::new(Vec3::new(4.0, y0, -1.0), d);
        let got = medium.optical_depth(&ray, 0.0, t_max).expect("closed form");
        let want: [f64; 3] = std::array::from_fn(|c| {
            truncated_tau(
                sigma_t[c] as f64,
                y0 as f64,
                d.y as f64,
                0.0,
                1.0,
                t_max as f64,
            )
        });
        for c in 0..3 {
            // The closed form is f64 but its result and σt0 are f32: 1e-6 relative.
            assert!(
                (got[c] as f64 - want[c]).abs() <= 1e-6 * want[c],
                "{name} channel {c}: {} vs {}",
                got[c],
                want[c]
            );
        }
        for estimator in [
            TransmittanceEstimator::Ratio,
            TransmittanceEstimator::ResidualRatio,
        ] {
            let est = tracked(&medium, &ray, t_max, estimator, 40 + i as u64, 20_000);
            let what = format!("{name} {estimator:?}");
            assert_estimate(&est, want.map(|w| (-w).exp()), &what);
        }
    }
}

/// A long, nearly level ray going down into the fog: over its 2000 units it
/// sinks 2 units (a third of a scale height), so its majorant grows by 40 %
/// along one segment whose decay rate times length is far above the 1e-4 under
/// which tracking steps a segment as constant. Delta tracking, which needs a
/// true bound, still matches the closed form.
#[test]
fn a_long_shallow_descent_is_tracked_under_a_growing_majorant() {
    let (h0, scale) = (0.0f32, 6.0f32);
    let sigma = Rgb::splat(4e-4);
    let medium = Medium::HeightFog(fog(sigma * 0.25, sigma * 0.75, h0, scale));
    let d = Vec3::new(1.0, -1e-3, 0.0).normalize();
    let (y0, t_max) = (1.0f32, 2000.0f32);
    let ray = Ray::new(Vec3::new(0.0, y0, 0.0), d);
    let depth = tau(
        4e-4,
        y0 as f64,
        d.y as f64,
        h0 as f64,
        scale as f64,
        t_max as f64,
    );
    let est = tracked(
        &medium,
        &ray,
        t_max,
        TransmittanceEstimator::Delta,
        91,
        20_000,
    );
    assert_estimate(
        &est,
        [(-depth).exp(); 3],
        "long shallow descent, delta tracking",
    );
}

/// Ratio and residual ratio tracking over the fog's majorant pieces are unbiased (RGB fog: null collisions occur).
#[test]
fn tracked_transmittance_matches_closed_form() {
    let medium = Medium::HeightFog(fog(
        Rgb::new(0.02, 0.05, 0.0),
        Rgb::new(0.1, 0.1, 0.3),
        0.0,
        6.0,
    ));
    let n = 20_000;
    for (name, y0, d) in rays() {
        let ray = Ray::new(Vec3::new(0.0, y0, 0.0), d);
        let t_max = 25.0;
        let want = medium
            .optical_depth(&ray, 0.0, t_max)
            .expect("closed form")
            .exp_neg();
        for estimator in [
            TransmittanceEstimator::Ratio,
            TransmittanceEstimator::ResidualRatio,
        ] {
            let e = tracked(&medium, &ray, t_max, estimator, 7, n);
            assert_estimate(
                &e,
                [want[0] as f64, want[1] as f64, want[2] as f64],
                &format!("{name} {estimator:?}"),
            );
        }
    }
}

/// Real scattering events sampled by free-flight tracking (albedo-1 grey fog,
/// so every weight stays 1) follow the CDF 1 - exp(-τ(t)).
#[test]
fn free_flight_distances_follow_closed_form_cdf() {
    let cases = [
        // (name, origin height, direction, t_max)
        ("down into fog", 30.0f32, Vec3::new(0.6, -0.8, 0.0), 60.0f32),
        ("up out of fog", -8.0, Vec3::new(0.8, 0.6, 0.0), 80.0),
        ("vertical up", -2.0, Vec3::Y, 60.0),
        ("horizontal", 1.0, Vec3::Z, 40.0),
    ];
    let (sigma0, h0, scale) = (0.15f64, 0.0f64, 5.0f64);
    let n = 50_000;
    for (i, (name, y0, d, t_max)) in cases.into_iter().enumerate() {
        let medium = Medium::HeightFog(fog(Rgb::BLACK, Rgb::splat(0.15), h0 as f32, scale as f32));
        let ray = Ray::new(Vec3::new(1.0, y0, 2.0), d);
        let mut sampler = Sampler::from_seed(100 + i as u64);
        let dy = d.y as f64;
        let tau_t = |t: f64| tau(sigma0, y0 as f64, dy, h0, scale, t);
        let pdf = |t: f32| {
            let t = t as f64;
            let sigma = sigma0 * (-(y0 as f64 + t * dy - h0) / scale).exp();
            (sigma * (-tau_t(t)).exp()) as f32
        };
        let result = IntervalChi2::new(0.0, t_max, n, 1).run(
            |_| match free_flight(std::slice::from_ref(&medium), &ray, t_max, &mut sampler) {
                (FreeFlight::Scatter { t, .. }, beta, _) => {
                    assert!((beta.r - 1.0).abs() < 1e-3, "{beta:?}");
                    Some(t)
                }
                _ => None,
            },
            pdf,
        );
        assert!(result.passes(ALPHA, CHI2_TEST_COUNT), "{name}: {result}");
        // Samples past t_max (reported as invalid) escape with probability T(t_max).
        let escape = (-tau_t(t_max as f64)).exp();
        let expected = n as f64 * escape;
        let sd = (n as f64 * escape * (1.0 - escape)).sqrt();
        assert_within(
            result.invalid_count as f64,
            sd,
            expected,
            1,
            &format!("{name}: escaped count"),
        );
    }
}

/// Spectral tracking through two overlapping absorbing fogs (one chromatic, one
/// nearly uniform with a huge scale height) and a homogeneous sphere:
/// E[weight·1{passed}] = exp(-τ1 - τ2 - τ3).
#[test]
fn overlapping_fogs_add_under_spectral_tracking() {
    let sphere = HomogeneousMedium {
        sigma_a: Rgb::new(0.02, 0.06, 0.01),
        sigma_s: Rgb::BLACK,
        emission: Rgb::BLACK,
        phase: PhaseFunction::Isotropic,
        region: Region::Sphere {
            world_to_local: Affine3A::IDENTITY,
            center: Vec3::new(6.0, 4.0, 0.0),
            radius: 8.0,
        },
    };
    let media = [
        Medium::HeightFog(fog(Rgb::new(0.05, 0.12, 0.3), Rgb::BLACK, 0.0, 4.0)),
        Medium::HeightFog(fog(Rgb::splat(0.03), Rgb::BLACK, 10.0, 1e4)),
        Medium::Homogeneous(sphere),
    ];
    let n = 40_000;
    for (name, y0, d) in rays() {
        let ray = Ray::new(Vec3::new(0.0, y0, 0.0), d);
        let t_max = 20.0;
        let want = media
            .iter()
            .map(|m| m.optical_depth(&ray, 0.0, t_max).unwrap())
            .fold(Rgb::BLACK, |a, b| a + b)
            .exp_neg();
        let mut acc = Accumulator::default();
        let mut sampler = Sampler::from_seed(11);
        for _ in 0..n {
            acc.add(match free_flight(&media, &ray, t_max, &mut sampler) {
                (FreeFlight::Passed, beta, _) => beta,
                _ => Rgb::BLACK,
            });
        }
        let e = acc.estimate();
        assert_estimate(&e, [want[0] as f64, want[1] as f64, want[2] as f64], name);
    }
}

/// An emitting, absorbing height fog in front of a constant sky: L = L_bg·T + Le·(1 - T) per channel.
#[test]
fn emission_absorption_radiance_through_height_fog() {
    let (bg, le) = ([0.2, 0.5, 1.0], [2.0, 1.0, 0.5]);
    let text = SceneText::camera([0.0; 3], [0.0, 0.0, -1.0], [4, 4])
        .environment(bg)
        .medium(&format!(
            "type = \"height_fog\"\nsigma_a = [0.3, 0.1, 0.05]\nemission = {le:?}\nheight = 1.0\nscale_height = 2.0"
        ));
    let scene = scene_from_str(&text.build());
    let medium = &scene.media[0];
    for (name, d) in [
        ("up", Vec3::new(0.0, 1.0, -0.3).normalize()),
        ("oblique", Vec3::new(0.0, 0.2, -1.0).normalize()),
        ("horizontal", Vec3::new(0.0, 0.0, -1.0)),
    ] {
        let ray = Ray::new(Vec3::ZERO, d);
        let t = medium
            .optical_depth(&ray, 0.0, f32::INFINITY)
            .unwrap()
            .exp_neg();
        let e = estimate_ray(&scene, ray, 20_000, 3);
        let want: [f64; 3] =
            std::array::from_fn(|c| bg[c] * t[c] as f64 + le[c] * (1.0 - t[c] as f64));
        assert_estimate(&e, want, name);
    }
}

fn fog_error(entry: &str) -> (String, String) {
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\n[[medium]]\ntype = \"height_fog\"\n{entry}\n"
    );
    let file = Path::new("fog.toml");
    let result = brume::scene::parse(&text, file)
        .and_then(|desc| brume::scene::build(&desc, file, Path::new(".")));
    match result {
        Err(Error::Scene { field, message, .. }) => (field, message),
        Err(e) => panic!("{entry}: unexpected error kind {e}"),
        Ok(_) => panic!("{entry}: accepted"),
    }
}

#[test]
fn bad_height_fog_entries_name_the_field() {
    for (entry, field) in [
        (
            "visibility = 100.0\nscale_height = 0.0",
            "medium[0].scale_height",
        ),
        (
            "visibility = 100.0\nscale_height = -3.0",
            "medium[0].scale_height",
        ),
        (
            "visibility = 100.0\nsigma_t = 0.1\nscale_height = 5.0",
            "medium[0].visibility",
        ),
        ("scale_height = 5.0", "medium[0]"),
        (
            "visibility = 0.0\nscale_height = 5.0",
            "medium[0].visibility",
        ),
        ("visibility = 100.0", "medium[0]"),
        (
            "visibility = 100.0\nscale_height = 5.0\nup = [0.0, 0.0, 0.0]",
            "medium[0].up",
        ),
        (
            "visibility = 100.0\nscale_height = 5.0\nalbedo = 1.5",
            "medium[0].albedo",
        ),
        (
            "visibility = 100.0\nscale_height = 5.0\ndensity = 1.0",
            "medium[0].density",
        ),
    ] {
        let (got, message) = fog_error(entry);
        assert_eq!(got, field, "{entry}: {message}");
    }
}
