//! Rays, orthonormal frames, bounding boxes and small helpers over glam.

pub mod color;

pub mod keyframes;

pub use glam::{Affine3A, Mat3, Mat4, Quat, UVec2, Vec2, Vec3, Vec3A, Vec4};

/// A ray `origin + t * direction` with a valid parametric interval `[0, t_max)`.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Unit propagation direction.
    pub direction: Vec3,
    /// The camera sample's time, in frames relative to the frame being rendered
    /// (0 without a shutter); every ray of a path carries the same time.
    pub time: f32,
}

impl Ray {
    /// A ray from `origin` along `direction` (which should be normalized), at time 0.
    pub fn new(origin: Vec3, direction: Vec3) -> Ray {
        Ray {
            origin,
            direction,
            time: 0.0,
        }
    }

    /// A ray continuing this one's path from `origin` along `direction`: same time.
    #[inline]
    pub fn spawn(&self, origin: Vec3, direction: Vec3) -> Ray {
        Ray {
            origin,
            direction,
            time: self.time,
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }
}

/// An orthonormal basis whose `z` axis is a given unit vector.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// First tangent.
    pub x: Vec3,
    /// Second tangent.
    pub y: Vec3,
    /// The axis the frame was built around.
    pub z: Vec3,
}

impl Frame {
    /// Builds a frame around unit vector `z` (Duff et al. 2017, branchless).
    pub fn from_z(z: Vec3) -> Frame {
        let sign = 1.0f32.copysign(z.z);
        let a = -1.0 / (sign + z.z);
        let b = z.x * z.y * a;
        let x = Vec3::new(1.0 + sign * z.x * z.x * a, sign * b, -sign * z.x);
        let y = Vec3::new(b, sign + z.y * z.y * a, -z.y);
        Frame { x, y, z }
    }

    /// Expresses a world vector in frame coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Expresses a frame-local vector in world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Bounds3 {
    /// The empty box (min = +inf, max = -inf), the identity of `union`.
    pub const EMPTY: Bounds3 = Bounds3 {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// A box from two corners in any order.
    pub fn new(a: Vec3, b: Vec3) -> Bounds3 {
        Bounds3 {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Bounds3) -> Bounds3 {
        Bounds3 {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The smallest box holding this one and a point.
    pub fn include(&self, p: Vec3) -> Bounds3 {
        Bounds3 {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// True when `p` lies inside or on the boundary.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Parametric interval `[t0, t1]` where the ray is inside the box, clipped to `[0, t_max]`.
    pub fn intersect_ray(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        let inv = ray.direction.recip();
        let ta = (self.min - ray.origin) * inv;
        let tb = (self.max - ray.origin) * inv;
        // NaN (0 * inf for a ray on a slab plane) is dropped by min/max against the other bound.
        let t_near = ta.min(tb).max_element().max(0.0);
        let t_far = ta.max(tb).min_element().min(t_max);
        (t_near <= t_far).then_some((t_near, t_far))
    }

    /// The box of the eight corners after an affine transform.
    pub fn transformed(&self, m: &Affine3A) -> Bounds3 {
        let mut out = Bounds3::EMPTY;
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            out = out.include(m.transform_point3(corner));
        }
        out
    }
}

/// Spherical direction from polar angle cosine and azimuth, around +z.
#[inline]
pub fn spherical_direction(cos_theta: f32, phi: f32) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (sin_phi, cos_phi) = phi.sin_cos();
    Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
}

/// Offsets a ray origin off a surface along its normal, on the side of `direction`.
#[inline]
pub fn offset_origin(p: Vec3, normal: Vec3, direction: Vec3) -> Vec3 {
    let scale = 1e-4 * (1.0 + p.abs().max_element());
    let n = if normal.dot(direction) >= 0.0 {
        normal
    } else {
        -normal
    };
    p + n * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_for_many_axes() {
        for i in 0..1000 {
            let t = i as f32 * 0.731;
            let z = Vec3::new(t.sin(), (t * 1.7).cos(), (t * 0.3).sin() - 0.5).normalize();
            let f = Frame::from_z(z);
            assert!((f.x.length() - 1.0).abs() < 1e-5);
            assert!((f.y.length() - 1.0).abs() < 1e-5);
            assert!(f.x.dot(f.y).abs() < 1e-5 && f.x.dot(z).abs() < 1e-5);
            assert!(f.x.cross(f.y).dot(z) > 0.999);
            let v = Vec3::new(0.3, -0.2, 0.9);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
        }
    }

    #[test]
    fn ray_box_interval() {
        let b = Bounds3::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let r = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
        assert_eq!(b.intersect_ray(&r, f32::INFINITY), Some((2.0, 4.0)));
        let miss = Ray::new(Vec3::new(-3.0, 2.0, 0.0), Vec3::X);
        assert_eq!(b.intersect_ray(&miss, f32::INFINITY), None);
        let inside = Ray::new(Vec3::ZERO, Vec3::Y);
        assert_eq!(b.intersect_ray(&inside, 0.5), Some((0.0, 0.5)));
    }
}
