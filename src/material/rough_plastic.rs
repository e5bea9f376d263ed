//! The rough coating of `plastic` (Mitsuba's `roughplastic`): a microfacet
//! reflection off the dielectric coating, f_s = s F(wo·m) D G2 / (4 cos θo
//! cos θi) (Walter et al. 2007), over the same diffuse term as the smooth
//! coating. The diffuse term's transmission factors are the smooth
//! interface's (1 − F(θi))(1 − F(θo)) at the macro angles: Mitsuba
//! tabulates the rough interface's transmittance instead, which brume does
//! not (documented in the README's Mitsuba table).
//!
//! Local shading frame: the macro normal is +z and `wo.z > 0`.

use super::lobe::Rough;
use super::microfacet::Distribution;
use super::rough::LocalSample;
use super::ConductorFresnel;
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};

/// The rough specular lobe of a plastic coating of relative index `eta`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Coating {
    /// Microfacet α of the coating.
    pub alpha: f32,
    /// GGX or Beckmann.
    pub distribution: Distribution,
    /// Relative index of the coating (inside over outside).
    pub eta: f32,
}

impl Coating {
    /// Mitsuba's roughplastic models single scattering between microfacets only.
    fn rough(self) -> Rough {
        Rough {
            alpha: self.alpha,
            distribution: self.distribution,
            multiscatter: false,
        }
    }

    /// `f_s · cos θi` of the specular reflection (without the factor s).
    pub fn eval(self, wo: Vec3, wi: Vec3) -> f32 {
        if wi.z <= 0.0 {
            return 0.0;
        }
        // The rough dielectric's reflection half is exactly F D G2 / (4 cos θo).
        self.rough().dielectric_eval(self.eta, wo, wi).r
    }

    /// Density of `sample` producing `wi`: reflection through a sampled normal.
    pub fn pdf(self, wo: Vec3, wi: Vec3) -> f32 {
        self.rough().conductor_pdf(wo, wi)
    }

    /// A direction reflected about a sampled microfacet normal (its weight is
    /// recomputed by the caller, who mixes it with the diffuse lobe).
    pub fn sample(self, wo: Vec3, u: Vec2) -> Option<Vec3> {
        let white = ConductorFresnel::Schlick { f0: Rgb::WHITE };
        let s: LocalSample = self.rough().conductor_sample(&white, wo, u, 0.0)?;
        Some(s.wi)
    }
}
