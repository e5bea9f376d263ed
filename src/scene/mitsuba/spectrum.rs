//! `<spectrum>` in Mitsuba's RGB mode.
//!
//! Mitsuba's scene-format documentation: `value="400:0.56, 500:0.18, ..."`
//! lists wavelength (nm):value pairs, linearly interpolated between them and
//! zero outside the listed range; one number is a flat spectrum. In its RGB
//! variants a flat spectrum is that grey, and a list is projected onto the
//! CIE 1931 2° colour-matching functions over 360–830 nm, normalised by
//! ∫ȳ (an equal-energy spectrum of 1 has Y = 1; no illuminant weighs the
//! spectrum), and converted XYZ → linear sRGB (Rec. 709 primaries, D65
//! white). The integral here takes 1 nm steps over the 5 nm table
//! (`cie1931`), interpolated linearly; values are not clamped (brume's
//! own checks refuse a reflectance outside [0, 1] where it matters).

mod cie1931;

use super::mechanics::Node;
use super::numbers::number;
use crate::error::Result;
use crate::medium::blackbody::xyz_to_linear_srgb;
use cie1931::{CIE_1931, CIE_FIRST_NM, CIE_STEP_NM};

/// The RGB of `<spectrum value>`: one number is a flat spectrum (grey),
/// wavelength:value pairs are projected as in Mitsuba's RGB mode.
pub(crate) fn to_rgb(node: &Node, value: &str) -> Result<[f64; 3]> {
    if !value.contains(':') {
        return Ok([number(node, value)?; 3]);
    }
    let pairs = pairs(node, value)?;
    Ok(xyz_to_linear_srgb(spectrum_xyz(&pairs)))
}

/// The (wavelength, value) pairs of `value`, wavelengths increasing.
fn pairs(node: &Node, value: &str) -> Result<Vec<(f64, f64)>> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for item in value.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((w, v)) = item.split_once(':') else {
            return Err(node.error(format!(
                "`{item}` is not wavelength:value (every entry of a spectrum list needs both)"
            )));
        };
        let (w, v) = (number(node, w)?, number(node, v)?);
        if out.last().is_some_and(|&(prev, _)| w <= prev) {
            return Err(node.error(format!(
                "wavelength {w} after {}: a spectrum's wavelengths must increase",
                out.last().map_or(0.0, |p| p.0)
            )));
        }
        out.push((w, v));
    }
    Ok(out)
}

/// The piecewise-linear spectrum of `pairs` at `lambda` (zero outside them).
fn spectrum_at(pairs: &[(f64, f64)], lambda: f64) -> f64 {
    let (first, last) = (pairs[0], pairs[pairs.len() - 1]);
    if lambda < first.0 || lambda > last.0 {
        return 0.0;
    }
    let i = pairs.partition_point(|p| p.0 <= lambda);
    if i == 0 || i == pairs.len() {
        return if i == 0 { first.1 } else { last.1 };
    }
    let ((w0, v0), (w1, v1)) = (pairs[i - 1], pairs[i]);
    v0 + (v1 - v0) * (lambda - w0) / (w1 - w0)
}

/// (x̄, ȳ, z̄) at `lambda` nm, linear between the 5 nm entries, zero outside 360–830.
pub(crate) fn cmf(lambda: f64) -> [f64; 3] {
    let u = (lambda - CIE_FIRST_NM) / CIE_STEP_NM;
    if !(0.0..=(CIE_1931.len() - 1) as f64).contains(&u) {
        return [0.0; 3];
    }
    let i = (u as usize).min(CIE_1931.len() - 2);
    let f = u - i as f64;
    let (a, b) = (CIE_1931[i], CIE_1931[i + 1]);
    [0, 1, 2].map(|c| a[c] + f * (b[c] - a[c]))
}

/// XYZ of the spectrum, normalised so that a spectrum of 1 everywhere has Y = 1.
fn spectrum_xyz(pairs: &[(f64, f64)]) -> [f64; 3] {
    let (mut xyz, mut y_norm) = ([0.0; 3], 0.0);
    for nm in 360..=830 {
        let lambda = nm as f64;
        let bar = cmf(lambda);
        let s = spectrum_at(pairs, lambda);
        for c in 0..3 {
            xyz[c] += s * bar[c];
        }
        y_norm += bar[1];
    }
    xyz.map(|v| v / y_norm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_has_the_published_sums() {
        // Column sums of the CVRL 5 nm table, a check of its transcription.
        let sums = [0, 1, 2].map(|c| CIE_1931.iter().map(|r| r[c]).sum::<f64>());
        let published = [21.373139988621006, 21.371407850470007, 21.378664308989997];
        for c in 0..3 {
            assert!((sums[c] - published[c]).abs() < 1e-12, "{sums:?}");
        }
        assert_eq!(cmf(555.0), [0.5120501, 1.0, 0.005749999]);
        assert_eq!(cmf(357.0), [0.0; 3]);
    }

    #[test]
    fn a_spectrum_is_linear_between_its_pairs_and_zero_outside() {
        let p = [(400.0, 1.0), (500.0, 3.0), (600.0, 0.0)];
        assert_eq!(spectrum_at(&p, 450.0), 2.0);
        assert_eq!(spectrum_at(&p, 400.0), 1.0);
        assert_eq!(spectrum_at(&p, 600.0), 0.0);
        assert_eq!(spectrum_at(&p, 399.0), 0.0);
        assert_eq!(spectrum_at(&p, 550.0), 1.5);
    }

    #[test]
    fn an_equal_energy_spectrum_has_unit_luminance_and_e_white_chromaticity() {
        let xyz = spectrum_xyz(&[(360.0, 1.0), (830.0, 1.0)]);
        assert!((xyz[1] - 1.0).abs() < 1e-12, "{xyz:?}");
        // The CMFs have (almost) equal integrals: illuminant E is x = y = 1/3.
        assert!(
            (xyz[0] - 1.0).abs() < 2e-3 && (xyz[2] - 1.0).abs() < 2e-3,
            "{xyz:?}"
        );
        // Half the range gives the ȳ mass of that half.
        let half = spectrum_xyz(&[(360.0, 1.0), (555.0, 1.0)]);
        assert!(half[1] > 0.4 && half[1] < 0.6, "{half:?}");
    }
}
