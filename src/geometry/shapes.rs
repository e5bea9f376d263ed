//! Primitive shapes: ray intersection, bounds and uniform area sampling.

use crate::math::{Bounds3, Ray, Vec2, Vec3};
use crate::sampling::warp;

/// One intersectable primitive, the unit the BVH is built over.
#[derive(Clone, Copy, Debug)]
pub enum Primitive {
    /// A sphere.
    Sphere {
        /// Centre in world space.
        center: Vec3,
        /// Radius (> 0).
        radius: f32,
    },
    /// A parallelogram `corner + s·edge_u + t·edge_v`, s, t ∈ [0, 1].
    Parallelogram {
        /// One corner.
        corner: Vec3,
        /// First edge vector.
        edge_u: Vec3,
        /// Second edge vector.
        edge_v: Vec3,
    },
    /// A flat disk `center + r·(cos φ·u_axis + sin φ·(normal × u_axis))`, r ≤ radius.
    Disk {
        /// Centre in world space.
        center: Vec3,
        /// Unit normal of the front side.
        normal: Vec3,
        /// Unit tangent where φ = 0 (perpendicular to `normal`).
        u_axis: Vec3,
        /// Radius (> 0).
        radius: f32,
    },
    /// A triangle with optional per-vertex shading normals.
    Triangle {
        /// Vertex positions.
        p: [Vec3; 3],
        /// Per-vertex shading normals (zero vectors when absent).
        n: [Vec3; 3],
    },
}

/// A parallelogram's ray test with what it can compute once: the plane's
/// normal and the dual edge vectors that give the surface parameters as dot
/// products (s = d·dual_u, t = d·dual_v for d = p − corner in the plane).
#[derive(Clone, Copy, Debug)]
pub struct QuadTest {
    corner: Vec3,
    /// edge_u × edge_v (not normalized).
    normal: Vec3,
    unit_normal: Vec3,
    dual_u: Vec3,
    dual_v: Vec3,
}

impl QuadTest {
    /// The test for parallelogram `corner + s·edge_u + t·edge_v`.
    pub fn new(corner: Vec3, edge_u: Vec3, edge_v: Vec3) -> QuadTest {
        let (uu, vv, uv) = (
            edge_u.length_squared(),
            edge_v.length_squared(),
            edge_u.dot(edge_v),
        );
        let det = uu * vv - uv * uv;
        let normal = edge_u.cross(edge_v);
        QuadTest {
            corner,
            normal,
            unit_normal: normal.normalize(),
            dual_u: (edge_u * vv - edge_v * uv) / det,
            dual_v: (edge_v * uu - edge_u * uv) / det,
        }
    }

    /// The hit with parameter in `(t_min, t_max)`, as [`Primitive::intersect`] finds it.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<PrimitiveHit> {
        let denom = self.normal.dot(ray.direction);
        if denom == 0.0 {
            return None;
        }
        let t = self.normal.dot(self.corner - ray.origin) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let d = ray.at(t) - self.corner;
        let s = d.dot(self.dual_u);
        let r = d.dot(self.dual_v);
        if !(0.0..=1.0).contains(&s) || !(0.0..=1.0).contains(&r) {
            return None;
        }
        Some(PrimitiveHit {
            t,
            geometric_normal: self.unit_normal,
            shading_normal: self.unit_normal,
            st: Vec2::new(s, r),
        })
    }
}

/// Where and how a ray met a primitive.
#[derive(Clone, Copy, Debug)]
pub struct PrimitiveHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Unit geometric normal (not flipped toward the ray).
    pub geometric_normal: Vec3,
    /// Unit shading normal, on the same side as the geometric normal.
    pub shading_normal: Vec3,
    /// Surface parameters of the hit: (s, t) along a parallelogram's edges,
    /// barycentrics (b1, b2) of a triangle's second and third vertex, (r / radius, φ / 2π)
    /// on a disk; unused (0) on a sphere.
    pub st: Vec2,
}

/// A point sampled uniformly by area on a primitive.
#[derive(Clone, Copy, Debug)]
pub struct AreaSample {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal there.
    pub n: Vec3,
    /// Surface parameters of the point, as in [`PrimitiveHit::st`].
    pub st: Vec2,
}

impl Primitive {
    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        match *self {
            Primitive::Sphere { center, radius } => {
                Bounds3::new(center - Vec3::splat(radius), center + Vec3::splat(radius))
            }
            Primitive::Parallelogram {
                corner,
                edge_u,
                edge_v,
            } => Bounds3::new(corner, corner + edge_u)
                .include(corner + edge_v)
                .include(corner + edge_u + edge_v),
            Primitive::Disk {
                center,
                normal,
                radius,
                ..
            } => {
                // The disk's extent along axis i is radius·sin(angle of the normal to axis i).
                let half = (Vec3::ONE - normal * normal).max(Vec3::ZERO).sqrt() * radius;
                Bounds3::new(center - half, center + half)
            }
            Primitive::Triangle { p, .. } => Bounds3::new(p[0], p[1]).include(p[2]),
        }
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        match *self {
            Primitive::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
            Primitive::Parallelogram { edge_u, edge_v, .. } => edge_u.cross(edge_v).length(),
            Primitive::Disk { radius, .. } => std::f32::consts::PI * radius * radius,
            Primitive::Triangle { p, .. } => 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length(),
        }
    }

    /// Closest intersection with parameter in `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<PrimitiveHit> {
        match *self {
            Primitive::Sphere { center, radius } => {
                intersect_sphere(ray, center, radius, t_min, t_max)
            }
            Primitive::Parallelogram {
                corner,
                edge_u,
                edge_v,
            } => intersect_parallelogram(ray, corner, [edge_u, edge_v], t_min, t_max),
            Primitive::Disk {
                center,
                normal,
                u_axis,
                radius,
            } => intersect_disk(ray, center, [normal, u_axis], radius, t_min, t_max),
            Primitive::Triangle { p, n } => intersect_triangle(ray, &p, &n, t_min, t_max),
        }
    }

    /// A point uniformly distributed by area.
    pub fn sample_area(&self, u: Vec2) -> AreaSample {
        match *self {
            Primitive::Sphere { center, radius } => {
                let n = warp::square_to_uniform_sphere(u);
                AreaSample {
                    p: center + n * radius,
                    n,
                    st: Vec2::ZERO,
                }
            }
            Primitive::Parallelogram {
                corner,
                edge_u,
                edge_v,
            } => AreaSample {
                p: corner + edge_u * u.x + edge_v * u.y,
                n: edge_u.cross(edge_v).normalize(),
                st: u,
            },
            Primitive::Disk {
                center,
                normal,
                u_axis,
                radius,
            } => {
                let d = warp::square_to_concentric_disk(u);
                let v_axis = normal.cross(u_axis);
                AreaSample {
                    p: center + (u_axis * d.x + v_axis * d.y) * radius,
                    n: normal,
                    st: disk_st(d.x, d.y, 1.0),
                }
            }
            Primitive::Triangle { p, .. } => {
                let b = warp::square_to_uniform_triangle(u);
                AreaSample {
                    p: p[0] * (1.0 - b.x - b.y) + p[1] * b.x + p[2] * b.y,
                    n: (p[1] - p[0]).cross(p[2] - p[0]).normalize(),
                    st: b,
                }
            }
        }
    }
}

/// Lat-long texture coordinates of the unit outward normal `n` of a sphere:
/// u = φ/2π with the azimuth φ from +X toward +Z, v = 1 − θ/π with θ from +Y
/// (v = 1 at the top), the convention of environment maps.
pub fn sphere_uv(n: Vec3) -> Vec2 {
    let theta = (n.x * n.x + n.z * n.z).sqrt().atan2(n.y);
    let mut phi = n.z.atan2(n.x);
    if phi < 0.0 {
        phi += 2.0 * std::f32::consts::PI;
    }
    Vec2::new(
        phi * (0.5 * std::f32::consts::FRAC_1_PI),
        1.0 - theta * std::f32::consts::FRAC_1_PI,
    )
}

/// Closest hit of a sphere in `(t_min, t_max)`.
#[inline]
fn intersect_sphere(
    ray: &Ray,
    center: Vec3,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<PrimitiveHit> {
    let oc = ray.origin - center;
    let b = oc.dot(ray.direction);
    // Subtracting the projected part first keeps precision for distant spheres.
    let perp = oc - b * ray.direction;
    let disc = radius * radius - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let q = -b - root.copysign(b);
    let c = oc.length_squared() - radius * radius;
    let (mut t0, mut t1) = (q, if q != 0.0 { c / q } else { -b + root });
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let t = if t0 > t_min { t0 } else { t1 };
    if t <= t_min || t >= t_max {
        return None;
    }
    let n = (ray.at(t) - center) / radius;
    Some(PrimitiveHit {
        t,
        geometric_normal: n,
        shading_normal: n,
        st: Vec2::ZERO,
    })
}

/// Hit of the parallelogram `corner + s·edge_u + r·edge_v`, (s, r) ∈ [0, 1]², in `(t_min, t_max)`.
#[inline]
fn intersect_parallelogram(
    ray: &Ray,
    corner: Vec3,
    [edge_u, edge_v]: [Vec3; 2],
    t_min: f32,
    t_max: f32,
) -> Option<PrimitiveHit> {
    let n = edge_u.cross(edge_v);
    let denom = n.dot(ray.direction);
    if denom == 0.0 {
        return None;
    }
    let t = n.dot(corner - ray.origin) / denom;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let d = ray.at(t) - corner;
    let uu = edge_u.length_squared();
    let vv = edge_v.length_squared();
    let uv = edge_u.dot(edge_v);
    let du = d.dot(edge_u);
    let dv = d.dot(edge_v);
    let det = uu * vv - uv * uv;
    let s = (du * vv - dv * uv) / det;
    let r = (dv * uu - du * uv) / det;
    if !(0.0..=1.0).contains(&s) || !(0.0..=1.0).contains(&r) {
        return None;
    }
    let n = n.normalize();
    Some(PrimitiveHit {
        t,
        geometric_normal: n,
        shading_normal: n,
        st: Vec2::new(s, r),
    })
}

/// Hit of the disk of `radius` about `center` with `[normal, u_axis]` in `(t_min, t_max)`.
#[inline]
fn intersect_disk(
    ray: &Ray,
    center: Vec3,
    [normal, u_axis]: [Vec3; 2],
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<PrimitiveHit> {
    let denom = normal.dot(ray.direction);
    if denom == 0.0 {
        return None;
    }
    let t = normal.dot(center - ray.origin) / denom;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let d = ray.at(t) - center;
    let (x, y) = (d.dot(u_axis), d.dot(normal.cross(u_axis)));
    if x * x + y * y > radius * radius {
        return None;
    }
    Some(PrimitiveHit {
        t,
        geometric_normal: normal,
        shading_normal: normal,
        st: disk_st(x, y, radius),
    })
}

/// Polar surface parameters (r / radius, φ / 2π ∈ [0, 1)) of the in-plane point (x, y) of a disk.
#[inline]
fn disk_st(x: f32, y: f32, radius: f32) -> Vec2 {
    let mut phi = y.atan2(x);
    if phi < 0.0 {
        phi += 2.0 * std::f32::consts::PI;
    }
    let r = (x * x + y * y).sqrt() / radius;
    Vec2::new(r.min(1.0), phi * (0.5 * std::f32::consts::FRAC_1_PI))
}

/// Möller–Trumbore ray/triangle test with interpolated shading normals.
fn intersect_triangle(
    ray: &Ray,
    p: &[Vec3; 3],
    normals: &[Vec3; 3],
    t_min: f32,
    t_max: f32,
) -> Option<PrimitiveHit> {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let pvec = ray.direction.cross(e2);
    let det = e1.dot(pvec);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv_det = 1.0 / det;
    let tvec = ray.origin - p[0];
    let b1 = tvec.dot(pvec) * inv_det;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let qvec = tvec.cross(e1);
    let b2 = ray.direction.dot(qvec) * inv_det;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return None;
    }
    let t = e2.dot(qvec) * inv_det;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let ng = e1.cross(e2).normalize();
    let interpolated = normals[0] * (1.0 - b1 - b2) + normals[1] * b1 + normals[2] * b2;
    let ns = if interpolated.length_squared() > 0.0 {
        let ns = interpolated.normalize();
        if ns.dot(ng) < 0.0 {
            -ns
        } else {
            ns
        }
    } else {
        ng
    };
    Some(PrimitiveHit {
        t,
        geometric_normal: ng,
        shading_normal: ns,
        st: Vec2::new(b1, b2),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_hits_from_outside_and_inside() {
        let s = Primitive::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let outside = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        let h = s.intersect(&outside, 0.0, f32::INFINITY).unwrap();
        assert!((h.t - 4.0).abs() < 1e-5);
        assert!((h.geometric_normal - -Vec3::Z).length() < 1e-5);
        let inside = Ray::new(Vec3::ZERO, Vec3::X);
        assert!((s.intersect(&inside, 0.0, f32::INFINITY).unwrap().t - 1.0).abs() < 1e-5);
        assert!(s.intersect(&outside, 0.0, 3.0).is_none());
    }

    #[test]
    fn parallelogram_and_triangle_bounds_of_hit() {
        let q = Primitive::Parallelogram {
            corner: Vec3::new(-1.0, 0.0, -1.0),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 2.0),
        };
        let down = Ray::new(Vec3::new(0.5, 3.0, 0.5), -Vec3::Y);
        assert!((q.intersect(&down, 0.0, f32::INFINITY).unwrap().t - 3.0).abs() < 1e-5);
        let off = Ray::new(Vec3::new(1.5, 3.0, 0.5), -Vec3::Y);
        assert!(q.intersect(&off, 0.0, f32::INFINITY).is_none());
        assert!((q.area() - 4.0).abs() < 1e-6);

        let t = Primitive::Triangle {
            p: [Vec3::ZERO, Vec3::X, Vec3::Z],
            n: [Vec3::ZERO; 3],
        };
        let hit = t
            .intersect(
                &Ray::new(Vec3::new(0.2, 1.0, 0.2), -Vec3::Y),
                0.0,
                f32::INFINITY,
            )
            .unwrap();
        assert!((hit.t - 1.0).abs() < 1e-6);
        assert!(t
            .intersect(
                &Ray::new(Vec3::new(0.8, 1.0, 0.8), -Vec3::Y),
                0.0,
                f32::INFINITY
            )
            .is_none());
        assert!((t.area() - 0.5).abs() < 1e-6);
    }

    #[test]
    fn disk_hits_inside_its_radius_with_polar_parameters() {
        let d = Primitive::Disk {
            center: Vec3::new(1.0, 2.0, 0.0),
            normal: Vec3::Z,
            u_axis: Vec3::X,
            radius: 2.0,
        };
        let down = Ray::new(Vec3::new(1.0, 3.0, 4.0), -Vec3::Z);
        let h = d.intersect(&down, 0.0, f32::INFINITY).unwrap();
        assert!((h.t - 4.0).abs() < 1e-6);
        assert!((h.geometric_normal - Vec3::Z).length() < 1e-6);
        // (0, 1) from the centre: r = 1/2 of the radius, φ = 90° = a quarter turn.
        assert!((h.st - Vec2::new(0.5, 0.25)).length() < 1e-6, "{:?}", h.st);
        // Inside the bounding square but outside the circle.
        let corner = Ray::new(Vec3::new(2.6, 3.6, 4.0), -Vec3::Z);
        assert!(d.intersect(&corner, 0.0, f32::INFINITY).is_none());
        assert!((d.area() - 4.0 * std::f32::consts::PI).abs() < 1e-5);
        let b = d.bounds();
        assert!((b.min - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6);
        assert!((b.max - Vec3::new(3.0, 4.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn area_samples_lie_on_the_surface() {
        let mut s = crate::sampling::Sampler::from_seed(5);
        let sphere = Primitive::Sphere {
            center: Vec3::ONE,
            radius: 2.0,
        };
        for _ in 0..100 {
            let a = sphere.sample_area(s.next_2d());
            assert!(((a.p - Vec3::ONE).length() - 2.0).abs() < 1e-4);
        }
        let normal = Vec3::new(1.0, 1.0, 0.0).normalize();
        let disk = Primitive::Disk {
            center: Vec3::ONE,
            normal,
            u_axis: Vec3::Z,
            radius: 2.0,
        };
        for _ in 0..100 {
            let a = disk.sample_area(s.next_2d());
            let d = a.p - Vec3::ONE;
            assert!(d.dot(normal).abs() < 1e-5 && d.length() <= 2.0 + 1e-5);
            assert!((d.length() / 2.0 - a.st.x).abs() < 1e-5);
        }
    }
}
