//! Sphere lights sampled by the cone of directions they subtend.
//!
//! Seen from a point outside, a sphere of radius r at distance d fills a cone
//! of half-angle θmax with sin θmax = r/d. Drawing directions uniformly in that
//! cone (density 1/(2π(1 − cos θmax)) per steradian) and taking the nearest
//! intersection only ever lands on the visible cap, where uniform area
//! sampling would put about half of its points on the far side. From inside,
//! or so close that the cone is a hemisphere to rounding, the light falls back
//! to area sampling.

use super::LightSample;
use crate::math::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};
use std::f32::consts::PI;

/// Above this sin²θmax the receiver counts as on or inside the sphere.
const MAX_SIN2: f32 = 0.999;

/// The cone a sphere subtends from a receiver outside it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cone {
    /// Unit axis from the receiver toward the centre.
    axis: Vec3,
    /// Distance from the receiver to the centre.
    distance: f32,
    /// 1 − cos θmax, formed without cancellation for small spheres.
    one_minus_cos_max: f32,
}

impl Cone {
    /// The cone of the sphere (`center`, `radius`) seen from `p`; `None` when `p` is not clearly outside.
    pub(super) fn new(p: Vec3, center: Vec3, radius: f32) -> Option<Cone> {
        let to_center = center - p;
        let dist2 = to_center.length_squared();
        let sin2_max = radius * radius / dist2;
        // Also rejects NaN (a receiver at the centre).
        if sin2_max.is_nan() || sin2_max >= MAX_SIN2 {
            return None;
        }
        let distance = dist2.sqrt();
        Some(Cone {
            axis: to_center / distance,
            distance,
            one_minus_cos_max: sin2_max / (1.0 + (1.0 - sin2_max).sqrt()),
        })
    }

    /// Solid-angle density of every direction inside the cone.
    pub(super) fn pdf(&self) -> f32 {
        1.0 / (2.0 * PI * self.one_minus_cos_max)
    }

    /// A direction uniform in the cone and the distance to the sphere along it.
    pub(super) fn sample(&self, u: Vec2, radius: f32) -> (Vec3, f32) {
        let one_minus_cos = u.x * self.one_minus_cos_max;
        let cos_theta = 1.0 - one_minus_cos;
        let sin2_theta = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0);
        let phi = 2.0 * PI * u.y;
        let sin_theta = sin2_theta.sqrt();
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        let wi = Frame::from_z(self.axis).to_world(local).normalize();
        // Nearest root of |p + t·wi − c| = r; the discriminant is ≥ 0 inside the cone up to rounding.
        let d = self.distance;
        let disc = (radius * radius - d * d * sin2_theta).max(0.0);
        (wi, d * cos_theta - disc.sqrt())
    }

    /// A light sample of a sphere of `radiance` drawn in the cone.
    pub(super) fn light_sample(&self, u: Vec2, radius: f32, radiance: Rgb) -> Option<LightSample> {
        let (wi, distance) = self.sample(u, radius);
        // The outward normal at the hit: from the centre (axis · distance away) to the point.
        let normal = ((wi * distance - self.axis * self.distance) / radius).normalize_or_zero();
        // Seen from outside, only the outward side faces the receiver.
        (distance > 0.0).then_some(LightSample {
            wi,
            distance,
            radiance,
            pdf: self.pdf(),
            is_delta: false,
            normal,
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::{Geometry, Primitive};
    use crate::light::Light;
    use crate::material::texture::Texture;
    use crate::math::color::Rgb;
    use crate::math::{Ray, Vec3};
    use crate::sampling::chi2::SphereChi2;

    fn sphere_light(center: Vec3, radius: f32, two_sided: bool) -> (Light, Geometry) {
        let geometry = Geometry::new(vec![(Primitive::Sphere { center, radius }, 0)]);
        (
            Light::area(0, Texture::Constant(Rgb::WHITE), two_sided, &geometry),
            geometry,
        )
    }

    /// The density of `sample` equals `area_pdf` at the hit point of each direction (what MIS uses).
    fn chi2_from(p: Vec3, center: Vec3, radius: f32, two_sided: bool) {
        let (light, geometry) = sphere_light(center, radius, two_sided);
        let result = SphereChi2::new(200_000, 17).run(
            |u| light.sample(p, u, &geometry).map(|ls| ls.wi),
            |wi| {
                let ray = Ray::new(p, wi);
                geometry
                    .intersect(&ray, f32::INFINITY)
                    .map_or(0.0, |h| light.area_pdf(p, h.p, h.geometric_normal))
            },
        );
        assert!(result.passes(0.01, 4), "from {p}: {result}");
    }

    #[test]
    fn cone_sampling_follows_its_pdf() {
        chi2_from(Vec3::ZERO, Vec3::new(0.3, 0.9, -0.6), 0.8, false);
        chi2_from(
            Vec3::new(1.0, -2.0, 0.5),
            Vec3::new(1.2, -1.0, 0.5),
            0.3,
            false,
        );
    }

    #[test]
    fn area_sampling_inside_follows_its_pdf() {
        chi2_from(Vec3::new(0.1, 0.2, -0.3), Vec3::ZERO, 1.0, true);
        chi2_from(Vec3::new(0.0, 0.9, 0.0), Vec3::ZERO, 1.0, true);
    }

    /// Every cone sample lands on the sphere's visible cap, at the distance it reports.
    #[test]
    fn cone_samples_land_on_the_visible_cap() {
        let (center, radius) = (Vec3::new(0.0, 4.0, 0.0), 0.2);
        let (light, geometry) = sphere_light(center, radius, false);
        let p = Vec3::new(3.0, 0.0, 1.0);
        let mut s = crate::sampling::Sampler::from_seed(3);
        for _ in 0..10_000 {
            let ls = light.sample(p, s.next_2d(), &geometry).expect("visible");
            let hit = p + ls.wi * ls.distance;
            assert!(((hit - center).length() - radius).abs() < 1e-4 * radius.max(1.0));
            assert!((hit - center).dot(p - hit) >= -1e-4);
        }
    }
}
