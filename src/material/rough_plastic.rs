//! The rough coating of `plastic` (Mitsuba's `roughplastic`): a microfacet
//! reflection off the dielectric coating, f_s = s F(wo·m) D G2 / (4 cos θo
//! cos θi) (Walter et al. 2007), over the same diffuse term as the smooth
//! coating. The diffuse term's transmission factors are the smooth
//! interface's (1 − F(θi))(1 − F(θo)) at the macro angles: Mitsuba
//! tabulates the rough interface's transmittance instead, which brume does
//! not (documented in the README's Mitsuba table).
//!
//! Local shading frame: the macro normal is +z and `wo.z > 0`.

use super::beckmann::Beckmann;
use super::fresnel;
use super::lobe::Rough;
use super::microfacet::{Distribution, Ggx, Microfacet};
use super::rough::LocalSample;
use super::ConductorFresnel;
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};
use crate::sampling::quadrature::gauss_legendre;

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

/// Cosines at which [`CoatingTables`] tabulate the transmittance (Mitsuba's count).
const TABLE_SIZE: usize = 64;

/// Mitsuba 3's weights of a rough coating's diffuse term
/// (`transmittance = "microfacet"`): the rough interface's single-scattering
/// transmittance t(μ), the light entering through a visible microfacet,
/// refracted, and not masked on its way down (what the facets reflect or
/// mask is lost), at 64 cosines from 0 to 1 interpolated linearly; and the
/// internal reflectance seen by the base, 2 · the mean over the same
/// cosines of μ·R_int(μ), the average Mitsuba's `roughplastic` takes.
#[derive(Debug, PartialEq)]
pub struct CoatingTables {
    /// t(μ) at μ = k / 63 (the first at 10⁻⁶).
    transmittance: [f32; TABLE_SIZE],
    /// The internal reflectance that replaces F_dr in ρ / (1 − F_dr).
    pub internal_reflectance: f32,
}

impl CoatingTables {
    /// The tables of a coating, built once per process for each distinct
    /// (distribution, α, η) and shared: materials are copied per hit, so
    /// they hold a reference, and the few kilobytes of each table live as
    /// long as any scene may use them.
    pub fn of(distribution: Distribution, alpha: f32, eta: f32) -> &'static CoatingTables {
        type Key = (Distribution, u32, u32);
        static BUILT: std::sync::Mutex<Vec<(Key, &'static CoatingTables)>> =
            std::sync::Mutex::new(Vec::new());
        let key = (distribution, alpha.to_bits(), eta.to_bits());
        let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, tables)) = built.iter().find(|(k, _)| *k == key) {
            return tables;
        }
        let tables: &'static CoatingTables =
            Box::leak(Box::new(CoatingTables::build(distribution, alpha, eta)));
        built.push((key, tables));
        tables
    }

    /// t(μ), linear between the tabulated cosines.
    pub fn transmittance(&self, mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
        let i = (x as usize).min(TABLE_SIZE - 2);
        let (a, b) = (self.transmittance[i], self.transmittance[i + 1]);
        a + (b - a) * (x - i as f32)
    }

    fn build(distribution: Distribution, alpha: f32, eta: f32) -> CoatingTables {
        let mut transmittance = [0.0; TABLE_SIZE];
        let mut internal = 0.0;
        for (k, t) in transmittance.iter_mut().enumerate() {
            let mu = (k as f64 / (TABLE_SIZE - 1) as f64).max(1e-6);
            let wi = Vec3::new((1.0 - mu * mu).sqrt() as f32, 0.0, mu as f32);
            let (entering, reflected) = match distribution {
                // The tables take one direction's masking at a time: the masking form is moot.
                Distribution::Ggx | Distribution::GgxSeparable => {
                    coating_albedos(Ggx { alpha }, wi, eta)
                }
                Distribution::Beckmann | Distribution::BeckmannSeparable => {
                    coating_albedos(Beckmann { alpha }, wi, eta)
                }
            };
            *t = entering as f32;
            internal += reflected * mu;
        }
        CoatingTables {
            transmittance,
            internal_reflectance: (2.0 * internal / TABLE_SIZE as f64) as f32,
        }
    }
}

/// For light arriving along `wi`: the fraction transmitted into a coating of
/// relative index `eta` unmasked, and the fraction reflected unmasked when it
/// arrives from inside (relative index 1/η, total internal reflection
/// included); both averages over the normals visible from `wi`.
fn coating_albedos<M: Microfacet + SlopeDensity>(mf: M, wi: Vec3, eta: f32) -> (f64, f64) {
    let transmitted = visible_average(mf, wi, |m| {
        let cos = wi.dot(m);
        match fresnel::refract(wi, m, eta) {
            Some(wt) if wt.z < 0.0 => ((1.0 - fresnel::dielectric(cos, eta)) * mf.g1(wt)) as f64,
            _ => 0.0,
        }
    });
    let reflected = visible_average(mf, wi, |m| {
        let cos = wi.dot(m);
        let wr = 2.0 * cos * m - wi;
        if wr.z <= 0.0 {
            return 0.0;
        }
        (fresnel::dielectric(cos, 1.0 / eta) * mf.g1(wr)) as f64
    });
    (transmitted, reflected)
}

/// A distribution's slopes: its width α, and the slope density of the
/// distribution of α = 1 as a function of t = |s|² (slopes s in units of
/// α): P22(s) α² = slope_density(|s/α|²).
trait SlopeDensity {
    fn alpha(&self) -> f32;
    fn slope_density(t: f64) -> f64;
}

impl SlopeDensity for Ggx {
    fn alpha(&self) -> f32 {
        self.alpha
    }
    fn slope_density(t: f64) -> f64 {
        1.0 / (std::f64::consts::PI * (1.0 + t) * (1.0 + t))
    }
}

impl SlopeDensity for Beckmann {
    fn alpha(&self) -> f32 {
        self.alpha
    }
    fn slope_density(t: f64) -> f64 {
        (-t).exp() / std::f64::consts::PI
    }
}

/// ∫ D_wi(m) g(m) dm over the normals visible from `wi` (in the xz plane),
/// D_wi = G1(wi) (wi·m)⁺ D(m) / cos θi, in slope space: there D(m) cos θm dm
/// is the slope density and wi·m / cos θm = cos θi − s_x sin θi, linear,
/// so the visible normals are the half-plane s_x < cot θi and the
/// integrand has no kink inside it. Slopes α tan a, α tan b over
/// a ∈ (−π/2, atan(cot θi / α)), b ∈ (0, π/2) (g must be even in m.y),
/// composite Gauss–Legendre in a and b.
fn visible_average<M: Microfacet + SlopeDensity>(mf: M, wi: Vec3, g: impl Fn(Vec3) -> f64) -> f64 {
    use std::f64::consts::FRAC_PI_2;
    let (sin_i, cos_i, alpha) = (wi.x as f64, wi.z as f64, mf.alpha() as f64);
    let a_max = if sin_i > 0.0 {
        (cos_i / (sin_i * alpha)).atan()
    } else {
        FRAC_PI_2
    };
    let over_a = |a: f64| {
        let (tan_a, sec2_a) = (a.tan(), 1.0 / a.cos().powi(2));
        let projected = (cos_i - alpha * tan_a * sin_i).max(0.0);
        let over_b = |b: f64| {
            let (tan_b, sec2_b) = (b.tan(), 1.0 / b.cos().powi(2));
            let density = M::slope_density(tan_a * tan_a + tan_b * tan_b) * sec2_a * sec2_b;
            let m = Vec3::new((-alpha * tan_a) as f32, (-alpha * tan_b) as f32, 1.0).normalize();
            density * g(m)
        };
        // b and −b alike.
        2.0 * projected * gauss_legendre(over_b, 0.0, FRAC_PI_2, 8)
    };
    mf.g1(wi) as f64 / cos_i * gauss_legendre(over_a, -FRAC_PI_2, a_max, 8)
}
