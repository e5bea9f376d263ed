use super::*;
use crate::math::spherical_direction;
use crate::sampling::quadrature::gauss_legendre;
use crate::sampling::Sampler;
use std::f64::consts::PI as PI64;

const HG_G: [f32; 6] = [-0.9, -0.3, 0.0, 0.5, 0.8, 0.95];

fn variants() -> Vec<PhaseFunction> {
    let mut all: Vec<_> = HG_G
        .iter()
        .map(|&g| PhaseFunction::HenyeyGreenstein { g })
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

/// Incoming directions: the poles and an oblique one, to exercise the frame.
fn dirs_in() -> [Vec3; 3] {
    [Vec3::Z, -Vec3::Z, Vec3::new(0.3, -0.5, 0.8).normalize()]
}

/// 2π ∫_0^π f(θ) p(cos θ) sin θ dθ with `panels` 8-point Gauss–Legendre panels in θ.
///
/// θ rather than cos θ as the variable: the forward peak of HG(0.95) is ~0.05 rad
/// wide in θ but ~1e-3 wide in cos θ, and sin θ vanishes where the peak sits.
fn sphere_moment(phase: &PhaseFunction, f: impl Fn(f64) -> f64, panels: usize) -> f64 {
    let integrand = |theta: f64| {
        let dir_out = spherical_direction(theta.cos() as f32, 0.7);
        f(theta) * phase.eval(Vec3::Z, dir_out) as f64 * theta.sin()
    };
    2.0 * PI64 * gauss_legendre(integrand, 0.0, PI64, panels)
}

#[test]
fn densities_integrate_to_one() {
    for phase in variants() {
        let coarse = sphere_moment(&phase, |_| 1.0, 256);
        let fine = sphere_moment(&phase, |_| 1.0, 512);
        // Halving panels of a converged 8-point rule changes the result by less than the
        // f32 rounding of the integrand (~1e-7 relative): the difference bounds the error.
        assert!(
            (coarse - fine).abs() < 1e-6,
            "{phase:?}: {coarse} vs {fine}"
        );
        assert!((fine - 1.0).abs() < 1e-5, "{phase:?}: ∫ p dω = {fine}");
    }
}

#[test]
fn mean_cosine_by_quadrature_matches_analytic() {
    for phase in variants() {
        let mean = sphere_moment(&phase, f64::cos, 512);
        let expected = phase.mean_cosine() as f64;
        assert!(
            (mean - expected).abs() < 1e-5,
            "{phase:?}: {mean} vs {expected}"
        );
    }
}

#[test]
fn mean_cosine_by_sampling_matches_analytic() {
    let n = 100_000;
    for phase in variants() {
        let mut rng = Sampler::from_seed(31);
        let dir_in = dirs_in()[2];
        let cosines: Vec<f64> = (0..n)
            .map(|_| {
                let s = phase.sample(dir_in, rng.next_2d()).unwrap();
                s.direction.dot(dir_in) as f64
            })
            .collect();
        let mean = cosines.iter().sum::<f64>() / n as f64;
        let var = cosines.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let bound = 4.0 * var.sqrt() / (n as f64).sqrt();
        let expected = phase.mean_cosine() as f64;
        assert!(
            (mean - expected).abs() < bound,
            "{phase:?}: {mean} vs {expected} ± {bound}"
        );
    }
}

#[test]
fn samples_are_unit_with_pdf_equal_to_eval_and_unit_weight() {
    for phase in variants() {
        let mut rng = Sampler::from_seed(7);
        for dir_in in dirs_in() {
            for _ in 0..5_000 {
                let s = phase.sample(dir_in, rng.next_2d()).unwrap();
                assert!((s.direction.length() - 1.0).abs() < 1e-5, "{phase:?}");
                let eval = phase.eval(dir_in, s.direction);
                assert!(
                    (s.pdf - eval).abs() <= 1e-4 * eval,
                    "{phase:?}: {} vs {eval}",
                    s.pdf
                );
                assert_eq!(phase.pdf(dir_in, s.direction), eval);
                assert!((s.weight - eval / s.pdf).abs() < 1e-4 && s.weight == 1.0);
            }
        }
    }
}

/// Henyey–Greenstein density in f64 as a function of cos θ.
fn hg_reference(g: f64, mu: f64) -> f64 {
    (1.0 - g * g) / (4.0 * PI64 * (1.0 + g * g - 2.0 * g * mu).powf(1.5))
}

/// The textbook inverse CDF of HG in f64, where its cancellation is harmless.
fn hg_inverse_reference(g: f64, u: f64) -> f64 {
    if g == 0.0 {
        return 2.0 * u - 1.0;
    }
    let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    (1.0 + g * g - s * s) / (2.0 * g)
}

/// Relative pdf error explained by storing the sampled direction in f32.
///
/// World components of a unit vector carry absolute errors δ of a few ulps of 1;
/// near the peak p ∝ ((1−|g|)² + |g| x²)^(−3/2) with x = |dir_in ∓ dir_out|, so
/// |d ln p / dx| ≤ 1.5 √|g| / (1 − |g|). That is 3e-4 for |g| = 0.999.
fn direction_tolerance(g: f32) -> f64 {
    let delta = 4.0 * f32::EPSILON as f64;
    1e-5 + 1.5 * (g.abs() as f64).sqrt() * delta / (1.0 - g.abs() as f64)
}

#[test]
fn hg_sampling_inverts_the_cdf_even_for_extreme_g() {
    let mut rng = Sampler::from_seed(13);
    for g in [-0.999, -0.9, -1e-5, 0.0, 1e-6, 0.3, 0.95, 0.999] {
        let phase = PhaseFunction::HenyeyGreenstein { g };
        for dir_in in dirs_in() {
            for _ in 0..2_000 {
                let u = rng.next_2d();
                let s = phase.sample(dir_in, u).unwrap();
                let mu = hg_inverse_reference(g as f64, u.x as f64);
                let expected = hg_reference(g as f64, mu);
                let rel = (s.pdf as f64 - expected).abs() / expected;
                assert!(
                    rel < direction_tolerance(g),
                    "g = {g}, u = {u}: pdf {} vs {expected}",
                    s.pdf
                );
            }
        }
    }
}

#[test]
fn rayleigh_sampling_inverts_its_cubic_cdf() {
    let mut rng = Sampler::from_seed(17);
    for _ in 0..10_000 {
        let u = rng.next_2d();
        let s = PhaseFunction::Rayleigh.sample(Vec3::Z, u).unwrap();
        let mu = s.direction.z as f64;
        // CDF (μ³ + 3μ + 4) / 8, whose slope is at most 3/4: errors in μ stay errors in u.
        let cdf = (mu * mu * mu + 3.0 * mu + 4.0) / 8.0;
        assert!((cdf - u.x as f64).abs() < 1e-6, "u = {}: cdf {cdf}", u.x);
    }
}

#[test]
fn double_hg_is_the_weighted_mixture() {
    let (g_f, g_b, w) = (0.8, -0.4, 0.7);
    let phase = PhaseFunction::DoubleHenyeyGreenstein {
        g_forward: g_f,
        g_back: g_b,
        weight_forward: w,
    };
    for (i, cos_theta) in [-1.0f32, -0.5, 0.0, 0.3, 0.99, 1.0].into_iter().enumerate() {
        let dir_out = spherical_direction(cos_theta, i as f32);
        let mu = cos_theta as f64;
        let mixture = w as f64 * hg_reference(g_f as f64, mu)
            + (1.0 - w as f64) * hg_reference(g_b as f64, mu);
        let got = phase.eval(Vec3::Z, dir_out) as f64;
        assert!(
            (got - mixture).abs() < 1e-5 * mixture,
            "cos θ = {cos_theta}"
        );
    }
    // Lobe weights at the ends select one lobe only.
    let only_back = PhaseFunction::DoubleHenyeyGreenstein {
        g_forward: g_f,
        g_back: g_b,
        weight_forward: 0.0,
    };
    let back = PhaseFunction::HenyeyGreenstein { g: g_b };
    let u = Vec2::new(0.37, 0.81);
    let (a, b) = (
        only_back.sample(Vec3::Z, u).unwrap(),
        back.sample(Vec3::Z, u).unwrap(),
    );
    assert!((a.direction - b.direction).length() < 1e-6);
}

#[test]
fn validate_names_the_bad_parameter() {
    assert!(PhaseFunction::Isotropic.validate().is_ok());
    assert!(PhaseFunction::Rayleigh.validate().is_ok());
    assert!(PhaseFunction::HenyeyGreenstein { g: 0.99 }
        .validate()
        .is_ok());
    for g in [1.0, -1.0, 2.0, f32::NAN, f32::INFINITY] {
        let err = PhaseFunction::HenyeyGreenstein { g }
            .validate()
            .unwrap_err();
        assert!(err.contains("g = "), "{err}");
    }
    let dhg = |g_forward, g_back, weight_forward| PhaseFunction::DoubleHenyeyGreenstein {
        g_forward,
        g_back,
        weight_forward,
    };
    assert!(dhg(0.5, -0.5, 0.5).validate().is_ok());
    assert!(dhg(1.5, -0.5, 0.5)
        .validate()
        .unwrap_err()
        .contains("g_forward"));
    assert!(dhg(0.5, -1.0, 0.5)
        .validate()
        .unwrap_err()
        .contains("g_back"));
    assert!(dhg(0.5, -0.5, 1.1)
        .validate()
        .unwrap_err()
        .contains("weight_forward"));
    assert!(dhg(0.5, -0.5, f32::NAN)
        .validate()
        .unwrap_err()
        .contains("weight_forward"));
}

/// The largest `f32` below 1: the top of the samplers' random numbers.
const TOP: f32 = 1.0 - f32::EPSILON / 2.0;

#[test]
fn every_variant_samples_the_corners_of_the_unit_square() {
    // The lobe weights 0 and 1 put the lobe boundary on the square's edge, where
    // `u.x / w` could be 0/0 if u.x = w were sent to the forward lobe.
    let mut phases = variants();
    for weight_forward in [0.0, 1.0] {
        phases.push(PhaseFunction::DoubleHenyeyGreenstein {
            g_forward: 0.8,
            g_back: -0.4,
            weight_forward,
        });
    }
    for phase in phases {
        for dir_in in dirs_in() {
            for u in [
                Vec2::new(0.0, 0.0),
                Vec2::new(0.0, TOP),
                Vec2::new(TOP, 0.0),
                Vec2::new(TOP, TOP),
            ] {
                let s = phase.sample(dir_in, u);
                let s = s.unwrap_or_else(|| panic!("{phase:?}, u = {u}: no sample"));
                assert!(
                    (s.direction.length() - 1.0).abs() < 1e-5,
                    "{phase:?}, u = {u}: {}",
                    s.direction
                );
            }
        }
    }
}

#[test]
fn double_hg_keeps_the_remapped_number_below_one() {
    // With u.x at the top, the back lobe's remapped number (u.x − w)/(1 − w) is
    // exactly u.x for w = 0, and rounds up to 1 for w = 3·2⁻²⁵ (both differences
    // land on ties that round to the same float). Either way the double HG must
    // draw what its back lobe draws from the largest number below 1, to the bit.
    let g_back = -0.4;
    let back = PhaseFunction::HenyeyGreenstein { g: g_back };
    for weight_forward in [0.0, 3.0 * (-25f32).exp2()] {
        let remapped = (TOP - weight_forward) / (1.0 - weight_forward);
        assert!(remapped == TOP || remapped == 1.0, "{remapped}");
        let double = PhaseFunction::DoubleHenyeyGreenstein {
            g_forward: 0.8,
            g_back,
            weight_forward,
        };
        for dir_in in dirs_in() {
            let u = Vec2::new(TOP, 0.3);
            let got = double.sample(dir_in, u).unwrap().direction;
            let expected = back.sample(dir_in, u).unwrap().direction;
            assert_eq!(got, expected, "w = {weight_forward}");
        }
    }
}

#[test]
fn rayleigh_inverse_cdf_is_accurate_to_a_few_ulps() {
    // Error budget in units of ε = 2⁻²⁴: √(z² + 1) and |z| + √… carry ≤ 3ε
    // relative, the cube root divides that by 3 and adds ≤ 2ε (one ulp), so
    // A = ∛… is within 3ε relative and 1/A within 4ε; with A ∈ [1, φ] the
    // difference A − 1/A is off by at most 3εφ + 4ε/φ + ε ≈ 8.3ε (6.2ε seen). The
    // cancelling form ∛(|z| − √(z² + 1)) loses up to three more bits near the poles.
    let eps = f32::EPSILON as f64 / 2.0;
    let bound = 9.0 * eps;
    let n = 1 << 16;
    for i in 0..n {
        let u = i as f32 / n as f32;
        let (one_minus, one_plus) = rayleigh_cos(u);
        let z = 4.0 * u as f64 - 2.0;
        let a = (z.abs() + (z * z + 1.0).sqrt()).cbrt();
        let mu = (a - 1.0 / a).copysign(z);
        for (got, expected) in [(one_minus, 1.0 - mu), (one_plus, 1.0 + mu)] {
            // 1 ∓ μ < 2 rounds once more, by at most half an ulp: ε.
            assert!(
                (got as f64 - expected).abs() <= bound + eps,
                "u = {u}: {got} vs {expected}"
            );
        }
    }
}
