//! The MIS weight of a connected path: the densities its connection
//! changes (the endpoints and their predecessors seen from the other side,
//! the light point as a light subpath's start and as next-event estimation
//! picks it), handed to the recurrence of module `mis`.
//!
//! Every strategy's weight of one path comes from the same functions of its
//! vertices, whichever strategy sampled it: that is what makes the weights
//! of a path sum to one (test: `weights_tests::partition_of_unity`).

use super::media::{self, Surrogate};
use super::mis::{weight, Strategy};
use super::subpath::reverse_density;
use super::vertex::{Kind, Vertex};
use crate::integrator::Scene;
use crate::light::SceneSphere;
use crate::math::Vec3;

/// What every strategy of one camera sample shares.
pub(super) struct Context<'a> {
    pub scene: &'a Scene,
    pub sur: Surrogate<'a>,
    pub sphere: SceneSphere,
    /// The sample's time, shared by both subpaths.
    pub time: f32,
}

impl Context<'_> {
    pub(super) fn light_pmf(&self, light: u32) -> f32 {
        self.scene.light_pick.pmf(light as usize)
    }

    /// L₀: density of light vertex `x0` as a light subpath's start.
    pub(super) fn emit_density(&self, x0: &Vertex) -> f32 {
        match x0.kind {
            Kind::Light { light } => {
                let l = &self.scene.lights[light as usize];
                let pos = l.emission_pdf_pos(&self.scene.geometry, self.time, &self.sphere);
                self.light_pmf(light) * pos
            }
            Kind::Infinite { light, dir } => {
                let l = &self.scene.lights[light as usize];
                self.light_pmf(light) * l.emission_pdf_dir(Vec3::ZERO, dir)
            }
            _ => 0.0,
        }
    }

    /// L₁: density of `x1` as the light at `x0` emits toward it, over surrogate depth `tau`.
    pub(super) fn emit_to(&self, x0: &Vertex, x1: &Vertex, tau: f32) -> f32 {
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
    pub(super) fn nee_density(&self, x0: &Vertex, x1: &Vertex, to_x2: Vec3) -> f32 {
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

    /// The solid-angle density with which camera vertex `z` (the lens when it
    /// starts the subpath) samples direction `w`.
    fn camera_side_pdf(&self, z: &Vertex, is_lens: bool, w: Vec3) -> f32 {
        if is_lens {
            self.scene.camera.direction_pdf(w, self.time)
        } else {
            z.pdf_dir(z.w_prev, w)
        }
    }
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

/// The weight of s = 0: the camera subpath's last vertex lies on light `x0`
/// (the same point, as a light vertex: an area light, or a light at infinity).
pub(super) fn weight_s0(ctx: &Context, camera: &[Vertex], x0: &Vertex) -> f32 {
    let t = camera.len();
    let (z, x1) = (&camera[t - 1], &camera[t - 2]);
    weight(&Strategy {
        light: &[],
        camera,
        emit: ctx.emit_density(x0),
        nee: ctx.nee_density(x0, x1, x1.w_prev),
        y_rev: 0.0,
        y_prev_rev: 0.0,
        z_rev: 0.0,
        z_prev_rev: ctx.emit_to(x0, x1, z.tau_in),
    })
}

/// The weight of joining light vertex s − 1 and camera vertex t − 1 (s, t ≥ 1,
/// not both 1): for s = 1 `light` holds the light point next-event estimation
/// picked, for t = 1 `camera` the lens point light tracing connected to.
pub(super) fn weight_joined(ctx: &Context, light: &[Vertex], camera: &[Vertex]) -> f32 {
    let (s, t) = (light.len(), camera.len());
    let (y, z) = (&light[s - 1], &camera[t - 1]);
    // Direction from z toward y, and the connection's surrogate depth.
    let (w, tau) = match y.kind {
        Kind::Infinite { dir, .. } => (-dir, ctx.sur.depth_to_infinity(z.p, -dir)),
        _ => ((y.p - z.p).normalize_or_zero(), ctx.sur.depth(z.p, y.p)),
    };
    let y_rev = reverse_density(ctx.scene, y, ctx.camera_side_pdf(z, t == 1, w), z.p, tau);
    let y_prev_rev = if s >= 2 {
        let pdf_sa = y.pdf_dir(-w, y.w_prev);
        reverse_density(ctx.scene, &light[s - 2], pdf_sa, y.p, y.tau_in)
    } else {
        0.0
    };
    let z_rev = if s == 1 {
        ctx.emit_to(y, z, tau)
    } else {
        z.density_from(y.pdf_dir(y.w_prev, -w), y.p, tau)
    };
    let (emit, x1, to_x2) = match s {
        1 => (ctx.emit_density(y), z, z.w_prev),
        _ => {
            let to_x2 = match light.get(2) {
                Some(x2) => -x2.w_prev,
                None => (z.p - light[1].p).normalize_or_zero(),
            };
            (light[0].pdf_fwd, &light[1], to_x2)
        }
    };
    weight(&Strategy {
        light,
        camera,
        emit,
        nee: ctx.nee_density(&light[0], x1, to_x2),
        y_rev,
        y_prev_rev,
        z_rev,
        z_prev_rev: camera_prev_rev(camera, z.pdf_dir(w, z.w_prev)),
    })
}
