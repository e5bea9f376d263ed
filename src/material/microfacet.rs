//! Isotropic microfacet distributions with height-correlated Smith masking:
//! GGX (Trowbridge–Reitz) with visible-normal sampling (Heitz 2018,
//! "Sampling the GGX Distribution of Visible Normals") and Beckmann
//! (`beckmann.rs`, Walter et al. 2007) sampled by D(m) cos θm.
//!
//! Everything here is in the local shading frame: the macro normal is +z and
//! `wo` has z > 0.

use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

/// Which microfacet distribution a rough lobe uses, with which Smith
/// masking–shadowing: height-correlated (brume's) or separable, G1(wo)·G1(wi)
/// (Mitsuba 3's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Distribution {
    /// GGX (Trowbridge–Reitz): brume's default, with energy compensation tables.
    #[default]
    Ggx,
    /// Beckmann (Gaussian slopes): Mitsuba 3's default; single scattering only.
    Beckmann,
    /// GGX with separable masking (single scattering only).
    GgxSeparable,
    /// Beckmann with separable masking.
    BeckmannSeparable,
}

/// A distribution whose masking–shadowing is separable, G1(wo)·G1(wi), as
/// Mitsuba 3's microfacet models have it (the facets' heights uncorrelated;
/// it masks more than the height-correlated form toward grazing angles).
#[derive(Clone, Copy, Debug)]
pub struct Separable<M>(pub M);

impl<M: Microfacet> Microfacet for Separable<M> {
    fn d(&self, m: Vec3) -> f32 {
        self.0.d(m)
    }
    fn lambda(&self, w: Vec3) -> f32 {
        self.0.lambda(w)
    }
    fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.0.g1(wo) * self.0.g1(wi)
    }
    fn normal_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        self.0.normal_pdf(wo, m)
    }
    fn sample_normal(&self, wo: Vec3, u: Vec2) -> Vec3 {
        self.0.sample_normal(wo, u)
    }
    fn sample_weight(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        // The weight is linear in G2: swap the correlated form for the separable one.
        let correlated = self.0.g2(wo, wi);
        if correlated > 0.0 {
            self.0.sample_weight(wo, wi, m) * (self.g2(wo, wi) / correlated)
        } else {
            0.0
        }
    }
}

/// What the rough lobes (`rough.rs`) need of a microfacet distribution.
pub trait Microfacet: Copy {
    /// Microfacet normal density D(m), normalized so that ∫ D(m) cos θm dm = 1.
    fn d(&self, m: Vec3) -> f32;
    /// Smith's Λ(w): masking is G1 = 1 / (1 + Λ).
    fn lambda(&self, w: Vec3) -> f32;
    /// Masking of one direction.
    fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }
    /// Height-correlated masking–shadowing of a pair of directions.
    fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }
    /// Density (solid angle of m) with which `sample_normal` draws `m` seen from `wo`.
    fn normal_pdf(&self, wo: Vec3, m: Vec3) -> f32;
    /// Draws a microfacet normal for `wo` from `u` ∈ [0,1)².
    fn sample_normal(&self, wo: Vec3, u: Vec2) -> Vec3;
    /// `D G2 (wo·m) / (cos θo normal_pdf)`: the weight f cos / pdf of a
    /// direction through `m` once the Fresnel and η factors are taken out.
    fn sample_weight(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32;
}

impl Microfacet for Ggx {
    fn d(&self, m: Vec3) -> f32 {
        Ggx::d(self, m)
    }
    fn lambda(&self, w: Vec3) -> f32 {
        Ggx::lambda(self, w)
    }
    fn normal_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        self.visible_pdf(wo, m)
    }
    fn sample_normal(&self, wo: Vec3, u: Vec2) -> Vec3 {
        self.sample_visible(wo, u)
    }
    fn sample_weight(&self, wo: Vec3, wi: Vec3, _m: Vec3) -> f32 {
        // With visible normals everything but G2 / G1 cancels.
        Ggx::g2(self, wo, wi) / Ggx::g1(self, wo)
    }
}

/// GGX with slope width α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// Width α of the slope distribution (0 < α; 1 is very rough).
    pub alpha: f32,
}

impl Ggx {
    /// Microfacet normal density D(m), normalized so that ∫ D(m) cos θm dm = 1.
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        // D = 1 / (π α² (cos²θ + sin²θ/α²)²), with sin²θ from x and y: the
        // textbook 1 + cos²θ (α² − 1) cancels catastrophically for small α.
        let a2 = self.alpha * self.alpha;
        let t = m.z * m.z + (m.x * m.x + m.y * m.y) / a2;
        1.0 / (PI * a2 * t * t)
    }

    /// Smith's Λ(w): masking is G1 = 1 / (1 + Λ).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (w.x * w.x + w.y * w.y) / cos2;
        0.5 * ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0)
    }

    /// Masking of one direction.
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking–shadowing of a pair of directions.
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of visible normals D_wo(m) = G1(wo) max(0, wo·m) D(m) / cos θo.
    pub fn visible_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        let cos_om = wo.dot(m);
        if cos_om <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * cos_om * self.d(m) / wo.z
    }

    /// Samples a visible normal for `wo` from `u` ∈ [0,1)² (density `visible_pdf`).
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        // Stretch to the hemisphere configuration of α = 1.
        let v = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
        let len2 = v.x * v.x + v.y * v.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-v.y, v.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = v.cross(t1);
        // A uniform disk point, squeezed onto the projected visible half-disk.
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let mut p2 = r * phi.sin();
        let s = 0.5 * (1.0 + v.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * v;
        // Unstretch back to the α ellipsoid.
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(1e-7)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::quadrature::gauss_legendre;

    #[test]
    fn projected_normals_integrate_to_one() {
        for alpha in [0.05f32, 0.2, 0.5, 1.0] {
            let ggx = Ggx { alpha };
            // ∫ D cosθ dω = 2π ∫0^1 D(μ) μ dμ.
            let total = 2.0
                * std::f64::consts::PI
                * gauss_legendre(
                    |mu| {
                        let m = Vec3::new((1.0 - mu * mu).sqrt() as f32, 0.0, mu as f32);
                        ggx.d(m) as f64 * mu
                    },
                    0.0,
                    1.0,
                    400,
                );
            assert!((total - 1.0).abs() < 1e-3, "alpha {alpha}: {total}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        // ∫ D_wo(m) dm = 1 is Smith's G1 being the right normalization for D.
        for alpha in [0.1f32, 0.5, 1.0] {
            for theta in [0.0f32, 0.7, 1.3] {
                let ggx = Ggx { alpha };
                let wo = Vec3::new(theta.sin(), 0.0, theta.cos());
                let total = gauss_legendre(
                    |mu| {
                        gauss_legendre(
                            |phi| {
                                let s = (1.0 - mu * mu).sqrt();
                                let m = Vec3::new(
                                    (s * phi.cos()) as f32,
                                    (s * phi.sin()) as f32,
                                    mu as f32,
                                );
                                ggx.visible_pdf(wo, m) as f64
                            },
                            0.0,
                            2.0 * std::f64::consts::PI,
                            64,
                        )
                    },
                    0.0,
                    1.0,
                    200,
                );
                assert!(
                    (total - 1.0).abs() < 2e-3,
                    "alpha {alpha}, θ {theta}: {total}"
                );
            }
        }
    }
}
