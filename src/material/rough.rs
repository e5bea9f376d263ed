//! Microfacet lobes: rough conductor reflection and rough dielectric
//! reflection + transmission (Walter et al. 2007), generic over the
//! distribution (GGX sampled through visible normals, Beckmann through
//! D cos θm). All functions work in the local frame (`wo.z > 0`).

use super::fresnel::{self, refract};
use super::microfacet::Microfacet;
use super::ConductorFresnel;
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};

/// A sampled direction in the local frame with its weight `f cos / pdf` and pdf.
pub(super) struct LocalSample {
    pub wi: Vec3,
    pub weight: Rgb,
    pub pdf: f32,
}

fn reflect(wo: Vec3, m: Vec3) -> Vec3 {
    2.0 * wo.dot(m) * m - wo
}

/// `f · cos θi` of the rough conductor.
pub(super) fn conductor_eval<M: Microfacet>(
    mf: M,
    fresnel: &ConductorFresnel,
    wo: Vec3,
    wi: Vec3,
) -> Rgb {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Rgb::BLACK;
    }
    let Some(m) = (wo + wi).try_normalize() else {
        return Rgb::BLACK;
    };
    // f = F D G2 / (4 cosθo cosθi); the cosθi cancels.
    fresnel.eval(wo.dot(m)) * (mf.d(m) * mf.g2(wo, wi) / (4.0 * wo.z))
}

/// Density of `conductor_sample` producing `wi`.
pub(super) fn conductor_pdf<M: Microfacet>(mf: M, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let Some(m) = (wo + wi).try_normalize() else {
        return 0.0;
    };
    // dωm/dωi = 1 / (4 |wo·m|) for reflection.
    mf.normal_pdf(wo, m) / (4.0 * wo.dot(m))
}

/// Reflects `wo` about a visible normal.
pub(super) fn conductor_sample<M: Microfacet>(
    mf: M,
    fresnel: &ConductorFresnel,
    wo: Vec3,
    u: Vec2,
) -> Option<LocalSample> {
    let m = mf.sample_normal(wo, u);
    let wi = reflect(wo, m);
    if wi.z <= 0.0 {
        return None;
    }
    let pdf = mf.normal_pdf(wo, m) / (4.0 * wo.dot(m));
    (pdf > 0.0).then(|| LocalSample {
        wi,
        weight: fresnel.eval(wo.dot(m)) * mf.sample_weight(wo, wi, m),
        pdf,
    })
}

/// The microfacet normal of a transmitted pair and the term `wo·m + η wi·m`.
///
/// `eta` = η on the side of `wi` over η on the side of `wo`.
fn transmission_normal(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut m = (wo + eta * wi).try_normalize()?;
    if m.z < 0.0 {
        m = -m;
    }
    // Both directions must see the facet from the sides they are on.
    if wo.dot(m) <= 0.0 || wi.dot(m) >= 0.0 {
        return None;
    }
    Some((m, wo.dot(m) + eta * wi.dot(m)))
}

/// `f · cos θi` of the rough dielectric, for radiance transport.
pub(super) fn dielectric_eval<M: Microfacet>(mf: M, eta: f32, wo: Vec3, wi: Vec3) -> Rgb {
    if wo.z <= 0.0 || wi.z == 0.0 {
        return Rgb::BLACK;
    }
    if wi.z > 0.0 {
        let Some(m) = (wo + wi).try_normalize() else {
            return Rgb::BLACK;
        };
        let f = fresnel::dielectric(wo.dot(m), eta);
        return Rgb::splat(f * mf.d(m) * mf.g2(wo, wi) / (4.0 * wo.z));
    }
    let Some((m, denom)) = transmission_normal(wo, wi, eta) else {
        return Rgb::BLACK;
    };
    let f = fresnel::dielectric(wo.dot(m), eta);
    // Walter's BTDF in radiance form; its |wi·n| cancels against cosθi.
    let value =
        (1.0 - f) * mf.d(m) * mf.g2(wo, wi) * wi.dot(m).abs() * wo.dot(m) / (wo.z * denom * denom);
    Rgb::splat(value)
}

/// Density of `dielectric_sample` producing `wi`.
pub(super) fn dielectric_pdf<M: Microfacet>(mf: M, eta: f32, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z == 0.0 {
        return 0.0;
    }
    if wi.z > 0.0 {
        let Some(m) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        let f = fresnel::dielectric(wo.dot(m), eta);
        return f * mf.normal_pdf(wo, m) / (4.0 * wo.dot(m));
    }
    let Some((m, denom)) = transmission_normal(wo, wi, eta) else {
        return 0.0;
    };
    let f = fresnel::dielectric(wo.dot(m), eta);
    // dωm/dωi = η² |wi·m| / (wo·m + η wi·m)².
    (1.0 - f) * mf.normal_pdf(wo, m) * eta * eta * wi.dot(m).abs() / (denom * denom)
}

/// Picks reflection (probability F) or refraction through a visible normal.
pub(super) fn dielectric_sample<M: Microfacet>(
    mf: M,
    eta: f32,
    wo: Vec3,
    u: Vec2,
    u_lobe: f32,
) -> Option<LocalSample> {
    let m = mf.sample_normal(wo, u);
    let cos_om = wo.dot(m);
    if cos_om <= 0.0 {
        return None;
    }
    let f = fresnel::dielectric(cos_om, eta);
    let vndf = mf.normal_pdf(wo, m);
    let g_ratio = |wi: Vec3| mf.sample_weight(wo, wi, m);
    if u_lobe < f {
        let wi = reflect(wo, m);
        if wi.z <= 0.0 {
            return None;
        }
        return Some(LocalSample {
            wi,
            weight: Rgb::splat(g_ratio(wi)),
            pdf: f * vndf / (4.0 * cos_om),
        });
    }
    let wi = refract(wo, m, eta)?;
    if wi.z >= 0.0 {
        return None;
    }
    let denom = cos_om + eta * wi.dot(m);
    let pdf = (1.0 - f) * vndf * eta * eta * wi.dot(m).abs() / (denom * denom);
    // Radiance is compressed by (η_wo / η_wi)² on the way through.
    (pdf > 0.0).then(|| LocalSample {
        wi,
        weight: Rgb::splat(g_ratio(wi) / (eta * eta)),
        pdf,
    })
}
