//! The rough lobe of a dielectric or conductor: one place that dispatches on
//! the microfacet distribution and on energy compensation, so that `mod.rs`
//! names each lobe once.

use super::beckmann::Beckmann;
use super::microfacet::{Distribution, Ggx};
use super::rough::{self, LocalSample};
use super::{multiscatter, ConductorFresnel};
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};

/// A rough surface's microfacet model.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rough {
    /// Roughness α of the distribution.
    pub alpha: f32,
    /// GGX or Beckmann.
    pub distribution: Distribution,
    /// Kulla–Conty compensation (tabulated for GGX only; the scene builder
    /// refuses it with Beckmann, so here it is read for GGX alone).
    pub multiscatter: bool,
}

impl Rough {
    /// `f · cos θi` of a rough conductor (local frame).
    pub fn conductor_eval(self, fresnel: &ConductorFresnel, wo: Vec3, wi: Vec3) -> Rgb {
        let a = self.alpha;
        match (self.distribution, self.multiscatter) {
            (Distribution::Ggx, true) => {
                multiscatter::conductor_eval(Ggx { alpha: a }, fresnel, wo, wi)
            }
            (Distribution::Ggx, false) => rough::conductor_eval(Ggx { alpha: a }, fresnel, wo, wi),
            (Distribution::Beckmann, _) => {
                rough::conductor_eval(Beckmann { alpha: a }, fresnel, wo, wi)
            }
        }
    }

    /// Density of `conductor_sample` producing `wi`.
    pub fn conductor_pdf(self, wo: Vec3, wi: Vec3) -> f32 {
        let a = self.alpha;
        match (self.distribution, self.multiscatter) {
            (Distribution::Ggx, true) => multiscatter::conductor_pdf(Ggx { alpha: a }, wo, wi),
            (Distribution::Ggx, false) => rough::conductor_pdf(Ggx { alpha: a }, wo, wi),
            (Distribution::Beckmann, _) => rough::conductor_pdf(Beckmann { alpha: a }, wo, wi),
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
        let a = self.alpha;
        match (self.distribution, self.multiscatter) {
            (Distribution::Ggx, true) => {
                multiscatter::conductor_sample(Ggx { alpha: a }, fresnel, wo, u, u_lobe)
            }
            (Distribution::Ggx, false) => rough::conductor_sample(Ggx { alpha: a }, fresnel, wo, u),
            (Distribution::Beckmann, _) => {
                rough::conductor_sample(Beckmann { alpha: a }, fresnel, wo, u)
            }
        }
    }

    /// `f · cos θi` of a rough dielectric of relative index `eta` (local frame).
    pub fn dielectric_eval(self, eta: f32, wo: Vec3, wi: Vec3) -> Rgb {
        let a = self.alpha;
        match (self.distribution, self.multiscatter) {
            (Distribution::Ggx, true) => {
                multiscatter::dielectric_eval(Ggx { alpha: a }, eta, wo, wi)
            }
            (Distribution::Ggx, false) => rough::dielectric_eval(Ggx { alpha: a }, eta, wo, wi),
            (Distribution::Beckmann, _) => {
                rough::dielectric_eval(Beckmann { alpha: a }, eta, wo, wi)
            }
        }
    }

    /// Density of `dielectric_sample` producing `wi`.
    pub fn dielectric_pdf(self, eta: f32, wo: Vec3, wi: Vec3) -> f32 {
        let a = self.alpha;
        match (self.distribution, self.multiscatter) {
            (Distribution::Ggx, true) => {
                multiscatter::dielectric_pdf(Ggx { alpha: a }, eta, wo, wi)
            }
            (Distribution::Ggx, false) => rough::dielectric_pdf(Ggx { alpha: a }, eta, wo, wi),
            (Distribution::Beckmann, _) => {
                rough::dielectric_pdf(Beckmann { alpha: a }, eta, wo, wi)
            }
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
        let a = self.alpha;
        match (self.distribution, self.multiscatter) {
            (Distribution::Ggx, true) => {
                multiscatter::dielectric_sample(Ggx { alpha: a }, eta, wo, u, u_lobe)
            }
            (Distribution::Ggx, false) => {
                rough::dielectric_sample(Ggx { alpha: a }, eta, wo, u, u_lobe)
            }
            (Distribution::Beckmann, _) => {
                rough::dielectric_sample(Beckmann { alpha: a }, eta, wo, u, u_lobe)
            }
        }
    }
}
