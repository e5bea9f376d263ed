//! The radiance estimator `li` and the runtime `Scene` it reads.
//!
//! One loop handles every vertex of a path: surface vertices (BSDF sampling
//! and next-event estimation combined by MIS) and, where media are present,
//! medium vertices. Helpers keep the loop short: `direct_light` for NEE,
//! `escaped` for rays leaving the scene.

use crate::camera::Camera;
use crate::color::Rgb;
use crate::geometry::{Geometry, SurfaceHit};
use crate::light::Light;
use crate::material::Material;
use crate::math::{offset_origin, Ray, Vec3};
use crate::sampling::{power_heuristic, Sampler};

/// Sampling settings of a render.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum number of scattering events on a path (0 = emission only, 1 = direct light).
    pub max_depth: u32,
    /// Maximum number of medium scattering events on a path.
    pub max_scatter_depth: u32,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Scene seed of the random streams.
    pub seed: u64,
}

/// Everything the estimator needs, built by `scene::load`.
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// All primitives and the BVH.
    pub geometry: Geometry,
    /// Material of each shape.
    pub shape_materials: Vec<Material>,
    /// Index into `lights` of each shape's area light, if it emits.
    pub shape_lights: Vec<Option<u32>>,
    /// All lights.
    pub lights: Vec<Light>,
    /// Sampling settings.
    pub settings: Settings,
}

impl Scene {
    /// Probability of choosing any one light for next-event estimation.
    fn light_pick_probability(&self) -> f32 {
        1.0 / self.lights.len() as f32
    }

    /// Radiance from infinite lights for a ray escaping along `dir`, MIS-weighted against light sampling.
    fn escaped(&self, dir: Vec3, prev_pdf: f32, prev_delta: bool) -> Rgb {
        let mut total = Rgb::BLACK;
        for light in self.lights.iter().filter(|l| l.is_infinite()) {
            let le = light.escaped_radiance(dir);
            if le.is_black() {
                continue;
            }
            let weight = if prev_delta {
                1.0
            } else {
                let light_pdf = light.escaped_pdf(dir) * self.light_pick_probability();
                power_heuristic(prev_pdf, light_pdf)
            };
            total += le * weight;
        }
        total
    }
}

/// Where next-event estimation looks from, and how the vertex scatters light.
enum Vertex<'a> {
    Surface {
        hit: &'a SurfaceHit,
        normal: Vec3,
        wo: Vec3,
        material: &'a Material,
    },
}

/// State of one path being traced.
struct PathState {
    throughput: Rgb,
    radiance: Rgb,
    /// Solid-angle pdf of the direction that produced the current ray.
    prev_pdf: f32,
    /// True when that direction came from a delta lobe (or the camera).
    prev_delta: bool,
    prev_point: Vec3,
}

/// Estimates the radiance arriving at the ray origin along `-ray.direction`.
pub fn li(scene: &Scene, mut ray: Ray, sampler: &mut Sampler) -> Rgb {
    let settings = &scene.settings;
    let mut path = PathState {
        throughput: Rgb::WHITE,
        radiance: Rgb::BLACK,
        prev_pdf: 1.0,
        prev_delta: true,
        prev_point: ray.origin,
    };
    let mut depth = 0u32;
    loop {
        let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            path.radiance +=
                path.throughput * scene.escaped(ray.direction, path.prev_pdf, path.prev_delta);
            break;
        };
        let wo = -ray.direction;
        if let Some(light_index) = scene.shape_lights[hit.shape as usize] {
            let light = &scene.lights[light_index as usize];
            let le = light.area_radiance(hit.geometric_normal, wo);
            if !le.is_black() {
                let weight = if path.prev_delta {
                    1.0
                } else {
                    let light_pdf = light.area_pdf(path.prev_point, hit.p, hit.geometric_normal)
                        * scene.light_pick_probability();
                    power_heuristic(path.prev_pdf, light_pdf)
                };
                path.radiance += path.throughput * le * weight;
            }
        }
        if depth >= settings.max_depth {
            break;
        }
        let material = &scene.shape_materials[hit.shape as usize];
        let normal = if hit.shading_normal.dot(wo) >= 0.0 {
            hit.shading_normal
        } else {
            -hit.shading_normal
        };
        let last_vertex = depth + 1 >= settings.max_depth;
        let vertex = Vertex::Surface {
            hit: &hit,
            normal,
            wo,
            material,
        };
        if !material.is_delta() {
            path.radiance += path.throughput * direct_light(scene, &vertex, sampler, last_vertex);
        }
        if last_vertex {
            break;
        }
        let Some(bs) = material.sample(normal, wo, sampler.next_2d()) else {
            break;
        };
        path.throughput *= bs.weight;
        path.prev_pdf = bs.pdf;
        path.prev_delta = bs.is_delta;
        path.prev_point = hit.p;
        ray = Ray::new(offset_origin(hit.p, hit.geometric_normal, bs.wi), bs.wi);
        depth += 1;
        if !russian_roulette(&mut path.throughput, depth, settings.rr_depth, sampler) {
            break;
        }
    }
    path.radiance
}

/// Ends the path with probability `1 - q` past `rr_depth`, reweighting survivors by `1/q`.
fn russian_roulette(
    throughput: &mut Rgb,
    depth: u32,
    rr_depth: u32,
    sampler: &mut Sampler,
) -> bool {
    if depth < rr_depth {
        return true;
    }
    let q = throughput.max_channel().min(0.95);
    if q <= 0.0 || sampler.next_1d() >= q {
        return false;
    }
    *throughput /= q;
    true
}

/// Next-event estimation from a vertex to one light chosen uniformly.
///
/// With `full_weight` the sample is not MIS-weighted (no BSDF strategy follows it).
fn direct_light(scene: &Scene, vertex: &Vertex, sampler: &mut Sampler, full_weight: bool) -> Rgb {
    if scene.lights.is_empty() {
        return Rgb::BLACK;
    }
    let pick = sampler.next_1d();
    let u = sampler.next_2d();
    let index = ((pick * scene.lights.len() as f32) as usize).min(scene.lights.len() - 1);
    let light = &scene.lights[index];
    let Vertex::Surface {
        hit,
        normal,
        wo,
        material,
    } = vertex;
    let Some(ls) = light.sample(hit.p, u, &scene.geometry) else {
        return Rgb::BLACK;
    };
    let f = material.eval(*normal, *wo, ls.wi);
    if f.is_black() {
        return Rgb::BLACK;
    }
    let origin = offset_origin(hit.p, hit.geometric_normal, ls.wi);
    let shadow = Ray::new(origin, ls.wi);
    let t_max = if ls.distance.is_finite() {
        ls.distance * (1.0 - 1e-4)
    } else {
        f32::INFINITY
    };
    if scene.geometry.occluded(&shadow, t_max) {
        return Rgb::BLACK;
    }
    let light_pdf = ls.pdf * scene.light_pick_probability();
    let weight = if ls.is_delta || full_weight {
        1.0
    } else {
        power_heuristic(light_pdf, material.pdf(*normal, *wo, ls.wi))
    };
    f * ls.radiance * (weight / light_pdf)
}
