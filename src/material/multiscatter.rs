//! Energy compensation of the rough lobes (Kulla & Conty 2017, "Revisiting
//! Physically Based Shading at Imageworks"): the energy 1 − E(μo) that the
//! single-scattering GGX lobe loses to masking comes back as a diffuse-like
//! lobe f_ms = (1 − E(μo)) (1 − E(μi)) / (π (1 − E_avg)), which is
//! reciprocal and reflects exactly 1 − E(μo).
//!
//! A conductor's lobe is tinted by F_avg² E_avg / (1 − F_avg (1 − E_avg)),
//! the energy a path bouncing between facets keeps with Fresnel. A
//! dielectric's is split between reflection (1 − t) and transmission (t),
//! with t on the two sides related by reciprocity:
//! t_enter (1 − E_avg,enter) = η² t_leave (1 − E_avg,leave), t_enter = 1 − F_avg(η)
//! unless that makes t_leave exceed 1.
//!
//! Sampling is one-sample MIS: the compensation lobe (cosine-distributed)
//! with probability 1 − E(μo), the single-scattering lobe otherwise; the
//! weight is the sum of both lobes over the sum of both densities, so
//! `eval`, `pdf` and `sample` agree for every integrator.

use super::albedo::{self, Side};
use super::microfacet::Ggx;
use super::rough::{self, LocalSample};
use super::ConductorFresnel;
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

/// A compensation lobe whose missing average energy is below this is off
/// (its normalization 1 / (1 − E_avg) would amplify table noise).
const MIN_LOSS: f32 = 1e-5;

/// The 8-point Gauss–Legendre rule on [0, 1]: (node, weight).
const GAUSS_8: [(f32, f32); 8] = [
    (0.019_855_072, 0.050_614_27),
    (0.101_666_76, 0.111_190_52),
    (0.237_233_79, 0.156_853_32),
    (0.408_282_68, 0.181_341_89),
    (0.591_717_3, 0.181_341_89),
    (0.762_766_2, 0.156_853_32),
    (0.898_333_24, 0.111_190_52),
    (0.980_144_9, 0.050_614_27),
];

/// 2∫F(μ) μ dμ, the hemispherical average of a conductor's Fresnel reflectance.
pub fn fresnel_average(fresnel: &ConductorFresnel) -> Rgb {
    match *fresnel {
        // 2∫(1 − μ)⁵ μ dμ = 1/21.
        ConductorFresnel::Schlick { f0 } => f0 + (Rgb::WHITE - f0) * (1.0 / 21.0),
        ConductorFresnel::Complex { .. } => GAUSS_8.iter().fold(Rgb::BLACK, |acc, &(mu, w)| {
            acc + fresnel.eval(mu) * (2.0 * w * mu)
        }),
    }
}

/// A cosine-distributed direction on the side of `wo` (`through` = false) or the other.
fn cosine_direction(u: Vec2, through: bool) -> Vec3 {
    let d = warp::square_to_cosine_hemisphere(u);
    if through {
        Vec3::new(d.x, d.y, -d.z)
    } else {
        d
    }
}

/// The conductor's compensation lobe: `f_ms · cos θi` and its sampling probability.
struct ConductorMs {
    loss_o: f32,
    loss_avg: f32,
    alpha: f32,
}

impl ConductorMs {
    fn new(alpha: f32, mu_o: f32) -> ConductorMs {
        let loss_avg = 1.0 - albedo::conductor_average(alpha);
        let loss_o = if loss_avg < MIN_LOSS {
            0.0
        } else {
            (1.0 - albedo::conductor(mu_o, alpha)).clamp(0.0, 1.0)
        };
        ConductorMs {
            loss_o,
            loss_avg,
            alpha,
        }
    }

    fn eval(&self, fresnel: &ConductorFresnel, wi: Vec3) -> Rgb {
        if self.loss_o == 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let e_avg = 1.0 - self.loss_avg;
        let f_avg = fresnel_average(fresnel);
        let tint = f_avg * f_avg * e_avg / (Rgb::WHITE - f_avg * self.loss_avg);
        let loss_i = 1.0 - albedo::conductor(wi.z, self.alpha);
        tint * (self.loss_o * loss_i * wi.z * FRAC_1_PI / self.loss_avg)
    }

    fn pdf(&self, wi: Vec3) -> f32 {
        self.loss_o * wi.z.max(0.0) * FRAC_1_PI
    }
}

/// `f · cos θi` of the compensated rough conductor.
pub(super) fn conductor_eval(ggx: Ggx, fresnel: &ConductorFresnel, wo: Vec3, wi: Vec3) -> Rgb {
    if wo.z <= 0.0 {
        return Rgb::BLACK;
    }
    let ms = ConductorMs::new(ggx.alpha, wo.z);
    rough::conductor_eval(ggx, fresnel, wo, wi) + ms.eval(fresnel, wi)
}

/// Density of `conductor_sample` producing `wi`.
pub(super) fn conductor_pdf(ggx: Ggx, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    let ms = ConductorMs::new(ggx.alpha, wo.z);
    (1.0 - ms.loss_o) * rough::conductor_pdf(ggx, wo, wi) + ms.pdf(wi)
}

/// Picks the compensation lobe with probability 1 − E(μo), else the single-scattering one.
pub(super) fn conductor_sample(
    ggx: Ggx,
    fresnel: &ConductorFresnel,
    wo: Vec3,
    u: Vec2,
    u_lobe: f32,
) -> Option<LocalSample> {
    let ms = ConductorMs::new(ggx.alpha, wo.z);
    let wi = if u_lobe < ms.loss_o {
        cosine_direction(u, false)
    } else {
        rough::conductor_sample(ggx, fresnel, wo, u)?.wi
    };
    let pdf = (1.0 - ms.loss_o) * rough::conductor_pdf(ggx, wo, wi) + ms.pdf(wi);
    let value = rough::conductor_eval(ggx, fresnel, wo, wi) + ms.eval(fresnel, wi);
    (pdf > 0.0).then(|| LocalSample {
        wi,
        weight: value / pdf,
        pdf,
    })
}

/// Shares of the compensation that cross the interface from each side,
/// for index ratio `eta` ≥ 1: (t_enter, t_leave).
fn transmitted_shares(alpha: f32, eta: f32) -> (f32, f32) {
    let loss_enter = 1.0 - albedo::dielectric_average(Side::Enter, eta, alpha);
    let loss_leave = 1.0 - albedo::dielectric_average(Side::Leave, eta, alpha);
    let t_enter = 1.0 - albedo::fresnel_average(eta);
    let t_leave = t_enter * loss_enter / (eta * eta * loss_leave);
    if t_leave <= 1.0 {
        (t_enter, t_leave)
    } else {
        ((eta * eta * loss_leave / loss_enter).min(1.0), 1.0)
    }
}

/// The dielectric's compensation lobe seen from `wo`.
struct DielectricMs {
    side: Side,
    ratio: f32,
    alpha: f32,
    loss_o: f32,
    /// 1 − E_avg of the side of `wo` (reflection) and of the other side (transmission).
    loss_avg: [f32; 2],
    /// Shares of the energy lost at `wo`: reflected, transmitted (0 for a lobe that is off).
    share: [f32; 2],
}

impl DielectricMs {
    fn new(alpha: f32, eta: f32, mu_o: f32) -> DielectricMs {
        let (side, ratio) = Side::of(eta);
        let loss_avg =
            [side, side.other()].map(|s| 1.0 - albedo::dielectric_average(s, ratio, alpha));
        let (t_enter, t_leave) = transmitted_shares(alpha, ratio);
        let t = if side == Side::Enter {
            t_enter
        } else {
            t_leave
        };
        let on = |lobe: usize| loss_avg[lobe] >= MIN_LOSS;
        let share = [
            if on(0) { 1.0 - t } else { 0.0 },
            if on(0) && on(1) { t } else { 0.0 },
        ];
        let loss_o = (1.0 - albedo::dielectric(side, ratio, mu_o, alpha)).clamp(0.0, 1.0);
        DielectricMs {
            side,
            ratio,
            alpha,
            loss_o,
            loss_avg,
            share,
        }
    }

    /// Probability of sampling the compensation lobe.
    fn probability(&self) -> f32 {
        self.loss_o * (self.share[0] + self.share[1])
    }

    /// `f_ms · |cos θi|` in radiance form (`eta` = far over near).
    fn eval(&self, eta: f32, wi: Vec3) -> Rgb {
        let lobe = usize::from(wi.z < 0.0);
        if self.share[lobe] == 0.0 || wi.z == 0.0 {
            return Rgb::BLACK;
        }
        let side_i = if lobe == 0 {
            self.side
        } else {
            self.side.other()
        };
        let mu_i = wi.z.abs();
        let loss_i = 1.0 - albedo::dielectric(side_i, self.ratio, mu_i, self.alpha);
        let energy = self.share[lobe] * self.loss_o * loss_i.max(0.0) * mu_i * FRAC_1_PI
            / self.loss_avg[lobe];
        // Radiance is compressed by (η_wo / η_wi)² on the way through.
        Rgb::splat(if lobe == 1 {
            energy / (eta * eta)
        } else {
            energy
        })
    }

    fn pdf(&self, wi: Vec3) -> f32 {
        let lobe = usize::from(wi.z < 0.0);
        self.loss_o * self.share[lobe] * wi.z.abs() * FRAC_1_PI
    }
}

/// `f · cos θi` of the compensated rough dielectric, for radiance transport.
pub(super) fn dielectric_eval(ggx: Ggx, eta: f32, wo: Vec3, wi: Vec3) -> Rgb {
    if wo.z <= 0.0 {
        return Rgb::BLACK;
    }
    let ms = DielectricMs::new(ggx.alpha, eta, wo.z);
    rough::dielectric_eval(ggx, eta, wo, wi) + ms.eval(eta, wi)
}

/// Density of `dielectric_sample` producing `wi`.
pub(super) fn dielectric_pdf(ggx: Ggx, eta: f32, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    let ms = DielectricMs::new(ggx.alpha, eta, wo.z);
    (1.0 - ms.probability()) * rough::dielectric_pdf(ggx, eta, wo, wi) + ms.pdf(wi)
}

/// Picks the compensation lobe (then reflection or transmission by their
/// shares), else the single-scattering lobe with the rest of `u_lobe`.
pub(super) fn dielectric_sample(
    ggx: Ggx,
    eta: f32,
    wo: Vec3,
    u: Vec2,
    u_lobe: f32,
) -> Option<LocalSample> {
    let ms = DielectricMs::new(ggx.alpha, eta, wo.z);
    let p = ms.probability();
    let wi = if u_lobe < p {
        let u_side = u_lobe / p * (ms.share[0] + ms.share[1]);
        cosine_direction(u, u_side >= ms.share[0])
    } else {
        let u_rest = ((u_lobe - p) / (1.0 - p)).min(1.0 - f32::EPSILON);
        rough::dielectric_sample(ggx, eta, wo, u, u_rest)?.wi
    };
    let pdf = (1.0 - p) * rough::dielectric_pdf(ggx, eta, wo, wi) + ms.pdf(wi);
    let value = rough::dielectric_eval(ggx, eta, wo, wi) + ms.eval(eta, wi);
    (pdf > 0.0).then(|| LocalSample {
        wi,
        weight: value / pdf,
        pdf,
    })
}
