//! The committed table is what `examples/ggx_albedo.rs` writes, and its
//! averages are those of the interpolant.

use super::*;
use crate::material::albedo_estimate;

/// Entries spread over the conductor and both dielectric sides, re-estimated
/// by the generator: the file must hold exactly these numbers.
#[test]
fn committed_table_is_what_the_generator_writes() {
    let t = tables();
    let picks = [
        5 * MU_NODES + 3,
        31 * MU_NODES + 30,
        dielectric_row(Side::Enter, 4, 15) + 7,
        dielectric_row(Side::Leave, 4, 15) + 7,
        dielectric_row(Side::Leave, 15, 31),
        dielectric_row(Side::Enter, 9, 2) + 31,
    ];
    for index in picks {
        assert_eq!(
            t.values[index].to_bits(),
            albedo_estimate::entry(index).min(1.0).to_bits(),
            "entry {index}: regenerate src/material/ggx_albedo.bin"
        );
    }
}

#[test]
fn averages_integrate_the_interpolant() {
    // A fine midpoint rule of 2∫E(μ)μ dμ over the lookup itself.
    for (alpha, eta, side) in [(0.3f32, 1.5f32, Side::Enter), (0.77, 2.2, Side::Leave)] {
        let n = 20_000;
        let mid = |f: &dyn Fn(f32) -> f32| {
            (0..n)
                .map(|i| {
                    let mu = (i as f32 + 0.5) / n as f32;
                    2.0 * mu as f64 * f(mu) as f64
                })
                .sum::<f64>()
                / n as f64
        };
        let c = mid(&|mu| conductor(mu, alpha));
        assert!((c - conductor_average(alpha) as f64).abs() < 1e-5, "{c}");
        let d = mid(&|mu| dielectric(side, eta, mu, alpha));
        let want = dielectric_average(side, eta, alpha) as f64;
        assert!((d - want).abs() < 1e-5, "{d} vs {want}");
    }
}

#[test]
fn smooth_and_index_matched_rows_lose_nothing() {
    for mu in [0.0f32, 0.4, 1.0] {
        assert_eq!(conductor(mu, 0.0), 1.0);
        assert_eq!(dielectric(Side::Enter, 2.0, mu, 0.0), 1.0);
        assert_eq!(dielectric(Side::Leave, 1.0, mu, 0.6), 1.0);
    }
    // Normal-incidence Fresnel of glass is 0.04; the average is larger (≈ 0.092).
    let f = fresnel_average(1.5);
    assert!(f > 0.08 && f < 0.1, "{f}");
}
