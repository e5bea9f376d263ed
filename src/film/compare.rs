//! `brume compare A.exr B.exr`: error statistics between two renders and a
//! false-colour picture of where they differ.
//!
//! B is the reference: the relative MSE divides by B. The statistics use
//! every pixel and every channel of the first RGB layer of each file.

use crate::error::{Error, Result};
use crate::film::image_io;
use crate::math::color::Rgb;
use std::fmt::Write as _;
use std::path::Path;

/// Added to the reference's square in the relative MSE, so black pixels do not dominate.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Error statistics of image A against reference B.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Width and height of both images.
    pub size: (usize, usize),
    /// Root mean square difference over all pixels and channels.
    pub rmse: f64,
    /// Mean over pixels and channels of (a − b)² / (b² + `REL_MSE_EPSILON`).
    pub rel_mse: f64,
    /// Mean of each channel (R, G, B) of A.
    pub mean_a: [f64; 3],
    /// Mean of each channel (R, G, B) of B.
    pub mean_b: [f64; 3],
    /// Largest |a − b| over all channels, and the pixel (x, y) where it is.
    pub max_difference: (f64, (usize, usize)),
    /// Channel values that are NaN or infinite in either image (left out of the sums).
    pub nonfinite: usize,
}

impl Comparison {
    /// The report printed by `brume compare`.
    pub fn report(&self) -> String {
        let mut s = String::new();
        let (w, h) = self.size;
        let _ = writeln!(s, "size            {w}x{h}");
        let _ = writeln!(s, "rmse            {:.6e}", self.rmse);
        let _ = writeln!(s, "relative mse    {:.6e}", self.rel_mse);
        let [r, g, b] = self.mean_a;
        let _ = writeln!(s, "mean A (R G B)  {r:.6} {g:.6} {b:.6}");
        let [r, g, b] = self.mean_b;
        let _ = writeln!(s, "mean B (R G B)  {r:.6} {g:.6} {b:.6}");
        let (d, (x, y)) = self.max_difference;
        let _ = writeln!(s, "max difference  {d:.6e} at pixel {x},{y}");
        if self.nonfinite > 0 {
            let _ = writeln!(s, "non-finite      {} channel values", self.nonfinite);
        }
        s
    }
}

/// Compares two images of equal size, A against the reference B.
pub fn compare(a: &[Rgb], b: &[Rgb], width: usize, height: usize) -> Comparison {
    let (mut se, mut rel, mut n) = (0.0f64, 0.0f64, 0usize);
    let (mut mean_a, mut mean_b) = ([0.0f64; 3], [0.0f64; 3]);
    let mut max_difference = (0.0f64, (0, 0));
    let mut nonfinite = 0;
    for (i, (pa, pb)) in a.iter().zip(b).enumerate() {
        for c in 0..3 {
            let (va, vb) = (pa[c] as f64, pb[c] as f64);
            if !(va.is_finite() && vb.is_finite()) {
                nonfinite += 1;
                continue;
            }
            let d = va - vb;
            se += d * d;
            rel += d * d / (vb * vb + REL_MSE_EPSILON);
            mean_a[c] += va;
            mean_b[c] += vb;
            n += 1;
            if d.abs() > max_difference.0 {
                max_difference = (d.abs(), (i % width, i / width));
            }
        }
    }
    let per_channel = (n as f64 / 3.0).max(1.0);
    Comparison {
        size: (width, height),
        rmse: (se / n.max(1) as f64).sqrt(),
        rel_mse: rel / n.max(1) as f64,
        mean_a: mean_a.map(|v| v / per_channel),
        mean_b: mean_b.map(|v| v / per_channel),
        max_difference,
        nonfinite,
    }
}

/// Reads both files and compares them; images of different sizes are bad input.
pub fn compare_files(a: &Path, b: &Path) -> Result<(Comparison, Vec<Rgb>, Vec<Rgb>)> {
    let (wa, ha, pa) = image_io::read_exr(a)?;
    let (wb, hb, pb) = image_io::read_exr(b)?;
    if (wa, ha) != (wb, hb) {
        return Err(Error::Input {
            path: b.to_path_buf(),
            message: format!(
                "is {wb}x{hb} pixels but {} is {wa}x{ha}: only images of one size can be compared",
                a.display()
            ),
        });
    }
    Ok((compare(&pa, &pb, wa, ha), pa, pb))
}

/// Per-pixel error image: the mean |a − b| over the channels through a
/// black–purple–orange–yellow ramp, saturating at `scale`. Returns 8-bit RGB.
pub fn false_colour(a: &[Rgb], b: &[Rgb], scale: f64) -> Vec<u8> {
    const RAMP: [[f64; 3]; 5] = [
        [0.0, 0.0, 0.02],
        [0.34, 0.06, 0.43],
        [0.73, 0.21, 0.33],
        [0.98, 0.55, 0.04],
        [0.99, 1.0, 0.64],
    ];
    let mut out = Vec::with_capacity(a.len() * 3);
    for (pa, pb) in a.iter().zip(b) {
        let e = pixel_error(pa, pb);
        let t = if e.is_finite() {
            (e / scale.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let f = t * (RAMP.len() - 1) as f64;
        let k = (f.floor() as usize).min(RAMP.len() - 2);
        let w = f - k as f64;
        for (lo, hi) in RAMP[k].iter().zip(&RAMP[k + 1]) {
            out.push(((lo * (1.0 - w) + hi * w) * 255.0 + 0.5) as u8);
        }
    }
    out
}

fn pixel_error(a: &Rgb, b: &Rgb) -> f64 {
    (0..3)
        .map(|c| (a[c] as f64 - b[c] as f64).abs())
        .sum::<f64>()
        / 3.0
}

/// The scale at which the false-colour image saturates: the 99th percentile of the per-pixel error.
pub fn diff_scale(a: &[Rgb], b: &[Rgb]) -> f64 {
    let mut errors: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(pa, pb)| pixel_error(pa, pb))
        .filter(|e| e.is_finite())
        .collect();
    if errors.is_empty() {
        return 1.0;
    }
    errors.sort_by(f64::total_cmp);
    let p99 = errors[((errors.len() - 1) as f64 * 0.99).round() as usize];
    if p99 > 0.0 {
        p99
    } else {
        errors[errors.len() - 1].max(f64::MIN_POSITIVE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_differences_give_known_statistics() {
        let b = vec![Rgb::splat(1.0); 8];
        let mut a = b.clone();
        a[5] = Rgb::new(1.4, 1.0, 1.0);
        let c = compare(&a, &b, 4, 2);
        // One channel value of 24 is off by 0.4.
        assert!((c.rmse - 0.4 / 24f64.sqrt()).abs() < 1e-6, "{c:?}");
        assert!((c.rel_mse - 0.16 / 1.01 / 24.0).abs() < 1e-6);
        assert!((c.mean_a[0] - (7.0 + 1.4) / 8.0).abs() < 1e-6);
        assert_eq!(c.mean_b, [1.0; 3]);
        assert!((c.max_difference.0 - 0.4).abs() < 1e-6);
        assert_eq!(c.max_difference.1, (1, 1));
        assert_eq!(compare(&b, &b, 4, 2).rmse, 0.0);
    }

    #[test]
    fn false_colour_runs_from_black_to_yellow() {
        let b = vec![Rgb::BLACK; 2];
        let a = vec![Rgb::BLACK, Rgb::splat(2.0)];
        let img = false_colour(&a, &b, diff_scale(&a, &b));
        assert_eq!(img.len(), 6);
        assert_eq!(&img[..3], &[0, 0, 5]);
        assert_eq!(&img[3..], &[252, 255, 163]);
    }
}
