//! Equiangular sampling (Kulla & Fajardo 2012) of in-scattering from point
//! and spot lights along each ray segment through media, combined by MIS
//! with the free-flight vertices' own next-event estimation.
//!
//! Two strategies estimate the single-scattered light from a point light
//! along a segment: free flight (a real collision at t, then NEE to the
//! light) and equiangular (t drawn with density ∝ 1/r², then the same
//! connection). The power heuristic weights each by the other's density.
//! Weights need only sum to one at every t, so the free-flight density in
//! them may be the closed-form σt·T of the media; that is why this
//! strategy is used only when every medium on the ray has a closed-form
//! optical depth (homogeneous media and height fog). Outside `[t0, t1]` the
//! equiangular density is zero and free flight keeps full weight.
//!
//! The interval is where the strategy matters, in the scene's own units so
//! that the image does not depend on them: it ends where the transmittance
//! from the ray origin has fallen below e^−`TAU_CUT` in every channel, and
//! at most `FAR` times the farthest point light's distance from the origin
//! (past that the lights subtend under 1/`FAR` rad of the ray). Unbounded
//! segments (global media, height fog) are thus covered where they light up.

use super::Scene;
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};
use crate::sampling::equiangular::{equiangular_pdf, sample_equiangular};
use crate::sampling::Sampler;

/// Optical depth past which the rest of a ray is left to free flight alone.
const TAU_CUT: f32 = 20.0;

/// How far past the farthest point light (in multiples of its distance) the interval may reach.
const FAR: f32 = 1.0e3;

/// Halvings the transmittance cut may try (a range of 2^40 in length).
const MAX_HALVINGS: u32 = 40;

/// The part of a ray segment where media are, for equiangular sampling.
#[derive(Clone, Copy, Debug)]
pub(super) struct Segment {
    /// The ray.
    pub ray: Ray,
    /// Start of the covered interval.
    pub t0: f32,
    /// End of the covered interval.
    pub t1: f32,
    /// Number of point and spot lights in the scene.
    pub point_lights: usize,
}

/// The segment to sample along `ray` up to the surface at `t_surface`, when the strategy applies.
pub(super) fn segment(scene: &Scene, ray: &Ray, t_surface: f32) -> Option<Segment> {
    if !scene.settings.equiangular {
        return None;
    }
    let (mut point_lights, mut farthest) = (0, 0.0f32);
    for position in scene.lights.iter().filter_map(|l| l.point_position()) {
        point_lights += 1;
        farthest = farthest.max((position - ray.origin).length());
    }
    if point_lights == 0 {
        return None;
    }
    let (mut t0, mut t1) = (f32::INFINITY, 0.0f32);
    for medium in &scene.media {
        let mut segments = medium.majorants(ray, t_surface).peekable();
        let Some(first) = segments.peek().copied() else {
            continue;
        };
        medium.optical_depth(ray, 0.0, first.t0)?;
        t0 = t0.min(first.t0);
        let last = segments.last().unwrap_or(first);
        t1 = t1.max(last.t1);
    }
    t1 = t1.min(farthest * (1.0 + FAR));
    t1 = transmittance_cut(scene, ray, t0, t1);
    (t0 < t1).then_some(Segment {
        ray: *ray,
        t0,
        t1,
        point_lights,
    })
}

/// The end of `[t0, t1]` after which the transmittance from the ray origin is below e^−`TAU_CUT`.
///
/// Only roughly: halving the stretch until the optical depth at its end falls
/// below the cut, then keeping the last length above it (at most twice the
/// needed one). Any end is unbiased; this one keeps samples where light arrives.
fn transmittance_cut(scene: &Scene, ray: &Ray, t0: f32, t1: f32) -> f32 {
    if t0 >= t1 || t0.is_nan() || t1.is_nan() {
        return t1;
    }
    let tau = |t: f32| -> f32 {
        let depth = scene.media.iter().fold(Rgb::BLACK, |sum, m| {
            sum + m.optical_depth(ray, 0.0, t).unwrap_or(Rgb::BLACK)
        });
        depth.min_channel()
    };
    let mut end = t1;
    for _ in 0..MAX_HALVINGS {
        let half = t0 + 0.5 * (end - t0);
        if half <= t0 || tau(half) < TAU_CUT {
            break;
        }
        end = half;
    }
    // `end` is the last length whose optical depth reached the cut (or `t1` if none did).
    end
}

/// What the media contribute at parameter `t` of a segment's ray (closed forms).
struct MediaAt {
    /// Transmittance from the ray origin to `t`.
    tr: Rgb,
    /// Total extinction at `t`.
    sigma_t: Rgb,
    /// Σ σs·p toward the light, when a light direction was given.
    in_scatter: Rgb,
}

impl MediaAt {
    /// Evaluates every medium once at `t`; `toward_light` adds the in-scattering toward it.
    fn new(scene: &Scene, ray: &Ray, t: f32, toward_light: Option<Vec3>) -> MediaAt {
        let p = ray.at(t);
        let (mut tau, mut sigma_t, mut in_scatter) = (Rgb::BLACK, Rgb::BLACK, Rgb::BLACK);
        for medium in &scene.media {
            tau += medium.optical_depth(ray, 0.0, t).unwrap_or(Rgb::BLACK);
            let props = medium.properties(p, ray.time);
            sigma_t += props.sigma_a + props.sigma_s;
            if let Some(wi) = toward_light {
                if !props.sigma_s.is_black() {
                    in_scatter += props.sigma_s * props.phase.eval(ray.direction, wi);
                }
            }
        }
        MediaAt {
            tr: tau.exp_neg(),
            sigma_t,
            in_scatter,
        }
    }

    /// The density of free-flight sampling producing a vertex here, as used in the MIS weights.
    fn free_flight_density(&self) -> f32 {
        (self.tr * self.sigma_t).average()
    }
}

/// MIS weight of a free-flight vertex at `t` whose NEE picked `light_index`.
pub(super) fn free_flight_weight(
    scene: &Scene,
    segment: &Segment,
    light_index: usize,
    t: f32,
) -> f32 {
    let Some(light_pos) = scene.lights[light_index].point_position() else {
        return 1.0;
    };
    let ray = &segment.ray;
    let eq = equiangular_pdf(
        ray.origin,
        ray.direction,
        light_pos,
        segment.t0,
        segment.t1,
        t,
    ) / segment.point_lights as f32;
    if eq == 0.0 {
        return 1.0;
    }
    let ff = MediaAt::new(scene, ray, t, None).free_flight_density()
        * scene.light_pick_probability(light_index);
    ff * ff / (ff * ff + eq * eq)
}

/// One equiangular estimate of in-scattered light from a point or spot light along the segment.
pub(super) fn estimate(scene: &Scene, segment: &Segment, sampler: &mut Sampler) -> Rgb {
    let pick = sampler.next_1d();
    let u = sampler.next_1d();
    let k = ((pick * segment.point_lights as f32) as usize).min(segment.point_lights - 1);
    let Some((light_index, light)) = scene
        .lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.point_position().is_some())
        .nth(k)
    else {
        return Rgb::BLACK;
    };
    let ray = &segment.ray;
    let light_pos = light.point_position().unwrap_or(Vec3::ZERO);
    let Some(sample) = sample_equiangular(
        ray.origin,
        ray.direction,
        light_pos,
        segment.t0,
        segment.t1,
        u,
    ) else {
        return Rgb::BLACK;
    };
    let t = sample.value;
    let p = ray.at(t);
    let Some(ls) = light.sample(p, crate::math::Vec2::ZERO, &scene.geometry) else {
        return Rgb::BLACK;
    };
    let media = MediaAt::new(scene, ray, t, Some(ls.wi));
    if media.in_scatter.is_black() {
        return Rgb::BLACK;
    }
    let shadow = ray.spawn(p, ls.wi);
    let t_light = ls.distance * (1.0 - 1e-4);
    if scene.geometry.occluded(&shadow, t_light) {
        return Rgb::BLACK;
    }
    let tr_light = scene.transmittance(&shadow, t_light, sampler);
    let eq = sample.pdf / segment.point_lights as f32;
    let ff = media.free_flight_density() * scene.light_pick_probability(light_index);
    let weight = eq * eq / (eq * eq + ff * ff);
    media.tr * media.in_scatter * tr_light * ls.radiance * (weight / eq)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// A point light at `light` (and one at the origin) in `medium`, seen along +x from (−5, 0, 0).
    fn scene_and_ray(light: [f32; 3], medium: &str) -> (Scene, Ray) {
        let text = format!(
            r#"
            [camera]
            position = [0.0, 0.0, 4.0]
            look_at = [0.0, 0.0, 0.0]
            [[light]]
            type = "point"
            position = {light:?}
            intensity = 1.0
            [[light]]
            type = "point"
            position = [0.0, 0.0, 0.0]
            intensity = 1.0
            [[medium]]
            {medium}
            "#
        );
        let file = Path::new("equiangular-test.toml");
        let desc = crate::scene::parse(&text, file).expect("parse");
        let scene = crate::scene::build(&desc, file, Path::new(".")).expect("build");
        (scene, Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X))
    }

    /// A homogeneous medium filling all space.
    fn global(sigma_a: f32, sigma_s: f32) -> String {
        format!(
            "type = \"homogeneous\"\nsigma_a = {sigma_a:?}\nsigma_s = {sigma_s:?}\nglobal = true"
        )
    }

    /// A purely absorbing homogeneous medium inside the box [min, max].
    fn in_box(sigma_a: f32, min: [f32; 3], max: [f32; 3]) -> String {
        format!(
            "type = \"homogeneous\"\nsigma_a = {sigma_a:?}\nsigma_s = 0.0\n\
             bounds = {{ type = \"box\", min = {min:?}, max = {max:?} }}"
        )
    }

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * b.abs()
    }

    #[test]
    fn a_thin_global_medium_is_covered_to_far_past_the_farthest_light() {
        // The light at (2, 3, 0) is √58 from the ray's origin, the other one 5.
        let (scene, ray) = scene_and_ray([2.0, 3.0, 0.0], &global(1e-5, 0.0));
        let segment = segment(&scene, &ray, f32::INFINITY).expect("a segment");
        assert_eq!(segment.point_lights, 2);
        assert_eq!(segment.t0, 0.0);
        let far = 58f32.sqrt() * (1.0 + FAR);
        assert!(
            close(segment.t1, far),
            "t1 = {}, expected {far}",
            segment.t1
        );
    }

    #[test]
    fn a_dense_medium_is_cut_where_its_optical_depth_reaches_the_cut() {
        let sigma = 0.5;
        let far = 58f32.sqrt() * (1.0 + FAR);
        let bounded = in_box(sigma, [-1.0, -10.0, -10.0], [1000.0, 10.0, 10.0]);
        // (medium, where it starts, where the interval would end uncut)
        for (medium, start, end) in [(global(sigma, 0.0), 0.0, far), (bounded, 4.0, 1005.0)] {
            let (scene, ray) = scene_and_ray([2.0, 3.0, 0.0], &medium);
            let segment = segment(&scene, &ray, f32::INFINITY).expect("a segment");
            assert!(close(segment.t0, start), "{segment:?}");
            // The stretch from the start halved until half of it would fall short of the cut.
            let (length, full) = (segment.t1 - start, end - start);
            let halvings = (full / length).log2();
            assert!(
                close(halvings.round().exp2() * length, full),
                "t1 = {} is not {start} + ({end} - {start}) halved",
                segment.t1
            );
            assert!(sigma * length >= TAU_CUT, "t1 = {}", segment.t1);
            assert!(sigma * length * 0.5 < TAU_CUT, "t1 = {}", segment.t1);
        }
    }

    #[test]
    fn a_bounded_medium_is_covered_from_where_the_ray_enters_it() {
        let medium = in_box(1e-5, [-1.0; 3], [1.0; 3]);
        let (scene, ray) = scene_and_ray([2.0, 3.0, 0.0], &medium);
        let segment = segment(&scene, &ray, f32::INFINITY).expect("a segment");
        assert!(
            close(segment.t0, 4.0) && close(segment.t1, 6.0),
            "{segment:?}"
        );
        // A surface in front of the medium leaves nothing to sample.
        assert!(super::segment(&scene, &ray, 3.0).is_none());
    }

    #[test]
    fn a_free_flight_vertex_is_weighed_by_the_power_heuristic_of_the_two_densities() {
        let (sigma_a, sigma_s) = (0.05f32, 0.2f32);
        let (scene, ray) = scene_and_ray([2.0, 3.0, 0.0], &global(sigma_a, sigma_s));
        let segment = segment(&scene, &ray, f32::INFINITY).expect("a segment");
        let sigma_t = sigma_a + sigma_s;
        // The light at (2, 3, 0) is 3 from the ray, its foot 7 along it.
        let angle = |t: f32| ((t - 7.0) / 3.0).atan();
        for t in [1.0f32, 6.0, 7.5, 30.0] {
            let equiangular =
                3.0 / ((angle(segment.t1) - angle(segment.t0)) * (9.0 + (t - 7.0).powi(2))) / 2.0;
            let free_flight = sigma_t * (-sigma_t * t).exp() * scene.light_pick_probability(0);
            let expected = free_flight.powi(2) / (free_flight.powi(2) + equiangular.powi(2));
            let weight = free_flight_weight(&scene, &segment, 0, t);
            assert!(
                (weight - expected).abs() <= 1e-5,
                "t = {t}: weight {weight}, power heuristic {expected}"
            );
        }
    }

    #[test]
    fn a_segment_is_never_empty() {
        // Both lights at the ray's origin: the interval [0, 0] is no segment.
        let (scene, _) = scene_and_ray([0.0, 0.0, 0.0], &global(0.1, 0.0));
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert!(segment(&scene, &ray, f32::INFINITY).is_none());
    }
}
