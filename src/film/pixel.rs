//! One pixel's beauty samples over one pass, summed by the one task that
//! renders the pixel, in sample order.

use crate::math::color::Rgb;

/// Sums of one pixel's finite radiance samples, their squares (for the
/// per-pixel variance) and the counts of kept and left-out samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelSums {
    /// Sum of the finite samples per channel.
    pub sum: [f64; 3],
    /// Sum of their squares per channel.
    pub squares: [f64; 3],
    /// Finite samples.
    pub count: u32,
    /// NaN or infinite samples, left out.
    pub nonfinite: u32,
    /// Medium lookups (tentative collisions and exact voxel steps) of all
    /// its samples: with `rays`, the adaptive pilot's deterministic measure
    /// of their cost.
    pub lookups: u64,
    /// Rays its samples traced through the geometry (camera, scattered and
    /// shadow rays).
    pub rays: u64,
}

impl PixelSums {
    /// Adds one radiance sample; a NaN or infinite one is only counted, so it
    /// cannot spread into the pixel (or, through filtering, its neighbours).
    #[inline]
    pub fn add(&mut self, l: Rgb) {
        if l.is_finite() {
            for (c, v) in [l.r, l.g, l.b].into_iter().enumerate() {
                let v = v as f64;
                self.sum[c] += v;
                self.squares[c] += v * v;
            }
            self.count += 1;
        } else {
            self.nonfinite += 1;
        }
    }

    /// The sums of `self`'s samples and `other`'s together.
    pub fn pooled(&self, other: &PixelSums) -> PixelSums {
        PixelSums {
            sum: std::array::from_fn(|c| self.sum[c] + other.sum[c]),
            squares: std::array::from_fn(|c| self.squares[c] + other.squares[c]),
            count: self.count + other.count,
            nonfinite: self.nonfinite + other.nonfinite,
            lookups: self.lookups + other.lookups,
            rays: self.rays + other.rays,
        }
    }

    /// Mean of the finite samples (black if there were none).
    pub fn mean(&self) -> Rgb {
        if self.count == 0 {
            return Rgb::BLACK;
        }
        let n = self.count as f64;
        Rgb::new(
            (self.sum[0] / n) as f32,
            (self.sum[1] / n) as f32,
            (self.sum[2] / n) as f32,
        )
    }
}

/// The variance of the mean of `count` samples with sums `sum` and
/// `squares` (the unbiased sample variance over `count`); None below 2 samples.
pub fn variance_of_mean(sum: f64, squares: f64, count: u32) -> Option<f64> {
    if count < 2 {
        return None;
    }
    let n = count as f64;
    let mean = sum / n;
    // Rounding can take the difference a hair below zero for constant samples.
    let variance = ((squares - n * mean * mean) / (n - 1.0)).max(0.0);
    Some(variance / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nonfinite_samples_are_counted_and_left_out() {
        let mut px = PixelSums::default();
        for l in [
            Rgb::new(1.0, 2.0, 3.0),
            Rgb::new(f32::NAN, 0.0, 0.0),
            Rgb::new(0.0, f32::INFINITY, 0.0),
            Rgb::new(0.0, 0.0, f32::NEG_INFINITY),
            Rgb::new(3.0, 2.0, 1.0),
        ] {
            px.add(l);
        }
        assert_eq!((px.count, px.nonfinite), (2, 3));
        assert_eq!(px.mean(), Rgb::new(2.0, 2.0, 2.0));
        assert_eq!(px.squares, [10.0, 8.0, 10.0]);
    }

    #[test]
    fn a_pixel_of_only_nonfinite_samples_is_black_not_nan() {
        let mut px = PixelSums::default();
        px.add(Rgb::new(f32::NAN, f32::NAN, f32::NAN));
        assert_eq!(px.mean(), Rgb::BLACK);
        assert_eq!(px.nonfinite, 1);
    }

    /// Samples 1, 2, 3, 6: mean 3, unbiased variance 14/3, of the mean 14/12.
    #[test]
    fn the_variance_of_the_mean_is_the_sample_variance_over_n() {
        let mut px = PixelSums::default();
        for v in [1.0, 2.0, 3.0, 6.0] {
            px.add(Rgb::splat(v));
        }
        let var = variance_of_mean(px.sum[1], px.squares[1], px.count).unwrap();
        assert!((var - 14.0 / 12.0).abs() < 1e-12, "{var}");
        assert_eq!(variance_of_mean(1.0, 1.0, 1), None);
        assert_eq!(variance_of_mean(4.0, 8.0, 2), Some(0.0));
    }
}
