//! Shapes moved by keyframed transforms: intersected in their own frame at
//! the ray's time, found through a BVH over the bounds they sweep.
//!
//! A moving shape keeps its primitives in its local frame with their own
//! BVH (an instance). A ray at time t is mapped into that frame by K(t)⁻¹
//! (`math::keyframes`), with its direction renormalized and its parameters
//! rescaled by the length L⁻¹d had, so a local hit at s is the world hit at
//! s/|L⁻¹d|; normals go back by the inverse transpose. The instances sit in
//! a top-level BVH over their swept bounds ([`Keyframes::swept_bounds`]),
//! which hold the shape at every time (proof there), so traversal never
//! skips an instance a ray at any time can hit. Still shapes stay in the
//! scene's own BVH, untouched.

use super::{Boxed, Geometry, Primitive, SurfaceHit};
use crate::math::keyframes::{Keyframes, Placement};
use crate::math::{Bounds3, Ray};
use obvhs::bvh2::{builder::build_bvh2, Bvh2};
use obvhs::ray::{Ray as BvhRay, RayHit};
use obvhs::BvhBuildParams;

/// One shape moved by keyframes: its primitives in its local frame.
pub struct MovingShape {
    shape: u32,
    local: Geometry,
    keys: Keyframes,
    swept: Bounds3,
}

impl MovingShape {
    /// Shape `shape` made of `primitives` (local frame), placed by `keys`.
    pub fn new(shape: u32, primitives: Vec<Primitive>, keys: Keyframes) -> MovingShape {
        let local = Geometry::new(primitives.into_iter().map(|p| (p, shape)).collect());
        let swept = keys.swept_bounds(&local.bounds());
        MovingShape {
            shape,
            local,
            keys,
            swept,
        }
    }

    /// The shape's primitives in its local frame.
    pub fn local(&self) -> &Geometry {
        &self.local
    }

    /// The placement at `time`.
    #[inline]
    pub fn placement(&self, time: f32) -> Placement {
        self.keys.at(time)
    }

    /// The keyframes.
    pub fn keyframes(&self) -> &Keyframes {
        &self.keys
    }

    /// Bounds over all times.
    pub fn swept_bounds(&self) -> Bounds3 {
        self.swept
    }

    /// The ray in the local frame (unit direction) and the local length of one world unit.
    #[inline]
    fn local_ray(&self, ray: &Ray) -> (Placement, Ray, f32) {
        let m = self.keys.at(ray.time);
        let d = m.vector_to_local(ray.direction);
        let len = d.length();
        let local = Ray {
            origin: m.point_to_local(ray.origin),
            direction: d / len,
            time: ray.time,
        };
        (m, local, len)
    }

    /// Closest hit with world parameter below `t_max`, at the ray's time.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let (m, local, len) = self.local_ray(ray);
        let h = self.local.intersect(&local, t_max * len)?;
        let t = h.t / len;
        (t < t_max).then(|| SurfaceHit {
            t,
            p: ray.at(t),
            geometric_normal: m.normal_to_world(h.geometric_normal),
            shading_normal: m.normal_to_world(h.shading_normal),
            primitive: h.primitive,
            shape: self.shape,
            st: h.st,
        })
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let (_, local, len) = self.local_ray(ray);
        self.local.occluded(&local, t_max * len)
    }
}

/// The moving shapes of a scene with a BVH over their swept bounds.
pub(super) struct MovingShapes {
    /// In increasing shape index.
    shapes: Vec<MovingShape>,
    bvh: Bvh2,
}

impl MovingShapes {
    /// `None` when there are none.
    pub(super) fn new(shapes: Vec<MovingShape>) -> Option<MovingShapes> {
        if shapes.is_empty() {
            return None;
        }
        let mut shapes = shapes;
        shapes.sort_by_key(|s| s.shape);
        // The BVH's primitive ids index `shapes` in this (sorted) order.
        let boxes: Vec<Boxed> = shapes.iter().map(|s| Boxed(s.swept)).collect();
        let mut build_time = std::time::Duration::ZERO;
        let bvh = build_bvh2(&boxes, BvhBuildParams::medium_build(), &mut build_time);
        Some(MovingShapes { shapes, bvh })
    }

    /// The moving shape with scene index `shape`.
    pub(super) fn get(&self, shape: u32) -> Option<&MovingShape> {
        self.shapes
            .binary_search_by_key(&shape, |s| s.shape)
            .ok()
            .map(|i| &self.shapes[i])
    }

    /// Union of the swept bounds.
    pub(super) fn bounds(&self) -> Bounds3 {
        self.shapes
            .iter()
            .fold(Bounds3::EMPTY, |b, s| b.union(&s.swept))
    }

    /// Closest hit of any moving shape below `t_max`.
    pub(super) fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), 0.0, t_max);
        let mut hit = RayHit::none();
        let mut best = None;
        self.bvh.ray_traverse(bvh_ray, &mut hit, |r, id| {
            let shape = &self.shapes[self.bvh.primitive_indices[id] as usize];
            match shape.intersect(ray, r.tmax) {
                Some(h) => {
                    best = Some(h);
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    /// True when a moving shape blocks the ray before `t_max`.
    pub(super) fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), 0.0, t_max);
        !self.bvh.ray_traverse_miss(bvh_ray, |_, id| {
            let shape = &self.shapes[self.bvh.primitive_indices[id] as usize];
            if shape.occluded(ray, t_max) {
                0.0
            } else {
                f32::INFINITY
            }
        })
    }
}
