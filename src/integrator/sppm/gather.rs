//! The eye pass's density estimates: photons on the surface where the eye
//! path first meets a non-Dirac BSDF, and the beam radiance estimate
//! (Jarosz, Zwicker and Jensen 2008) of the medium photons along every eye
//! segment before it.
//!
//! A photon's `beta` is its light path's throughput per emitted path, so
//! with `M` paths and gather radius `r`:
//! - surface: L = Σ β·f(wo, w)·|ns·w| / |ng·w| / (π r² M) over photons within
//!   `r` (the |ng·w| undoes the projected area photons land on, the |ns·w|
//!   is the path tracer's shading cosine);
//! - beam: L = Σ T(t)·β·p(ω, w) / (π r² M) over photons within `r` of the
//!   segment, `t` their projection on it and T the eye transmittance there
//!   (β holds σs: a photon is a real scattering event).

use super::photons::PhotonMap;
use crate::geometry::SurfaceHit;
use crate::integrator::{Gather, Scene};
use crate::material::{Material, Shading};
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};
use crate::sampling::Sampler;
use std::f32::consts::PI;

/// Photons whose surface normal is further than this (a cosine) from the
/// gather point's belong to another surface (a corner, the far side of a thin wall).
const SAME_SURFACE_COS: f32 = 0.5;

/// The eye pass's [`Gather`]: adds the photons' indirect light to `radiance`.
pub(super) struct Gatherer<'a> {
    /// The pass's photons.
    pub map: &'a PhotonMap,
    /// Photons met along one segment, as (t, β·phase), sorted by `t` for the transmittance walk.
    pub beam: &'a mut Vec<(f32, Rgb)>,
    /// The indirect radiance gathered so far.
    pub radiance: Rgb,
}

impl Gatherer<'_> {
    /// 1 / (π r² M): the kernel over the disk of radius r, per emitted path.
    fn norm(&self) -> f32 {
        let r = self.map.radius;
        1.0 / (PI * r * r * self.map.emitted.max(1) as f32)
    }
}

impl Gather for Gatherer<'_> {
    const ACTIVE: bool = true;

    fn surface(
        &mut self,
        _scene: &Scene,
        hit: &SurfaceHit,
        material: &Material,
        wo: Vec3,
        throughput: Rgb,
        depth: u32,
    ) {
        let photons = &self.map.surface;
        let r2 = self.map.radius * self.map.radius;
        let shading = Shading::facing(hit.shading_normal, wo);
        let ng = hit.geometric_normal;
        let mut sum = Rgb::BLACK;
        for &i in photons.grid.near(hit.p) {
            let ph = &photons.data[i as usize];
            if ph.budget < depth
                || (photons.positions[i as usize] - hit.p).length_squared() >= r2
                || ph.ng.dot(ng) < SAME_SURFACE_COS
            {
                continue;
            }
            let cos = ng.dot(ph.w).abs();
            if cos <= 1e-6 {
                continue;
            }
            sum += material.eval(&shading, wo, ph.w) * ph.beta / cos;
        }
        self.radiance += throughput * sum * self.norm();
    }

    fn segment(
        &mut self,
        scene: &Scene,
        ray: &Ray,
        t_surface: f32,
        throughput: Rgb,
        depth: u32,
        sampler: &mut Sampler,
    ) {
        let photons = &self.map.volume;
        let beam = &mut *self.beam;
        beam.clear();
        photons
            .grid
            .along(ray, (0.0, t_surface), &photons.positions, |i, t| {
                let ph = &photons.data[i as usize];
                if ph.budget >= depth {
                    beam.push((t, ph.beta * ph.phase.eval(ray.direction, ph.w)));
                }
            });
        if beam.is_empty() {
            return;
        }
        beam.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        // One transmittance walk from the eye to the farthest photon: the
        // product of unbiased estimates over disjoint pieces is unbiased.
        let (mut tr, mut t_prev, mut sum) = (Rgb::WHITE, 0.0f32, Rgb::BLACK);
        for &(t, c) in beam.iter() {
            if t > t_prev {
                let mut piece = Ray::new(ray.at(t_prev), ray.direction);
                piece.time = ray.time;
                tr *= scene.transmittance(&piece, t - t_prev, sampler);
                t_prev = t;
                if tr.is_black() {
                    break;
                }
            }
            sum += tr * c;
        }
        self.radiance += throughput * sum * self.norm();
    }
}
