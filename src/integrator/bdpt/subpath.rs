//! Camera and light subpaths: random walks with the path tracer's free
//! flights, BSDF and phase sampling, and Russian roulette, recording each
//! vertex with its densities in both directions.

use super::media::Surrogate;
use super::positive;
use super::vertex::{Kind, Vertex};
use crate::geometry::SurfaceHit;
use crate::integrator::tracking::{sample_free_flight, FreeFlight};
use crate::integrator::Scene;

use crate::light::{EmissionSample, SceneSphere};
use crate::material::Shading;
use crate::math::color::Rgb;
use crate::math::{offset_origin, Ray, Vec3};
use crate::sampling::Sampler;

/// Which way a subpath carries light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// From the lens: BSDFs sampled as the path tracer does.
    Camera,
    /// From a light: BSDFs sampled by their adjoint.
    Light,
}

/// Where a walk is and what it carries between two vertices.
struct Walk {
    ray: Ray,
    beta: Rgb,
    /// Solid-angle density of `ray`'s direction at its origin vertex.
    pdf_dir: f32,
    /// The walk left a light at infinity: the next vertex's density is the disk's.
    from_infinity: Option<f32>,
    /// Most vertices the subpath may hold.
    limit: usize,
    mode: Mode,
    /// Throughput of the first segment, the scale Russian roulette compares against.
    beta_start: f32,
}

/// Traces the camera subpath of `ray` into `path` (z₀ the lens), at most
/// `max_vertices` long (Metropolis states need one strategy's prefix only).
///
/// Medium emission met on the way is added to `radiance`, as the path
/// tracer does: no other strategy samples it, so it needs no weight.
pub(super) fn camera_subpath(
    scene: &Scene,
    sur: &Surrogate,
    ray: Ray,
    sampler: &mut Sampler,
    (path, max_vertices): (&mut Vec<Vertex>, usize),
    radiance: &mut Rgb,
) {
    path.clear();
    let mut z0 = Vertex::new(Kind::Camera, ray.origin, Vec3::ZERO, Rgb::WHITE);
    z0.pdf_fwd = 1.0;
    path.push(z0);
    let pdf_dir = scene.camera.direction_pdf(ray.direction, ray.time);
    if pdf_dir <= 0.0 {
        return;
    }
    let settings = &scene.settings;
    // Without medium events allowed, the path tracer only gathers emission along the first ray.
    let limit = match settings.max_scatter_depth {
        0 => 2,
        _ => (settings.max_depth as usize).saturating_add(2),
    }
    .min(max_vertices);
    let walk = Walk {
        ray,
        beta: Rgb::WHITE,
        pdf_dir,
        from_infinity: None,
        limit,
        mode: Mode::Camera,
        beta_start: 1.0,
    };
    random_walk(scene, sur, walk, sampler, path, radiance);
}

/// Traces a light subpath from a light picked by power into `path` (y₀ on
/// the light), at most `max_vertices` long.
pub(super) fn light_subpath(
    scene: &Scene,
    sur: &Surrogate,
    sphere: &SceneSphere,
    time: f32,
    sampler: &mut Sampler,
    (path, max_vertices): (&mut Vec<Vertex>, usize),
) {
    path.clear();
    let pick = sampler.next_1d();
    let (u_pos, u_dir) = (sampler.next_2d(), sampler.next_2d());
    let Some(index) = scene.light_pick.sample(pick) else {
        return;
    };
    let light = &scene.lights[index];
    let pmf = scene.light_pick.pmf(index);
    let Some(es) = light.sample_emission(u_pos, u_dir, &scene.geometry, time, sphere) else {
        return;
    };
    if es.pdf_pos <= 0.0 || es.pdf_dir <= 0.0 || es.radiance.is_black() || pmf <= 0.0 {
        return;
    }
    let infinite = light.is_infinite();
    let (y0, origin) = light_vertex(index, pmf, &es, infinite);
    path.push(y0);
    let mut ray = Ray::new(origin, es.dir);
    ray.time = time;
    let beta = emitted_throughput(scene, &es, pmf, infinite, time, sampler);
    if beta.is_black() {
        return;
    }
    let walk = Walk {
        ray,
        beta,
        pdf_dir: es.pdf_dir,
        from_infinity: infinite.then_some(es.pdf_pos),
        limit: (scene.settings.max_depth as usize)
            .saturating_add(1)
            .min(max_vertices),
        mode: Mode::Light,
        beta_start: beta.max_channel(),
    };
    let mut ignored = Rgb::BLACK;
    random_walk(scene, sur, walk, sampler, path, &mut ignored);
}

/// The light subpath's first vertex y₀ (on the light, or on the scene's
/// disk for light from infinity) and the origin of its first ray.
fn light_vertex(index: usize, pmf: f32, es: &EmissionSample, infinite: bool) -> (Vertex, Vec3) {
    let (kind, origin_pdf, origin) = if infinite {
        let kind = Kind::Infinite {
            light: index as u32,
            dir: es.dir,
        };
        (kind, pmf * es.pdf_dir, es.p)
    } else {
        let origin = if es.n == Vec3::ZERO {
            es.p
        } else {
            offset_origin(es.p, es.n, es.dir)
        };
        (
            Kind::Light {
                light: index as u32,
            },
            pmf * es.pdf_pos,
            origin,
        )
    };
    let mut y0 = Vertex::new(kind, es.p, es.n, es.radiance / origin_pdf);
    y0.pdf_fwd = origin_pdf;
    (y0, origin)
}

/// The throughput of the light subpath's first ray: emitted radiance × cos
/// over the pick, position and direction densities (times the media's
/// transmittance beyond the disk for light from infinity).
fn emitted_throughput(
    scene: &Scene,
    es: &EmissionSample,
    pmf: f32,
    infinite: bool,
    time: f32,
    sampler: &mut Sampler,
) -> Rgb {
    let cos = if es.n == Vec3::ZERO {
        1.0
    } else {
        es.n.dot(es.dir).abs()
    };
    let mut beta = es.radiance * (cos / (pmf * es.pdf_pos * es.pdf_dir));
    if infinite && !scene.media.is_empty() {
        // Light from infinity crosses the media beyond the disk before it starts.
        let mut behind = Ray::new(es.p, -es.dir);
        behind.time = time;
        beta *= scene.transmittance(&behind, f32::INFINITY, sampler);
    }
    beta
}

/// Extends `path` vertex by vertex until the walk leaves the scene, is
/// absorbed or killed, or reaches its limit.
fn random_walk(
    scene: &Scene,
    sur: &Surrogate,
    mut walk: Walk,
    sampler: &mut Sampler,
    path: &mut Vec<Vertex>,
    radiance: &mut Rgb,
) {
    let max_media = scene.settings.max_scatter_depth as usize;
    while path.len() < walk.limit {
        let Some(mut v) = next_vertex(scene, &mut walk, sampler, radiance) else {
            return;
        };
        let prev = path.len() - 1;
        let (dir, pdf_dir) = (walk.ray.direction, walk.pdf_dir);
        forward_density(sur, &path[prev], &mut v, dir, pdf_dir, walk.from_infinity);
        v.media = path[prev].media + matches!(v.kind, Kind::Medium { .. }) as u32;
        path.push(v);
        if walk.mode == Mode::Camera && v.media as usize >= max_media {
            // The path tracer's last medium event: only the segment after it, for emission.
            walk.limit = walk.limit.min(path.len() + 1);
        }
        if path.len() >= walk.limit || !v.scatters() {
            return;
        }
        if !scatter(scene, &mut walk, path, sampler) {
            return;
        }
    }
}

/// Follows the walk's ray to its next vertex: a medium event, a surface,
/// or (for the camera) the escape toward lights at infinity.
fn next_vertex(
    scene: &Scene,
    walk: &mut Walk,
    sampler: &mut Sampler,
    radiance: &mut Rgb,
) -> Option<Vertex> {
    let hit = scene.geometry.intersect(&walk.ray, f32::INFINITY);
    let t_surface = hit.map_or(f32::INFINITY, |h| h.t);
    let flight = if scene.media.is_empty() {
        FreeFlight::Passed
    } else {
        sample_free_flight(
            &scene.media,
            &walk.ray,
            t_surface,
            &mut walk.beta,
            radiance,
            sampler,
        )
    };
    let w_prev = -walk.ray.direction;
    let mut v = match (flight, hit) {
        (FreeFlight::Absorbed, _) => return None,
        (FreeFlight::Scatter { t, properties, .. }, _) => Vertex::new(
            Kind::Medium {
                phase: properties.phase,
            },
            walk.ray.at(t),
            Vec3::ZERO,
            walk.beta,
        ),
        (FreeFlight::Passed, Some(h)) => surface_vertex(scene, &h, walk.beta),
        (FreeFlight::Passed, None) if walk.mode == Mode::Camera => Vertex::new(
            Kind::Escaped {
                dir: walk.ray.direction,
            },
            walk.ray.origin,
            Vec3::ZERO,
            walk.beta,
        ),
        (FreeFlight::Passed, None) => return None,
    };
    v.w_prev = w_prev;
    Some(v)
}

/// The vertex where a walk with throughput `beta` meets the surface at `h`.
fn surface_vertex(scene: &Scene, h: &SurfaceHit, beta: Rgb) -> Vertex {
    let material = scene.material_at(h);
    let mut v = Vertex::new(
        Kind::Surface {
            material,
            ns: h.shading_normal,
            shape: h.shape,
            primitive: h.primitive,
            st: h.st,
        },
        h.p,
        h.geometric_normal,
        beta,
    );
    v.delta = material.is_delta();
    v
}

/// Sets the density of `v` reached from `prev` along `dir`, sampled there
/// with solid-angle density `pdf_dir` (or, just after a light at infinity,
/// from its disk of density `from_infinity`), with its surrogate free flight.
pub(super) fn forward_density(
    sur: &Surrogate,
    prev: &Vertex,
    v: &mut Vertex,
    dir: Vec3,
    pdf_dir: f32,
    from_infinity: Option<f32>,
) {
    if let Kind::Medium { .. } = v.kind {
        v.sigma_t = sur.sigma_t(v.p);
    }
    if let Some(disk_pdf) = from_infinity {
        v.tau_in = sur.depth_to_infinity(v.p, -dir);
        v.pdf_fwd = disk_pdf * v.cos(dir) * super::media::transmittance(v.tau_in) * v.sigma_t;
    } else if v.is_infinite() {
        v.tau_in = sur.depth_to_infinity(prev.p, dir);
        v.pdf_fwd = v.density_from(pdf_dir, prev.p, v.tau_in);
    } else {
        v.tau_in = sur.depth(prev.p, v.p);
        v.pdf_fwd = v.density_from(pdf_dir, prev.p, v.tau_in);
    }
}

/// The solid-angle density with which scattering vertex `v`, arriving from
/// `next_dir` (its successor), samples the direction back to its predecessor.
pub(super) fn reverse_pdf(v: &Vertex, next_dir: Vec3) -> f32 {
    v.pdf_dir(next_dir, v.w_prev)
}

/// Samples the direction leaving the last vertex of `path`, updates the
/// throughput and the previous vertex's reverse density, and plays Russian
/// roulette; false when the walk ends.
fn scatter(scene: &Scene, walk: &mut Walk, path: &mut [Vertex], sampler: &mut Sampler) -> bool {
    let n = path.len();
    let v = path[n - 1];
    let u = sampler.next_2d();
    let (dir, weight, pdf) = match &v.kind {
        Kind::Surface { material, ns, .. } => {
            let bs = match walk.mode {
                Mode::Camera => material.sample(
                    &Shading::facing(*ns, v.w_prev),
                    v.w_prev,
                    u,
                    sampler.next_1d(),
                ),
                Mode::Light => material.sample_adjoint(*ns, v.w_prev, u, sampler.next_1d()),
            };
            let Some(bs) = bs else {
                return false;
            };
            let mut weight = bs.weight;
            if walk.mode == Mode::Light {
                let denom = v.ng.dot(v.w_prev).abs();
                if denom == 0.0 {
                    return false;
                }
                weight *= v.ng.dot(bs.wi).abs() / denom;
            }
            (bs.wi, weight, bs.pdf)
        }
        Kind::Medium { phase } => {
            let Some(ps) = phase.sample(walk.ray.direction, u) else {
                return false;
            };
            (ps.direction, Rgb::splat(ps.weight), ps.pdf)
        }
        _ => return false,
    };
    if !positive(pdf) || weight.is_black() {
        return false;
    }
    walk.beta *= weight;
    // The previous vertex as sampled from this one, arriving from the new direction.
    let rev = reverse_pdf(&v, dir);
    let prev = &mut path[n - 2];
    prev.pdf_rev = reverse_density(scene, prev, rev, v.p, v.tau_in);
    walk.from_infinity = None;
    walk.pdf_dir = pdf;
    let origin = if v.ng == Vec3::ZERO {
        v.p
    } else {
        offset_origin(v.p, v.ng, dir)
    };
    walk.ray = walk.ray.spawn(origin, dir);
    roulette(scene, walk, n - 1, sampler)
}

/// Density of `prev` sampled from point `from` with solid-angle density
/// `pdf_sa` over surrogate depth `tau`: zero for the lens and for lights no
/// path can hit (points, spots, a delta sun).
pub(super) fn reverse_density(
    scene: &Scene,
    prev: &Vertex,
    pdf_sa: f32,
    from: Vec3,
    tau: f32,
) -> f32 {
    match prev.kind {
        Kind::Light { light } | Kind::Infinite { light, .. } => {
            let l = &scene.lights[light as usize];
            if l.is_delta_position() || l.is_delta_direction() {
                return 0.0;
            }
        }
        Kind::Camera => return 0.0,
        _ => {}
    }
    prev.density_from(pdf_sa, from, tau)
}

/// Russian roulette past `rr_depth` scattering events, as the path tracer
/// plays it; a light subpath's throughput is measured against its start.
fn roulette(scene: &Scene, walk: &mut Walk, depth: usize, sampler: &mut Sampler) -> bool {
    if depth < scene.settings.rr_depth as usize {
        return true;
    }
    let q = crate::integrator::survival_probability(
        walk.beta.max_channel() / walk.beta_start,
        depth as u32,
    );
    if !positive(q) || sampler.next_1d() >= q {
        return false;
    }
    walk.beta /= q;
    true
}
