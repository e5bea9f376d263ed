//! BSDFs: Lambertian, normalized Phong lobe, mirror, smooth and rough
//! (GGX or Beckmann) dielectrics and conductors, thin dielectric sheets and
//! plastic (a diffuse base under a dielectric coating).
//!
//! Directions are world-space unit vectors; `wo` points back along the
//! arriving path (toward the previous vertex), `wi` toward the next one.
//! A `Shading` carries the shading normal flipped to the side of `wo` and
//! which side of the surface that is (dielectrics need it for η).

mod adjoint;
pub mod texture;

pub mod albedo;
pub mod albedo_estimate;
pub mod beckmann;
pub mod fresnel;
pub mod layered;
mod lobe;
pub mod microfacet;
pub mod multiscatter;
mod rough;
pub mod rough_plastic;

use crate::math::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};
use crate::sampling::warp;
use layered::Plastic;
use lobe::Rough;
pub use microfacet::Distribution;
use std::f32::consts::{FRAC_1_PI, PI};

/// Smallest GGX α of a rough lobe; below it the lobe is treated as smooth.
pub const MIN_ALPHA: f32 = 1e-3;

/// The local geometry a BSDF is evaluated in.
#[derive(Clone, Copy, Debug)]
pub struct Shading {
    /// Unit shading normal on the side of `wo`.
    pub n: Vec3,
    /// True when `wo` is on the front (outward normal) side of the surface.
    pub front: bool,
}

impl Shading {
    /// The shading frame of a surface with outward shading normal `normal`, seen from `wo`.
    pub fn facing(normal: Vec3, wo: Vec3) -> Shading {
        let front = normal.dot(wo) >= 0.0;
        Shading {
            n: if front { normal } else { -normal },
            front,
        }
    }
}

/// How a conductor's reflectance varies with the angle of incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Exact Fresnel equations of a complex index of refraction η + ik per channel.
    Complex {
        /// Real part η.
        eta: Rgb,
        /// Extinction coefficient k.
        k: Rgb,
    },
    /// Schlick's approximation from the reflectance at normal incidence (F = 1 for F0 = 1).
    Schlick {
        /// Reflectance at normal incidence.
        f0: Rgb,
    },
}

impl ConductorFresnel {
    /// Reflectance at incidence cosine `cos_i`.
    pub fn eval(&self, cos_i: f32) -> Rgb {
        match *self {
            ConductorFresnel::Complex { eta, k } => fresnel::conductor(cos_i, eta, k),
            ConductorFresnel::Schlick { f0 } => fresnel::schlick(cos_i, f0),
        }
    }
}

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
    /// A dielectric interface (glass, water): Fresnel-weighted reflection and refraction.
    Dielectric {
        /// Index of refraction of the inside (the normal points outside, index 1).
        ior: f32,
        /// Microfacet α of the surface; 0 is a smooth (delta) interface.
        alpha: f32,
        /// The microfacet distribution of a rough surface.
        distribution: Distribution,
        /// Kulla–Conty energy compensation of a rough surface ([`multiscatter`]; GGX only).
        multiscatter: bool,
    },
    /// A metal: Fresnel-weighted reflection off a smooth or GGX-rough surface.
    Conductor {
        /// Microfacet α of the surface; 0 is a smooth (delta) mirror.
        alpha: f32,
        /// Reflectance model.
        fresnel: ConductorFresnel,
        /// The microfacet distribution of a rough surface.
        distribution: Distribution,
        /// Kulla–Conty energy compensation of a rough surface ([`multiscatter`]; GGX only).
        multiscatter: bool,
    },
    /// A thin dielectric sheet (window pane, soap film): reflects with the
    /// summed reflectance of its two faces, transmits straight through ([`layered`]).
    ThinDielectric {
        /// Index of refraction of the sheet (the outside has index 1).
        ior: f32,
    },
    /// A Lambertian base under a smooth dielectric coating (Mitsuba's `plastic`, [`layered`]).
    Plastic(Plastic),
}

/// A direction sampled from a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled direction (toward the next vertex).
    pub wi: Vec3,
    /// `f · cosθi / pdf`.
    pub weight: Rgb,
    /// Solid-angle density (for a delta lobe: the probability of choosing it; MIS does not apply).
    pub pdf: f32,
    /// True for a Dirac lobe.
    pub is_delta: bool,
}

/// Mirror direction of `wo` about `n`.
#[inline]
fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// η on the far side of the interface over η on the side of `wo`.
#[inline]
fn relative_eta(ior: f32, sp: &Shading) -> f32 {
    if sp.front {
        ior
    } else {
        1.0 / ior
    }
}

impl Material {
    /// True when the BSDF is a Dirac delta (no evaluation, no light sampling).
    pub fn is_delta(&self) -> bool {
        match *self {
            Material::Mirror { .. } => true,
            Material::Dielectric { alpha, .. } | Material::Conductor { alpha, .. } => {
                alpha < MIN_ALPHA
            }
            Material::ThinDielectric { .. } => true,
            Material::Diffuse { .. } | Material::Phong { .. } | Material::Plastic(_) => false,
        }
    }

    /// The same material with its colour parameter (diffuse and Phong albedo,
    /// mirror reflectance, Schlick F0, plastic base) set to `color`; others are returned as they are.
    #[inline]
    pub fn with_color(self, color: Rgb) -> Material {
        match self {
            Material::Diffuse { .. } => Material::Diffuse { albedo: color },
            Material::Phong { exponent, .. } => Material::Phong {
                albedo: color,
                exponent,
            },
            Material::Mirror { .. } => Material::Mirror { reflectance: color },
            Material::Plastic(p) => Material::Plastic(Plastic {
                diffuse: color,
                ..p
            }),
            Material::Conductor {
                alpha,
                fresnel: ConductorFresnel::Schlick { .. },
                distribution,
                multiscatter,
            } => Material::Conductor {
                alpha,
                fresnel: ConductorFresnel::Schlick { f0: color },
                distribution,
                multiscatter,
            },
            other => other,
        }
    }

    /// `f(wo, wi) · |cosθi|`; zero for directions the lobe does not reach.
    pub fn eval(&self, sp: &Shading, wo: Vec3, wi: Vec3) -> Rgb {
        let n = sp.n;
        if self.is_delta() || n.dot(wo) <= 0.0 {
            return Rgb::BLACK;
        }
        let cos_i = n.dot(wi);
        match *self {
            Material::Diffuse { albedo } if cos_i > 0.0 => albedo * (FRAC_1_PI * cos_i),
            Material::Phong { albedo, exponent } if cos_i > 0.0 => {
                let cos_alpha = reflect(wo, n).dot(wi).max(0.0);
                albedo * ((exponent + 2.0) / (2.0 * PI) * cos_alpha.powf(exponent) * cos_i)
            }
            Material::Dielectric { ior, .. } => {
                let frame = Frame::from_z(n);
                let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
                self.rough().dielectric_eval(relative_eta(ior, sp), lo, li)
            }
            Material::Conductor { fresnel, .. } => {
                let frame = Frame::from_z(n);
                let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
                self.rough().conductor_eval(&fresnel, lo, li)
            }
            Material::Plastic(p) => p.eval(sp, wo, wi),
            _ => Rgb::BLACK,
        }
    }

    /// Solid-angle density of `sample` producing `wi` (0 for delta lobes).
    pub fn pdf(&self, sp: &Shading, wo: Vec3, wi: Vec3) -> f32 {
        let n = sp.n;
        if self.is_delta() || n.dot(wo) <= 0.0 {
            return 0.0;
        }
        let cos_i = n.dot(wi);
        match *self {
            Material::Diffuse { .. } if cos_i > 0.0 => cos_i * FRAC_1_PI,
            Material::Phong { exponent, .. } if cos_i > 0.0 => {
                let cos_alpha = reflect(wo, n).dot(wi).max(0.0);
                (exponent + 1.0) / (2.0 * PI) * cos_alpha.powf(exponent)
            }
            Material::Dielectric { ior, .. } => {
                let frame = Frame::from_z(n);
                let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
                self.rough().dielectric_pdf(relative_eta(ior, sp), lo, li)
            }
            Material::Conductor { .. } => {
                let frame = Frame::from_z(n);
                let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
                self.rough().conductor_pdf(lo, li)
            }
            Material::Plastic(p) => p.pdf(sp, wo, wi),
            _ => 0.0,
        }
    }

    /// Samples `wi` from `u` (the lobe's direction) and `u_lobe` (which lobe, for dielectrics).
    pub fn sample(&self, sp: &Shading, wo: Vec3, u: Vec2, u_lobe: f32) -> Option<BsdfSample> {
        let n = sp.n;
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
            Material::Phong { albedo, exponent } => sample_phong(albedo, exponent, n, wo, u),
            Material::Mirror { reflectance } => Some(BsdfSample {
                wi: reflect(wo, n),
                weight: reflectance,
                pdf: 1.0,
                is_delta: true,
            }),
            Material::Dielectric { ior, alpha, .. } if alpha < MIN_ALPHA => {
                sample_smooth_dielectric(relative_eta(ior, sp), n, wo, u_lobe)
            }
            Material::Conductor { alpha, fresnel, .. } if alpha < MIN_ALPHA => Some(BsdfSample {
                wi: reflect(wo, n),
                weight: fresnel.eval(n.dot(wo)),
                pdf: 1.0,
                is_delta: true,
            }),
            Material::Dielectric { .. } | Material::Conductor { .. } => {
                self.sample_rough(sp, wo, u, u_lobe)
            }
            Material::ThinDielectric { ior } => Some(layered::sample_thin(ior, sp, wo, u_lobe)),
            Material::Plastic(p) => p.sample(sp, wo, u, u_lobe),
        }
    }

    /// [`Material::sample`] of a rough dielectric or conductor: the GGX lobe,
    /// GGX or Beckmann,
    /// with its energy compensation where `multiscatter` is on.
    fn sample_rough(&self, sp: &Shading, wo: Vec3, u: Vec2, u_lobe: f32) -> Option<BsdfSample> {
        let frame = Frame::from_z(sp.n);
        let lo = frame.to_local(wo);
        let s = match *self {
            Material::Dielectric { ior, .. } => {
                self.rough()
                    .dielectric_sample(relative_eta(ior, sp), lo, u, u_lobe)
            }
            Material::Conductor { fresnel, .. } => {
                self.rough().conductor_sample(&fresnel, lo, u, u_lobe)
            }
            _ => None,
        }?;
        Some(to_world(&frame, s))
    }

    /// The microfacet model of a dielectric or conductor (a smooth GGX for the others, unused).
    fn rough(&self) -> Rough {
        match *self {
            Material::Dielectric {
                alpha,
                distribution,
                multiscatter,
                ..
            }
            | Material::Conductor {
                alpha,
                distribution,
                multiscatter,
                ..
            } => Rough {
                alpha,
                distribution,
                multiscatter,
            },
            _ => Rough {
                alpha: 0.0,
                distribution: Distribution::Ggx,
                multiscatter: false,
            },
        }
    }
}

/// A rough lobe's local sample in world space.
fn to_world(frame: &Frame, s: rough::LocalSample) -> BsdfSample {
    BsdfSample {
        wi: frame.to_world(s.wi),
        weight: s.weight,
        pdf: s.pdf,
        is_delta: false,
    }
}

/// Samples the Phong lobe around the mirror direction.
fn sample_phong(albedo: Rgb, exponent: f32, n: Vec3, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
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

/// Reflects with probability F, else refracts: each delta lobe's weight is its
/// value over its probability, so the Fresnel factor cancels.
fn sample_smooth_dielectric(eta: f32, n: Vec3, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
    let f = fresnel::dielectric(n.dot(wo), eta);
    if u_lobe < f {
        return Some(BsdfSample {
            wi: reflect(wo, n),
            weight: Rgb::WHITE,
            pdf: f,
            is_delta: true,
        });
    }
    let wi = fresnel::refract(wo, n, eta)?.normalize();
    // Radiance is compressed by (η_wo / η_wi)² on the way through.
    Some(BsdfSample {
        wi,
        weight: Rgb::splat(1.0 / (eta * eta)),
        pdf: 1.0 - f,
        is_delta: true,
    })
}

#[cfg(test)]
mod tests;
