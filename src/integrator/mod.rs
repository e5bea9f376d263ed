//! The radiance estimator `li` and the runtime `Scene` it reads.
//!
//! One loop handles every vertex of a path. Along each ray segment the
//! media are tracked first (free-flight sampling); a real scattering event
//! makes a medium vertex, otherwise the ray reaches a surface (or escapes).
//! Both kinds of vertex do next-event estimation with transmittance-weighted
//! shadow rays, combined by MIS with phase/BSDF sampling.

mod direct;
mod equiangular;
pub mod tracking;

use crate::camera::Camera;
use crate::color::Rgb;
use crate::geometry::Geometry;
use crate::light::Light;
use crate::material::{Material, Shading};
use crate::math::{offset_origin, Ray, Vec3};
use crate::medium::Medium;
use crate::sampling::{power_heuristic, Sampler};
use direct::{direct_light, Vertex};
pub use tracking::TransmittanceEstimator;
use tracking::{sample_free_flight, FreeFlight};

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
    /// Transmittance estimator for shadow rays.
    pub transmittance: TransmittanceEstimator,
    /// Add equiangular sampling toward point and spot lights along rays in media.
    pub equiangular: bool,
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
    /// All participating media (they overlap additively).
    pub media: Vec<Medium>,
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

    /// Transmittance along `ray` over `[0, t_max)` through every medium (1 with no media).
    pub fn transmittance(&self, ray: &Ray, t_max: f32, sampler: &mut Sampler) -> Rgb {
        let mut tr = Rgb::WHITE;
        for medium in &self.media {
            tr *= tracking::medium_transmittance(
                medium,
                ray,
                t_max,
                self.settings.transmittance,
                sampler,
            );
            if tr.is_black() {
                break;
            }
        }
        tr
    }
}

/// State of one path being traced.
struct PathState {
    throughput: Rgb,
    radiance: Rgb,
    /// Solid-angle pdf of the direction that produced the current ray.
    prev_pdf: f32,
    /// True when that direction came from a delta lobe (or the camera).
    prev_delta: bool,
    /// Where the current ray started (for area-light MIS).
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
    let mut scatter_depth = 0u32;
    loop {
        let hit = scene.geometry.intersect(&ray, f32::INFINITY);
        let t_surface = hit.map_or(f32::INFINITY, |h| h.t);
        if !scene.media.is_empty() {
            let segment = if depth < settings.max_depth {
                equiangular::segment(scene, &ray, t_surface)
            } else {
                None
            };
            if let Some(segment) = &segment {
                path.radiance += path.throughput * equiangular::estimate(scene, segment, sampler);
            }
            let event = sample_free_flight(
                &scene.media,
                &ray,
                t_surface,
                &mut path.throughput,
                &mut path.radiance,
                sampler,
            );
            match event {
                FreeFlight::Absorbed => break,
                FreeFlight::Passed => {}
                FreeFlight::Scatter { t, properties, .. } => {
                    if depth >= settings.max_depth {
                        break;
                    }
                    let p = ray.at(t);
                    scatter_depth += 1;
                    let last_vertex = depth + 1 >= settings.max_depth
                        || scatter_depth >= settings.max_scatter_depth;
                    let vertex = Vertex::Medium {
                        p,
                        dir_in: ray.direction,
                        phase: &properties.phase,
                        equiangular: segment.as_ref().map(|s| (s, t)),
                    };
                    path.radiance +=
                        path.throughput * direct_light(scene, &vertex, sampler, last_vertex);
                    if last_vertex {
                        break;
                    }
                    let Some(ps) = properties.phase.sample(ray.direction, sampler.next_2d()) else {
                        break;
                    };
                    path.throughput *= ps.weight;
                    path.prev_pdf = ps.pdf;
                    path.prev_delta = false;
                    path.prev_point = p;
                    ray = Ray::new(p, ps.direction);
                    depth += 1;
                    if !russian_roulette(&mut path.throughput, depth, settings.rr_depth, sampler) {
                        break;
                    }
                    continue;
                }
            }
        }
        let Some(hit) = hit else {
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
        let shading = Shading::facing(hit.shading_normal, wo);
        let last_vertex = depth + 1 >= settings.max_depth;
        if !material.is_delta() {
            let vertex = Vertex::Surface {
                hit: &hit,
                shading,
                wo,
                material,
            };
            path.radiance += path.throughput * direct_light(scene, &vertex, sampler, last_vertex);
        }
        if last_vertex {
            break;
        }
        let u = sampler.next_2d();
        let Some(bs) = material.sample(&shading, wo, u, sampler.next_1d()) else {
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
