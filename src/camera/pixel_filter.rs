//! The pixel filter: how much each film point counts toward a pixel.
//! Samples are drawn from the filter itself (importance sampling), so each
//! camera ray still adds to one pixel with weight 1 and the pixel's
//! expectation is ∫ f(p − centre) L(p) dp / ∫ f over the image: what a
//! renderer that splats uniform samples with filter weights and normalizes
//! converges to (Mitsuba's films do), restricted like it to the image.

use crate::math::Vec2;
use std::sync::Arc;

/// Bins of the tabulated 1D cumulative filter.
const BINS: usize = 2048;

/// How a pixel weighs the film around it.
#[derive(Clone, Debug, Default)]
pub enum PixelFilter {
    /// Uniform over the pixel's square.
    #[default]
    Box,
    /// A separable windowed Gaussian (Mitsuba's `gaussian`).
    Gaussian(Arc<Tabulated>),
}

/// A separable 1D filter f(x) on [−radius, radius], tabulated by its integral.
#[derive(Debug)]
pub struct Tabulated {
    radius: f32,
    /// ∫ f from −radius to the bin edges, normalized to end at 1 (`BINS + 1` values).
    cumulative: Vec<f32>,
}

impl PixelFilter {
    /// Mitsuba's Gaussian: standard deviation `stddev` pixels, radius
    /// 4 · stddev, f(x) = max(0, exp(−x²/2σ²) − exp(−r²/2σ²)).
    pub fn gaussian(stddev: f32) -> PixelFilter {
        let (sigma, radius) = (stddev as f64, 4.0 * stddev as f64);
        let bias = (-radius * radius / (2.0 * sigma * sigma)).exp();
        let f = |x: f64| ((-x * x / (2.0 * sigma * sigma)).exp() - bias).max(0.0);
        // Each bin's integral by Simpson's rule, exact far below a bin's share.
        let width = 2.0 * radius / BINS as f64;
        let mut sums = vec![0.0f64; BINS + 1];
        for k in 0..BINS {
            let a = -radius + k as f64 * width;
            let integral = width / 6.0 * (f(a) + 4.0 * f(a + width / 2.0) + f(a + width));
            sums[k + 1] = sums[k] + integral;
        }
        let total = sums[BINS];
        PixelFilter::Gaussian(Arc::new(Tabulated {
            radius: radius as f32,
            cumulative: sums.iter().map(|s| (s / total) as f32).collect(),
        }))
    }

    /// The film point of pixel `(x, y)` for `u` ∈ [0,1)², as an offset from
    /// the pixel's corner, kept inside the `width` × `height` image.
    #[inline]
    pub fn offset(&self, x: u32, y: u32, (width, height): (u32, u32), u: Vec2) -> Vec2 {
        match self {
            PixelFilter::Box => u,
            PixelFilter::Gaussian(table) => {
                // Offsets from the pixel's centre that stay on the image.
                let dx = table.sample(u.x, -(x as f32 + 0.5), width as f32 - x as f32 - 0.5);
                let dy = table.sample(u.y, -(y as f32 + 0.5), height as f32 - y as f32 - 0.5);
                Vec2::new(0.5 + dx, 0.5 + dy)
            }
        }
    }
}

impl Tabulated {
    /// The cumulative filter at `x`.
    fn cdf(&self, x: f32) -> f32 {
        let t = ((x + self.radius) / (2.0 * self.radius) * BINS as f32).clamp(0.0, BINS as f32);
        let k = (t as usize).min(BINS - 1);
        let (a, b) = (self.cumulative[k], self.cumulative[k + 1]);
        a + (b - a) * (t - k as f32)
    }

    /// The offset drawn by `u` from the filter restricted to [lo, hi].
    fn sample(&self, u: f32, lo: f32, hi: f32) -> f32 {
        let (c_lo, c_hi) = (self.cdf(lo), self.cdf(hi));
        let target = c_lo + u * (c_hi - c_lo);
        // The bin holding `target`: the last edge at or below it.
        let k = self.cumulative[1..BINS]
            .partition_point(|&c| c <= target)
            .min(BINS - 1);
        let (a, b) = (self.cumulative[k], self.cumulative[k + 1]);
        let within = if b > a { (target - a) / (b - a) } else { 0.5 };
        let width = 2.0 * self.radius / BINS as f32;
        (-self.radius + (k as f32 + within) * width).clamp(lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Offsets follow the filter: the share of draws within each of 16
    /// slices of [−2, 2] is the filter's integral over it.
    #[test]
    fn gaussian_offsets_follow_the_filter() {
        let filter = PixelFilter::gaussian(0.5);
        let n = 64_000;
        let mut counts = [0usize; 16];
        for i in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, 0.5);
            let d = filter.offset(500, 500, (1000, 1000), u).x - 0.5;
            counts[(((d + 2.0) / 0.25) as usize).min(15)] += 1;
        }
        let f = |x: f64| ((-2.0 * x * x).exp() - (-8.0f64).exp()).max(0.0);
        let total: f64 = (0..40_000).map(|k| f(-2.0 + (k as f64 + 0.5) * 1e-4)).sum();
        for (s, &c) in counts.iter().enumerate() {
            let share: f64 = (0..2_500)
                .map(|k| f(-2.0 + s as f64 * 0.25 + (k as f64 + 0.5) * 1e-4))
                .sum::<f64>()
                / total;
            assert!(
                (c as f64 / n as f64 - share).abs() < 2e-4,
                "slice {s}: {c} vs {share}"
            );
        }
    }

    /// At the image's edge the offsets stay on the image.
    #[test]
    fn offsets_stay_on_the_image() {
        let filter = PixelFilter::gaussian(0.5);
        for i in 0..1000 {
            let u = Vec2::splat((i as f32 + 0.5) / 1000.0);
            let p = filter.offset(0, 3, (4, 4), u);
            assert!(p.x >= 0.0 && p.y <= 1.0 + 0.5 + 1e-6, "{p}");
            assert!(p.y >= -3.0 && p.y < 4.0 - 3.0 + 1e-6, "{p}");
        }
    }
}
