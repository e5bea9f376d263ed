//! The one statistical assertion of the suite.
//!
//! Every Monte Carlo check compares an estimate with its expectation (a closed
//! form, a quadrature, a stored reference or another estimate) within `k`
//! standard errors of the estimator itself, with fixed seeds. One call of an
//! `assert_*` function here is one *family* of `m` simultaneous checks (3
//! channels, or 3 channels × every pixel); the family may fail by chance with
//! probability at most `FAMILY_FALSE_ALARM` = 1e-5 (module `k_sigma`, under
//! the central-limit approximation). For a single check that is
//! k = 4.42 standard errors; for a family of `m` checks each one gets the
//! Šidák-corrected level α_m = 1 − (1 − α)^(1/m), so
//! k(3) = 4.65, k(108) = 5.34, k(3·1024) = 5.92 (see [`k_sigma`]).
//!
//! A check also allows a rounding floor of [`ROUNDING`] relative to the
//! expected value (plus 1e-7 absolute), so that a zero-variance estimator must
//! match to f32 rounding and no more. Never widen either to make a test pass:
//! a failure at this level is a bias to find.

pub use super::k_sigma::k_sigma;
use super::Estimate;

/// Relative allowance for f32 rounding (radiance is f32, closed forms are f64).
pub const ROUNDING: f64 = 2e-5;

/// The tolerance of one check with standard error `se` and expectation `expected`.
pub fn tolerance(se: f64, expected: f64, k: f64) -> f64 {
    k * se + ROUNDING * expected.abs() + 1e-7
}

/// Deviation in standard errors, for messages.
fn sigmas(diff: f64, se: f64) -> f64 {
    diff / se.max(1e-300)
}

/// Asserts `value` (standard error `se`) equals `expected`, as one of `m` checks of a family.
pub fn assert_within(value: f64, se: f64, expected: f64, m: usize, what: &str) {
    let k = k_sigma(m);
    let diff = value - expected;
    assert!(
        diff.abs() <= tolerance(se, expected, k),
        "{what}: {value} ± {se} vs {expected} (off by {:.2} σ, allowed {k:.2} σ)",
        sigmas(diff, se)
    );
}

/// Asserts every channel of `est` equals `expected` (one family of 3 checks).
pub fn assert_estimate(est: &Estimate, expected: [f64; 3], what: &str) {
    let k = k_sigma(3);
    for c in 0..3 {
        let diff = est.mean[c] - expected[c];
        assert!(
            diff.abs() <= tolerance(est.std_error[c], expected[c], k),
            "{what}: channel {c}: {} ± {} (n = {}) vs {} (off by {:.2} σ, allowed {k:.2} σ)",
            est.mean[c],
            est.std_error[c],
            est.n,
            expected[c],
            sigmas(diff, est.std_error[c]),
        );
    }
}

/// Asserts that `better`'s standard error is below `factor` times `worse`'s in every channel.
pub fn assert_lower_error(better: &Estimate, worse: &Estimate, factor: f64, what: &str) {
    for c in 0..3 {
        assert!(
            better.std_error[c] < factor * worse.std_error[c],
            "{what}: channel {c}: standard error {} not below {factor} × {}",
            better.std_error[c],
            worse.std_error[c]
        );
    }
}

/// Asserts two independent estimates of the same quantity agree (one family of 3 checks).
pub fn assert_same(a: &Estimate, b: &Estimate, what: &str) {
    let k = k_sigma(3);
    for c in 0..3 {
        let se = a.std_error[c].hypot(b.std_error[c]);
        let diff = a.mean[c] - b.mean[c];
        assert!(
            diff.abs() <= tolerance(se, b.mean[c], k),
            "{what}: channel {c}: {} ± {} vs {} ± {} (off by {:.2} σ, allowed {k:.2} σ)",
            a.mean[c],
            a.std_error[c],
            b.mean[c],
            b.std_error[c],
            sigmas(diff, se),
        );
    }
}

/// Asserts every pixel equals its expectation, each with standard error
/// `expected_se` (0 for a closed form, the reference's own error for a stored
/// reference), and the pooled mean of the differences is zero.
///
/// Two families: the per-pixel checks (3 × pixels, Šidák-corrected) and the
/// pooled check (3 channels), whose standard error is √(Σ se²) / pixels, so a
/// small bias shared by all pixels is caught even when no single pixel shows it.
pub fn assert_pixels(
    pixels: &[Estimate],
    expected: &[[f64; 3]],
    expected_se: &[[f64; 3]],
    what: &str,
) {
    assert_eq!(pixels.len(), expected.len(), "{what}: pixel count");
    assert_eq!(pixels.len(), expected_se.len(), "{what}: pixel count");
    let n = pixels.len() as f64;
    let k_pixel = k_sigma(3 * pixels.len());
    let mut pooled_diff = [0.0; 3];
    let mut pooled_var = [0.0; 3];
    let mut pooled_expected = [0.0; 3];
    for (i, p) in pixels.iter().enumerate() {
        for c in 0..3 {
            let se = p.std_error[c].hypot(expected_se[i][c]);
            let diff = p.mean[c] - expected[i][c];
            assert!(
                diff.abs() <= tolerance(se, expected[i][c], k_pixel),
                "{what}: pixel {i} channel {c}: {} ± {} vs {} ± {} (off by {:.2} σ, allowed {k_pixel:.2} σ)",
                p.mean[c],
                p.std_error[c],
                expected[i][c],
                expected_se[i][c],
                sigmas(diff, se),
            );
            pooled_diff[c] += diff / n;
            pooled_var[c] += se * se / (n * n);
            pooled_expected[c] += expected[i][c] / n;
        }
    }
    let k = k_sigma(3);
    for c in 0..3 {
        let se = pooled_var[c].sqrt();
        assert!(
            pooled_diff[c].abs() <= tolerance(se, pooled_expected[c], k),
            "{what}: image mean channel {c}: off by {} ± {se} from {} (off by {:.2} σ, allowed {k:.2} σ)",
            pooled_diff[c],
            pooled_expected[c],
            sigmas(pooled_diff[c], se),
        );
    }
}

/// Asserts every pixel and the image mean equal one closed-form value.
pub fn assert_pixels_equal(pixels: &[Estimate], expected: [f64; 3], what: &str) {
    let want = vec![expected; pixels.len()];
    let zero = vec![[0.0; 3]; pixels.len()];
    assert_pixels(pixels, &want, &zero, what);
}
