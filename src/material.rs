//! BSDFs: Lambertian, normalized Phong lobe and perfect mirror.
//!
//! Directions are world-space unit vectors; `wo` points back along the
//! arriving path (toward the previous vertex), `wi` toward the next one.
//! `n` is the shading normal already flipped to the side of `wo`.

use crate::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::{FRAC_1_PI, PI};

/// A surface's scattering model.
#[derive(Clone, Copy, Debug)]
pub enum Material {
    /// Lambertian reflector: `f = albedo / π`.
    Diffuse {
        /// Reflectance in [0, 1].
        albedo: Rgb,
    },
    /// Energy-normalized Phong lobe around the mirror direction: `f = albedo (e+2)/(2π) cos^e α`.
    Phong {
        /// Reflectance at normal incidence in [0, 1].
        albedo: Rgb,
        /// Lobe exponent e ≥ 0 (larger is shinier).
        exponent: f32,
    },
    /// Perfect specular reflector.
    Mirror {
        /// Reflectance in [0, 1].
        reflectance: Rgb,
    },
}

/// A direction sampled from a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled direction (toward the next vertex).
    pub wi: Vec3,
    /// `f · cosθi / pdf`.
    pub weight: Rgb,
    /// Solid-angle density (1 for the delta mirror, where MIS does not apply).
    pub pdf: f32,
    /// True for a Dirac lobe.
    pub is_delta: bool,
}

/// Mirror direction of `wo` about `n`.
#[inline]
fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

impl Material {
    /// True when the BSDF is a Dirac delta (no evaluation, no light sampling).
    pub fn is_delta(&self) -> bool {
        matches!(self, Material::Mirror { .. })
    }

    /// `f(wo, wi) · cosθi`, zero for directions below the surface.
    pub fn eval(&self, n: Vec3, wo: Vec3, wi: Vec3) -> Rgb {
        let cos_i = n.dot(wi);
        if cos_i <= 0.0 || n.dot(wo) <= 0.0 {
            return Rgb::BLACK;
        }
        match *self {
            Material::Diffuse { albedo } => albedo * (FRAC_1_PI * cos_i),
            Material::Phong { albedo, exponent } => {
                let cos_alpha = reflect(wo, n).dot(wi).max(0.0);
                albedo * ((exponent + 2.0) / (2.0 * PI) * cos_alpha.powf(exponent) * cos_i)
            }
            Material::Mirror { .. } => Rgb::BLACK,
        }
    }

    /// Solid-angle density of `sample` producing `wi`.
    pub fn pdf(&self, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        if n.dot(wi) <= 0.0 || n.dot(wo) <= 0.0 {
            return 0.0;
        }
        match *self {
            Material::Diffuse { .. } => n.dot(wi) * FRAC_1_PI,
            Material::Phong { exponent, .. } => {
                let cos_alpha = reflect(wo, n).dot(wi).max(0.0);
                (exponent + 1.0) / (2.0 * PI) * cos_alpha.powf(exponent)
            }
            Material::Mirror { .. } => 0.0,
        }
    }

    /// Samples `wi` proportionally to the BSDF (times cosine for the diffuse lobe).
    pub fn sample(&self, n: Vec3, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if n.dot(wo) <= 0.0 {
            return None;
        }
        match *self {
            Material::Diffuse { albedo } => {
                let local = warp::square_to_cosine_hemisphere(u);
                if local.z <= 0.0 {
                    return None;
                }
                Some(BsdfSample {
                    wi: Frame::from_z(n).to_world(local),
                    weight: albedo,
                    pdf: warp::cosine_hemisphere_pdf(local),
                    is_delta: false,
                })
            }
            Material::Phong { albedo, exponent } => {
                let r = reflect(wo, n);
                let cos_alpha = u.x.powf(1.0 / (exponent + 1.0));
                let local = crate::math::spherical_direction(cos_alpha, 2.0 * PI * u.y);
                let wi = Frame::from_z(r).to_world(local);
                let cos_i = n.dot(wi);
                if cos_i <= 0.0 {
                    return None;
                }
                let pdf = (exponent + 1.0) / (2.0 * PI) * cos_alpha.powf(exponent);
                Some(BsdfSample {
                    wi,
                    weight: albedo * ((exponent + 2.0) / (exponent + 1.0) * cos_i),
                    pdf,
                    is_delta: false,
                })
            }
            Material::Mirror { reflectance } => Some(BsdfSample {
                wi: reflect(wo, n),
                weight: reflectance,
                pdf: 1.0,
                is_delta: true,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    /// Checks weight = eval / pdf and pdf consistency for sampled directions.
    fn check_consistency(m: Material) {
        let n = Vec3::new(0.2, 0.9, -0.1).normalize();
        let wo = Vec3::new(-0.5, 0.7, 0.3).normalize();
        let mut s = Sampler::from_seed(9);
        for _ in 0..2000 {
            if let Some(bs) = m.sample(n, wo, s.next_2d()) {
                let pdf = m.pdf(n, wo, bs.wi);
                assert!(
                    (pdf - bs.pdf).abs() <= 1e-3 * pdf.max(1.0),
                    "{pdf} vs {}",
                    bs.pdf
                );
                let expected = m.eval(n, wo, bs.wi) / bs.pdf;
                assert!((expected - bs.weight).max_channel().abs() < 1e-3);
            }
        }
    }

    #[test]
    fn sampling_matches_eval_and_pdf() {
        check_consistency(Material::Diffuse {
            albedo: Rgb::new(0.2, 0.5, 0.9),
        });
        for exponent in [0.0, 1.0, 10.0, 200.0] {
            check_consistency(Material::Phong {
                albedo: Rgb::splat(0.8),
                exponent,
            });
        }
    }

    #[test]
    fn phong_albedo_at_normal_incidence_is_its_albedo() {
        // ∫ f cosθ dω by Monte Carlo over the lobe sampler: the weight's mean.
        let m = Material::Phong {
            albedo: Rgb::WHITE,
            exponent: 20.0,
        };
        let mut s = Sampler::from_seed(2);
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let w = m
                .sample(Vec3::Z, Vec3::Z, s.next_2d())
                .map_or(0.0, |b| b.weight.r as f64);
            sum += w;
            sum2 += w * w;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!((mean - 1.0).abs() < 4.0 * se + 1e-6, "{mean} ± {se}");
    }

    #[test]
    fn mirror_reflects() {
        let m = Material::Mirror {
            reflectance: Rgb::WHITE,
        };
        let wo = Vec3::new(1.0, 1.0, 0.0).normalize();
        let bs = m.sample(Vec3::Y, wo, Vec2::ZERO).unwrap();
        assert!((bs.wi - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        assert!(bs.is_delta);
    }
}
