//! Chi-square goodness-of-fit tests: do a sampler's samples follow its claimed pdf?
//!
//! The idea follows Mitsuba 3's harness: bin the domain, integrate the pdf over
//! each bin numerically for the expected counts, pool cells expecting fewer than
//! 5 samples, form Pearson's statistic and its p-value, and reject when the
//! p-value falls below the Šidák-corrected level of a suite of tests.

use super::quadrature::adaptive_simpson;
use super::Sampler;
use crate::math::{spherical_direction, Vec2, Vec3};
use std::f64::consts::PI;
use std::fmt::Write;

/// Cells expecting fewer samples than this are pooled: Pearson's χ² approximation needs it.
const MIN_EXPECTED: f64 = 5.0;

/// The outcome of one chi-square test.
#[derive(Clone, Debug)]
pub struct Chi2Result {
    /// Pearson's statistic Σ (observed − expected)² / expected over pooled cells.
    pub statistic: f64,
    /// Degrees of freedom: cells after pooling, minus one.
    pub dof: usize,
    /// Probability of a statistic at least this large if the pdf were right.
    pub p_value: f64,
    /// Samples drawn.
    pub sample_count: usize,
    /// Samples that were `None`, non-finite or outside the domain.
    pub invalid_count: usize,
    /// Observed and expected counts per bin, for failure messages.
    pub histogram: String,
}

impl Chi2Result {
    /// True unless the test rejects at level `alpha`, Šidák-corrected for `test_count` tests.
    pub fn passes(&self, alpha: f64, test_count: usize) -> bool {
        self.dof > 0 && self.p_value >= sidak_alpha(alpha, test_count)
    }
}

impl std::fmt::Display for Chi2Result {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "chi2 = {:.3}, dof = {}, p = {:.3e}, samples = {} ({} invalid)",
            self.statistic, self.dof, self.p_value, self.sample_count, self.invalid_count
        )?;
        f.write_str(&self.histogram)
    }
}

/// Per-test level giving family-wise level `alpha` over `test_count` independent tests.
pub fn sidak_alpha(alpha: f64, test_count: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / test_count.max(1) as f64)
}

/// A chi-square test of directions, binned in (cos θ, φ) around +z.
#[derive(Clone, Copy, Debug)]
pub struct SphereChi2 {
    /// Bins in cos θ over [−1, 1].
    pub cos_theta_bins: usize,
    /// Bins in φ over [0, 2π).
    pub phi_bins: usize,
    /// Samples to draw.
    pub sample_count: usize,
    /// Seed of the `Sampler` stream that feeds the sampler.
    pub seed: u64,
}

impl SphereChi2 {
    /// A 10 × 20 binning with the given sample count and seed.
    pub fn new(sample_count: usize, seed: u64) -> SphereChi2 {
        SphereChi2 {
            cos_theta_bins: 10,
            phi_bins: 20,
            sample_count,
            seed,
        }
    }

    /// Tests `sample` (uniform [0, 1)² → direction) against `pdf` (per steradian).
    pub fn run(
        &self,
        mut sample: impl FnMut(Vec2) -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) -> Chi2Result {
        let (n_theta, n_phi) = (self.cos_theta_bins, self.phi_bins);
        let mut observed = vec![0.0; n_theta * n_phi];
        let mut invalid = 0;
        let mut rng = Sampler::from_seed(self.seed);
        for _ in 0..self.sample_count {
            let cell = sample(rng.next_2d()).and_then(|d| {
                let unit = d.is_finite() && (d.length() - 1.0).abs() < 1e-3;
                unit.then(|| {
                    let (d, tau) = (d.as_dvec3(), 2.0 * PI);
                    let i = bin_index((d.z.clamp(-1.0, 1.0) + 1.0) / 2.0, n_theta);
                    let j = bin_index(d.y.atan2(d.x).rem_euclid(tau) / tau, n_phi);
                    i * n_phi + j
                })
            });
            match cell {
                Some(c) => observed[c] += 1.0,
                None => invalid += 1,
            }
        }
        let (dc, dphi) = (2.0 / n_theta as f64, 2.0 * PI / n_phi as f64);
        let density = |c: f64, phi: f64| pdf(spherical_direction(c as f32, phi as f32)) as f64;
        let expected: Vec<f64> = (0..n_theta * n_phi)
            .map(|cell| {
                let (c0, phi0) = (
                    -1.0 + (cell / n_phi) as f64 * dc,
                    (cell % n_phi) as f64 * dphi,
                );
                let over_phi =
                    |c: f64| adaptive_simpson(&|phi| density(c, phi), phi0, phi0 + dphi, 1e-10);
                self.sample_count as f64 * adaptive_simpson(&over_phi, c0, c0 + dc, 1e-9)
            })
            .collect();
        let histogram = format!(
            "observed (rows: cos θ from −1 up, columns: φ from 0)\n{}expected\n{}",
            grid(&observed, n_phi),
            grid(&expected, n_phi)
        );
        finish(&observed, &expected, self.sample_count, invalid, histogram)
    }
}

/// A chi-square test of scalar samples (e.g. distances) on an interval [a, b].
#[derive(Clone, Copy, Debug)]
pub struct IntervalChi2 {
    /// Lower end of the domain.
    pub a: f32,
    /// Upper end of the domain.
    pub b: f32,
    /// Equal-width bins over [a, b].
    pub bins: usize,
    /// Samples to draw.
    pub sample_count: usize,
    /// Seed of the `Sampler` stream that feeds the sampler.
    pub seed: u64,
}

impl IntervalChi2 {
    /// A 40-bin test over [a, b] with the given sample count and seed.
    pub fn new(a: f32, b: f32, sample_count: usize, seed: u64) -> IntervalChi2 {
        IntervalChi2 {
            a,
            b,
            bins: 40,
            sample_count,
            seed,
        }
    }

    /// Tests `sample` (uniform [0, 1) → value) against `pdf` on [a, b].
    pub fn run(
        &self,
        mut sample: impl FnMut(f32) -> Option<f32>,
        pdf: impl Fn(f32) -> f32,
    ) -> Chi2Result {
        let (a, b, n) = (self.a as f64, self.b as f64, self.bins);
        let width = (b - a) / n as f64;
        let mut observed = vec![0.0; n];
        let mut invalid = 0;
        let mut rng = Sampler::from_seed(self.seed);
        for _ in 0..self.sample_count {
            match sample(rng.next_1d()).map(|x| x as f64) {
                Some(x) if (a..=b).contains(&x) => observed[bin_index((x - a) / (b - a), n)] += 1.0,
                _ => invalid += 1,
            }
        }
        let expected: Vec<f64> = (0..n)
            .map(|i| {
                let lo = a + i as f64 * width;
                let integral = adaptive_simpson(&|x| pdf(x as f32) as f64, lo, lo + width, 1e-11);
                self.sample_count as f64 * integral
            })
            .collect();
        let mut histogram = String::from("bin range: observed / expected\n");
        for (i, (o, e)) in observed.iter().zip(&expected).enumerate() {
            let lo = a + i as f64 * width;
            let _ = writeln!(histogram, "[{lo:.4}, {:.4}): {o:.0} / {e:.1}", lo + width);
        }
        finish(&observed, &expected, self.sample_count, invalid, histogram)
    }
}

/// The bin of a position `x` in [0, 1] among `n` equal bins.
fn bin_index(x: f64, n: usize) -> usize {
    ((x * n as f64) as usize).min(n - 1)
}

/// Rows of `values`, `columns` per row, as fixed-width text.
fn grid(values: &[f64], columns: usize) -> String {
    let mut out = String::new();
    for row in values.chunks(columns) {
        for v in row {
            let _ = write!(out, "{v:7.0}");
        }
        out.push('\n');
    }
    out
}

/// Pools sparse cells, then forms the statistic and p-value.
fn finish(
    observed: &[f64],
    expected: &[f64],
    sample_count: usize,
    invalid_count: usize,
    mut histogram: String,
) -> Chi2Result {
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&i, &j| expected[i].total_cmp(&expected[j]));
    let (mut statistic, mut cells) = (0.0, 0usize);
    let (mut pooled_observed, mut pooled_expected) = (0.0, 0.0);
    let mut impossible = 0.0;
    for &i in &order {
        let (o, e) = (observed[i], expected[i]);
        if e <= 0.0 {
            impossible += o;
        } else if e < MIN_EXPECTED || (pooled_expected > 0.0 && pooled_expected < MIN_EXPECTED) {
            // Sorted ascending, so the pool absorbs the sparsest cells until it is large enough.
            pooled_observed += o;
            pooled_expected += e;
        } else {
            statistic += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pooled_expected > 0.0 {
        let d = pooled_observed - pooled_expected;
        statistic += d * d / pooled_expected;
        cells += 1;
    }
    let dof = cells.saturating_sub(1);
    let p_value = if impossible > 0.0 {
        // Samples where the pdf is zero refute it outright, whatever the statistic.
        let _ = writeln!(histogram, "{impossible} samples fell where the pdf is 0");
        0.0
    } else {
        chi2_survival(statistic, dof)
    };
    Chi2Result {
        statistic,
        dof,
        p_value,
        sample_count,
        invalid_count,
        histogram,
    }
}

/// P(X ≥ x) for X chi-square distributed with `dof` degrees of freedom.
pub fn chi2_survival(x: f64, dof: usize) -> f64 {
    regularized_gamma_q(0.5 * dof as f64, 0.5 * x)
}

/// The regularized upper incomplete gamma function Q(a, x) = Γ(a, x) / Γ(a), for a > 0.
///
/// The power series of P = 1 − Q converges fast for x < a + 1; beyond, the
/// continued fraction for Q (evaluated by Lentz's method) does.
pub fn regularized_gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    // x^a e^−x / Γ(a), the common prefactor of both expansions.
    let prefactor = (a * x.ln() - x - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = prefactor · Σ_n x^n / (a (a+1) … (a+n)).
        let (mut term, mut sum, mut denom) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            denom += 1.0;
            term *= x / denom;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - prefactor * sum).max(0.0)
    } else {
        // Q(a, x) = prefactor / (x+1−a − 1(1−a)/(x+3−a − 2(2−a)/(x+5−a − …))).
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            d = if d.abs() < TINY { TINY } else { d };
            c = b + an / c;
            c = if c.abs() < TINY { TINY } else { c };
            d = 1.0 / d;
            let step = d * c;
            h *= step;
            if (step - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

/// ln Γ(x) for x > 0 by the Lanczos approximation (g = 7, 9 terms; ~15 digits).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const COEFFICIENTS: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection Γ(x) Γ(1 − x) = π / sin(πx) keeps the series in its accurate range.
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let z = x - 1.0;
    let series = COEFFICIENTS[1..]
        .iter()
        .enumerate()
        .fold(COEFFICIENTS[0], |acc, (i, &c)| {
            acc + c / (z + i as f64 + 1.0)
        });
    let t = z + G + 0.5;
    0.5 * (2.0 * PI).ln() + (z + 0.5) * t.ln() - t + series.ln()
}

#[cfg(test)]
mod tests;
