//! The rough lobe of a dielectric or conductor: one place that dispatches on
//! the microfacet distribution and on energy compensation, so that `mod.rs`
//! names each lobe once.

use super::beckmann::Beckmann;
use super::microfacet::{Distribution, Ggx, Separable};
use super::rough::{self, LocalSample};
use super::{multiscatter, ConductorFresnel};
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};

/// A rough surface's microfacet model.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rough {
    /// Roughness α of the distribution.
    pub alpha: f32,
    /// GGX or Beckmann, with correlated or separable masking.
    pub distribution: Distribution,
    /// Kulla–Conty compensation (tabulated for GGX only; the scene builder
    /// refuses it with Beckmann, so here it is read for GGX alone).
    pub multiscatter: bool,
}

/// Calls `rough::function(model, args…)` with the single-scattering
/// microfacet model of `rough`: its distribution and masking.
macro_rules! single {
    ($rough:expr, $function:ident ( $($arg:expr),* )) => {{
        let a = $rough.alpha;
        match $rough.distribution {
            Distribution::Ggx => rough::$function(Ggx { alpha: a }, $($arg),*),
            Distribution::Beckmann => rough::$function(Beckmann { alpha: a }, $($arg),*),
            Distribution::GgxSeparable => rough::$function(Separable(Ggx { alpha: a }), $($arg),*),
            Distribution::BeckmannSeparable => {
                rough::$function(Separable(Beckmann { alpha: a }), $($arg),*)
            }
        }
    }};
}

impl Rough {
    /// The GGX lobe with Kulla–Conty compensation, when it applies.
    fn compensated(self) -> Option<Ggx> {
        (self.multiscatter && self.distribution == Distribution::Ggx)
            .then_some(Ggx { alpha: self.alpha })
    }

    /// `f · cos θi` of a rough conductor (local frame).
    pub fn conductor_eval(self, fresnel: &ConductorFresnel, wo: Vec3, wi: Vec3) -> Rgb {
        match self.compensated() {
            Some(ggx) => multiscatter::conductor_eval(ggx, fresnel, wo, wi),
            None => single!(self, conductor_eval(fresnel, wo, wi)),
        }
    }

    /// Density of `conductor_sample` producing `wi`.
    pub fn conductor_pdf(self, wo: Vec3, wi: Vec3) -> f32 {
        match self.compensated() {
            Some(ggx) => multiscatter::conductor_pdf(ggx, wo, wi),
            None => single!(self, conductor_pdf(wo, wi)),
        }
    }

    /// Samples a rough conductor.
    pub fn conductor_sample(
        self,
        fresnel: &ConductorFresnel,
        wo: Vec3,
        u: Vec2,
        u_lobe: f32,
    ) -> Option<LocalSample> {
        match self.compensated() {
            Some(ggx) => multiscatter::conductor_sample(ggx, fresnel, wo, u, u_lobe),
            None => single!(self, conductor_sample(fresnel, wo, u)),
        }
    }

    /// `f · cos θi` of a rough dielectric of relative index `eta` (local frame).
    pub fn dielectric_eval(self, eta: f32, wo: Vec3, wi: Vec3) -> Rgb {
        match self.compensated() {
            Some(ggx) => multiscatter::dielectric_eval(ggx, eta, wo, wi),
            None => single!(self, dielectric_eval(eta, wo, wi)),
        }
    }

    /// Density of `dielectric_sample` producing `wi`.
    pub fn dielectric_pdf(self, eta: f32, wo: Vec3, wi: Vec3) -> f32 {
        match self.compensated() {
            Some(ggx) => multiscatter::dielectric_pdf(ggx, eta, wo, wi),
            None => single!(self, dielectric_pdf(eta, wo, wi)),
        }
    }

    /// Samples a rough dielectric.
    pub fn dielectric_sample(
        self,
        eta: f32,
        wo: Vec3,
        u: Vec2,
        u_lobe: f32,
    ) -> Option<LocalSample> {
        match self.compensated() {
            Some(ggx) => multiscatter::dielectric_sample(ggx, eta, wo, u, u_lobe),
            None => single!(self, dielectric_sample(eta, wo, u, u_lobe)),
        }
    }
}
