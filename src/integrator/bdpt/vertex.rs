//! Subpath vertices: what each one is, how it scatters toward another, and
//! the densities bidirectional MIS needs of it in both directions.
//!
//! Densities are per unit area at surfaces, per unit volume in media (per
//! steradian for a vertex at infinity), each including the surrogate
//! free-flight factor of module `media`: `exp(−τ̃)` of the segment that
//! reaches the vertex and, in a medium, the surrogate extinction there.

use super::media;
use crate::material::{Material, Shading};
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};
use crate::medium::PhaseFunction;

/// What a subpath vertex is.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    /// The lens point a camera subpath starts from.
    Camera,
    /// A point on light `light` (area, point or spot): a light subpath's
    /// start, or the light next-event estimation (s = 1) picked.
    Light {
        /// Index into `Scene::lights`.
        light: u32,
    },
    /// Light `light` at infinity, shining along `dir` (propagation direction).
    Infinite {
        /// Index into `Scene::lights`.
        light: u32,
        /// Unit propagation direction of its light.
        dir: Vec3,
    },
    /// A camera subpath that left the scene along `dir` (seen by every light at infinity).
    Escaped {
        /// Unit direction of the escaping ray.
        dir: Vec3,
    },
    /// A surface point.
    Surface {
        /// The BSDF there (textures applied).
        material: Material,
        /// Unit shading normal on the outward side.
        ns: Vec3,
        /// Scene shape (for its area light, if it emits).
        shape: u32,
        /// Primitive and surface parameters, for a textured emitter.
        primitive: u32,
        /// Surface parameters of the hit.
        st: Vec2,
    },
    /// A real scattering event in a medium.
    Medium {
        /// The phase function there.
        phase: PhaseFunction,
    },
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vertex {
    /// What the vertex is.
    pub kind: Kind,
    /// Position (unused at infinity).
    pub p: Vec3,
    /// Unit outward geometric normal at surfaces and area lights, zero elsewhere.
    pub ng: Vec3,
    /// Unit direction toward the previous vertex of the subpath (zero at its start).
    pub w_prev: Vec3,
    /// Throughput of the subpath up to and including this vertex's density.
    pub beta: Rgb,
    /// Density of this vertex from the previous one, along the subpath's direction.
    pub pdf_fwd: f32,
    /// Density of this vertex from the next one, against the subpath's direction.
    pub pdf_rev: f32,
    /// Surrogate optical depth of the segment from the previous vertex.
    pub tau_in: f32,
    /// Surrogate extinction at a medium vertex (1 elsewhere).
    pub sigma_t: f32,
    /// Scattered by a Dirac BSDF: no connection can end here.
    pub delta: bool,
    /// Medium vertices on the subpath up to and including this one.
    pub media: u32,
}

impl Vertex {
    /// A vertex of `kind` at `p` with normal `ng`, reached from `prev` with surrogate depth `tau_in`.
    pub(super) fn new(kind: Kind, p: Vec3, ng: Vec3, beta: Rgb) -> Vertex {
        Vertex {
            kind,
            p,
            ng,
            w_prev: Vec3::ZERO,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            tau_in: 0.0,
            sigma_t: 1.0,
            delta: false,
            media: 0,
        }
    }

    /// True for vertices at infinity (no position, densities per steradian).
    #[inline]
    pub(super) fn is_infinite(&self) -> bool {
        matches!(self.kind, Kind::Infinite { .. } | Kind::Escaped { .. })
    }

    /// True when a connection may end here: not behind a Dirac BSDF.
    #[inline]
    pub(crate) fn connectable(&self) -> bool {
        !self.delta
    }

    /// True for a surface or medium vertex (one that scatters light).
    #[inline]
    pub(crate) fn scatters(&self) -> bool {
        matches!(self.kind, Kind::Surface { .. } | Kind::Medium { .. })
    }

    /// |cos| between the vertex's geometric normal and `w` (1 off surfaces).
    #[inline]
    pub(super) fn cos(&self, w: Vec3) -> f32 {
        if self.ng == Vec3::ZERO {
            1.0
        } else {
            self.ng.dot(w).abs()
        }
    }

    /// Converts a solid-angle density at `from` toward this vertex into this
    /// vertex's measure, over a segment of surrogate optical depth `tau`.
    pub(super) fn density_from(&self, pdf_sa: f32, from: Vec3, tau: f32) -> f32 {
        let t = media::transmittance(tau) * self.sigma_t;
        if self.is_infinite() {
            return pdf_sa * t;
        }
        let d = self.p - from;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return 0.0;
        }
        pdf_sa * self.cos(d / dist2.sqrt()) / dist2 * t
    }

    /// Solid-angle density of this scattering vertex sampling `to` after arriving from `from`
    /// (both pointing away from it); a delta BSDF gives its lobe's probability.
    pub(super) fn pdf_dir(&self, from: Vec3, to: Vec3) -> f32 {
        match &self.kind {
            Kind::Surface { material, ns, .. } => {
                let sp = Shading::facing(*ns, from);
                if self.delta {
                    material.delta_pdf(&sp, from, to)
                } else {
                    material.pdf(&sp, from, to)
                }
            }
            Kind::Medium { phase } => phase.pdf(-from, to),
            _ => 0.0,
        }
    }

    /// Scattering of this camera-subpath vertex toward `to`: the path tracer's `f·|ns·to|`.
    pub(super) fn f_camera(&self, to: Vec3) -> Rgb {
        match &self.kind {
            Kind::Surface { material, ns, .. } => {
                material.eval(&Shading::facing(*ns, self.w_prev), self.w_prev, to)
            }
            Kind::Medium { phase } => Rgb::splat(phase.eval(-self.w_prev, to)),
            _ => Rgb::BLACK,
        }
    }

    /// Scattering of this light-subpath vertex toward `to`: the radiance
    /// BSDF of light arriving from `w_prev`, with the adjoint shading-normal
    /// correction |ng·to| / |ng·w_prev| (Veach 1997, §5.3).
    pub(super) fn f_light(&self, to: Vec3) -> Rgb {
        match &self.kind {
            Kind::Surface { material, ns, .. } => {
                let denom = self.ng.dot(self.w_prev).abs();
                if denom == 0.0 {
                    return Rgb::BLACK;
                }
                material.eval(&Shading::facing(*ns, to), to, self.w_prev)
                    * (self.ng.dot(to).abs() / denom)
            }
            Kind::Medium { phase } => Rgb::splat(phase.eval(-self.w_prev, to)),
            _ => Rgb::BLACK,
        }
    }

    /// The shading normal next-event estimation from this vertex uses, on the side of `wo`.
    pub(super) fn nee_normal(&self, wo: Vec3) -> Option<Vec3> {
        match &self.kind {
            Kind::Surface { ns, .. } => Some(Shading::facing(*ns, wo).n),
            _ => None,
        }
    }
}
