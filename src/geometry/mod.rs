//! Shapes, intersection records and the BVH (obvhs) over all primitives.

pub mod moving;
pub mod shapes;

pub use moving::MovingShape;
pub use shapes::{AreaSample, Primitive, PrimitiveHit};

use crate::math::{Bounds3, Ray, Vec3};
use obvhs::aabb::Aabb;
use obvhs::bvh2::{builder::build_bvh2, Bvh2};
use obvhs::ray::{Ray as BvhRay, RayHit};
use obvhs::BvhBuildParams;

/// Smallest ray parameter accepted as a hit, relative to the scene scale.
const T_MIN: f32 = 0.0;

/// The closest surface point found along a ray.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    /// Ray parameter.
    pub t: f32,
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal, as stored (not flipped).
    pub geometric_normal: Vec3,
    /// Unit shading normal, on the geometric normal's side.
    pub shading_normal: Vec3,
    /// Index of the primitive in `Geometry::primitives`.
    pub primitive: u32,
    /// Index of the scene shape the primitive belongs to.
    pub shape: u32,
}

/// All primitives of a scene with their BVH.
pub struct Geometry {
    primitives: Vec<Primitive>,
    primitive_shape: Vec<u32>,
    bvh: Option<Bvh2>,
    bounds: Bounds3,
    /// Shapes moved by keyframes (none in a still scene).
    moving: Option<moving::MovingShapes>,
}

struct Boxed(Bounds3);

impl obvhs::Boundable for Boxed {
    fn aabb(&self) -> Aabb {
        Aabb::new(self.0.min.into(), self.0.max.into())
    }
}

impl Geometry {
    /// Builds the BVH over `(primitive, shape index)` pairs; primitives are reordered for traversal.
    pub fn new(items: Vec<(Primitive, u32)>) -> Geometry {
        let boxes: Vec<Boxed> = items.iter().map(|(p, _)| Boxed(p.bounds())).collect();
        let bounds = boxes.iter().fold(Bounds3::EMPTY, |acc, b| acc.union(&b.0));
        if items.is_empty() {
            return Geometry {
                primitives: Vec::new(),
                primitive_shape: Vec::new(),
                bvh: None,
                bounds,
                moving: None,
            };
        }
        let mut build_time = std::time::Duration::ZERO;
        let bvh = build_bvh2(&boxes, BvhBuildParams::medium_build(), &mut build_time);
        // Reorder so that BVH leaf ranges index our arrays directly.
        let (primitives, primitive_shape) = bvh
            .primitive_indices
            .iter()
            .map(|&i| items[i as usize])
            .unzip();
        Geometry {
            primitives,
            primitive_shape,
            bvh: Some(bvh),
            bounds,
            moving: None,
        }
    }

    /// The same geometry with `shapes` moved by keyframes beside the still primitives.
    pub fn with_moving(mut self, shapes: Vec<MovingShape>) -> Geometry {
        self.moving = moving::MovingShapes::new(shapes);
        if let Some(m) = &self.moving {
            self.bounds = self.bounds.union(&m.bounds());
        }
        self
    }

    /// The moving shape with scene index `shape`, if that shape moves.
    #[inline]
    pub fn moving_shape(&self, shape: u32) -> Option<&MovingShape> {
        self.moving.as_ref()?.get(shape)
    }

    /// Primitives in traversal order.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// Shape index of each primitive (same order as `primitives`).
    pub fn primitive_shapes(&self) -> &[u32] {
        &self.primitive_shape
    }

    /// Bounds of all primitives (moving ones over all times).
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Closest hit with `t < t_max` (moving shapes at the ray's time).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let still = self.intersect_still(ray, t_max);
        let Some(moving) = &self.moving else {
            return still;
        };
        moving
            .intersect(ray, still.map_or(t_max, |h| h.t))
            .or(still)
    }

    fn intersect_still(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let bvh = self.bvh.as_ref()?;
        let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), T_MIN, t_max);
        let mut hit = RayHit::none();
        let mut best: Option<PrimitiveHit> = None;
        // Every accepted hit is closer than the previous one (the closure only
        // reports hits before `r.tmax`), so the last one recorded is the closest.
        bvh.ray_traverse(bvh_ray, &mut hit, |r, id| {
            match self.primitives[id].intersect(ray, T_MIN, r.tmax) {
                Some(h) => {
                    best = Some(h);
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        let h = best?;
        Some(SurfaceHit {
            t: h.t,
            p: ray.at(h.t),
            geometric_normal: h.geometric_normal,
            shading_normal: h.shading_normal,
            primitive: hit.primitive_id,
            shape: self.primitive_shape[hit.primitive_id as usize],
        })
    }

    /// True when anything blocks the ray before `t_max` (moving shapes at the ray's time).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluded_still(ray, t_max)
            || self.moving.as_ref().is_some_and(|m| m.occluded(ray, t_max))
    }

    fn occluded_still(&self, ray: &Ray, t_max: f32) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), T_MIN, t_max);
        !bvh.ray_traverse_miss(bvh_ray, |r, id| {
            self.primitives[id]
                .intersect(ray, T_MIN, r.tmax)
                .map_or(f32::INFINITY, |h| h.t)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bvh_finds_closest_of_many_spheres() {
        let items: Vec<(Primitive, u32)> = (0..50)
            .map(|i| {
                (
                    Primitive::Sphere {
                        center: Vec3::new(0.0, 0.0, i as f32 * 3.0),
                        radius: 1.0,
                    },
                    i,
                )
            })
            .collect();
        let g = Geometry::new(items);
        let ray = Ray::new(Vec3::new(0.0, 0.0, -10.0), Vec3::Z);
        let hit = g.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t - 9.0).abs() < 1e-4);
        assert_eq!(hit.shape, 0);
        let from_middle = Ray::new(Vec3::new(0.0, 0.0, 31.5), Vec3::Z);
        let hit = g.intersect(&from_middle, f32::INFINITY).unwrap();
        assert_eq!(hit.shape, 11);
        assert!(g.occluded(&ray, 20.0));
        assert!(!g.occluded(&ray, 8.0));
        assert!(!g.occluded(&Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::Z), 1e3));
    }

    #[test]
    fn empty_and_single_primitive_scenes() {
        let empty = Geometry::new(Vec::new());
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(empty.intersect(&ray, f32::INFINITY).is_none());
        assert!(!empty.occluded(&ray, f32::INFINITY));
        let one = Geometry::new(vec![(
            Primitive::Sphere {
                center: Vec3::new(0.0, 0.0, 5.0),
                radius: 1.0,
            },
            7,
        )]);
        assert_eq!(one.intersect(&ray, f32::INFINITY).unwrap().shape, 7);
    }
}
