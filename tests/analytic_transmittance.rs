//! Analytic-media suite, transmittance: every estimator against T = exp(-σt d)
//! in homogeneous media, and the variance law of ratio tracking.
//!
//! d is the length of ray inside the medium, computed here from points the
//! test chose on the region's boundary (not by the renderer's intersection
//! code), so the intersection and the estimators are checked together.

mod analytic_support;

use analytic_support::*;
use brume::integrator::tracking::{
    medium_transmittance, ratio_tracking_scaled_majorant, FreeFlight, Tracker,
    TransmittanceEstimator,
};
use brume::math::color::Rgb;
use brume::math::{Affine3A, Bounds3, Quat, Ray, Vec3};
use brume::medium::{HomogeneousMedium, Medium, PhaseFunction, Region};

/// A ray through a medium and the length of it inside the medium.
struct Case {
    name: &'static str,
    medium: Medium,
    ray: Ray,
    t_max: f32,
    /// Length of `[0, t_max)` inside the region.
    inside: f64,
    sigma_t: [f64; 3],
}

fn homogeneous(sigma_t: [f64; 3], region: Region) -> Medium {
    // Split σt into absorption and scattering: estimators must only see the sum.
    let t = Rgb::new(sigma_t[0] as f32, sigma_t[1] as f32, sigma_t[2] as f32);
    Medium::Homogeneous(HomogeneousMedium {
        sigma_a: t * 0.3,
        sigma_s: t * 0.7,
        emission: Rgb::BLACK,
        phase: PhaseFunction::Isotropic,
        region,
    })
}

fn unit_box(to_world: Affine3A) -> Region {
    Region::Box {
        world_to_local: to_world.inverse(),
        local: Bounds3::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
    }
}

/// A ray that enters a convex region at `entry` and leaves at `exit`, starting `before` ahead of `entry`.
fn chord(entry: Vec3, exit: Vec3, before: f32) -> (Ray, f64) {
    let dir = (exit - entry).normalize();
    let d = (exit.as_dvec3() - entry.as_dvec3()).length();
    (Ray::new(entry - dir * before, dir), d)
}

fn cases() -> Vec<Case> {
    let grey = |s: f64| [s; 3];
    let chroma = [0.4, 1.1, 2.5];
    let mut out = vec![
        Case {
            name: "global medium, grey",
            medium: homogeneous(grey(0.5), Region::Everywhere),
            ray: Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.6, 0.0, -0.8)),
            t_max: 3.0,
            inside: 3.0,
            sigma_t: grey(0.5),
        },
        Case {
            name: "global medium, chromatic",
            medium: homogeneous(chroma, Region::Everywhere),
            ray: Ray::new(Vec3::ZERO, Vec3::Y),
            t_max: 1.5,
            inside: 1.5,
            sigma_t: chroma,
        },
        Case {
            name: "box, straight through, grey",
            medium: homogeneous(grey(1.3), unit_box(Affine3A::IDENTITY)),
            ray: Ray::new(Vec3::new(-3.0, 0.2, 0.1), Vec3::X),
            t_max: f32::INFINITY,
            inside: 2.0,
            sigma_t: grey(1.3),
        },
        Case {
            name: "box, ray starting inside, chromatic",
            medium: homogeneous(chroma, unit_box(Affine3A::IDENTITY)),
            ray: Ray::new(Vec3::new(0.25, 0.0, 0.0), Vec3::X),
            t_max: f32::INFINITY,
            inside: 0.75,
            sigma_t: chroma,
        },
        Case {
            name: "box, ray ending inside (t_max), grey",
            medium: homogeneous(grey(2.0), unit_box(Affine3A::IDENTITY)),
            ray: Ray::new(Vec3::new(0.0, -3.0, 0.3), Vec3::Y),
            t_max: 2.6,
            inside: 0.6,
            sigma_t: grey(2.0),
        },
    ];
    let (ray, d) = chord(Vec3::new(-1.0, -0.5, 0.2), Vec3::new(0.3, 1.0, -0.4), 2.0);
    out.push(Case {
        name: "box, oblique, grey",
        medium: homogeneous(grey(0.9), unit_box(Affine3A::IDENTITY)),
        ray,
        t_max: f32::INFINITY,
        inside: d,
        sigma_t: grey(0.9),
    });
    // Non-uniform scale, rotation, translation: the segment between two
    // boundary points of the local box maps to the world chord.
    let to_world = Affine3A::from_scale_rotation_translation(
        Vec3::new(2.0, 0.5, 1.0),
        Quat::from_rotation_z(-0.3) * Quat::from_rotation_y(0.9) * Quat::from_rotation_x(0.4),
        Vec3::new(3.0, -1.0, 2.0),
    );
    let (ray, d) = chord(
        to_world.transform_point3(Vec3::new(-1.0, 0.3, -0.2)),
        to_world.transform_point3(Vec3::new(0.5, -0.4, 1.0)),
        1.5,
    );
    out.push(Case {
        name: "transformed box, oblique, chromatic",
        medium: homogeneous(chroma, unit_box(to_world)),
        ray,
        t_max: f32::INFINITY,
        inside: d,
        sigma_t: chroma,
    });
    // Unit sphere scaled by 2, rotated, centred at c: a ray at distance h from c has chord 2√(4 - h²).
    let c = Vec3::new(5.0, 1.0, 0.0);
    let sphere = Region::Sphere {
        world_to_local: Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            Quat::from_rotation_z(0.7),
            c,
        )
        .inverse(),
        center: Vec3::ZERO,
        radius: 1.0,
    };
    let h = 1.2f64;
    out.push(Case {
        name: "transformed sphere, grey",
        medium: homogeneous(grey(0.7), sphere),
        ray: Ray::new(c + Vec3::new(-6.0, h as f32, 0.0), Vec3::X),
        t_max: f32::INFINITY,
        inside: 2.0 * (4.0 - h * h).sqrt(),
        sigma_t: grey(0.7),
    });
    out.push(Case {
        name: "transformed sphere, ray ending at the centre, chromatic",
        medium: homogeneous(chroma, sphere),
        ray: Ray::new(c + Vec3::new(0.0, 0.0, 6.0), -Vec3::Z),
        t_max: 6.0,
        inside: 2.0,
        sigma_t: chroma,
    });
    out
}

fn closed_form(case: &Case) -> [f64; 3] {
    per_channel(|c| (-case.sigma_t[c] * case.inside).exp())
}

const N: usize = 50_000;

/// `Medium::optical_depth` equals σt·d (also from a start parameter inside the chord).
#[test]
fn optical_depth_matches_chord_length() {
    for case in cases() {
        let tau = case
            .medium
            .optical_depth(&case.ray, 0.0, case.t_max)
            .unwrap();
        for c in 0..3 {
            let expected = case.sigma_t[c] * case.inside;
            assert!(
                (tau[c] as f64 - expected).abs() <= 1e-5 * expected.max(1.0),
                "{}: τ = {} vs σt d = {expected}",
                case.name,
                tau[c]
            );
        }
    }
    // Starting half way along a known chord.
    let medium = homogeneous([1.0; 3], unit_box(Affine3A::IDENTITY));
    let ray = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
    let tau = medium.optical_depth(&ray, 2.5, 10.0).unwrap();
    assert!((tau.r - 1.5).abs() < 1e-5, "τ from inside: {}", tau.r);
    let tau = medium.optical_depth(&ray, 0.0, 1.0).unwrap();
    assert_eq!(tau.r, 0.0, "segment before the box");
}

/// Auto (closed form), ratio and residual ratio tracking: T = exp(-σt d) per channel.
#[test]
fn transmittance_estimators_match_closed_form() {
    for (k, case) in cases().iter().enumerate() {
        for estimator in [
            TransmittanceEstimator::Auto,
            TransmittanceEstimator::Ratio,
            TransmittanceEstimator::ResidualRatio,
        ] {
            let est = estimate(N, 100 + k as u64, |s| {
                medium_transmittance(&case.medium, &case.ray, case.t_max, estimator, s)
            });
            assert_estimate(
                &est,
                closed_form(case),
                &format!("{} with {estimator:?}", case.name),
            );
        }
    }
}

/// Delta tracking: T = exp(-σt d), on grey media only.
///
/// Delta tracking decides real collisions on one scalar extinction (the max
/// channel), so for chromatic σt it estimates exp(-max σt · d) in every
/// channel; chromatic shadow rays must use ratio tracking (the default).
#[test]
fn delta_tracking_matches_closed_form_on_grey_media() {
    for (k, case) in cases().iter().enumerate() {
        if case.sigma_t[0] != case.sigma_t[1] || case.sigma_t[1] != case.sigma_t[2] {
            continue;
        }
        let est = estimate(N, 200 + k as u64, |s| {
            medium_transmittance(
                &case.medium,
                &case.ray,
                case.t_max,
                TransmittanceEstimator::Delta,
                s,
            )
        });
        assert_estimate(
            &est,
            closed_form(case),
            &format!("{} with Delta", case.name),
        );
    }
}

/// Ratio tracking with σ̄ = 1×, 2×, 10× the max channel of σt: the mean is
/// exp(-σt d) and the second moment exp(-(2σt - σt²/σ̄) d), per channel.
#[test]
fn ratio_tracking_moments_with_loose_majorants() {
    for (k, sigma_t) in [[1.0; 3], [0.3, 0.8, 1.5]].into_iter().enumerate() {
        let medium = homogeneous(sigma_t, unit_box(Affine3A::IDENTITY));
        let (ray, d) = chord(Vec3::new(-1.0, -0.2, 0.6), Vec3::new(1.0, 0.4, -0.3), 1.0);
        let sigma_max = sigma_t.iter().cloned().fold(0.0, f64::max);
        for scale in [1.0f32, 2.0, 10.0] {
            let sigma_maj = sigma_max * scale as f64;
            let mut first = Accumulator::default();
            let mut second = Accumulator::default();
            for i in 0..N {
                let mut s = brume::sampling::Sampler::new(300 + k as u64, 0, 0, i as u64);
                let t = ratio_tracking_scaled_majorant(&medium, &ray, f32::INFINITY, scale, &mut s);
                first.add(t);
                second.add(t * t);
            }
            let what = format!("σt = {sigma_t:?}, σ̄ = {scale}× max σt");
            assert_estimate(
                &first.estimate(),
                per_channel(|c| (-sigma_t[c] * d).exp()),
                &format!("{what}: mean"),
            );
            assert_estimate(
                &second.estimate(),
                per_channel(|c| {
                    (-(2.0 * sigma_t[c] - sigma_t[c] * sigma_t[c] / sigma_maj) * d).exp()
                }),
                &format!("{what}: second moment"),
            );
        }
    }
}

/// A segment that never ends: a global medium and a ray escaping to infinity.
///
/// The first tentative collision is exponential with mean 1/σ̄, and every
/// estimator gives T = 0 when all channels of σt are positive. (Regression:
/// the tracker once computed 0·∞ = NaN for the length of such a segment and
/// returned no collision at all, so global media were invisible along
/// escaping rays; the product of null-collision ratios then also had to stop
/// at underflow instead of waiting for an exact zero.)
#[test]
fn unbounded_segments_are_tracked() {
    let sigma_t = [0.2, 0.5, 0.8];
    let medium = homogeneous(sigma_t, Region::Everywhere);
    let ray = Ray::new(Vec3::new(0.5, -1.0, 2.0), Vec3::new(0.0, 0.6, 0.8));
    let est = estimate(N, 400, |s| {
        let mut tracker = Tracker::new(&medium, &ray, f32::INFINITY);
        Rgb::splat(
            tracker
                .next(s)
                .expect("a collision on an unbounded segment")
                .t,
        )
    });
    assert_estimate(
        &est,
        [1.0 / 0.8; 3],
        "mean free path along an unbounded segment",
    );
    for estimator in [
        TransmittanceEstimator::Auto,
        TransmittanceEstimator::Ratio,
        TransmittanceEstimator::ResidualRatio,
        TransmittanceEstimator::Delta,
    ] {
        let est = estimate(1000, 401, |s| {
            medium_transmittance(&medium, &ray, f32::INFINITY, estimator, s)
        });
        assert_estimate(&est, [0.0; 3], &format!("T to infinity with {estimator:?}"));
    }
    let media = [medium];
    for i in 0..1000 {
        let mut s = brume::sampling::Sampler::new(402, 0, 0, i);
        let (event, _, _) = free_flight(&media, &ray, f32::INFINITY, &mut s);
        assert!(
            !matches!(event, FreeFlight::Passed),
            "a path cannot pass through an infinite medium"
        );
    }
}

/// A global medium that is transparent in some channels: to infinity those
/// channels keep T = 1 and the others reach 0, with every estimator, and a
/// path escapes carrying exactly the transparent channels. (Regression: the
/// transparent channels made tracking along the unbounded segment endless.)
#[test]
fn unbounded_segments_with_transparent_channels_end() {
    let sigma_t = [0.3, 0.0, 0.0];
    let medium = homogeneous(sigma_t, Region::Everywhere);
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.6, 0.8));
    for estimator in [
        TransmittanceEstimator::Auto,
        TransmittanceEstimator::Ratio,
        TransmittanceEstimator::ResidualRatio,
    ] {
        let est = estimate(1000, 410, |s| {
            medium_transmittance(&medium, &ray, f32::INFINITY, estimator, s)
        });
        assert_estimate(
            &est,
            [0.0, 1.0, 1.0],
            &format!("T to infinity with {estimator:?}"),
        );
    }
    let media = [medium];
    let est = estimate(1000, 411, |s| {
        match free_flight(&media, &ray, f32::INFINITY, s) {
            (FreeFlight::Passed, throughput, _) => throughput,
            _ => Rgb::BLACK,
        }
    });
    assert_estimate(&est, [0.0, 1.0, 1.0], "free flight to infinity");
}
