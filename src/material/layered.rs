//! Mitsuba 3's `plastic` (a Lambertian base under a smooth dielectric
//! coating, with internal reflections between the two summed in closed form)
//! and `thindielectric` (a sheet whose two parallel faces reflect and
//! transmit in turn: light passes straight through, unbent).
//!
//! Plastic: a specular Fresnel reflection F(θo)·s plus the diffuse term
//! f = (1 − F(θi))(1 − F(θo)) ρ' / (π η²), where the light that entered is
//! reflected back down by the coating with the internal diffuse Fresnel
//! reflectance F_dr: ρ' = ρ / (1 − F_dr ρ) ("nonlinear", the geometric
//! series of bounces off a base of albedo ρ) or ρ / (1 − F_dr) (the linear
//! default). A white base (ρ = 1) conserves energy exactly, because
//! η² (1 − F_dr,int) = 1 − F_dr,ext.
//!
//! A rough coating (α > 0, Mitsuba's `roughplastic`) replaces the delta
//! reflection by a microfacet lobe ([`super::rough_plastic`]); the lobe is
//! chosen with the same probability as the smooth one's, and the sample's
//! density is the two lobes' combined so that MIS sees one BSDF.

use super::microfacet::Distribution;
use super::rough_plastic::{Coating, CoatingTables};
use super::{fresnel, BsdfSample, Shading, MIN_ALPHA};
use crate::math::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};
use crate::sampling::quadrature::gauss_legendre;
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

/// The parameters of a smooth plastic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    /// Albedo ρ of the Lambertian base.
    pub diffuse: Rgb,
    /// Factor on the coating's specular reflection.
    pub specular: Rgb,
    /// Relative index η of the coating (inside over outside).
    pub ior: f32,
    /// Internal diffuse Fresnel reflectance of the coating ([`diffuse_fresnel`] of 1/η).
    pub fdr_int: f32,
    /// ρ / (1 − F_dr ρ) instead of ρ / (1 − F_dr).
    pub nonlinear: bool,
    /// Microfacet α of the coating; below [`MIN_ALPHA`] it is smooth (a delta reflection).
    pub alpha: f32,
    /// The microfacet distribution of a rough coating.
    pub distribution: Distribution,
    /// A rough coating's tabulated transmittance and internal reflectance
    /// (Mitsuba's `roughplastic`), or `None`: the smooth interface's Fresnel
    /// factors at the macro angles and `fdr_int`.
    pub tables: Option<&'static CoatingTables>,
}

/// Cosine-weighted hemispherical average of the Fresnel reflectance for
/// light arriving from the side of relative index 1 toward `eta`:
/// F_dr = 2 ∫0^1 F(μ) μ dμ, by quadrature split at the critical angle.
pub fn diffuse_fresnel(eta: f32) -> f32 {
    let f = |mu: f64| fresnel::dielectric(mu as f32, eta) as f64 * mu;
    // Below the critical cosine (eta < 1) everything is reflected: ∫0^μc μ dμ = μc²/2.
    let mu_c = if eta < 1.0 {
        (1.0 - (eta as f64).powi(2)).max(0.0).sqrt()
    } else {
        0.0
    };
    (2.0 * (0.5 * mu_c * mu_c + gauss_legendre(f, mu_c, 1.0, 64))) as f32
}

impl Plastic {
    /// The base's effective albedo ρ' with the internal reflections summed,
    /// and the coating's transmittance in and out at cosines `cos_o`, `cos_i`.
    fn base_weights(&self, cos_o: f32, cos_i: f32) -> (Rgb, f32) {
        let (internal, transmittance) = match self.tables {
            Some(tables) => (
                tables.internal_reflectance,
                tables.transmittance(cos_o) * tables.transmittance(cos_i),
            ),
            None => {
                let f_o = fresnel::dielectric(cos_o, self.ior);
                let f_i = fresnel::dielectric(cos_i, self.ior);
                (self.fdr_int, (1.0 - f_o) * (1.0 - f_i))
            }
        };
        let d = self.diffuse;
        let albedo = if self.nonlinear {
            let ch = |x: f32| x / (1.0 - internal * x);
            Rgb::new(ch(d.r), ch(d.g), ch(d.b))
        } else {
            d * (1.0 / (1.0 - internal))
        };
        (albedo, transmittance)
    }

    /// Probability of sampling the specular lobe, in proportion to the lobes' weights.
    fn specular_probability(&self, f_o: f32) -> f32 {
        let mean = |c: Rgb| (c.r + c.g + c.b) / 3.0;
        let (s, d) = (mean(self.specular), mean(self.diffuse));
        let (ps, pd) = (f_o * s, (1.0 - f_o) * d);
        if ps + pd <= 0.0 {
            return 0.0;
        }
        ps / (ps + pd)
    }

    /// `f · cos θi` of the diffuse term (the specular one is a delta).
    pub fn eval(&self, sp: &Shading, wo: Vec3, wi: Vec3) -> Rgb {
        let (cos_o, cos_i) = (sp.n.dot(wo), sp.n.dot(wi));
        if cos_o <= 0.0 || cos_i <= 0.0 {
            return Rgb::BLACK;
        }
        let (albedo, transmittance) = self.base_weights(cos_o, cos_i);
        let t = transmittance / (self.ior * self.ior);
        let diffuse = albedo * (t * FRAC_1_PI * cos_i);
        match self.coating() {
            Some(c) => {
                let frame = Frame::from_z(sp.n);
                let s = c.eval(frame.to_local(wo), frame.to_local(wi));
                diffuse + self.specular * s
            }
            None => diffuse,
        }
    }

    /// The rough specular lobe, or `None` for a smooth (delta) coating.
    fn coating(&self) -> Option<Coating> {
        (self.alpha >= MIN_ALPHA).then_some(Coating {
            alpha: self.alpha,
            distribution: self.distribution,
            eta: self.ior,
        })
    }

    /// Density of sampling `wi` by the diffuse lobe (and the rough specular one).
    pub fn pdf(&self, sp: &Shading, wo: Vec3, wi: Vec3) -> f32 {
        let (cos_o, cos_i) = (sp.n.dot(wo), sp.n.dot(wi));
        if cos_o <= 0.0 || cos_i <= 0.0 {
            return 0.0;
        }
        let p_s = self.specular_probability(fresnel::dielectric(cos_o, self.ior));
        let diffuse = (1.0 - p_s) * cos_i * FRAC_1_PI;
        match self.coating() {
            Some(c) => {
                let frame = Frame::from_z(sp.n);
                diffuse + p_s * c.pdf(frame.to_local(wo), frame.to_local(wi))
            }
            None => diffuse,
        }
    }

    /// Picks the specular reflection (a delta) or a cosine-distributed direction.
    pub fn sample(&self, sp: &Shading, wo: Vec3, u: Vec2, u_lobe: f32) -> Option<BsdfSample> {
        let cos_o = sp.n.dot(wo);
        let f_o = fresnel::dielectric(cos_o, self.ior);
        let p_s = self.specular_probability(f_o);
        if let Some(c) = self.coating() {
            return self.sample_rough(c, sp, wo, u, u_lobe < p_s);
        }
        if u_lobe < p_s {
            return Some(BsdfSample {
                wi: 2.0 * cos_o * sp.n - wo,
                weight: self.specular * (f_o / p_s),
                pdf: p_s,
                is_delta: true,
            });
        }
        let local = warp::square_to_cosine_hemisphere(u);
        if local.z <= 0.0 {
            return None;
        }
        let wi = Frame::from_z(sp.n).to_world(local);
        let pdf = (1.0 - p_s) * warp::cosine_hemisphere_pdf(local);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: self.eval(sp, wo, wi) / pdf,
            pdf,
            is_delta: false,
        })
    }
}

impl Plastic {
    /// Samples a rough coating's specular lobe or the diffuse one; the
    /// weight is the whole BSDF over the mixture's density.
    fn sample_rough(
        &self,
        c: Coating,
        sp: &Shading,
        wo: Vec3,
        u: Vec2,
        specular: bool,
    ) -> Option<BsdfSample> {
        let frame = Frame::from_z(sp.n);
        let wi = if specular {
            frame.to_world(c.sample(frame.to_local(wo), u)?)
        } else {
            frame.to_world(warp::square_to_cosine_hemisphere(u))
        };
        let pdf = self.pdf(sp, wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: self.eval(sp, wo, wi) / pdf,
            pdf,
            is_delta: false,
        })
    }
}

/// Reflectance of a thin sheet of relative index `ior` seen at cosine
/// `cos_o`: R + T² R (1 + R² + R⁴ + …) = 2R / (1 + R) with T = 1 − R.
pub fn thin_reflectance(cos_o: f32, ior: f32) -> f32 {
    let r = fresnel::dielectric(cos_o, ior);
    2.0 * r / (1.0 + r)
}

/// A thin sheet's lobe drawn by `u_lobe`: mirror reflection with
/// probability R', else straight through. Returns the direction, the
/// lobe's probability, and whether it reflects.
pub fn thin_lobe(ior: f32, sp: &Shading, wo: Vec3, u_lobe: f32) -> (Vec3, f32, bool) {
    let cos_o = sp.n.dot(wo);
    let r = thin_reflectance(cos_o, ior);
    if u_lobe < r {
        (2.0 * cos_o * sp.n - wo, r, true)
    } else {
        (-wo, 1.0 - r, false)
    }
}

/// Samples a thin sheet ([`thin_lobe`]); each lobe's weight is its value
/// over its probability (1).
pub fn sample_thin(ior: f32, sp: &Shading, wo: Vec3, u_lobe: f32) -> BsdfSample {
    let (wi, pdf, _) = thin_lobe(ior, sp, wo, u_lobe);
    BsdfSample {
        wi,
        weight: Rgb::WHITE,
        pdf,
        is_delta: true,
    }
}
