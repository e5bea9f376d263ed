//! The strategies (s, t): a camera subpath hitting a light (s = 0),
//! next-event estimation (s = 1), connecting two subpaths (s, t ≥ 2) and
//! light tracing onto the film (t = 1), each with its MIS weight.

use super::media::{self, Surrogate};
use super::mis::{weight, Strategy};
use super::positive;
use super::subpath::reverse_density;
use super::vertex::{Kind, Vertex};
use crate::camera::CameraConnection;
use crate::color::Rgb;
use crate::integrator::Scene;
use crate::light::SceneSphere;
use crate::math::{offset_origin, Ray, Vec2, Vec3};
use crate::sampling::Sampler;

/// What every strategy of one camera sample shares.
pub(super) struct Context<'a> {
    pub scene: &'a Scene,
    pub sur: Surrogate<'a>,
    pub sphere: SceneSphere,
    /// The sample's time, shared by both subpaths.
    pub time: f32,
}

/// A strategy's estimate before and after its MIS weight.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Contribution {
    /// Weighted by MIS: what the image gets.
    pub weighted: Rgb,
    /// Alone: an estimate of all paths of this length.
    pub unweighted: Rgb,
}

impl Contribution {
    fn new(value: Rgb, w: f32) -> Contribution {
        Contribution {
            weighted: value * w,
            unweighted: value,
        }
    }
}

impl Context<'_> {
    fn light_pmf(&self, light: u32) -> f32 {
        self.scene.light_pick.pmf(light as usize)
    }

    /// L₀: density of light vertex `x0` as a light subpath's start.
    fn emit_density(&self, x0: &Vertex) -> f32 {
        match x0.kind {
            Kind::Light { light } => {
                let l = &self.scene.lights[light as usize];
                self.light_pmf(light)
                    * l.emission_pdf_pos(&self.scene.geometry, self.time, &self.sphere)
            }
            Kind::Infinite { light, dir } => {
                let l = &self.scene.lights[light as usize];
                self.light_pmf(light) * l.emission_pdf_dir(Vec3::ZERO, dir)
            }
            _ => 0.0,
        }
    }

    /// L₁: density of `x1` as the light at `x0` emits toward it, over surrogate depth `tau`.
    fn emit_to(&self, x0: &Vertex, x1: &Vertex, tau: f32) -> f32 {
        match x0.kind {
            Kind::Light { light } => {
                let l = &self.scene.lights[light as usize];
                let dir = (x1.p - x0.p).normalize_or_zero();
                x1.density_from(l.emission_pdf_dir(x0.ng, dir), x0.p, tau)
            }
            Kind::Infinite { dir, .. } => {
                if !self.sphere.reaches(dir, x1.p) {
                    return 0.0;
                }
                self.sphere.disk_pdf() * x1.cos(dir) * media::transmittance(tau) * x1.sigma_t
            }
            _ => 0.0,
        }
    }

    /// N: density of `x0` as next-event estimation from `x1` samples it,
    /// `to_x2` the direction from `x1` toward the path's next vertex.
    fn nee_density(&self, x0: &Vertex, x1: &Vertex, to_x2: Vec3) -> f32 {
        match x0.kind {
            Kind::Light { light } => {
                let l = &self.scene.lights[light as usize];
                if l.is_delta_position() {
                    return self.light_pmf(light);
                }
                let geometry = &self.scene.geometry;
                let d = x0.p - x1.p;
                let dist2 = d.length_squared();
                let sa = l.area_pdf_at(x1.p, x0.p, x0.ng, geometry, self.time);
                self.light_pmf(light) * sa * x0.cos(d / dist2.sqrt()) / dist2
            }
            Kind::Infinite { light, dir } => {
                let l = &self.scene.lights[light as usize];
                let sa = if l.is_delta_direction() {
                    1.0
                } else {
                    l.escaped_pdf_facing(-dir, x1.nee_normal(to_x2))
                };
                self.light_pmf(light) * sa
            }
            _ => 0.0,
        }
    }

    /// Transmittance of the open segment between the endpoints `a` and `b`
    /// (each nudged off its surface toward the other), zero when blocked.
    fn visibility(&self, a: &Vertex, b: Vec3, b_normal: Vec3, sampler: &mut Sampler) -> Rgb {
        let toward = b - a.p;
        let from = nudge(a.p, a.ng, toward);
        let to = nudge(b, b_normal, -toward);
        let chord = to - from;
        let length = chord.length();
        if !positive(length) {
            return Rgb::BLACK;
        }
        let mut ray = Ray::new(from, chord / length);
        ray.time = self.time;
        self.segment_transmittance(&ray, length * (1.0 - 1e-4), sampler)
    }

    fn segment_transmittance(&self, ray: &Ray, t_max: f32, sampler: &mut Sampler) -> Rgb {
        if self.scene.geometry.occluded(ray, t_max) {
            return Rgb::BLACK;
        }
        if self.scene.media.is_empty() {
            Rgb::WHITE
        } else {
            self.scene.transmittance(ray, t_max, sampler)
        }
    }
}

/// `p` moved off its surface (normal `n`, zero in a medium) toward `toward`.
fn nudge(p: Vec3, n: Vec3, toward: Vec3) -> Vec3 {
    if n == Vec3::ZERO {
        p
    } else {
        offset_origin(p, n, toward)
    }
}

/// The direction from `x1` toward the vertex after it on the camera side of
/// a light-subpath prefix (`light[1]` is x1; `next` the camera-side endpoint).
fn light_side_next(light: &[Vertex], next: Vec3) -> Vec3 {
    match light.get(2) {
        Some(x2) => -x2.w_prev,
        None => (next - light[1].p).normalize_or_zero(),
    }
}

/// s = 0: the camera subpath's vertex t − 1 lies on a light or escaped to the lights at infinity.
pub(super) fn emission(ctx: &Context, camera: &[Vertex]) -> Contribution {
    let t = camera.len();
    let z = &camera[t - 1];
    let x1 = &camera[t - 2];
    let to_x2 = x1.w_prev;
    let scene = ctx.scene;
    let mut total = Contribution::default();
    let mut add = |x0: Vertex, le: Rgb| {
        let st = Strategy {
            light: &[],
            camera,
            emit: ctx.emit_density(&x0),
            nee: ctx.nee_density(&x0, x1, to_x2),
            y_rev: 0.0,
            y_prev_rev: 0.0,
            z_rev: 0.0,
            z_prev_rev: ctx.emit_to(&x0, x1, z.tau_in),
        };
        let c = Contribution::new(z.beta * le, weight(&st));
        total.weighted += c.weighted;
        total.unweighted += c.unweighted;
    };
    match z.kind {
        Kind::Surface {
            shape,
            primitive,
            st,
            ..
        } => {
            let Some(light) = scene.shape_lights[shape as usize] else {
                return total;
            };
            let le = scene.lights[light as usize]
                .area_radiance(z.ng, z.w_prev, || scene.geometry.uv(primitive, st, z.p));
            if !le.is_black() {
                add(
                    Vertex {
                        kind: Kind::Light { light },
                        ..*z
                    },
                    le,
                );
            }
        }
        Kind::Escaped { dir } => {
            for (i, light) in scene.lights.iter().enumerate() {
                let le = light.escaped_radiance(dir);
                if light.is_infinite() && !le.is_black() {
                    let kind = Kind::Infinite {
                        light: i as u32,
                        dir: -dir,
                    };
                    add(Vertex { kind, ..*z }, le);
                }
            }
        }
        _ => {}
    }
    total
}

/// s = 1: next-event estimation from camera vertex t − 1 to a light picked by power.
pub(super) fn next_event(ctx: &Context, camera: &[Vertex], sampler: &mut Sampler) -> Contribution {
    let t = camera.len();
    let z = &camera[t - 1];
    let scene = ctx.scene;
    let pick = sampler.next_1d();
    let u = sampler.next_2d();
    let Some(index) = scene.light_pick.sample(pick) else {
        return Contribution::default();
    };
    let light = &scene.lights[index];
    let normal = z.nee_normal(z.w_prev);
    let Some(ls) = light.sample_facing(z.p, normal, u, &scene.geometry, ctx.time) else {
        return Contribution::default();
    };
    let f = z.f_camera(ls.wi);
    let pmf = ctx.light_pmf(index as u32);
    if f.is_black() || !positive(ls.pdf) || ls.radiance.is_black() {
        return Contribution::default();
    }
    let infinite = !ls.distance.is_finite();
    let tr = if infinite {
        let mut ray = Ray::new(nudge(z.p, z.ng, ls.wi), ls.wi);
        ray.time = ctx.time;
        ctx.segment_transmittance(&ray, f32::INFINITY, sampler)
    } else {
        ctx.visibility(z, z.p + ls.wi * ls.distance, ls.normal, sampler)
    };
    if tr.is_black() {
        return Contribution::default();
    }
    let value = z.beta * f * tr * ls.radiance / (pmf * ls.pdf);
    let (kind, p) = if infinite {
        let kind = Kind::Infinite {
            light: index as u32,
            dir: -ls.wi,
        };
        (kind, z.p)
    } else {
        (
            Kind::Light {
                light: index as u32,
            },
            z.p + ls.wi * ls.distance,
        )
    };
    let mut y0 = Vertex::new(kind, p, ls.normal, Rgb::WHITE);
    let tau = if infinite {
        ctx.sur.depth_to_infinity(z.p, ls.wi)
    } else {
        ctx.sur.depth(z.p, p)
    };
    y0.tau_in = tau;
    let mut z_conn = *z;
    z_conn.tau_in = tau;
    let st = Strategy {
        light: std::slice::from_ref(&y0),
        camera,
        emit: ctx.emit_density(&y0),
        nee: ctx.nee_density(&y0, z, z.w_prev),
        y_rev: reverse_density(scene, &y0, z.pdf_dir(z.w_prev, ls.wi), &z_conn),
        y_prev_rev: 0.0,
        z_rev: ctx.emit_to(&y0, z, tau),
        z_prev_rev: camera_prev_rev(camera, z.pdf_dir(ls.wi, z.w_prev)),
    };
    Contribution::new(value, weight(&st))
}

/// L of z_{t−2} given the solid-angle density `pdf_sa` at z_{t−1} toward it
/// (0 when z_{t−2} is the lens: t′ = 0 is never traced).
fn camera_prev_rev(camera: &[Vertex], pdf_sa: f32) -> f32 {
    let t = camera.len();
    if t < 3 {
        return 0.0;
    }
    let z = &camera[t - 1];
    camera[t - 2].density_from(pdf_sa, z.p, z.tau_in)
}

/// C of y_{s−2} given the solid-angle density `pdf_sa` at y_{s−1} toward it.
fn light_prev_rev(ctx: &Context, light: &[Vertex], pdf_sa: f32) -> f32 {
    let s = light.len();
    reverse_density(ctx.scene, &light[s - 2], pdf_sa, &light[s - 1])
}

/// s ≥ 2, t ≥ 2: joins light vertex s − 1 and camera vertex t − 1.
pub(super) fn connect(
    ctx: &Context,
    light: &[Vertex],
    camera: &[Vertex],
    sampler: &mut Sampler,
) -> Contribution {
    let (y, z) = (&light[light.len() - 1], &camera[camera.len() - 1]);
    let d = y.p - z.p;
    let dist2 = d.length_squared();
    if !positive(dist2) {
        return Contribution::default();
    }
    let w = d / dist2.sqrt();
    let f = z.f_camera(w) * y.f_light(-w);
    if f.is_black() {
        return Contribution::default();
    }
    let tr = ctx.visibility(z, y.p, y.ng, sampler);
    if tr.is_black() {
        return Contribution::default();
    }
    let value = z.beta * f * y.beta * tr / dist2;
    let tau = ctx.sur.depth(z.p, y.p);
    let st = Strategy {
        light,
        camera,
        emit: light[0].pdf_fwd,
        nee: ctx.nee_density(&light[0], &light[1], light_side_next(light, z.p)),
        y_rev: y.density_from(z.pdf_dir(z.w_prev, w), z.p, tau),
        y_prev_rev: light_prev_rev(ctx, light, y.pdf_dir(-w, y.w_prev)),
        z_rev: z.density_from(y.pdf_dir(y.w_prev, -w), y.p, tau),
        z_prev_rev: camera_prev_rev(camera, z.pdf_dir(w, z.w_prev)),
    };
    Contribution::new(value, weight(&st))
}

/// t = 1: light vertex s − 1 seen by the camera; the radiance lands on the
/// film at the returned raster position (to be divided by the samples per pixel).
pub(super) fn light_trace(
    ctx: &Context,
    light: &[Vertex],
    sampler: &mut Sampler,
) -> Option<(Vec2, Contribution)> {
    let y = &light[light.len() - 1];
    let u_lens = sampler.next_2d();
    let c: CameraConnection = ctx.scene.camera.connect(y.p, ctx.time, u_lens)?;
    let w = -c.direction;
    let f = y.f_light(w);
    if f.is_black() {
        return None;
    }
    let lens = Vertex::new(Kind::Camera, c.lens, Vec3::ZERO, Rgb::WHITE);
    let tr = ctx.visibility(&lens, y.p, y.ng, sampler);
    if tr.is_black() {
        return None;
    }
    let value = y.beta * f * tr * (c.importance / (c.distance * c.distance));
    let tau = ctx.sur.depth(c.lens, y.p);
    let mut z0 = Vertex {
        pdf_fwd: 1.0,
        ..lens
    };
    z0.tau_in = 0.0;
    let pdf_lens = ctx.scene.camera.direction_pdf(c.direction, ctx.time);
    let st = Strategy {
        light,
        camera: std::slice::from_ref(&z0),
        emit: light[0].pdf_fwd,
        nee: ctx.nee_density(&light[0], &light[1], light_side_next(light, c.lens)),
        y_rev: y.density_from(pdf_lens, c.lens, tau),
        y_prev_rev: light_prev_rev(ctx, light, y.pdf_dir(w, y.w_prev)),
        z_rev: 0.0,
        z_prev_rev: 0.0,
    };
    Some((c.raster, Contribution::new(value, weight(&st))))
}
