//! Equiangular distance sampling toward a point light (Kulla & Fajardo 2012).
//!
//! Single scattering from a point light along a ray falls off as 1/r², peaking
//! where the ray passes closest to the light. Sampling t uniformly in the angle
//! θ subtended at the light cancels that factor exactly. With Δ = (c − o)·d the
//! parameter of the closest point, D the light's distance from the line and
//! θ(t) = atan((t − Δ)/D), the density on [t_min, t_max] is
//!
//!   pdf(t) = D / ((θ_b − θ_a) (D² + (t − Δ)²)).
//!
//! Degenerate case: when the light lies on the ray's line (D below 1e-6 of the
//! light's distance from the ray origin, the rounding noise of D itself: a
//! threshold that scales with the scene, unlike one tied to the segment's
//! length, which would call a light beside a long segment "on it"), the density above tends
//! to `s_a s_b / ((s_b − s_a) s²)` with s = t − Δ if the light is outside the
//! segment, and that limit is sampled instead; if the light is on the segment no
//! normalizable density exists, so `sample_equiangular` returns `None` and
//! `equiangular_pdf` returns 0. Both functions classify through the same code.

use super::Sample;
use crate::math::Vec3;

/// Below this ratio of D to the light's distance from the ray origin, the light counts as on the line.
const ON_LINE_RATIO: f32 = 1e-6;

/// The shape of the density for one (ray, light, interval).
enum Shape {
    /// Light off the line at distance `d`, the segment subtending angle `theta` at it.
    Angular { d: f32, theta: f32 },
    /// Light on the line beyond the segment: the 1/s² limit.
    OnLine,
}

/// The interval relative to the closest point: s = t − Δ runs over [s_a, s_b].
struct Setup {
    delta: f32,
    s_a: f32,
    s_b: f32,
    shape: Shape,
}

/// Classifies the configuration; `None` for an empty or non-finite interval or a light on it.
fn setup(origin: Vec3, dir: Vec3, light_pos: Vec3, t_min: f32, t_max: f32) -> Option<Setup> {
    if !(t_min.is_finite() && t_max.is_finite() && t_min < t_max) {
        return None;
    }
    let to_light = light_pos - origin;
    let delta = to_light.dot(dir);
    // |(c − o) × d| rather than |c − (o + Δd)|: no cancellation when the light is far away.
    let d = to_light.cross(dir).length();
    let (s_a, s_b) = (t_min - delta, t_max - delta);
    let shape = if d > ON_LINE_RATIO * to_light.length() {
        // θ_b − θ_a by the tangent subtraction formula: stays accurate when both
        // angles crowd ±π/2, where subtracting two atans would cancel.
        let theta = (d * (s_b - s_a)).atan2(d * d + s_a * s_b);
        Shape::Angular { d, theta }
    } else if s_a * s_b > 0.0 {
        Shape::OnLine
    } else {
        return None;
    };
    Some(Setup {
        delta,
        s_a,
        s_b,
        shape,
    })
}

impl Setup {
    /// Density of s = t − Δ.
    fn pdf(&self, s: f32) -> f32 {
        if !(self.s_a..=self.s_b).contains(&s) {
            return 0.0;
        }
        match self.shape {
            Shape::Angular { d, theta } => d / (theta * (d * d + s * s)),
            Shape::OnLine => self.s_a * self.s_b / ((self.s_b - self.s_a) * s * s),
        }
    }

    /// Inverse CDF in s.
    fn invert(&self, u: f32) -> f32 {
        let (s_a, s_b) = (self.s_a, self.s_b);
        match self.shape {
            Shape::Angular { d, theta } => {
                // s = D tan(θ_a + uΘ) with tan θ_a = s_a / D, expanded by the tangent
                // addition formula so that nothing divides by a tiny D.
                let tan_phi = (u * theta).tan();
                d * (s_a + d * tan_phi) / (d - s_a * tan_phi)
            }
            // 1/s interpolates linearly in u, the CDF of the 1/s² density.
            Shape::OnLine => s_a * s_b / (s_b - u * (s_b - s_a)),
        }
    }
}

/// Samples a distance `t` in [t_min, t_max] along the ray `origin + t·dir` (unit `dir`)
/// equiangularly toward a point light at `light_pos`, from uniform `u` in [0, 1).
///
/// Returns `value = t`, `pdf` per unit length (equal to `equiangular_pdf` at t) and
/// `weight = 1 / pdf`; `None` when the interval is empty or not finite, or the light lies on it.
pub fn sample_equiangular(
    origin: Vec3,
    dir: Vec3,
    light_pos: Vec3,
    t_min: f32,
    t_max: f32,
    u: f32,
) -> Option<Sample<f32>> {
    let setup = setup(origin, dir, light_pos, t_min, t_max)?;
    // Clamping absorbs rounding at the ends; the pdf is then evaluated where t really is.
    let t = (setup.delta + setup.invert(u)).clamp(t_min, t_max);
    let pdf = setup.pdf(t - setup.delta);
    (pdf.is_finite() && pdf > 0.0).then(|| Sample {
        value: t,
        pdf,
        weight: 1.0 / pdf,
    })
}

/// Density per unit length with which `sample_equiangular` produces `t` (0 outside the interval).
pub fn equiangular_pdf(
    origin: Vec3,
    dir: Vec3,
    light_pos: Vec3,
    t_min: f32,
    t_max: f32,
    t: f32,
) -> f32 {
    match setup(origin, dir, light_pos, t_min, t_max) {
        Some(setup) if (t_min..=t_max).contains(&t) => setup.pdf(t - setup.delta),
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests;
