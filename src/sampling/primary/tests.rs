//! The mutation kernel leaves its target invariant (detailed balance with
//! Metropolis–Hastings acceptance): chains started from the target are still
//! distributed by it after many mutations, checked by chi-square on a 2-D
//! target with closed-form cell integrals and on a third number the target
//! only sometimes uses (the lazily drawn coordinates of a longer path).

use super::{PrimarySamples, Stream};
use crate::sampling::chi2::chi2_survival;
use crate::sampling::Sampler;
use crate::suite_k::FAMILY_FALSE_ALARM;

/// f(x, y, z) = (1 + 8xy²) · (2z if x > ½ else 1): its (x, y) marginal is
/// 1 + 8xy², and z given x > ½ has density 2z.
fn target(x: f32, y: f32, z: f32) -> f64 {
    let (x, y, z) = (x as f64, y as f64, z as f64);
    (1.0 + 8.0 * x * y * y) * if x > 0.5 { 2.0 * z } else { 1.0 }
}

/// The state's numbers: x, y from the camera stream; z from the light
/// stream, drawn only when x > ½ (as a longer path draws more numbers).
fn evaluate(ps: &mut PrimarySamples) -> (f32, f32, f32) {
    ps.rewind();
    ps.set_stream(Stream::Camera);
    let (x, y) = (ps.next_1d(), ps.next_1d());
    ps.set_stream(Stream::Light);
    let z = if x > 0.5 { ps.next_1d() } else { 0.5 };
    (x, y, z)
}

/// Pearson's statistic and p-value of `observed` against `expected` counts.
fn chi2(observed: &[f64], expected: &[f64]) -> (f64, f64) {
    let stat: f64 = observed
        .iter()
        .zip(expected)
        .map(|(o, e)| (o - e) * (o - e) / e)
        .sum();
    (stat, chi2_survival(stat, observed.len() - 1))
}

/// The final states of `chains` chains, each started from an exact draw of
/// the target (rejection sampling) and mutated `steps` times.
fn final_states(chains: usize, steps: usize, sigma: f32, large: f32) -> Vec<(f32, f32, f32)> {
    let mut rng = Sampler::from_seed(77);
    (0..chains)
        .map(|i| {
            let mut attempt = 0u64;
            let mut ps = loop {
                let mut ps = PrimarySamples::new((i as u64) << 20 | attempt, sigma, large);
                let (x, y, z) = evaluate(&mut ps);
                attempt += 1;
                if (rng.next_1d() as f64) * 18.0 < target(x, y, z) {
                    ps.accept();
                    break ps;
                }
            };
            let mut current = evaluate(&mut ps);
            for _ in 0..steps {
                ps.start_iteration();
                let proposal = evaluate(&mut ps);
                let (fc, fp) = (
                    target(current.0, current.1, current.2),
                    target(proposal.0, proposal.1, proposal.2),
                );
                if (rng.next_1d() as f64) * fc < fp {
                    ps.accept();
                    current = proposal;
                } else {
                    ps.reject();
                }
            }
            current
        })
        .collect()
}

fn assert_invariant(sigma: f32, large: f32) {
    let (n, cells) = (40_000, 8);
    let states = final_states(n, 24, sigma, large);
    // (x, y) on an 8 × 8 grid: ∫∫ 1 + 8xy² over a cell, over the total 7/3.
    let mut observed = vec![0.0; cells * cells];
    let mut expected = vec![0.0; cells * cells];
    let h = 1.0 / cells as f64;
    for i in 0..cells {
        for j in 0..cells {
            let (x0, y0) = (i as f64 * h, j as f64 * h);
            let (x1, y1) = (x0 + h, y0 + h);
            let integral =
                h * h + 8.0 * (x1 * x1 - x0 * x0) / 2.0 * (y1.powi(3) - y0.powi(3)) / 3.0;
            expected[i * cells + j] = n as f64 * integral / (7.0 / 3.0);
        }
    }
    // z given x > ½: density 2z, cell integral z1² − z0².
    let mut z_observed = vec![0.0; cells];
    for &(x, y, z) in &states {
        let (i, j) = ((x as f64 / h) as usize, (y as f64 / h) as usize);
        observed[i * cells + j] += 1.0;
        if x > 0.5 {
            z_observed[(z as f64 / h) as usize] += 1.0;
        }
    }
    let upper: f64 = z_observed.iter().sum();
    let z_expected: Vec<f64> = (0..cells)
        .map(|k| upper * (((k + 1) as f64 * h).powi(2) - (k as f64 * h).powi(2)))
        .collect();
    for (what, o, e) in [
        ("(x, y)", &observed, &expected),
        ("z | x > 1/2", &z_observed, &z_expected),
    ] {
        let (stat, p) = chi2(o, e);
        assert!(
            p > FAMILY_FALSE_ALARM / 4.0,
            "σ = {sigma}, large steps {large}: {what}: chi2 {stat:.1} over {} cells, p = {p:.2e}\nobserved {o:?}\nexpected {e:?}",
            o.len()
        );
    }
}

#[test]
fn small_steps_keep_the_target_invariant() {
    assert_invariant(0.05, 0.0);
}

#[test]
fn mixed_large_and_small_steps_keep_the_target_invariant() {
    assert_invariant(0.2, 0.3);
}

#[test]
fn large_steps_alone_keep_the_target_invariant() {
    assert_invariant(0.1, 1.0);
}

/// A rejected proposal leaves the state as it was, the numbers drawn for it included.
#[test]
fn a_rejected_proposal_restores_every_number() {
    let mut ps = PrimarySamples::new(3, 0.1, 0.5);
    let before = evaluate(&mut ps);
    ps.accept();
    for _ in 0..50 {
        ps.start_iteration();
        let proposal = evaluate(&mut ps);
        ps.reject();
        assert_eq!(evaluate(&mut ps), before);
        assert!(proposal != before || ps.large_step);
    }
}
