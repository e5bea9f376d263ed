//! Phase functions: the angular distribution of light scattered in a medium.
//!
//! Direction convention: both arguments are *propagation* directions of the
//! path (unit vectors), the one arriving at the scattering point and the one
//! leaving it, so `cos θ = dir_in · dir_out` and θ = 0 means the path keeps
//! going straight on. With this convention a positive Henyey–Greenstein `g`
//! is forward scattering. Every variant is sampled exactly, so `pdf == eval`
//! and sampled weights are 1.

use crate::math::{Frame, Vec2, Vec3};
use std::f32::consts::PI;

const INV_FOUR_PI: f32 = 0.25 / PI;

/// The largest `f32` below 1, so remapped random numbers stay in [0, 1).
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// The angular scattering distribution of a medium (a closed set, matched, never boxed).
///
/// In a scene file it is an inline table, e.g.
/// ```toml
/// phase = { type = "hg", g = 0.3 }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseFunction {
    /// Uniform over the sphere: p = 1/(4π).
    Isotropic,
    /// Henyey & Greenstein (1941): p = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}).
    HenyeyGreenstein {
        /// Mean cosine of the scattering angle, in (−1, 1); positive is forward.
        g: f32,
    },
    /// Scattering by particles much smaller than the wavelength: p = 3/(16π) (1 + cos²θ).
    Rayleigh,
    /// The mixture `w·HG(g_forward) + (1 − w)·HG(g_back)`, e.g. a cloud's forward peak plus backscatter.
    DoubleHenyeyGreenstein {
        /// Asymmetry of the first lobe, in (−1, 1).
        g_forward: f32,
        /// Asymmetry of the second lobe, in (−1, 1).
        g_back: f32,
        /// Weight `w` of the first lobe, in [0, 1].
        weight_forward: f32,
    },
}

/// A direction drawn from a phase function.
#[derive(Clone, Copy, Debug)]
pub struct PhaseSample {
    /// Unit propagation direction after scattering.
    pub direction: Vec3,
    /// Density of `direction` per steradian; equal to `PhaseFunction::pdf`.
    pub pdf: f32,
    /// `eval / pdf`: 1 for every variant, since all are sampled exactly.
    pub weight: f32,
}

impl PhaseFunction {
    /// Phase function value per steradian for propagation directions `dir_in` → `dir_out`.
    pub fn eval(&self, dir_in: Vec3, dir_out: Vec3) -> f32 {
        match *self {
            PhaseFunction::Isotropic => INV_FOUR_PI,
            PhaseFunction::HenyeyGreenstein { g } => henyey_greenstein(g, dir_in, dir_out),
            PhaseFunction::Rayleigh => {
                let cos_theta = dir_in.dot(dir_out).clamp(-1.0, 1.0);
                3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta)
            }
            PhaseFunction::DoubleHenyeyGreenstein {
                g_forward,
                g_back,
                weight_forward: w,
            } => {
                w * henyey_greenstein(g_forward, dir_in, dir_out)
                    + (1.0 - w) * henyey_greenstein(g_back, dir_in, dir_out)
            }
        }
    }

    /// Density of `sample` producing `dir_out`; identical to `eval` for every variant.
    #[inline]
    pub fn pdf(&self, dir_in: Vec3, dir_out: Vec3) -> f32 {
        self.eval(dir_in, dir_out)
    }

    /// Draws an outgoing propagation direction for incoming `dir_in` from uniform `u` in [0, 1)².
    ///
    /// `u.x` picks cos θ (and, for double HG, first the lobe), `u.y` the azimuth;
    /// isotropic scattering, the same in every frame, takes `u` as a uniform
    /// direction in world space (no frame about `dir_in` to build).
    /// `None` only for parameters that fail `validate`.
    pub fn sample(&self, dir_in: Vec3, u: Vec2) -> Option<PhaseSample> {
        let (one_minus_cos, one_plus_cos) = match *self {
            PhaseFunction::Isotropic => {
                return Some(PhaseSample {
                    direction: crate::sampling::warp::square_to_uniform_sphere(u),
                    pdf: INV_FOUR_PI,
                    weight: 1.0,
                })
            }
            PhaseFunction::HenyeyGreenstein { g } => henyey_greenstein_cos(g, u.x),
            PhaseFunction::Rayleigh => rayleigh_cos(u.x),
            PhaseFunction::DoubleHenyeyGreenstein {
                g_forward,
                g_back,
                weight_forward: w,
            } => {
                // The lobe choice reuses u.x: its position inside the chosen stratum is again uniform.
                let (g, v) = if u.x < w {
                    (g_forward, u.x / w)
                } else {
                    (g_back, (u.x - w) / (1.0 - w))
                };
                henyey_greenstein_cos(g, v.clamp(0.0, ONE_MINUS_EPSILON))
            }
        };
        let cos_theta = if one_minus_cos < one_plus_cos {
            1.0 - one_minus_cos
        } else {
            one_plus_cos - 1.0
        };
        // (1 − cos)(1 + cos) keeps sin θ accurate near both poles, where 1 − cos² cancels.
        let sin_theta = (one_minus_cos * one_plus_cos).clamp(0.0, 1.0).sqrt();
        let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
        let local = Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta);
        let direction = Frame::from_z(dir_in).to_world(local).normalize();
        let pdf = self.pdf(dir_in, direction);
        (direction.is_finite() && pdf.is_finite() && pdf > 0.0).then_some(PhaseSample {
            direction,
            pdf,
            weight: 1.0,
        })
    }

    /// The mean cosine ⟨cos θ⟩ of the scattering angle, analytically.
    pub fn mean_cosine(&self) -> f32 {
        match *self {
            PhaseFunction::Isotropic | PhaseFunction::Rayleigh => 0.0,
            PhaseFunction::HenyeyGreenstein { g } => g,
            PhaseFunction::DoubleHenyeyGreenstein {
                g_forward,
                g_back,
                weight_forward: w,
            } => w * g_forward + (1.0 - w) * g_back,
        }
    }

    /// Checks the parameters; the error message names the offending one and its value.
    pub fn validate(&self) -> Result<(), String> {
        let check_g = |name: &str, g: f32| {
            if g.is_finite() && g.abs() < 1.0 {
                Ok(())
            } else {
                Err(format!(
                    "phase function parameter {name} = {g} must be finite with |{name}| < 1"
                ))
            }
        };
        match *self {
            PhaseFunction::Isotropic | PhaseFunction::Rayleigh => Ok(()),
            PhaseFunction::HenyeyGreenstein { g } => check_g("g", g),
            PhaseFunction::DoubleHenyeyGreenstein {
                g_forward,
                g_back,
                weight_forward,
            } => {
                check_g("g_forward", g_forward)?;
                check_g("g_back", g_back)?;
                if (0.0..=1.0).contains(&weight_forward) {
                    Ok(())
                } else {
                    Err(format!(
                        "phase function parameter weight_forward = {weight_forward} must lie in [0, 1]"
                    ))
                }
            }
        }
    }
}

/// Henyey–Greenstein density per steradian between propagation directions.
fn henyey_greenstein(g: f32, dir_in: Vec3, dir_out: Vec3) -> f32 {
    // 1 + g² − 2g cos θ as a sum of non-negative terms, using 1 ∓ cos θ = |a ∓ b|²/2:
    // the peak of a strongly forward (or backward) lobe would otherwise be lost to cancellation.
    let denom = if g >= 0.0 {
        (1.0 - g) * (1.0 - g) + g * (dir_in - dir_out).length_squared()
    } else {
        (1.0 + g) * (1.0 + g) - g * (dir_in + dir_out).length_squared()
    };
    INV_FOUR_PI * (1.0 - g * g) / (denom * denom.sqrt())
}

/// Inverts the Henyey–Greenstein CDF in cos θ, returning `(1 − cos θ, 1 + cos θ)`.
///
/// The textbook inverse `(1 + g² − s²) / (2g)` cancels catastrophically as g → 0
/// and near the peak as |g| → 1. Expanding it gives, with `q = (1−g)(1−u) + (1+g)u`,
///   `1 − cos θ = 2 (1−g)² (1−u) ((1−u) + (1+g)u) / q²`,
///   `1 + cos θ = 2 (1+g)² u ((1−g)(1−u) + u) / q²`,
/// products of non-negative factors only, so both stay accurate to a few ulps.
fn henyey_greenstein_cos(g: f32, u: f32) -> (f32, f32) {
    let (a, b) = (1.0 - g, 1.0 + g);
    let v = 1.0 - u;
    let q = a * v + b * u;
    let scale = 2.0 / (q * q);
    (
        scale * a * a * v * (v + b * u),
        scale * b * b * u * (a * v + u),
    )
}

/// Inverts the Rayleigh CDF in cos θ exactly, returning `(1 − cos θ, 1 + cos θ)`.
///
/// The CDF is `(μ³ + 3μ + 4) / 8`, so μ solves the depressed cubic `μ³ + 3μ − 2z = 0`
/// with `z = 4u − 2`. Its discriminant is positive, and Cardano's formula gives the one
/// real root `μ = A − 1/A` with `A = ∛(z + √(z² + 1))`. Using |z| and restoring the sign
/// avoids the cancellation in `z + √(z² + 1)` for negative z.
fn rayleigh_cos(u: f32) -> (f32, f32) {
    let z = 4.0 * u - 2.0;
    let big_a = (z.abs() + (z * z + 1.0).sqrt()).cbrt();
    let mu = (big_a - 1.0 / big_a).copysign(z).clamp(-1.0, 1.0);
    (1.0 - mu, 1.0 + mu)
}

#[cfg(test)]
mod tests;
