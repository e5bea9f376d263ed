use super::*;
use crate::sampling::warp;

#[test]
fn ln_gamma_matches_factorials_and_sqrt_pi() {
    assert!((ln_gamma(0.5) - 0.5 * PI.ln()).abs() < 1e-13);
    // Below ½ by the reflection formula: Γ(¼) = 3.625609908221908…
    assert!((ln_gamma(0.25) - 3.625_609_908_221_908_f64.ln()).abs() < 1e-13);
    let mut factorial = 1.0f64;
    for n in 1..30 {
        // Γ(n) = (n − 1)!
        assert!((ln_gamma(n as f64) - factorial.ln()).abs() < 1e-12 * (1.0 + factorial.ln()));
        factorial *= n as f64;
    }
}

#[test]
fn incomplete_gamma_matches_closed_forms_on_both_branches() {
    for x in [0.01f64, 0.3, 1.0, 2.5, 4.0, 9.0, 30.0] {
        // Q(1, x) = e^−x and Q(3, x) = e^−x (1 + x + x²/2).
        let q1 = f64::exp(-x);
        assert!((regularized_gamma_q(1.0, x) - q1).abs() < 1e-13, "x = {x}");
        let q3 = q1 * (1.0 + x + 0.5 * x * x);
        assert!((regularized_gamma_q(3.0, x) - q3).abs() < 1e-13, "x = {x}");
    }
    // Q(1/2, x) = erfc(√x); erfc(1) = 0.157299207050285.
    assert!((regularized_gamma_q(0.5, 1.0) - 0.157_299_207_050_285).abs() < 1e-13);
}

#[test]
fn chi2_survival_matches_tables() {
    // (dof, quantile, upper-tail probability) from standard chi-square tables.
    let table = [
        (1, 3.841_459, 0.05),
        (1, 6.634_897, 0.01),
        (2, 5.991_465, 0.05),
        (5, 1.145_476, 0.95),
        (10, 18.307_038, 0.05),
        (10, 23.209_251, 0.01),
        (100, 124.342_113, 0.05),
    ];
    for (dof, x, p) in table {
        let got = chi2_survival(x, dof);
        assert!((got - p).abs() < 2e-6, "dof {dof}, x {x}: {got} vs {p}");
    }
}

#[test]
fn sidak_level_is_below_alpha_and_exact_for_one_test() {
    assert!((sidak_alpha(0.01, 1) - 0.01).abs() < 1e-15);
    let a = sidak_alpha(0.01, 20);
    assert!(a < 0.01 / 19.0 && a > 0.01 / 21.0);
}

#[test]
fn sphere_harness_accepts_the_right_pdf() {
    let result = SphereChi2::new(50_000, 5).run(
        |u| Some(warp::square_to_cosine_hemisphere(u)),
        warp::cosine_hemisphere_pdf,
    );
    assert!(result.passes(0.01, 1), "{result}");
    // The 100 upper-hemisphere cells count; the lower ones expect (and get) nothing.
    assert_eq!(result.dof, 99, "{result}");
}

#[test]
fn sphere_harness_rejects_a_wrong_pdf() {
    // Cosine-weighted samples tested against the uniform-hemisphere density 1/(2π).
    let uniform_hemisphere = |d: Vec3| if d.z >= 0.0 { 0.5 / PI as f32 } else { 0.0 };
    let result = SphereChi2::new(50_000, 5).run(
        |u| Some(warp::square_to_cosine_hemisphere(u)),
        uniform_hemisphere,
    );
    assert!(result.p_value < 1e-12, "{result}");
    assert!(!result.passes(0.01, 1));
}

#[test]
fn interval_harness_accepts_right_and_rejects_wrong_pdf() {
    // x = √u has density 2x on [0, 1].
    let test = IntervalChi2::new(0.0, 1.0, 50_000, 9);
    let right = test.run(|u| Some(u.sqrt()), |x| 2.0 * x);
    assert!(right.passes(0.01, 1), "{right}");
    let wrong = test.run(|u| Some(u.sqrt()), |x| 1.9 * x + 0.05);
    assert!(wrong.p_value < 1e-6, "{wrong}");
}

#[test]
fn missing_samples_and_impossible_samples_are_caught() {
    let test = IntervalChi2::new(0.0, 1.0, 20_000, 3);
    // A sampler that gives up a tenth of the time has a deficient density.
    let lossy = test.run(|u| (u < 0.9).then_some(u / 0.9), |_| 1.0);
    // About 2000 expected, with a binomial σ of about 42.
    assert!((1_800..2_200).contains(&lossy.invalid_count), "{lossy}");
    assert!(lossy.p_value < 1e-6, "{lossy}");
    // Samples where the pdf vanishes reject outright.
    let outside = test.run(Some, |x| if x < 0.5 { 2.0 } else { 0.0 });
    assert_eq!(outside.p_value, 0.0);
}

#[test]
fn p_values_of_a_correct_sampler_are_uniform() {
    // Under the null hypothesis p ~ U(0, 1): a miscounted dof or a biased statistic
    // would shift the mean or pile p-values up near 0.
    let runs = 200;
    let p: Vec<f64> = (0..runs)
        .map(|seed| {
            let test = IntervalChi2::new(0.0, 1.0, 4_000, 1_000 + seed);
            test.run(|u| Some(u.sqrt()), |x| 2.0 * x).p_value
        })
        .collect();
    let mean = p.iter().sum::<f64>() / runs as f64;
    // σ of a mean of U(0,1) is √(1/12)/√runs ≈ 0.020; of a 10% fraction √(0.09/runs) ≈ 0.021.
    // Two checks at the suite's k (tests/common/k_sigma.rs).
    let k = crate::suite_k::k_sigma(2);
    assert!((mean - 0.5).abs() < k * 0.0205, "mean p = {mean}");
    let low = p.iter().filter(|&&x| x < 0.1).count() as f64 / runs as f64;
    assert!((low - 0.1).abs() < k * 0.0213, "fraction below 0.1 = {low}");
}

#[test]
fn a_test_without_degrees_of_freedom_never_passes() {
    // Every sample in one pooled cell: nothing was tested, whatever the p-value says.
    let result = Chi2Result {
        statistic: 0.0,
        dof: 0,
        p_value: 1.0,
        sample_count: 1000,
        invalid_count: 0,
        histogram: String::new(),
    };
    assert!(!result.passes(0.01, 1));
    assert!(Chi2Result { dof: 1, ..result }.passes(0.01, 1));
}

#[test]
fn a_failure_message_shows_the_statistic_and_the_histogram() {
    let result = IntervalChi2::new(0.0, 1.0, 1_000, 4).run(Some, |_| 1.0);
    let message = result.to_string();
    assert!(message.starts_with("chi2 = "), "{message}");
    assert!(
        message.contains(&format!("dof = {}", result.dof)),
        "{message}"
    );
    assert!(message.ends_with(&result.histogram), "{message}");
}

#[test]
fn directions_that_are_not_unit_vectors_are_invalid() {
    // Right directions, wrong length: a sampler that forgot to normalise.
    let result = SphereChi2::new(2_000, 6).run(
        |u| Some(2.0 * warp::square_to_cosine_hemisphere(u)),
        warp::cosine_hemisphere_pdf,
    );
    assert_eq!(result.invalid_count, result.sample_count, "{result}");
    assert!(!result.passes(0.01, 1));
}

#[test]
fn samples_outside_the_interval_are_invalid() {
    let test = IntervalChi2::new(1.0, 2.0, 2_000, 8);
    let result = test.run(|u| Some(if u < 0.5 { 0.5 * u } else { 2.0 + u }), |_| 1.0);
    assert_eq!(result.invalid_count, result.sample_count, "{result}");
    assert!(!result.passes(0.01, 1));
}

#[test]
fn the_interval_histogram_labels_each_bin_with_its_range() {
    // 40 bins over [1, 2]: bin 1 is [1.025, 1.05).
    let result = IntervalChi2::new(1.0, 2.0, 1_000, 4).run(|u| Some(1.0 + u), |_| 1.0);
    let second = result.histogram.lines().nth(2).unwrap_or_default();
    assert!(
        second.starts_with("[1.0250, 1.0500): "),
        "{}",
        result.histogram
    );
}

#[test]
fn the_sphere_histogram_shows_every_bin_observed_and_expected() {
    let test = SphereChi2::new(1_000, 2);
    let result = test.run(
        |u| Some(warp::square_to_uniform_sphere(u)),
        |_| 0.25 / PI as f32,
    );
    let lines: Vec<&str> = result.histogram.lines().collect();
    // a header, the observed rows, a header, the expected rows
    assert_eq!(lines.len(), 2 * test.cos_theta_bins + 2, "{result}");
    // 1000 samples over the bins, uniform: about 1000 / bins each
    let per_bin = 1_000.0 / (test.cos_theta_bins * test.phi_bins) as f64;
    for row in &lines[test.cos_theta_bins + 2..] {
        let values: Vec<f64> = row.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert_eq!(values.len(), test.phi_bins, "{result}");
        assert!(
            values.iter().all(|&v| (v - per_bin).abs() <= 1.0),
            "{result}"
        );
    }
}

#[test]
fn a_few_samples_where_the_pdf_is_zero_reject_whatever_the_statistic() {
    // 40 bins of width 1 over [0, 40]; the pdf is 0 on [20, 40]. A handful of
    // samples (u < 2·10⁻⁴) land there; the other bins alone would pass.
    let test = IntervalChi2::new(0.0, 40.0, 20_000, 12);
    let pdf = |x: f32| if x < 20.0 { 0.05 } else { 0.0 };
    let result = test.run(|u| Some(if u < 2e-4 { 30.0 } else { 20.0 * u }), pdf);
    assert_eq!(result.invalid_count, 0, "{result}");
    assert_eq!(result.p_value, 0.0, "{result}");
    assert!(
        result.histogram.contains("samples fell where the pdf is 0"),
        "{result}"
    );
    // Without them the same sampler passes: the rejection is theirs alone.
    let clean = test.run(|u| Some(20.0 * u), pdf);
    assert!(clean.passes(0.01, 1), "{clean}");
}

#[test]
fn sparse_cells_are_pooled_until_the_pool_expects_five() {
    // Sorted by expectation: 2 and 2 are pooled, and the pool (4) still takes
    // the 10; the 20 stands alone. Pool: observed 4 + 3 + 9 = 16 against 14.
    let result = finish(
        &[9.0, 4.0, 25.0, 3.0],
        &[10.0, 2.0, 20.0, 2.0],
        41,
        0,
        String::new(),
    );
    let want = 2.0 * 2.0 / 14.0 + 5.0 * 5.0 / 20.0;
    assert!((result.statistic - want).abs() < 1e-12, "{result}");
    assert_eq!(result.dof, 1, "{result}");
    assert_eq!(result.p_value, chi2_survival(want, 1));
    // Nothing sparse: one term per cell.
    let plain = finish(&[9.0, 26.0], &[10.0, 25.0], 35, 0, String::new());
    assert!(
        (plain.statistic - (0.1 + 1.0 / 25.0)).abs() < 1e-12,
        "{plain}"
    );
    assert_eq!(plain.dof, 1, "{plain}");
}
