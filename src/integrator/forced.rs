//! Forced in-scattering: next-event estimation at a point drawn over the
//! whole medium part of a ray segment, whether or not the free flight
//! scatters there.
//!
//! Free flight decides whether a segment scatters at all (probability
//! 1 − T̄ through its majorant) before its vertex samples a light. Along a
//! thin segment that coin is most of the noise of single-scattered light: a
//! ray that passes gathers none of the segment's in-scattering, one that
//! scatters gathers it divided by 1 − T. Here the segment instead draws one
//! point t with the free-flight density conditioned on scattering inside,
//! p(t) = σ̄(t)·T̄(0, t) / (1 − T̄), and samples a light there, weighted
//! σs(t)·T(0, t) / p(t) (T in closed form: the strategy is used only in
//! media that have one); the real collision of the free flight, if any,
//! then samples only the path's continuation.
//!
//! The MIS partition between light and phase sampling is kept: a path
//! through a point t of the segment toward a light has weight
//! w_light(t, ω) as a light sample from the forced point and w_phase(t, ω)
//! as a phase sample from the collision, which still sum to one; only the
//! densities of t differ between the two, and each estimator divides by its
//! own.

use super::direct::{direct_light, Vertex};
use super::Scene;
use crate::math::color::Rgb;
use crate::math::Ray;
use crate::medium::{HomogeneousMedium, Medium};
use crate::sampling::Sampler;

/// A point drawn along a segment and its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ForcedPoint {
    /// Ray parameter.
    pub t: f32,
    /// Density of `t` on the segment: σ̄(t)·T̄(0, t) / (1 − T̄).
    pub pdf: f32,
}

/// The majorant optical depth of `medium` over `[0, t_max)` of `ray`, when its
/// majorant is constant on each piece (`None` for decaying majorants: height fog).
pub(super) fn majorant_depth(medium: &Medium, ray: &Ray, t_max: f32) -> Option<f32> {
    let mut depth = 0.0f32;
    for seg in medium.majorants(ray, t_max) {
        if seg.decay != 0.0 {
            return None;
        }
        if seg.sigma_maj > 0.0 {
            depth += seg.sigma_maj * (seg.t1 - seg.t0);
        }
    }
    Some(depth)
}

/// Draws t over `[0, t_max)` with density σ̄(t)·T̄(0, t) / (1 − T̄) from `u` ∈ [0, 1),
/// given the majorant optical depth `depth` of the whole stretch ([`majorant_depth`]).
pub(super) fn sample_point(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    depth: f32,
    u: f32,
) -> Option<ForcedPoint> {
    if depth.is_nan() || depth <= 0.0 {
        return None;
    }
    // 1 − T̄ and the depth whose conditioned CDF is u, without cancellation on thin segments.
    let scatter = one_minus_exp_neg(depth);
    let target = neg_ln_one_minus(u * scatter);
    let mut before = 0.0f32;
    let mut last = None;
    for seg in medium.majorants(ray, t_max) {
        if seg.sigma_maj <= 0.0 {
            continue;
        }
        let piece = seg.sigma_maj * (seg.t1 - seg.t0);
        last = Some(seg);
        if before + piece >= target {
            let t = (seg.t0 + (target - before) / seg.sigma_maj).clamp(seg.t0, seg.t1);
            let pdf = seg.sigma_maj * (-target).exp() / scatter;
            return Some(ForcedPoint { t, pdf });
        }
        before += piece;
    }
    // Rounding put the target past the last piece: its far end.
    let seg = last?;
    let t = seg.t1.min(t_max);
    t.is_finite().then(|| ForcedPoint {
        t,
        pdf: seg.sigma_maj * (-before).exp() / scatter,
    })
}

/// The density [`sample_point`] gives `t` (0 outside the medium's majorant pieces).
#[cfg(test)]
fn point_pdf(medium: &Medium, ray: &Ray, t_max: f32, depth: f32, t: f32) -> f32 {
    if depth.is_nan() || depth <= 0.0 {
        return 0.0;
    }
    let scatter = -(-depth).exp_m1();
    let mut before = 0.0f32;
    for seg in medium.majorants(ray, t_max) {
        if seg.sigma_maj <= 0.0 {
            continue;
        }
        if t >= seg.t0 && t < seg.t1 {
            let tau = before + seg.sigma_maj * (t - seg.t0);
            return seg.sigma_maj * (-tau).exp() / scatter;
        }
        before += seg.sigma_maj * (seg.t1 - seg.t0);
    }
    0.0
}

/// The in-scattered light along `ray` over `[0, t_surface)` through `medium`
/// from one forced point, or `None` where the strategy does not apply (the
/// collision's own next-event estimation then stands). `at`: the path's time
/// and the medium it is in, for the shadow ray.
pub(super) fn estimate(
    scene: &Scene,
    medium: &Medium,
    ray: &Ray,
    t_surface: f32,
    at: (f32, Option<u32>),
    sampler: &mut Sampler,
) -> Option<Rgb> {
    if let Medium::Homogeneous(m) = medium {
        return Some(estimate_homogeneous(scene, m, ray, t_surface, at, sampler));
    }
    medium.optical_depth(ray, 0.0, 0.0)?;
    let depth = majorant_depth(medium, ray, t_surface)?;
    let u = sampler.next_1d();
    let Some(point) = sample_point(medium, ray, t_surface, depth, u) else {
        return Some(Rgb::BLACK);
    };
    let p = ray.at(point.t);
    let properties = medium.properties(p, ray.time);
    if properties.sigma_s.is_black() {
        return Some(Rgb::BLACK);
    }
    let tr = medium.optical_depth(ray, 0.0, point.t)?.exp_neg();
    if tr.is_black() {
        return Some(Rgb::BLACK);
    }
    let vertex = Vertex::Medium {
        p,
        dir_in: ray.direction,
        phase: &properties.phase,
        equiangular: None,
    };
    let light = direct_light(scene, &vertex, at, sampler);
    Some(light * properties.sigma_s * tr * (1.0 / point.pdf))
}

/// [`estimate`] in a homogeneous medium, from the one interval the ray
/// spends inside it ([`homogeneous_point`]).
fn estimate_homogeneous(
    scene: &Scene,
    medium: &HomogeneousMedium,
    ray: &Ray,
    t_surface: f32,
    at: (f32, Option<u32>),
    sampler: &mut Sampler,
) -> Rgb {
    let u = sampler.next_1d();
    let Some((t, weight)) = homogeneous_point(medium, ray, t_surface, u) else {
        return Rgb::BLACK;
    };
    let vertex = Vertex::Medium {
        p: ray.at(t),
        dir_in: ray.direction,
        phase: &medium.phase,
        equiangular: None,
    };
    direct_light(scene, &vertex, at, sampler) * weight
}

/// The forced point of a homogeneous medium along `ray` over `[0, t_surface)`
/// from `u`, and its weight σs·T(0, t) / p(t): what [`sample_point`] and the
/// closed-form transmittance give, from one intersection of the region
/// instead of four (a shadow ray's worth of work on a fog's every segment).
fn homogeneous_point(
    medium: &HomogeneousMedium,
    ray: &Ray,
    t_surface: f32,
    u: f32,
) -> Option<(f32, Rgb)> {
    let (t0, t1) = medium.region.interval(ray, t_surface)?;
    let sigma_t = medium.sigma_t();
    let sigma_maj = sigma_t.max_channel();
    let depth = sigma_maj * (t1 - t0);
    if depth.is_nan() || depth <= 0.0 || medium.sigma_s.is_black() {
        return None;
    }
    let scatter = one_minus_exp_neg(depth);
    // The majorant depth into the interval whose conditioned CDF is u.
    let target = neg_ln_one_minus(u * scatter).min(depth);
    let t = (t0 + target / sigma_maj).clamp(t0, t1);
    if !t.is_finite() {
        return None;
    }
    // p(t) = σ̄·T̄(t0, t) / (1 − T̄), so T / p = (T / T̄)·(1 − T̄) / σ̄, and T = T̄ where σt is grey.
    let ratio = if sigma_t.min_channel() == sigma_maj {
        Rgb::WHITE
    } else {
        let length = t - t0;
        sigma_t.map(|s| ((sigma_maj - s) * length).exp())
    };
    Some((t, medium.sigma_s * ratio * (scatter / sigma_maj)))
}

/// 1 − e^(−x) for x ≥ 0, without cancellation for small x (and without
/// `exp_m1`, several times slower than `exp` in glibc's single precision).
#[inline]
fn one_minus_exp_neg(x: f32) -> f32 {
    if x < 0.03 {
        -(-x).exp_m1()
    } else {
        1.0 - (-x).exp()
    }
}

/// −ln(1 − x) for x in [0, 1), without cancellation for small x (`ln_1p` only there).
#[inline]
fn neg_ln_one_minus(x: f32) -> f32 {
    if x < 0.03 {
        -(-x).ln_1p()
    } else {
        -(1.0 - x).ln()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Affine3A, Bounds3, Vec3};
    use crate::medium::{HomogeneousMedium, PhaseFunction, Region};

    fn slab_medium(sigma_t: f32) -> Medium {
        Medium::Homogeneous(HomogeneousMedium {
            sigma_a: Rgb::splat(0.2 * sigma_t),
            sigma_s: Rgb::splat(0.8 * sigma_t),
            emission: Rgb::BLACK,
            phase: PhaseFunction::Isotropic,
            region: Region::Box {
                world_to_local: Affine3A::IDENTITY,
                local: Bounds3::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 2.0)),
            },
        })
    }

    #[test]
    fn the_point_density_integrates_to_one_over_the_medium() {
        for sigma_t in [1e-4, 0.3, 2.0, 40.0] {
            let medium = slab_medium(sigma_t);
            let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0));
            let t_max = 10.0;
            let depth = majorant_depth(&medium, &ray, t_max).unwrap();
            assert!((depth - 2.0 * sigma_t).abs() < 1e-5 * depth.max(1.0));
            let n = 200_000;
            let (a, b) = (1.0f64, 3.0f64);
            let h = (b - a) / n as f64;
            let integral: f64 = (0..n)
                .map(|i| {
                    point_pdf(
                        &medium,
                        &ray,
                        t_max,
                        depth,
                        (a + (i as f64 + 0.5) * h) as f32,
                    ) as f64
                        * h
                })
                .sum();
            assert!(
                (integral - 1.0).abs() < 2e-3,
                "σt {sigma_t}: ∫p = {integral}"
            );
            assert_eq!(point_pdf(&medium, &ray, t_max, depth, 0.5), 0.0);
            assert_eq!(point_pdf(&medium, &ray, t_max, depth, 3.5), 0.0);
        }
    }

    #[test]
    fn sampled_points_lie_in_the_medium_with_the_density_they_report() {
        let medium = slab_medium(0.7);
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0));
        let depth = majorant_depth(&medium, &ray, 10.0).unwrap();
        for i in 0..1000 {
            let u = (i as f32 + 0.5) / 1000.0;
            let point = sample_point(&medium, &ray, 10.0, depth, u).unwrap();
            assert!((1.0..=3.0).contains(&point.t), "t = {}", point.t);
            let pdf = point_pdf(&medium, &ray, 10.0, depth, point.t);
            assert!(
                (point.pdf - pdf).abs() <= 1e-4 * pdf,
                "{} against {pdf}",
                point.pdf
            );
            // The CDF of t is u: 1 − e^(−σ(t − 1)) over 1 − e^(−2σ).
            let cdf = (1.0 - (-0.7 * (point.t - 1.0)).exp()) / (1.0 - (-1.4f32).exp());
            assert!((cdf - u).abs() < 1e-4, "CDF {cdf} at u {u}");
        }
    }

    /// The homogeneous shortcut gives the point and weight of the general
    /// path (its point density, the closed-form transmittance), grey or not.
    #[test]
    fn the_homogeneous_point_is_the_general_one() {
        let grey = slab_medium(0.7);
        let mut coloured = slab_medium(0.7);
        if let Medium::Homogeneous(m) = &mut coloured {
            m.sigma_s = Rgb::new(0.3, 0.5, 0.56);
            m.sigma_a = Rgb::new(0.1, 0.2, 0.14);
        }
        let ray = Ray::new(Vec3::new(0.0, 0.3, -1.0), Vec3::new(0.0, 0.0, 1.0));
        for medium in [grey, coloured] {
            let Medium::Homogeneous(m) = &medium else {
                unreachable!()
            };
            for t_surface in [2.2, 10.0, f32::INFINITY] {
                let depth = majorant_depth(&medium, &ray, t_surface).unwrap();
                for i in 0..200 {
                    let u = (i as f32 + 0.5) / 200.0;
                    let point = sample_point(&medium, &ray, t_surface, depth, u).unwrap();
                    let tr = medium.optical_depth(&ray, 0.0, point.t).unwrap().exp_neg();
                    let weight = m.sigma_s * tr * (1.0 / point.pdf);
                    let (t, w) = homogeneous_point(m, &ray, t_surface, u).unwrap();
                    assert!((t - point.t).abs() < 1e-4, "t {t} against {}", point.t);
                    let error = ((w - weight) / weight).map(f32::abs).max_channel();
                    assert!(error < 1e-4, "weight {w:?} against {weight:?}");
                }
            }
            let before = homogeneous_point(m, &ray, 0.5, 0.3);
            assert!(before.is_none(), "{before:?}");
        }
    }

    /// 1 − e^(−x) and −ln(1 − x) keep their relative precision on both
    /// sides of the switch to `exp_m1` / `ln_1p` near 0.
    #[test]
    fn the_exponential_helpers_are_precise_near_zero_and_beyond() {
        for x in [1e-7f64, 1e-5, 1e-3, 0.029, 0.031, 0.3, 3.0, 30.0] {
            let exact = -(-x).exp_m1();
            let got = one_minus_exp_neg(x as f32) as f64;
            assert!(
                (got - exact).abs() <= 1e-6 * exact,
                "1 − e^−{x}: {got} against {exact}"
            );
            if x < 1.0 {
                let exact = -(-x).ln_1p();
                let got = neg_ln_one_minus(x as f32) as f64;
                assert!(
                    (got - exact).abs() <= 1e-6 * exact,
                    "−ln(1 − {x}): {got} against {exact}"
                );
            }
        }
    }

    /// A medium that scatters nothing has no forced point.
    #[test]
    fn an_absorber_draws_no_forced_point() {
        let mut medium = slab_medium(0.7);
        let Medium::Homogeneous(m) = &mut medium else {
            unreachable!()
        };
        m.sigma_a += m.sigma_s;
        m.sigma_s = Rgb::BLACK;
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(homogeneous_point(m, &ray, 10.0, 0.4), None);
    }

    #[test]
    fn a_segment_before_the_medium_draws_nothing() {
        let medium = slab_medium(0.7);
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0));
        let depth = majorant_depth(&medium, &ray, 0.5).unwrap();
        assert_eq!(depth, 0.0);
        assert_eq!(sample_point(&medium, &ray, 0.5, depth, 0.3), None);
    }
}
