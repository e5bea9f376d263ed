//! Deterministic 1D quadrature in f64, for normalization checks and chi-square bins.

/// Nodes and weights of the `n`-point Gauss–Legendre rule on [−1, 1].
pub fn gauss_legendre_rule(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            // Newton's method on P_n from the classical cosine guess converges in a few steps.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                let (p_n, p_prev) = legendre(n, x);
                derivative = n as f64 * (x * p_n - p_prev) / (x * x - 1.0);
                let step = p_n / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}

/// `(P_n(x), P_{n−1}(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p_prev, mut p) = (1.0, x);
    for k in 2..=n {
        let k = k as f64;
        let next = ((2.0 * k - 1.0) * x * p - (k - 1.0) * p_prev) / k;
        p_prev = p;
        p = next;
    }
    (p, p_prev)
}

/// Composite 8-point Gauss–Legendre quadrature of `f` over [a, b] with `panels` equal panels.
///
/// Exact for polynomials of degree 15 on each panel; for smooth integrands the
/// error falls like `panels^−16`, so doubling `panels` and comparing is a sharp
/// error estimate.
pub fn gauss_legendre(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let rule = gauss_legendre_rule(8);
    let h = (b - a) / panels as f64;
    (0..panels)
        .map(|k| {
            let mid = a + (k as f64 + 0.5) * h;
            rule.iter()
                .map(|&(x, w)| w * f(mid + 0.5 * h * x))
                .sum::<f64>()
                * 0.5
                * h
        })
        .sum()
}

/// Adaptive Simpson quadrature of `f` over [a, b] to absolute tolerance `tol`.
///
/// Always subdivides to at least 2^4 intervals so that a narrow peak between
/// the first few nodes is not mistaken for a flat function. A piece also stops
/// once its error estimate is below 1e-7 of its value: integrands evaluated in
/// f32 carry that much noise, and chasing a tighter absolute tolerance through
/// noise would subdivide to the depth limit everywhere.
pub fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let m = 0.5 * (a + b);
    simpson_step(f, [a, m, b], [f(a), f(m), f(b)], tol, 0)
}

const MIN_DEPTH: u32 = 4;
const MAX_DEPTH: u32 = 24;
const RELATIVE_FLOOR: f64 = 1e-7;

fn simpson_step(
    f: &dyn Fn(f64) -> f64,
    [a, m, b]: [f64; 3],
    [fa, fm, fb]: [f64; 3],
    tol: f64,
    depth: u32,
) -> f64 {
    // Recomputed, not passed down: it is the parent's `left` or `right`, the same
    // expression on the same values, so the same bits.
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    // Richardson: the error of the refined estimate is about delta / 15.
    let converged = delta.abs() <= 15.0 * tol.max(RELATIVE_FLOOR * (left + right).abs());
    if depth >= MAX_DEPTH || (depth >= MIN_DEPTH && converged) {
        return left + right + delta / 15.0;
    }
    simpson_step(f, [a, lm, m], [fa, flm, fm], 0.5 * tol, depth + 1)
        + simpson_step(f, [m, rm, b], [fm, frm, fb], 0.5 * tol, depth + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_weights_and_exactness() {
        let rule = gauss_legendre_rule(8);
        assert!((rule.iter().map(|r| r.1).sum::<f64>() - 2.0).abs() < 1e-14);
        // Degree 15 is integrated exactly by one 8-point panel: ∫_0^1 x^15 = 1/16.
        let one_panel = gauss_legendre(|x| x.powi(15), 0.0, 1.0, 1);
        assert!((one_panel - 1.0 / 16.0).abs() < 1e-14);
    }

    #[test]
    fn each_rule_is_exact_to_degree_2n_minus_1_and_no_further() {
        for n in 1..=12 {
            let rule = gauss_legendre_rule(n);
            // ∫_{−1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k.
            let moment = |k: i32| rule.iter().map(|&(x, w)| w * x.powi(k)).sum::<f64>();
            let exact = |k: i32| {
                if k % 2 == 0 {
                    2.0 / (k + 1) as f64
                } else {
                    0.0
                }
            };
            for k in 0..2 * n as i32 {
                assert!((moment(k) - exact(k)).abs() < 1e-13, "n = {n}, x^{k}");
            }
            // The n-point rule misses x^2n by 2^(2n+1) (n!)^4 / ((2n+1) ((2n)!)^2), ≥ 1.8e−7 up to n = 12.
            let k = 2 * n as i32;
            assert!(
                (moment(k) - exact(k)).abs() > 1e-10,
                "n = {n} exact for x^{k}"
            );
        }
    }

    #[test]
    fn gauss_legendre_panels_tile_an_interval_away_from_zero() {
        let e = std::f64::consts::E;
        for panels in [1, 3, 8] {
            let integral = gauss_legendre(f64::exp, 1.0, 3.0, panels);
            assert!(
                (integral / (e.powi(3) - e) - 1.0).abs() < 1e-12,
                "{panels} panels"
            );
        }
        // Degree 15 on each of 3 panels of [−2, 1]: ∫ x^15 = (1 − 2^16) / 16.
        let integral = gauss_legendre(|x| x.powi(15), -2.0, 1.0, 3);
        assert!((integral / ((1.0 - 65536.0) / 16.0) - 1.0).abs() < 1e-13);
    }

    #[test]
    fn adaptive_simpson_is_exact_for_cubics_at_its_minimum_depth() {
        let evaluations = std::cell::Cell::new(0);
        let cubic = |x: f64| {
            // Densities are often undefined outside their interval.
            assert!((3.0..=5.0).contains(&x), "evaluated at {x}, outside [3, 5]");
            evaluations.set(evaluations.get() + 1);
            1.0 - 2.0 * x + 3.0 * x * x * x
        };
        // ∫_3^5 = [x − x² + ¾x⁴]_3^5 = 448.75 − 54.75. (On [3, 5] a midpoint
        // mistaken for a·b or a + b + ½ lies outside the interval.)
        assert!((adaptive_simpson(&cubic, 3.0, 5.0, 1e-10) - 394.0).abs() < 1e-10);
        // Simpson's rule is exact for cubics, so every piece stops at depth 4:
        // 3 evaluations, then 2 in each of the 1 + 2 + 4 + 8 + 16 steps.
        assert_eq!(evaluations.get(), 3 + 2 * 31);
    }

    #[test]
    fn adaptive_simpson_adds_the_richardson_correction() {
        // Simpson's rule plus delta/15 is Boole's rule, exact for quintics; with
        // a loose tolerance every piece stops at depth 4, where Simpson alone
        // is off by about 2e−9 of the value.
        let quintic = |x: f64| x.powi(5);
        let exact = (5f64.powi(6) - 3f64.powi(6)) / 6.0;
        let integral = adaptive_simpson(&quintic, 3.0, 5.0, 1e-3);
        assert!(
            (integral / exact - 1.0).abs() < 1e-13,
            "{integral} against {exact}"
        );
    }

    #[test]
    fn adaptive_simpson_stops_at_the_relative_floor_on_noisy_integrands() {
        let evaluations = std::cell::Cell::new(0);
        // Noise of ±0.5e−8 (a hash of x), like the rounding of an integrand computed in f32,
        // over an interval short enough that each piece's value is far below 1.
        let noisy = |x: f64| {
            evaluations.set(evaluations.get() + 1);
            let hash = x.to_bits().wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 11;
            1.0 + 1e-8 * (hash as f64 / (1u64 << 53) as f64 - 0.5)
        };
        // No absolute tolerance: only the floor of 1e−7 of each piece's value stops it.
        assert!((adaptive_simpson(&noisy, 0.0, 0.01, 0.0) - 0.01).abs() < 1e-9);
        assert_eq!(evaluations.get(), 3 + 2 * 31);
    }

    #[test]
    fn adaptive_simpson_handles_peaks_and_jumps() {
        let peak = |x: f64| 1e-3 / (std::f64::consts::PI * (1e-6 + (x - 0.3) * (x - 0.3)));
        // ∫ of the Cauchy density over [0, 1] = (atan(0.7/1e-3) + atan(0.3/1e-3)) / π.
        let exact = ((0.7f64 / 1e-3).atan() + (0.3f64 / 1e-3).atan()) / std::f64::consts::PI;
        assert!((adaptive_simpson(&peak, 0.0, 1.0, 1e-10) - exact).abs() < 1e-7);
        let step = |x: f64| if x < 0.123 { 1.0 } else { 0.0 };
        assert!((adaptive_simpson(&step, 0.0, 1.0, 1e-10) - 0.123).abs() < 1e-7);
    }
}
