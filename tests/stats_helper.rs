//! The shared statistical assertion (`tests/common/stats.rs`): its k values
//! are the documented ones, and it fails on what it must catch.

mod common;

use common::k_sigma::{k_sigma, two_sided_p, FAMILY_FALSE_ALARM};
use common::{assert_pixels, assert_pixels_equal, Estimate};

fn est(mean: f64, se: f64) -> Estimate {
    Estimate {
        mean: [mean; 3],
        std_error: [se; 3],
        n: 1000,
    }
}

#[test]
fn k_follows_the_documented_family_false_alarm_rate() {
    // two-sided Gaussian tails: 2.7e-3 at 3σ, 5.73e-7 at 5σ
    assert!((two_sided_p(3.0) / 2.6998e-3 - 1.0).abs() < 1e-3);
    assert!((two_sided_p(5.0) / 5.7330e-7 - 1.0).abs() < 1e-3);
    for (m, k) in [(1, 4.417), (3, 4.649), (108, 5.341), (3072, 5.918)] {
        assert!((k_sigma(m) - k).abs() < 1e-3, "k({m}) = {}", k_sigma(m));
        // Šidák: m checks at the corrected level fail together with probability α
        let family = 1.0 - (1.0 - two_sided_p(k_sigma(m))).powi(m as i32);
        assert!(
            (family / FAMILY_FALSE_ALARM - 1.0).abs() < 1e-3,
            "{m}: {family}"
        );
    }
}

#[test]
fn pixels_within_k_pass() {
    let pixels: Vec<Estimate> = (0..36)
        .map(|i| est(1.0 + 0.01 * (if i % 2 == 0 { 1.0 } else { -1.0 }), 0.01))
        .collect();
    assert_pixels_equal(&pixels, [1.0; 3], "±1σ alternating");
}

#[test]
#[should_panic(expected = "pixel 7")]
fn one_pixel_off_fails() {
    let mut pixels = vec![est(1.0, 0.01); 36];
    pixels[7] = est(1.06, 0.01);
    assert_pixels_equal(&pixels, [1.0; 3], "one pixel 6σ off");
}

#[test]
#[should_panic(expected = "image mean")]
fn a_bias_shared_by_all_pixels_fails_pooled() {
    // 1σ per pixel is fine alone, but 100 pixels all +1σ is 10σ pooled
    let pixels = vec![est(1.01, 0.01); 100];
    assert_pixels_equal(&pixels, [1.0; 3], "shared 1σ bias");
}

#[test]
#[should_panic(expected = "pixel 0")]
fn reference_error_is_combined_not_ignored() {
    let pixels = vec![est(1.0, 0.01)];
    // 0.1 apart with 0.01 + 0.01 errors: 7σ
    assert_pixels(&pixels, &[[1.1; 3]], &[[0.01; 3]], "vs reference");
}
