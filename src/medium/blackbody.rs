//! The colour of a blackbody: Planck's law integrated against the CIE 1931
//! colour-matching functions, converted to linear sRGB (Rec. 709 primaries,
//! D65 white).
//!
//! Normalization (what a temperature grid emits): for a temperature T in kelvin,
//!
//! ```text
//! Le(T) = emission_scale · chroma(T) · (T / 1000 K)⁴
//! chroma(T) = max(M · ∫ B(λ, T) (x̄, ȳ, z̄)(λ) dλ, 0) / luminance(same)
//! ```
//!
//! so chroma(T) is the blackbody's colour with luminance 0.2126 R + 0.7152 G +
//! 0.0722 B = 1 (negative sRGB components, out of gamut below about 1900 K, are
//! clamped to 0 before normalizing), and brightness follows Stefan–Boltzmann's
//! T⁴ relative to 1000 K. The integral runs over 360–830 nm in 1 nm steps with
//! the multi-lobe Gaussian fit of the CIE 1931 2° functions (Wyman, Sloan and
//! Shirley 2013, JCGT 2(2)); M is the XYZ → linear sRGB matrix of IEC 61966-2-1.
//! T ≤ 0 emits nothing.

use crate::math::color::Rgb;

/// Second radiation constant c₂ = h·c/k in nm·K.
const C2: f64 = 1.438_776_877e7;

/// One asymmetric Gaussian lobe of the Wyman et al. fit.
fn lobe(lambda: f64, mu: f64, sigma_lo: f64, sigma_hi: f64) -> f64 {
    let s = if lambda < mu { sigma_lo } else { sigma_hi };
    let x = (lambda - mu) / s;
    (-0.5 * x * x).exp()
}

/// The CIE 1931 2° colour-matching functions (x̄, ȳ, z̄) at `lambda` nm (Wyman et al. 2013 fit).
pub fn cie_xyz_bar(lambda: f64) -> [f64; 3] {
    let x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
        - 0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    [x, y, z]
}

/// Planck's spectral radiance at `lambda` nm and `t` K, divided by its value at 830 nm
/// (a scale that keeps the arithmetic finite at any temperature; colour ignores it).
fn planck_relative(lambda: f64, t: f64) -> f64 {
    let (a, b) = (C2 / (lambda * t), C2 / (830.0 * t));
    // B(λ)/B(830) = (830/λ)⁵ (e^b - 1)/(e^a - 1) = (830/λ)⁵ e^(b-a) (1 - e^-b)/(1 - e^-a)
    (830.0 / lambda).powi(5) * (b - a).exp() * (-(-b).exp_m1()) / (-(-a).exp_m1())
}

/// XYZ tristimulus values of a blackbody at `t` K, up to a common factor.
pub fn blackbody_xyz(t: f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for nm in 360..=830 {
        let lambda = nm as f64;
        let b = planck_relative(lambda, t);
        let bar = cie_xyz_bar(lambda);
        for c in 0..3 {
            xyz[c] += b * bar[c];
        }
    }
    xyz
}

/// Linear sRGB from CIE XYZ (IEC 61966-2-1).
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = xyz;
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

/// chroma(T): the blackbody colour at `t` K in linear sRGB, clamped to ≥ 0 and scaled to luminance 1.
pub fn blackbody_chroma(t: f64) -> Rgb {
    if t.is_nan() || t <= 0.0 {
        return Rgb::BLACK;
    }
    let rgb = xyz_to_linear_srgb(blackbody_xyz(t)).map(|c| c.max(0.0));
    let luminance = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    if luminance.is_nan() || luminance <= 0.0 || !luminance.is_finite() {
        return Rgb::BLACK;
    }
    Rgb::new(
        (rgb[0] / luminance) as f32,
        (rgb[1] / luminance) as f32,
        (rgb[2] / luminance) as f32,
    )
}

/// Le(T) / emission_scale = chroma(T) · (T / 1000 K)⁴.
pub fn blackbody_emission(t: f64) -> Rgb {
    blackbody_chroma(t) * ((t / 1000.0).powi(4) as f32)
}

/// `blackbody_emission` tabulated over `[0, t_max]` K and interpolated linearly,
/// so that lookups in the tracking loop cost no spectral integral.
#[derive(Clone, Debug)]
pub struct BlackbodyTable {
    t_max: f32,
    values: Vec<Rgb>,
}

/// Intervals of a [`BlackbodyTable`].
const TABLE_STEPS: usize = 2048;

impl BlackbodyTable {
    /// Tabulates temperatures up to `t_max` K (larger ones are clamped to it).
    pub fn new(t_max: f32) -> BlackbodyTable {
        let t_max = t_max.max(1.0);
        let values = (0..=TABLE_STEPS)
            .map(|i| blackbody_emission(t_max as f64 * i as f64 / TABLE_STEPS as f64))
            .collect();
        BlackbodyTable { t_max, values }
    }

    /// Le(T) / emission_scale at `t` K.
    #[inline]
    pub fn lookup(&self, t: f32) -> Rgb {
        if t.is_nan() || t <= 0.0 {
            return Rgb::BLACK;
        }
        let x = (t / self.t_max).min(1.0) * TABLE_STEPS as f32;
        let i = (x as usize).min(TABLE_STEPS - 1);
        let w = x - i as f32;
        self.values[i] * (1.0 - w) + self.values[i + 1] * w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CIE illuminant A is a 2856 K blackbody at chromaticity (0.44757, 0.40745).
    #[test]
    fn illuminant_a_chromaticity() {
        let [x, y, z] = blackbody_xyz(2856.0);
        let s = x + y + z;
        assert!((x / s - 0.44757).abs() < 2e-3, "x = {}", x / s);
        assert!((y / s - 0.40745).abs() < 2e-3, "y = {}", y / s);
    }

    /// Planck's law as written, B(λ) ∝ λ⁻⁵ / (e^(c₂/λT) − 1), against the
    /// rearranged ratio B(λ)/B(830 nm), from 1000 K (Wien's regime) to
    /// 10⁵ K (where the −1 matters at every visible wavelength).
    #[test]
    fn planck_relative_is_plancks_law_over_its_value_at_830_nm() {
        let planck = |lambda: f64, t: f64| lambda.powi(-5) / ((C2 / (lambda * t)).exp() - 1.0);
        for t in [1000.0, 2856.0, 6500.0, 20_000.0, 1e5] {
            for nm in (360..=830).step_by(10) {
                let lambda = nm as f64;
                let want = planck(lambda, t) / planck(830.0, t);
                let got = planck_relative(lambda, t);
                assert!(
                    (got - want).abs() <= 1e-12 * want,
                    "{t} K, {nm} nm: {got} vs {want}"
                );
            }
        }
    }

    /// T ≤ 0 and NaN emit nothing (a temperature grid's trilinear lookup can
    /// go negative): neither the colour nor the table extrapolates below 0 K
    /// (negative emission) or reads NaN as the hottest entry.
    #[test]
    fn non_positive_and_nan_temperatures_emit_nothing() {
        let table = BlackbodyTable::new(4000.0);
        for t in [-500.0f32, -1e-3, 0.0, f32::NAN] {
            assert_eq!(blackbody_chroma(t as f64), Rgb::BLACK, "chroma at {t} K");
            assert_eq!(table.lookup(t), Rgb::BLACK, "table at {t} K");
        }
    }

    #[test]
    fn chroma_has_unit_luminance_and_table_matches() {
        for t in [800.0, 1500.0, 3000.0, 6500.0, 12000.0] {
            assert!((blackbody_chroma(t).luminance() - 1.0).abs() < 1e-5);
        }
        let table = BlackbodyTable::new(4000.0);
        let exact = blackbody_emission(2345.6);
        let tab = table.lookup(2345.6);
        for c in 0..3 {
            assert!((tab[c] - exact[c]).abs() <= 1e-3 * exact[c].abs().max(1e-3));
        }
    }
}
