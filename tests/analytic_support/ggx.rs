//! An independent quadrature of the GGX lobe, in f64 with its own D and Λ.

use brume::sampling::quadrature::gauss_legendre;
use std::f64::consts::PI;

/// GGX single-scattering albedo of a white (F = 1) conductor, by 2-D
/// Gauss–Legendre quadrature of D G2 / (4 cos θo) over the hemisphere, in f64
/// and with its own D and Λ (not brume's).
pub fn ggx_white_albedo(alpha: f64, theta_o: f64, panels: usize) -> f64 {
    let a2 = alpha * alpha;
    let lambda = |cos: f64| {
        let tan2 = (1.0 - cos * cos) / (cos * cos);
        0.5 * ((1.0 + a2 * tan2).sqrt() - 1.0)
    };
    let wo = [theta_o.sin(), 0.0, theta_o.cos()];
    gauss_legendre(
        |mu| {
            gauss_legendre(
                |phi| {
                    let s = (1.0 - mu * mu).sqrt();
                    let wi = [s * phi.cos(), s * phi.sin(), mu];
                    let h = [wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]];
                    let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
                    let hz = h[2] / len;
                    let t = hz * hz * (a2 - 1.0) + 1.0;
                    let d = a2 / (PI * t * t);
                    let g2 = 1.0 / (1.0 + lambda(wo[2]) + lambda(mu));
                    d * g2 / (4.0 * wo[2])
                },
                0.0,
                2.0 * PI,
                panels,
            )
        },
        0.0,
        1.0,
        panels,
    )
}
