//! Mitsuba's rule for the medium a ray is in, for imported scenes where it
//! differs from brume's containment: the medium is the one set by the last
//! surface the ray crossed (the shape's interior when the ray goes against
//! the stored normal, its exterior otherwise), or the sensor's medium before
//! any crossing. Media are then unbounded and never added together: a ray
//! segment is tracked through its current medium only.
//!
//! Shapes without a surface (Mitsuba's `null` BSDF) are in the geometry so
//! that rays find the crossings; the path tracer and its shadow rays pass
//! through them, changing medium. Any other surface blocks a shadow ray, as
//! in Mitsuba (light reaches through glass by sampled refraction only).

use super::tracking::medium_transmittance;
use super::Scene;
use crate::math::color::Rgb;
use crate::math::{offset_origin, Ray, Vec3};
use crate::sampling::Sampler;

/// The interface rule of one scene: each shape's media and the camera's.
#[derive(Clone, Debug)]
pub struct Interfaces {
    /// Each shape's `[interior, exterior]` media (indices into `Scene::media`,
    /// `None`: vacuum), or `None` for a shape that changes no medium.
    pub sides: Vec<Option<[Option<u32>; 2]>>,
    /// Shapes without a surface (Mitsuba's `null` BSDF): rays pass through.
    pub null: Vec<bool>,
    /// The medium the camera is in.
    pub camera: Option<u32>,
}

impl Interfaces {
    /// The medium of a ray leaving a point of `shape` (stored normal `n`)
    /// along `dir`, when it was in `current` before.
    #[inline]
    pub fn after(&self, shape: u32, n: Vec3, dir: Vec3, current: Option<u32>) -> Option<u32> {
        match self.sides[shape as usize] {
            None => current,
            Some([interior, _]) if n.dot(dir) < 0.0 => interior,
            Some([_, exterior]) => exterior,
        }
    }

    /// True when `shape` has no surface: rays pass through it.
    #[inline]
    pub fn is_null(&self, shape: u32) -> bool {
        self.null[shape as usize]
    }
}

impl Scene {
    /// The media a ray segment in medium `current` is tracked through: all
    /// of them (containment) or the current one (interface rule).
    #[inline]
    pub(crate) fn media_along(&self, current: Option<u32>) -> &[crate::medium::Medium] {
        match (&self.interfaces, current) {
            (None, _) => &self.media,
            (Some(_), Some(m)) => std::slice::from_ref(&self.media[m as usize]),
            (Some(_), None) => &[],
        }
    }

    /// Transmittance of a shadow ray over `[0, t_max)` starting in medium
    /// `current`, under the interface rule: through surfaceless shapes,
    /// changing medium at each, and zero at any other surface.
    pub fn interface_transmittance(
        &self,
        interfaces: &Interfaces,
        ray: &Ray,
        t_max: f32,
        mut current: Option<u32>,
        sampler: &mut Sampler,
    ) -> Rgb {
        // A shadow ray toward an infinite light has no end point to aim at.
        let target = t_max.is_finite().then(|| ray.at(t_max));
        let (mut ray, mut t_max, mut tr) = (*ray, t_max, Rgb::WHITE);
        loop {
            let hit = self.geometry.intersect(&ray, t_max);
            let end = hit.map_or(t_max, |h| h.t);
            if let Some(m) = current {
                let medium = &self.media[m as usize];
                let estimator = self.settings.transmittance;
                tr *= medium_transmittance(medium, &ray, end, estimator, sampler);
                if tr.is_black() {
                    return tr;
                }
            }
            let Some(hit) = hit else {
                return tr;
            };
            if !interfaces.is_null(hit.shape) {
                return Rgb::BLACK;
            }
            let dir = ray.direction;
            current = interfaces.after(hit.shape, hit.geometric_normal, dir, current);
            // Re-aimed at the end point: the offset origin has moved along
            // the crossed surface's normal, and a ray kept parallel with its
            // length cut by hit.t would overshoot the end (by up to the offset
            // per crossing) into the light's own surface. Progress is certain:
            // each hit lies past the geometry's minimum t toward the end point.
            let origin = offset_origin(hit.p, hit.geometric_normal, dir);
            let Some(target) = target else {
                ray = ray.spawn(origin, dir);
                continue;
            };
            let to_target = target - origin;
            t_max = to_target.length();
            if to_target.dot(dir) <= 0.0 || t_max == 0.0 {
                return tr;
            }
            ray = ray.spawn(origin, to_target / t_max);
        }
    }
}
