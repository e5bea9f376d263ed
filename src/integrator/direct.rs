//! Next-event estimation from surface and medium vertices.

use super::equiangular::{free_flight_weight, Segment};
use super::Scene;
use crate::geometry::SurfaceHit;
use crate::light::LightSample;
use crate::material::{Material, Shading};
use crate::math::color::Rgb;
use crate::math::{offset_origin, Ray, Vec3};
use crate::medium::PhaseFunction;
use crate::sampling::{power_heuristic, Sampler};

/// A path vertex seen from next-event estimation.
pub(super) enum Vertex<'a> {
    /// A surface point with its BSDF.
    Surface {
        hit: &'a SurfaceHit,
        /// Shading frame on the side of `wo`.
        shading: Shading,
        wo: Vec3,
        material: &'a Material,
    },
    /// A real scattering event in a medium.
    Medium {
        p: Vec3,
        /// Propagation direction of the arriving path.
        dir_in: Vec3,
        phase: &'a PhaseFunction,
        /// The equiangular segment this vertex lies on and its parameter there, for MIS.
        equiangular: Option<(&'a Segment, f32)>,
    },
}

impl Vertex<'_> {
    /// Where shadow rays toward `wi` start: off the surface on the side of `wi`.
    fn shadow_origin(&self, wi: Vec3) -> Vec3 {
        match self {
            Vertex::Surface { hit, .. } => offset_origin(hit.p, hit.geometric_normal, wi),
            Vertex::Medium { p, .. } => *p,
        }
    }

    /// The unit normal of a surface vertex on the side it scatters into (`None` in a medium).
    fn normal(&self) -> Option<Vec3> {
        match self {
            Vertex::Surface { shading, .. } => Some(shading.n),
            Vertex::Medium { .. } => None,
        }
    }

    /// The point itself, where lights are sampled from.
    fn position(&self) -> Vec3 {
        match self {
            Vertex::Surface { hit, .. } => hit.p,
            Vertex::Medium { p, .. } => *p,
        }
    }

    /// Scattering toward `wi` (BSDF·cos, or phase) and the density of sampling it.
    fn scattering(&self, wi: Vec3) -> (Rgb, f32) {
        match self {
            Vertex::Surface {
                shading,
                wo,
                material,
                ..
            } => (
                material.eval(shading, *wo, wi),
                material.pdf(shading, *wo, wi),
            ),
            Vertex::Medium { dir_in, phase, .. } => {
                let p = phase.eval(*dir_in, wi);
                (Rgb::splat(p), phase.pdf(*dir_in, wi))
            }
        }
    }
}

/// The shadow ray from `origin` (the receiver `p` nudged off its surface) to the light sample.
///
/// Direction and length are those of the chord from `origin` to the sampled
/// light point itself, stopped just short of it: the chord from a point
/// outside a convex light to a point of it that the point sees never enters
/// the light. (Keeping the direction from `p` and only moving the start would
/// run the ray parallel to that chord, into the light near its silhouette.)
fn shadow_ray(origin: Vec3, p: Vec3, ls: &LightSample) -> (Ray, f32) {
    if !ls.distance.is_finite() {
        return (Ray::new(origin, ls.wi), f32::INFINITY);
    }
    let chord = p + ls.wi * ls.distance - origin;
    let length = chord.length();
    if length == 0.0 {
        return (Ray::new(origin, ls.wi), 0.0);
    }
    (Ray::new(origin, chord / length), length * (1.0 - 1e-4))
}

/// Transmittance of the shadow ray from `vertex` (zero if a surface blocks
/// it); under the interface rule it starts in the medium on the side the ray
/// leaves to, from the path's `medium`.
#[inline]
fn shadow_transmittance(
    scene: &Scene,
    vertex: &Vertex,
    (shadow, t_max): (&Ray, f32),
    medium: Option<u32>,
    sampler: &mut Sampler,
) -> Rgb {
    if let Some(interfaces) = &scene.interfaces {
        let start = match vertex {
            Vertex::Surface { hit, .. } => {
                interfaces.after(hit.shape, hit.geometric_normal, shadow.direction, medium)
            }
            Vertex::Medium { .. } => medium,
        };
        return scene.interface_transmittance(interfaces, shadow, t_max, start, sampler);
    }
    if scene.geometry.occluded(shadow, t_max) {
        return Rgb::BLACK;
    }
    if scene.media.is_empty() {
        Rgb::WHITE
    } else {
        scene.transmittance(shadow, t_max, sampler)
    }
}

/// Next-event estimation from `vertex` to one light picked by `Scene::nee_pick`, at the path's `time`.
///
/// Shadow rays carry the media's transmittance. The sample is MIS-weighted
/// against the BSDF/phase sampling that every vertex also does.
pub(super) fn direct_light(
    scene: &Scene,
    vertex: &Vertex,
    at: (f32, Option<u32>),
    sampler: &mut Sampler,
) -> Rgb {
    direct_light_mixed(scene, vertex, at, sampler, |_, pdf| pdf)
}

/// [`direct_light`] for a vertex that samples its continuation from a
/// mixture (path guiding): `mixture(wi, scatter_pdf)` is the density MIS weighs against.
/// `(time, medium)`: the path's time and the medium it is in (interface rule).
pub(super) fn direct_light_mixed(
    scene: &Scene,
    vertex: &Vertex,
    (time, medium): (f32, Option<u32>),
    sampler: &mut Sampler,
    mixture: impl Fn(Vec3, f32) -> f32,
) -> Rgb {
    let pick = sampler.next_1d();
    let u = sampler.next_2d();
    let Some(index) = scene.nee_pick.sample(pick) else {
        return Rgb::BLACK;
    };
    let light = &scene.lights[index];
    // A sky left to the control variate (a sky alone keeps its pick) lights nothing here.
    if scene.sky_controls(light) {
        return Rgb::BLACK;
    }
    let p = vertex.position();
    let Some(ls) = light.sample_facing(p, vertex.normal(), u, &scene.geometry, time) else {
        return Rgb::BLACK;
    };
    let (f, scatter_pdf) = vertex.scattering(ls.wi);
    let scatter_pdf = mixture(ls.wi, scatter_pdf);
    if f.is_black() {
        return Rgb::BLACK;
    }
    let (mut shadow, t_max) = shadow_ray(vertex.shadow_origin(ls.wi), p, &ls);
    shadow.time = time;
    let tr = shadow_transmittance(scene, vertex, (&shadow, t_max), medium, sampler);
    if tr.is_black() {
        return Rgb::BLACK;
    }
    let light_pdf = ls.pdf * scene.light_pick_probability(index);
    let weight = match vertex {
        // Point and spot lights are also reached by equiangular sampling along the segment.
        Vertex::Medium {
            equiangular: Some((segment, t)),
            ..
        } if light.point_position().is_some() => free_flight_weight(scene, segment, index, *t),
        _ if ls.is_delta => 1.0,
        _ => power_heuristic(light_pdf, scatter_pdf),
    };
    f * tr * ls.radiance * (weight / light_pdf)
}
