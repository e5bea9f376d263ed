//! The suite's one k: how many standard errors a Monte Carlo check allows
//! (module `stats` explains the choice). A file of its own, without
//! dependencies, so that the library's unit tests include the same code
//! (`src/lib.rs`, `#[path]`) instead of copying its numbers.

/// Probability that one call of an assertion fails by chance on a correct estimator.
pub const FAMILY_FALSE_ALARM: f64 = 1e-5;

/// Coefficients of `erfc`'s series in t, from t⁰ up (Numerical Recipes' `erfcc`).
const ERFC_SERIES: [f64; 9] = [
    1.000_023_68,
    0.374_091_96,
    0.096_784_18,
    -0.186_288_06,
    0.278_868_07,
    -1.135_203_98,
    1.488_515_87,
    -0.822_152_23,
    0.170_872_77,
];

/// Complementary error function, |relative error| < 1.2e-7 (Chebyshev fit of
/// Numerical Recipes' `erfcc`), ample for tail probabilities down to 1e-300.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    // Horner's rule, innermost coefficient first (a loop: rustfmt takes seconds on the nested form).
    let series = ERFC_SERIES.iter().rev().fold(0.0, |acc, &c| c + t * acc);
    let poly = -z * z - 1.265_512_23 + t * series;
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Two-sided Gaussian tail probability of a deviation of `k` standard errors.
pub fn two_sided_p(k: f64) -> f64 {
    erfc(k / std::f64::consts::SQRT_2)
}

/// The number of standard errors allowed to each of `m` simultaneous checks.
pub fn k_sigma(m: usize) -> f64 {
    let m = m.max(1) as f64;
    // Šidák: 1 - (1 - α)^(1/m), computed without cancellation
    let alpha_m = -((-FAMILY_FALSE_ALARM).ln_1p() / m).exp_m1();
    // two_sided_p is decreasing in k: bisect
    let (mut lo, mut hi) = (0.0_f64, 40.0_f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if two_sided_p(mid) > alpha_m {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}
