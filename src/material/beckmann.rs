//! The isotropic Beckmann microfacet distribution (Gaussian slopes; Walter et
//! al. 2007, "Microfacet Models for Refraction through Rough Surfaces"), with
//! Smith masking and sampling of D(m) cos θm, whose density is exact.
//!
//! Local shading frame: the macro normal is +z.

use super::microfacet::Microfacet;
use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

/// Beckmann with RMS slope α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beckmann {
    /// RMS slope α (0 < α; 1 is very rough).
    pub alpha: f32,
}

/// The complementary error function, |error| < 1.5e-7 (Abramowitz & Stegun 7.1.26).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.327_591_1 * z);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let r = poly * (-z * z).exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

impl Microfacet for Beckmann {
    fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let cos2 = m.z * m.z;
        let tan2 = (m.x * m.x + m.y * m.y) / cos2;
        let a2 = self.alpha * self.alpha;
        (-tan2 / a2).exp() / (PI * a2 * cos2 * cos2)
    }

    fn lambda(&self, w: Vec3) -> f32 {
        // A direction below the macro surface (a refracted one) is masked
        // by the facets as seen from its own side: Λ depends on |cos θ|,
        // as GGX's does. Refusing it (Λ = ∞) zeroed every transmission.
        if w.z == 0.0 {
            return f32::INFINITY;
        }
        let sin = ((w.x * w.x + w.y * w.y) as f64).sqrt();
        if sin == 0.0 {
            return 0.0;
        }
        // a = 1 / (α tan θ); Λ = (erf(a) − 1)/2 + e^(−a²) / (2a√π), in f64
        // because the two terms nearly cancel for steep directions.
        let a = w.z.abs() as f64 / (self.alpha as f64 * sin);
        let spi = std::f64::consts::PI.sqrt();
        (0.5 * ((-a * a).exp() / (a * spi) - erfc(a))).max(0.0) as f32
    }

    fn normal_pdf(&self, _wo: Vec3, m: Vec3) -> f32 {
        self.d(m) * m.z.max(0.0)
    }

    fn sample_normal(&self, _wo: Vec3, u: Vec2) -> Vec3 {
        // Inverting the cdf of D cos θ: tan²θ = −α² ln(1 − u).
        let tan2 = -self.alpha * self.alpha * (1.0 - u.x).ln();
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
    }

    fn sample_weight(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        // D G2 (wo·m) / (cos θo · D cos θm): D cancels.
        self.g2(wo, wi) * wo.dot(m) / (wo.z * m.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::quadrature::gauss_legendre;
    use std::f64::consts::PI as PI64;

    fn sphere_integral(f: impl Fn(Vec3) -> f64) -> f64 {
        gauss_legendre(
            |mu| {
                gauss_legendre(
                    |phi| {
                        let s = (1.0 - mu * mu).sqrt();
                        f(Vec3::new(
                            (s * phi.cos()) as f32,
                            (s * phi.sin()) as f32,
                            mu as f32,
                        ))
                    },
                    0.0,
                    2.0 * PI64,
                    64,
                )
            },
            0.0,
            1.0,
            400,
        )
    }

    #[test]
    fn projected_normals_integrate_to_one() {
        for alpha in [0.05f32, 0.2, 0.5, 1.0] {
            let b = Beckmann { alpha };
            let total = sphere_integral(|m| b.d(m) as f64 * m.z as f64);
            assert!((total - 1.0).abs() < 1e-3, "alpha {alpha}: {total}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        // ∫ G1(wo) max(0, wo·m) D(m) / cos θo dm = 1 holds only for the right Λ.
        for alpha in [0.1f32, 0.5, 1.0] {
            for theta in [0.0f32, 0.7, 1.3] {
                let b = Beckmann { alpha };
                let wo = Vec3::new(theta.sin(), 0.0, theta.cos());
                let total =
                    sphere_integral(|m| (b.g1(wo) * wo.dot(m).max(0.0) * b.d(m) / wo.z) as f64);
                assert!(
                    (total - 1.0).abs() < 2e-3,
                    "alpha {alpha}, θ {theta}: {total}"
                );
            }
        }
    }

    #[test]
    fn erfc_matches_known_values() {
        // erfc(0) = 1, erfc(1) = 0.157299207, erfc(−0.5) = 1.520499878.
        for (x, v) in [(0.0, 1.0), (1.0, 0.157_299_207), (-0.5, 1.520_499_878)] {
            assert!((erfc(x) - v).abs() < 2e-7, "erfc({x}) = {}", erfc(x));
        }
    }
}
