//! The strategies (s, t): a camera subpath hitting a light (s = 0),
//! next-event estimation (s = 1), connecting two subpaths (s, t ≥ 2) and
//! light tracing onto the film (t = 1), each with its MIS weight.

use super::positive;
use super::vertex::{Kind, Vertex};
use super::weights::{weight_joined, weight_s0, Context};
use crate::camera::CameraConnection;
use crate::math::color::Rgb;
use crate::math::{offset_origin, Ray, Vec2, Vec3};
use crate::sampling::Sampler;

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

/// s = 0: the camera subpath's vertex t − 1 lies on a light or escaped to the lights at infinity.
pub(super) fn emission(ctx: &Context, camera: &[Vertex]) -> Contribution {
    let z = &camera[camera.len() - 1];
    let scene = ctx.scene;
    let mut total = Contribution::default();
    let mut add = |x0: Vertex, le: Rgb| {
        let c = Contribution::new(z.beta * le, weight_s0(ctx, camera, &x0));
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
    let y0 = Vertex::new(kind, p, ls.normal, Rgb::WHITE);
    let w = weight_joined(ctx, std::slice::from_ref(&y0), camera);
    Contribution::new(value, w)
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
    Contribution::new(value, weight_joined(ctx, light, camera))
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
    let lens = Vertex {
        pdf_fwd: 1.0,
        ..lens
    };
    let w = weight_joined(ctx, light, std::slice::from_ref(&lens));
    Some((c.raster, Contribution::new(value, w)))
}
