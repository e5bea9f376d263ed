//! Piecewise-constant 1-D and 2-D distributions (for importance-sampling images).

use glam::Vec2;

/// A piecewise-constant density on [0, 1) with `n` equal cells.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// Cell weights (non-negative).
    func: Vec<f32>,
    /// Normalized cumulative sums, `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f32>,
    /// Integral of `func` over [0, 1).
    integral: f32,
}

impl Distribution1D {
    /// A distribution proportional to `func`; `None` if it has no positive weight.
    pub fn new(func: &[f32]) -> Option<Distribution1D> {
        let n = func.len();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f32);
        // Accumulate in f64 so long rows keep their small cells.
        let mut acc = 0.0f64;
        let mut sums = Vec::with_capacity(n);
        for &f in func {
            acc += f.max(0.0) as f64 / n as f64;
            sums.push(acc);
        }
        if acc <= 0.0 || !acc.is_finite() {
            return None;
        }
        cdf.extend(sums.iter().map(|&s| (s / acc) as f32));
        cdf[n] = 1.0;
        Some(Distribution1D {
            func: func.iter().map(|f| f.max(0.0)).collect(),
            cdf,
            integral: acc as f32,
        })
    }

    /// Number of cells (at least one: `new` refuses an empty function).
    fn cells(&self) -> usize {
        self.func.len()
    }

    /// Integral of the unnormalized function over [0, 1).
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Density at `x` ∈ [0, 1] (x = 1, where a direction's coordinate can round, is in the last cell).
    pub fn pdf(&self, x: f32) -> f32 {
        let i = ((x * self.cells() as f32) as usize).min(self.cells() - 1);
        self.func[i] / self.integral
    }

    /// Samples x ∈ [0, 1) from `u`: returns (x, density, cell index).
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        // The last cell whose cdf is ≤ u, skipping zero-width cells.
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(self.cells() - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        let t = if width > 0.0 {
            ((u - self.cdf[i]) / width).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let x = ((i as f32 + t) / self.cells() as f32).min(1.0 - f32::EPSILON);
        (x, self.func[i] / self.integral, i)
    }
}

/// A piecewise-constant density on [0, 1)² from a row-major grid of weights.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    /// One conditional distribution in x per row.
    rows: Vec<Distribution1D>,
    /// The marginal distribution of rows (in y).
    marginal: Distribution1D,
}

impl Distribution2D {
    /// A distribution proportional to `func` (`width` × `height`, row 0 at y = 0).
    pub fn new(func: &[f32], width: usize, height: usize) -> Option<Distribution2D> {
        let mut rows = Vec::with_capacity(height);
        let mut row_integrals = Vec::with_capacity(height);
        for row in func.chunks_exact(width).take(height) {
            match Distribution1D::new(row) {
                Some(d) => {
                    row_integrals.push(d.integral());
                    rows.push(d);
                }
                None => {
                    // An all-black row is never chosen; keep a uniform placeholder.
                    row_integrals.push(0.0);
                    rows.push(Distribution1D::new(&vec![1.0; width])?);
                }
            }
        }
        let marginal = Distribution1D::new(&row_integrals)?;
        Some(Distribution2D { rows, marginal })
    }

    /// Samples a point of [0, 1)² with its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (y, pdf_y, row) = self.marginal.sample(u.y);
        let (x, pdf_x, _) = self.rows[row].sample(u.x);
        (Vec2::new(x, y), pdf_x * pdf_y)
    }

    /// Density at `p` ∈ [0, 1]² (coordinates of 1 fall in the last cells).
    pub fn pdf(&self, p: Vec2) -> f32 {
        let row = ((p.y * self.rows.len() as f32) as usize).min(self.rows.len() - 1);
        let pdf_y = self.marginal.pdf(p.y);
        if pdf_y == 0.0 {
            return 0.0;
        }
        pdf_y * self.rows[row].pdf(p.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    #[test]
    fn one_d_samples_land_in_proportion_and_report_their_density() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 0.0]).unwrap();
        let mut s = Sampler::from_seed(1);
        let mut counts = [0usize; 4];
        let n = 40_000;
        for _ in 0..n {
            let (x, pdf, i) = d.sample(s.next_1d());
            assert_eq!(i, (x * 4.0) as usize);
            assert_eq!(pdf, d.pdf(x));
            counts[i] += 1;
        }
        assert_eq!(counts[1] + counts[3], 0);
        // Binomial: p = 1/4, σ = sqrt(n p (1-p)) ≈ 87.
        assert!(
            (counts[0] as f64 - n as f64 / 4.0).abs() < 5.0 * 87.0,
            "{counts:?}"
        );
        assert!(Distribution1D::new(&[0.0, 0.0]).is_none());
    }

    #[test]
    fn two_d_density_integrates_to_one_and_matches_samples() {
        let (w, h) = (5, 3);
        let func: Vec<f32> = (0..w * h).map(|i| ((i * 7) % 4) as f32).collect();
        let d = Distribution2D::new(&func, w, h).unwrap();
        let mut total = 0.0;
        for y in 0..h {
            for x in 0..w {
                let p = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                total += d.pdf(p) / (w * h) as f32;
            }
        }
        assert!((total - 1.0).abs() < 1e-5);
        let mut s = Sampler::from_seed(2);
        for _ in 0..1000 {
            let (p, pdf) = d.sample(s.next_2d());
            assert!((pdf - d.pdf(p)).abs() < 1e-5 * pdf, "{p}");
            assert!(pdf > 0.0);
        }
    }

    #[test]
    fn coordinates_of_one_fall_in_the_last_cells() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]).unwrap();
        assert_eq!(d.pdf(1.0), d.pdf(0.9));
        assert_eq!(d.pdf(1.0), 3.0 / (4.0 / 3.0));
        // 2 × 2, rows from y = 0: the last cell in both coordinates weighs 4 of 10.
        let d = Distribution2D::new(&[1.0, 2.0, 3.0, 4.0], 2, 2).unwrap();
        let last = 4.0 / (10.0 / 4.0);
        for p in [
            Vec2::new(1.0, 1.0),
            Vec2::new(0.75, 1.0),
            Vec2::new(1.0, 0.75),
        ] {
            assert!((d.pdf(p) - last).abs() < 1e-6, "{p}: {}", d.pdf(p));
        }
        // And samples stay below 1: where the last cell is heavier than the
        // average, (n − 1 + t)/n rounds up to 1 for the largest u.
        let u = 1.0 - f32::EPSILON / 2.0;
        for weights in [&[1.0, 3.0][..], &[1.0, 1.0, 10.0], &[1.0, 1.0, 1.0, 100.0]] {
            let (x, _, i) = Distribution1D::new(weights).unwrap().sample(u);
            assert!(
                x < 1.0 && i == weights.len() - 1,
                "{weights:?}: x = {x} in cell {i}"
            );
        }
    }
}
