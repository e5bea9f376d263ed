//! Where a bounded medium lives: all space, a transformed box or a transformed sphere.

use crate::math::{Affine3A, Bounds3, Ray, Vec3};
use glam::{Mat3A, Vec3A};

/// The part of space a medium fills.
#[derive(Clone, Copy, Debug)]
pub enum Region {
    /// All of space.
    Everywhere,
    /// A box in world space, placed without rotation or scale ([`Region::boxed`]):
    /// its slab test needs no transform (a fog bank's `bounds`).
    AlignedBox(Bounds3),
    /// A box given in local coordinates, placed by `world_to_local`'s inverse.
    Box {
        /// World → local map.
        world_to_local: Affine3A,
        /// The box in local coordinates.
        local: Bounds3,
    },
    /// A sphere given in local coordinates.
    Sphere {
        /// World → local map.
        world_to_local: Affine3A,
        /// Centre in local coordinates.
        center: Vec3,
        /// Radius in local coordinates.
        radius: f32,
    },
}

impl Region {
    /// The box `local` placed by `world_to_local`'s inverse: a
    /// [`Region::AlignedBox`] where that map only translates.
    pub fn boxed(world_to_local: Affine3A, local: Bounds3) -> Region {
        if world_to_local.matrix3 == Mat3A::IDENTITY {
            let shift = Vec3::from(world_to_local.translation);
            return Region::AlignedBox(Bounds3::new(local.min - shift, local.max - shift));
        }
        Region::Box {
            world_to_local,
            local,
        }
    }

    /// The ray-parameter interval inside the region, clipped to `[0, t_max]`.
    ///
    /// The ray is mapped to local space without renormalizing its direction,
    /// so parameters are the same in both spaces.
    pub fn interval(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        match self {
            Region::Everywhere => (t_max > 0.0).then_some((0.0, t_max)),
            Region::AlignedBox(b) => {
                let inv = Vec3A::from(ray.direction).recip();
                slab_interval(b, ray.origin.into(), inv, t_max)
            }
            Region::Box {
                world_to_local,
                local,
            } => {
                let o = world_to_local.transform_point3a(ray.origin.into());
                let inv = world_to_local
                    .transform_vector3a(ray.direction.into())
                    .recip();
                slab_interval(local, o, inv, t_max)
            }
            Region::Sphere {
                world_to_local,
                center,
                radius,
            } => {
                let o = world_to_local.transform_point3(ray.origin) - *center;
                let d = world_to_local.transform_vector3(ray.direction);
                let a = d.length_squared();
                let b = o.dot(d);
                // Subtract the projected part first: precise for distant origins.
                let perp = o - d * (b / a);
                let disc = a * (radius * radius - perp.length_squared());
                if disc < 0.0 {
                    return None;
                }
                let root = disc.sqrt();
                let t0 = ((-b - root) / a).max(0.0);
                let t1 = ((-b + root) / a).min(t_max);
                (t0 < t1).then_some((t0, t1))
            }
        }
    }

    /// True when world point `p` lies in the region.
    pub fn contains(&self, p: Vec3) -> bool {
        match self {
            Region::Everywhere => true,
            Region::AlignedBox(b) => b.contains(p),
            Region::Box {
                world_to_local,
                local,
            } => local.contains(world_to_local.transform_point3(p)),
            Region::Sphere {
                world_to_local,
                center,
                radius,
            } => (world_to_local.transform_point3(p) - *center).length_squared() <= radius * radius,
        }
    }
}

/// The slab test of `Bounds3::intersect_ray` in SIMD lanes (Vec3A), for the
/// ray `o + t·(1 / inv)` clipped to `[0, t_max]`.
#[inline]
fn slab_interval(b: &Bounds3, o: Vec3A, inv: Vec3A, t_max: f32) -> Option<(f32, f32)> {
    let ta = (Vec3A::from(b.min) - o) * inv;
    let tb = (Vec3A::from(b.max) - o) * inv;
    let t_near = ta.min(tb).max_element().max(0.0);
    let t_far = ta.max(tb).min_element().min(t_max);
    (t_near <= t_far).then_some((t_near, t_far))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformed_box_and_sphere_intervals() {
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            crate::math::Quat::from_rotation_y(0.3),
            Vec3::new(5.0, 0.0, 0.0),
        );
        let world_to_local = to_world.inverse();
        let sphere = Region::Sphere {
            world_to_local,
            center: Vec3::ZERO,
            radius: 1.0,
        };
        // World sphere: centre (5,0,0), radius 2.
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let (t0, t1) = sphere.interval(&ray, f32::INFINITY).unwrap();
        assert!((t0 - 3.0).abs() < 1e-4 && (t1 - 7.0).abs() < 1e-4);
        let boxed = Region::Box {
            world_to_local: Affine3A::from_translation(Vec3::new(-5.0, 0.0, 0.0)),
            local: Bounds3::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
        };
        let (t0, t1) = boxed.interval(&ray, 5.5).unwrap();
        assert!((t0 - 4.0).abs() < 1e-5 && (t1 - 5.5).abs() < 1e-5);
        assert!(boxed.contains(Vec3::new(5.5, 0.5, 0.0)));
        // Placed by a translation only, the same box needs no transform.
        let Region::Box {
            world_to_local,
            local,
        } = boxed
        else {
            unreachable!()
        };
        let aligned = Region::boxed(world_to_local, local);
        assert!(matches!(aligned, Region::AlignedBox(_)), "{aligned:?}");
        let turned = Region::boxed(to_world.inverse(), local);
        assert!(matches!(turned, Region::Box { .. }), "{turned:?}");
        let mut rng = crate::sampling::Sampler::from_seed(3);
        for _ in 0..2000 {
            let o = Vec3::new(rng.next_1d(), rng.next_1d(), rng.next_1d()) * 8.0
                - Vec3::new(-1.0, 4.0, 4.0);
            let d = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
            let ray = Ray::new(o, d);
            let (a, b) = (aligned.interval(&ray, 6.0), boxed.interval(&ray, 6.0));
            match (a, b) {
                (Some(a), Some(b)) => {
                    assert!(
                        (a.0 - b.0).abs() < 1e-5 && (a.1 - b.1).abs() < 1e-5,
                        "{a:?} {b:?}"
                    )
                }
                (None, None) => {}
                _ => panic!("{ray:?}: {a:?} against {b:?}"),
            }
            assert_eq!(aligned.contains(o), boxed.contains(o), "{o}");
        }
        assert!(!sphere.contains(Vec3::new(5.0, 2.5, 0.0)));
    }
}
