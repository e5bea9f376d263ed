//! What light tracing needs of a BSDF: sampling the direction light leaves
//! in, given the one it arrives from, with the radiance BSDF's value (the
//! adjoint of the path tracer's sampling), and the probability of a delta
//! lobe, which bidirectional MIS weighs like a density.
//!
//! Every BSDF here is sampled through [`Material::sample`] with the roles of
//! the directions swapped. Reflection is reciprocal, so its weight carries
//! over; refraction is not. A non-delta lobe's weight is the radiance
//! BSDF of the pair as the light crosses it, f(wo, wi)·|n·wi| / pdf, and a
//! smooth interface's refraction weight is that expression's limit:
//! the path tracer's 1/η² times the η² of the BSDF's non-symmetry
//! (f(a→b)/η_b² = f(b→a)/η_a², Veach 1997, ch. 5), leaving
//! |n·wi| / |n·wo|, the ratio of the arriving and leaving cosines. (An
//! earlier η² weight was right only where a light path crossed glass twice
//! through parallel or spherical faces, where the cosines cancel; a lamp
//! inside glass came out 2.8× too dark.)

use super::{fresnel, relative_eta, BsdfSample, Material, Shading};
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};

impl Material {
    /// Samples the direction `wo` light leaves in after arriving from
    /// `wi` (toward the light), at a surface with outward shading normal
    /// `normal`. The weight is `f(wo, wi)·|n·wi| / pdf` with the radiance
    /// BSDF `f` of [`Material::eval`], the pdf that of `wo` given `wi`.
    pub fn sample_adjoint(
        &self,
        normal: Vec3,
        wi: Vec3,
        u: Vec2,
        u_lobe: f32,
    ) -> Option<BsdfSample> {
        let sp = Shading::facing(normal, wi);
        let s = self.sample(&sp, wi, u, u_lobe)?;
        let weight = if s.is_delta {
            let crossed = sp.n.dot(s.wi) < 0.0;
            match (*self, crossed) {
                // The smooth interface's transmission: the inverse of the path tracer's compression.
                (Material::Dielectric { .. }, true) => {
                    let cos_out = sp.n.dot(s.wi).abs();
                    if cos_out <= 0.0 {
                        return None;
                    }
                    Rgb::splat(sp.n.dot(wi).abs() / cos_out)
                }
                _ => s.weight,
            }
        } else {
            if s.pdf <= 0.0 {
                return None;
            }
            self.eval(&Shading::facing(normal, s.wi), s.wi, wi) / s.pdf
        };
        Some(BsdfSample { weight, ..s })
    }

    /// Probability that sampling at a delta surface from `wo` picks the lobe
    /// that leads to `wi` (1 for mirrors, F or 1 − F for a smooth dielectric, R' or 1 − R' for a thin sheet);
    /// 0 for BSDFs that are not delta.
    pub fn delta_pdf(&self, sp: &Shading, wo: Vec3, wi: Vec3) -> f32 {
        if !self.is_delta() {
            return 0.0;
        }
        match *self {
            Material::Dielectric { ior, .. } => {
                let f = fresnel::dielectric(sp.n.dot(wo), relative_eta(ior, sp));
                if sp.n.dot(wi) >= 0.0 {
                    f
                } else {
                    1.0 - f
                }
            }
            Material::ThinDielectric { ior } => {
                let r = super::layered::thin_reflectance(sp.n.dot(wo), ior);
                if sp.n.dot(wi) >= 0.0 {
                    r
                } else {
                    1.0 - r
                }
            }
            _ => 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{ConductorFresnel, Distribution};
    use crate::sampling::Sampler;

    /// The adjoint weight of every non-delta BSDF is `eval` of the swapped
    /// pair over the pdf of the sampled direction, which is `pdf` with the
    /// roles swapped (rough glass included, where `eval` is not symmetric).
    #[test]
    fn adjoint_weight_is_the_radiance_bsdf_of_the_swapped_pair() {
        let n = Vec3::new(0.2, 1.0, -0.1).normalize();
        let materials = [
            Material::Diffuse {
                albedo: Rgb::new(0.8, 0.5, 0.2),
            },
            Material::Phong {
                albedo: Rgb::splat(0.7),
                exponent: 12.0,
            },
            Material::Dielectric {
                ior: 1.5,
                alpha: 0.3,
                distribution: Distribution::Ggx,
                multiscatter: false,
            },
            Material::Conductor {
                alpha: 0.2,
                fresnel: ConductorFresnel::Schlick {
                    f0: Rgb::new(0.9, 0.6, 0.3),
                },
                distribution: Distribution::Ggx,
                multiscatter: false,
            },
            Material::Dielectric {
                ior: 1.5,
                alpha: 0.6,
                distribution: Distribution::Ggx,
                multiscatter: true,
            },
            Material::Conductor {
                alpha: 0.7,
                fresnel: ConductorFresnel::Schlick {
                    f0: Rgb::new(0.9, 0.6, 0.3),
                },
                distribution: Distribution::Ggx,
                multiscatter: true,
            },
        ];
        let mut s = Sampler::from_seed(11);
        for m in materials {
            let mut checked = 0;
            for _ in 0..2000 {
                let wi = crate::sampling::warp::square_to_uniform_sphere(s.next_2d());
                let Some(a) = m.sample_adjoint(n, wi, s.next_2d(), s.next_1d()) else {
                    continue;
                };
                let want = m.eval(&Shading::facing(n, a.wi), a.wi, wi) / a.pdf;
                let pdf = m.pdf(&Shading::facing(n, wi), wi, a.wi);
                assert!(
                    (a.pdf - pdf).abs() <= 1e-3 * pdf,
                    "{m:?}: {} vs {pdf}",
                    a.pdf
                );
                for c in 0..3 {
                    assert!(
                        (a.weight[c] - want[c]).abs() <= 1e-4 * want[c].max(1.0),
                        "{m:?}"
                    );
                }
                checked += 1;
            }
            assert!(checked > 500, "{m:?}: {checked}");
        }
    }

    /// Smooth glass: light crossing into or out of glass (η 1.5) carries
    /// cos θ (arriving) / cos θ (leaving) by Snell's law, whichever side it
    /// comes from; reflection keeps its weight; lobe probabilities are F and 1 − F.
    #[test]
    fn smooth_glass_adjoint_weights_and_lobe_probabilities() {
        let glass = Material::Dielectric {
            ior: 1.5,
            alpha: 0.0,
            distribution: Distribution::Ggx,
            multiscatter: false,
        };
        let n = Vec3::Y;
        let inside = Vec3::new(0.3, -1.0, 0.0).normalize();
        let outside = Vec3::new(-0.3, 1.0, 0.2).normalize();
        for (wi, eta_ratio) in [(inside, 1.5f32), (outside, 1.0 / 1.5)] {
            let cos_in = wi.y.abs();
            let sin_out = eta_ratio * (1.0 - cos_in * cos_in).sqrt();
            let expected = cos_in / (1.0 - sin_out * sin_out).sqrt();
            // u_lobe near 1 picks refraction (F is small at these angles).
            let a = glass
                .sample_adjoint(n, wi, Vec2::splat(0.5), 0.999)
                .expect("refracts");
            assert!(a.is_delta && a.wi.y * wi.y < 0.0, "{:?}", a.wi);
            assert!((a.weight.r - expected).abs() < 1e-5, "{:?}", a.weight);
            let sp = Shading::facing(n, wi);
            let f = fresnel::dielectric(sp.n.dot(wi), relative_eta(1.5, &sp));
            assert!((glass.delta_pdf(&sp, wi, a.wi) - (1.0 - f)).abs() < 1e-6);
            assert!((a.pdf - (1.0 - f)).abs() < 1e-6);
            let r = glass
                .sample_adjoint(n, wi, Vec2::splat(0.5), 0.0)
                .expect("reflects");
            assert_eq!(r.weight, Rgb::WHITE);
            assert!((glass.delta_pdf(&sp, wi, r.wi) - f).abs() < 1e-6);
        }
        let diffuse = Material::Diffuse { albedo: Rgb::WHITE };
        assert_eq!(
            diffuse.delta_pdf(&Shading::facing(n, outside), outside, n),
            0.0
        );
    }
}
