//! Chi-square goodness-of-fit tests of every sampler against its own pdf.
//!
//! Each accepting test runs at family-wise level ALPHA, Šidák-corrected for the
//! CHI2_TEST_COUNT tests in this file, so a correct sampler fails the suite with
//! probability below 1% overall; seeds are fixed, so results are reproducible.

use brume::math::{Frame, Vec3};
use brume::medium::phase::PhaseFunction;
use brume::sampling::chi2::{Chi2Result, IntervalChi2, SphereChi2};
use brume::sampling::equiangular::{equiangular_pdf, sample_equiangular};
use brume::sampling::warp;

const ALPHA: f64 = 0.01;
/// 3 warps + 9 phase functions × 2 incoming directions + 4 equiangular setups.
const CHI2_TEST_COUNT: usize = 3 + 9 * 2 + 4;
const SPHERE_SAMPLES: usize = 100_000;
const INTERVAL_SAMPLES: usize = 50_000;

fn assert_passes(name: &str, result: &Chi2Result) {
    assert!(result.passes(ALPHA, CHI2_TEST_COUNT), "{name}: {result}");
    assert_eq!(result.invalid_count, 0, "{name}: {result}");
}

#[test]
fn uniform_sphere_warp() {
    let result = SphereChi2::new(SPHERE_SAMPLES, 1).run(
        |u| Some(warp::square_to_uniform_sphere(u)),
        |_| warp::uniform_sphere_pdf(),
    );
    assert_passes("uniform sphere", &result);
}

#[test]
fn cosine_hemisphere_warp() {
    let result = SphereChi2::new(SPHERE_SAMPLES, 2).run(
        |u| Some(warp::square_to_cosine_hemisphere(u)),
        warp::cosine_hemisphere_pdf,
    );
    assert_passes("cosine hemisphere", &result);
}

#[test]
fn uniform_cone_warp() {
    // cos_max inside a cos θ bin, so the pdf's edge is integrated, not aligned with a bin.
    let cos_max = 0.75;
    let result = SphereChi2::new(SPHERE_SAMPLES, 3).run(
        |u| Some(warp::square_to_uniform_cone(u, cos_max)),
        |d| {
            if d.z >= cos_max {
                warp::uniform_cone_pdf(cos_max)
            } else {
                0.0
            }
        },
    );
    assert_passes("uniform cone", &result);
}

fn phase_functions() -> Vec<PhaseFunction> {
    let mut all: Vec<_> = [-0.9, -0.3, 0.0, 0.5, 0.8, 0.95]
        .into_iter()
        .map(|g| PhaseFunction::HenyeyGreenstein { g })
        .collect();
    all.push(PhaseFunction::Isotropic);
    all.push(PhaseFunction::Rayleigh);
    all.push(PhaseFunction::DoubleHenyeyGreenstein {
        g_forward: 0.8,
        g_back: -0.4,
        weight_forward: 0.7,
    });
    all
}

#[test]
fn phase_functions_along_the_pole() {
    for (k, phase) in phase_functions().into_iter().enumerate() {
        // Along +z the bins resolve the scattering angle directly.
        let result = SphereChi2::new(SPHERE_SAMPLES, 10 + k as u64).run(
            |u| phase.sample(Vec3::Z, u).map(|s| s.direction),
            |d| phase.pdf(Vec3::Z, d),
        );
        assert_passes(&format!("{phase:?} along +z"), &result);
    }
}

#[test]
fn phase_functions_oblique() {
    // An oblique incoming direction exercises the frame and the azimuth.
    let dir_in = Vec3::new(0.6, -0.3, -0.5).normalize();
    for (k, phase) in phase_functions().into_iter().enumerate() {
        let result = SphereChi2::new(SPHERE_SAMPLES, 30 + k as u64).run(
            |u| phase.sample(dir_in, u).map(|s| s.direction),
            |d| phase.pdf(dir_in, d),
        );
        assert_passes(&format!("{phase:?} oblique"), &result);
    }
}

#[test]
fn equiangular_distances() {
    let origin = Vec3::new(0.5, -1.0, 2.0);
    let dir = Vec3::new(1.0, 2.0, -0.5).normalize();
    let frame = Frame::from_z(dir);
    // (name, light, t range) with lights placed relative to the ray.
    let setups = [
        ("beside", origin + dir * 3.0 + frame.x * 0.5, 0.0, 6.0),
        ("ahead", origin + dir * 12.0 + frame.y * 2.0, 1.0, 4.0),
        ("behind", origin - dir * 2.0 + frame.x * 0.3, 0.5, 10.0),
        ("on the line beyond", origin + dir * 9.0, 0.0, 5.0),
    ];
    for (k, (name, light, t_min, t_max)) in setups.into_iter().enumerate() {
        let result = IntervalChi2::new(t_min, t_max, INTERVAL_SAMPLES, 50 + k as u64).run(
            |u| sample_equiangular(origin, dir, light, t_min, t_max, u).map(|s| s.value),
            |t| equiangular_pdf(origin, dir, light, t_min, t_max, t),
        );
        assert_passes(&format!("equiangular {name}"), &result);
    }
}

/// The harness must have power: each wrong pdf here is rejected far below any level in use.
#[test]
fn rejects_wrong_pdfs() {
    let uniform_hemisphere = |d: Vec3| {
        if d.z >= 0.0 {
            0.5 * std::f32::consts::FRAC_1_PI
        } else {
            0.0
        }
    };
    let cosine_vs_uniform = SphereChi2::new(SPHERE_SAMPLES, 70).run(
        |u| Some(warp::square_to_cosine_hemisphere(u)),
        uniform_hemisphere,
    );
    assert!(cosine_vs_uniform.p_value < 1e-12, "{cosine_vs_uniform}");

    // A nearby HG parameter is still told apart.
    let sampled = PhaseFunction::HenyeyGreenstein { g: 0.5 };
    let claimed = PhaseFunction::HenyeyGreenstein { g: 0.45 };
    let hg = SphereChi2::new(SPHERE_SAMPLES, 71).run(
        |u| sampled.sample(Vec3::Z, u).map(|s| s.direction),
        |d| claimed.pdf(Vec3::Z, d),
    );
    assert!(hg.p_value < 1e-6, "{hg}");

    // Equiangular samples against the pdf for a light moved by a fifth of its distance.
    let (o, d) = (Vec3::ZERO, Vec3::X);
    let (light, moved) = (Vec3::new(2.0, 1.0, 0.0), Vec3::new(2.0, 1.2, 0.0));
    let distances = IntervalChi2::new(0.0, 4.0, INTERVAL_SAMPLES, 72).run(
        |u| sample_equiangular(o, d, light, 0.0, 4.0, u).map(|s| s.value),
        |t| equiangular_pdf(o, d, moved, 0.0, 4.0, t),
    );
    assert!(distances.p_value < 1e-6, "{distances}");
}
