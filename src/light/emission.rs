//! Sampling rays leaving a light (light tracing, bidirectional path tracing)
//! and the densities of such rays, for every light type.
//!
//! A finite light emits from a point `p` (density `pdf_pos` per unit area, 1
//! for point and spot lights) into a direction (density `pdf_dir` per
//! steradian about `p`). A light at infinity (sun, environment) emits along a
//! direction drawn with the same density its next-event sampling has from a
//! point in a medium, from a point of a disk of the scene's bounding sphere's
//! radius, perpendicular to it and just outside the sphere: `pdf_pos` is per
//! unit area of that disk (Veach 1997, §10.3; pbrt's disk, not its code).
//!
//! Area lights emit cosine-weighted about their normal (on a side picked
//! evenly when two-sided), spot lights uniformly inside their outer cone, so
//! every density here is closed form and the MIS weights need no estimate.

use super::{sun_radiance, Environment, Light};
use crate::geometry::{Geometry, Primitive};
use crate::math::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

/// The sphere that rays from lights at infinity are started around.
#[derive(Clone, Copy, Debug)]
pub struct SceneSphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (positive).
    pub radius: f32,
}

impl SceneSphere {
    /// Density per unit area of the disk rays from infinity start on.
    pub fn disk_pdf(&self) -> f32 {
        1.0 / (std::f32::consts::PI * self.radius * self.radius)
    }

    /// True when a ray from infinity propagating along `dir` can reach `p`:
    /// inside the cylinder of the disk, and not behind the disk.
    pub fn reaches(&self, dir: Vec3, p: Vec3) -> bool {
        let d = p - self.center;
        let along = d.dot(dir);
        along >= -self.radius && (d - dir * along).length_squared() <= self.radius * self.radius
    }
}

/// A ray leaving a light.
#[derive(Clone, Copy, Debug)]
pub struct EmissionSample {
    /// Where the ray starts (on the disk for lights at infinity).
    pub p: Vec3,
    /// Unit geometric normal of an area light at `p` (zero otherwise).
    pub n: Vec3,
    /// Unit propagation direction.
    pub dir: Vec3,
    /// Radiance along `dir` (intensity for point and spot lights, irradiance for a delta sun).
    pub radiance: Rgb,
    /// Density of `p`: per unit area on the light or the disk, 1 for point and spot lights.
    pub pdf_pos: f32,
    /// Density of `dir` per steradian (1 for a delta sun).
    pub pdf_dir: f32,
}

impl Light {
    /// True when the light sits at one point (point and spot lights).
    pub fn is_delta_position(&self) -> bool {
        matches!(self, Light::Point { .. } | Light::Spot { .. })
    }

    /// True when the light shines along one direction (a sun of angular radius 0).
    pub fn is_delta_direction(&self) -> bool {
        matches!(self, Light::Sun { cos_max, .. } if *cos_max >= 1.0)
    }

    /// Samples a ray leaving the light at `time` from `u_pos` (where) and `u_dir` (which way).
    pub fn sample_emission(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        geometry: &Geometry,
        time: f32,
        sphere: &SceneSphere,
    ) -> Option<EmissionSample> {
        match self {
            Light::Point {
                position,
                intensity,
            } => Some(EmissionSample {
                p: *position,
                n: Vec3::ZERO,
                dir: warp::square_to_uniform_sphere(u_dir),
                radiance: *intensity,
                pdf_pos: 1.0,
                pdf_dir: warp::uniform_sphere_pdf(),
            }),
            Light::Spot {
                position,
                axis,
                intensity,
                cos_inner,
                cos_outer,
                edge,
            } => {
                let dir = Frame::from_z(*axis)
                    .to_world(warp::square_to_uniform_cone(u_dir, *cos_outer))
                    .normalize();
                let falloff = edge.falloff(axis.dot(dir), *cos_inner, *cos_outer);
                (falloff > 0.0).then(|| EmissionSample {
                    p: *position,
                    n: Vec3::ZERO,
                    dir,
                    radiance: *intensity * falloff,
                    pdf_pos: 1.0,
                    pdf_dir: warp::uniform_cone_pdf(*cos_outer),
                })
            }
            Light::Area { .. } => self.sample_area_emission(u_pos, u_dir, geometry, time),
            Light::Sun { .. } | Light::Environment(_) => {
                let (wi, radiance, pdf_dir) = self.sample_infinite_direction(u_dir)?;
                let dir = -wi;
                let disk = warp::square_to_concentric_disk(u_pos) * sphere.radius;
                let frame = Frame::from_z(dir);
                let p = sphere.center + (frame.x * disk.x + frame.y * disk.y) - dir * sphere.radius;
                Some(EmissionSample {
                    p,
                    n: Vec3::ZERO,
                    dir,
                    radiance,
                    pdf_pos: sphere.disk_pdf(),
                    pdf_dir,
                })
            }
        }
    }

    /// A direction toward a light at infinity, its radiance and its density
    /// (the next-event density from a point in a medium).
    fn sample_infinite_direction(&self, u: Vec2) -> Option<(Vec3, Rgb, f32)> {
        match self {
            Light::Sun {
                to_sun,
                irradiance,
                cos_max,
            } => {
                if *cos_max >= 1.0 {
                    return Some((*to_sun, *irradiance, 1.0));
                }
                let local = warp::square_to_uniform_cone(u, *cos_max);
                Some((
                    Frame::from_z(*to_sun).to_world(local).normalize(),
                    sun_radiance(*irradiance, *cos_max),
                    warp::uniform_cone_pdf(*cos_max),
                ))
            }
            Light::Environment(Environment::Map(map)) => {
                map.sample(u).map(|s| (s.wi, s.radiance, s.pdf))
            }
            Light::Environment(env) => {
                let wi = warp::square_to_uniform_sphere(u);
                Some((wi, env.radiance(wi), warp::uniform_sphere_pdf()))
            }
            _ => None,
        }
    }

    /// An area light's emission: a point uniform by area (placed at `time`
    /// when the shape moves), a direction cosine-weighted about its normal.
    fn sample_area_emission(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        geometry: &Geometry,
        time: f32,
    ) -> Option<EmissionSample> {
        let Light::Area {
            shape,
            radiance,
            two_sided,
            primitives,
            cumulative_area,
            moving,
            ..
        } = self
        else {
            return None;
        };
        let (local_geometry, placement) = if *moving {
            let m = geometry.moving_shape(*shape)?;
            (m.local(), Some(m.placement(time)))
        } else {
            (geometry, None)
        };
        let total = *cumulative_area.last()?;
        let (k, ux) = super::pick_by_area(cumulative_area, primitives.len(), u_pos.x)?;
        let prim: &Primitive = &local_geometry.primitives()[primitives[k] as usize];
        let a = prim.sample_area(Vec2::new(ux, u_pos.y));
        let le = match radiance.constant() {
            Some(c) => c,
            None => radiance.eval(local_geometry.uv(primitives[k], a.st, a.p)),
        };
        let (p, n, scale2) = match placement {
            Some(m) => (
                m.point_to_world(a.p),
                m.normal_to_world(a.n),
                m.scale.x * m.scale.x,
            ),
            None => (a.p, a.n, 1.0),
        };
        let (dir, pdf_dir) = cosine_emission_direction(n, *two_sided, u_dir);
        (pdf_dir > 0.0 && !le.is_black()).then(|| EmissionSample {
            p,
            n,
            dir,
            radiance: le,
            pdf_pos: 1.0 / (total * scale2),
            pdf_dir,
        })
    }

    /// Density per unit area of the point an emission sample starts from (the
    /// disk's for lights at infinity), for a light placed at `time`.
    pub fn emission_pdf_pos(&self, geometry: &Geometry, time: f32, sphere: &SceneSphere) -> f32 {
        match self {
            Light::Point { .. } | Light::Spot { .. } => 1.0,
            Light::Area {
                cumulative_area,
                moving,
                shape,
                ..
            } => {
                let total = cumulative_area.last().copied().unwrap_or(0.0);
                let scale2 = match (*moving, geometry.moving_shape(*shape)) {
                    (true, Some(m)) => m.placement(time).scale.x.powi(2),
                    _ => 1.0,
                };
                if total > 0.0 {
                    1.0 / (total * scale2)
                } else {
                    0.0
                }
            }
            Light::Sun { .. } | Light::Environment(_) => sphere.disk_pdf(),
        }
    }

    /// Density per steradian that the light emits along `dir` (propagation
    /// direction) from its point with normal `n` (ignored by other lights).
    pub fn emission_pdf_dir(&self, n: Vec3, dir: Vec3) -> f32 {
        match self {
            Light::Point { .. } => warp::uniform_sphere_pdf(),
            Light::Spot {
                axis, cos_outer, ..
            } => {
                if axis.dot(dir) >= *cos_outer {
                    warp::uniform_cone_pdf(*cos_outer)
                } else {
                    0.0
                }
            }
            Light::Area { two_sided, .. } => {
                let cos = n.dot(dir);
                match two_sided {
                    true => 0.5 * cos.abs() * FRAC_1_PI,
                    false => cos.max(0.0) * FRAC_1_PI,
                }
            }
            Light::Sun { .. } if self.is_delta_direction() => 1.0,
            Light::Sun { .. } | Light::Environment(_) => self.escaped_pdf(-dir),
        }
    }
}

/// A direction cosine-weighted about the normal `n` (either side of a
/// two-sided light) and its solid-angle density.
fn cosine_emission_direction(n: Vec3, two_sided: bool, u_dir: Vec2) -> (Vec3, f32) {
    // A two-sided light picks its side with the first direction number, reused inside the side.
    let (side, ux) = match (two_sided, u_dir.x < 0.5) {
        (false, _) => (1.0, u_dir.x),
        (true, true) => (1.0, 2.0 * u_dir.x),
        (true, false) => (-1.0, 2.0 * u_dir.x - 1.0),
    };
    let local = warp::square_to_cosine_hemisphere(Vec2::new(ux.min(1.0 - f32::EPSILON), u_dir.y));
    let dir = Frame::from_z(n * side).to_world(local).normalize();
    let sides = if two_sided { 0.5 } else { 1.0 };
    (dir, warp::cosine_hemisphere_pdf(local) * sides)
}
