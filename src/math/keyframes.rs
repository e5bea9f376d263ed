//! Keyframed (animated) transforms: translate, rotate and scale keyed at
//! times, interpolated per ray time.
//!
//! ```toml
//! transform = { keyframes = [
//!     { time = -0.5, translate = [0.0, 0.0, 0.0] },
//!     { time = 0.5, translate = [1.0, 0.0, 0.0], rotate = [0.0, 30.0, 0.0] },
//! ] }
//! ```
//!
//! Times are in frames relative to the frame's own time, the unit of
//! `camera.shutter`. Between two keys the placement x ↦ T + R·(S·x) is
//! interpolated component-wise: T and S linearly, R by quaternion slerp
//! along the shorter arc (so two keys must be less than 180° apart; add keys
//! in between for a longer turn). Before the first key the first placement
//! holds, after the last the last.
//!
//! # Swept bounds
//!
//! [`Keyframes::swept_bounds`] bounds every placement of a local box over
//! all times. On an interval whose two keys share R, x(u) = T(u) + R·S(u)·p
//! is affine in u for every point p, so each point moves on a segment
//! between its images at the two keys, inside the (convex) union of the two
//! keys' boxes. When R changes, |R(u)·S(u)·p| = |S(u)·p| ≤ max over the box
//! corners c and both keys of |S·c| = ρ (S(u)·p is affine in u and in p, the
//! norm convex), so x(u) lies within ρ of T(u), on the segment T0–T1: the
//! box of that segment widened by ρ holds it. Both are widened by a relative
//! [`BOUNDS_PAD`] for the f32 rounding of the transform.

use super::{Affine3A, Bounds3, Quat, Ray, Vec3};

/// Relative widening of swept bounds, for f32 rounding.
const BOUNDS_PAD: f32 = 1e-5;

/// One key: the placement at `time`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key {
    /// Time in frames relative to the frame's time.
    pub time: f32,
    /// Translation.
    pub translate: Vec3,
    /// Rotation (unit quaternion).
    pub rotation: Quat,
    /// Per-axis scale (> 0).
    pub scale: Vec3,
}

/// A placement x ↦ T + R·(S·x) at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Translation T.
    pub translate: Vec3,
    /// Rotation R.
    pub rotation: Quat,
    /// Scale S.
    pub scale: Vec3,
}

impl Placement {
    /// Local → world for a point.
    #[inline]
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.translate + self.rotation * (self.scale * p)
    }

    /// Local → world for a vector.
    #[inline]
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.rotation * (self.scale * v)
    }

    /// World → local for a point.
    #[inline]
    pub fn point_to_local(&self, p: Vec3) -> Vec3 {
        (self.rotation.inverse() * (p - self.translate)) / self.scale
    }

    /// World → local for a vector.
    #[inline]
    pub fn vector_to_local(&self, v: Vec3) -> Vec3 {
        (self.rotation.inverse() * v) / self.scale
    }

    /// A local normal in world space (inverse transpose of R·S), unit length.
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        (self.rotation * (n / self.scale)).normalize()
    }

    /// The world ray in local space at the same parameters: the direction is
    /// mapped, not renormalized, so `local.at(t)` is the local image of `ray.at(t)`.
    #[inline]
    pub fn ray_to_local(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.point_to_local(ray.origin),
            direction: self.vector_to_local(ray.direction),
            time: ray.time,
        }
    }

    /// The same map as an affine matrix.
    pub fn affine(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(self.scale, self.rotation, self.translate)
    }
}

/// One interval between two keys, with its slerp precomputed.
#[derive(Clone, Copy, Debug)]
struct Span {
    t0: f32,
    inv_length: f32,
    a: Key,
    /// `b` with its quaternion on a's side (shorter arc).
    b: Key,
    /// Angle between the two quaternions (0 when the rotation does not change).
    theta: f32,
}

/// Keys in increasing time, at least two of them.
#[derive(Clone, Debug)]
pub struct Keyframes {
    first: Key,
    spans: Vec<Span>,
}

impl Keyframes {
    /// Keyframes from `keys` in strictly increasing time; `None` with fewer than two keys or out of order.
    pub fn new(keys: &[Key]) -> Option<Keyframes> {
        if keys.len() < 2
            || keys
                .windows(2)
                .any(|w| w[0].time.partial_cmp(&w[1].time) != Some(std::cmp::Ordering::Less))
        {
            return None;
        }
        let spans = keys
            .windows(2)
            .map(|w| {
                let (a, mut b) = (w[0], w[1]);
                let mut dot = a.rotation.dot(b.rotation);
                if dot < 0.0 {
                    b.rotation = -b.rotation;
                    dot = -dot;
                }
                let theta = if a.rotation == b.rotation {
                    0.0
                } else {
                    dot.min(1.0).acos()
                };
                Span {
                    t0: a.time,
                    inv_length: 1.0 / (b.time - a.time),
                    a,
                    b,
                    theta,
                }
            })
            .collect();
        Some(Keyframes {
            first: keys[0],
            spans,
        })
    }

    /// Time of the first and of the last key.
    pub fn time_range(&self) -> (f32, f32) {
        (self.first.time, self.spans[self.spans.len() - 1].b.time)
    }

    /// The placement at `time` (held before the first key and after the last).
    #[inline]
    pub fn at(&self, time: f32) -> Placement {
        let span = match self.spans.iter().position(|s| time < s.b.time) {
            Some(i) => &self.spans[i],
            None => {
                let last = self.spans[self.spans.len() - 1].b;
                return placement(&last);
            }
        };
        let u = (time - span.t0) * span.inv_length;
        if u <= 0.0 {
            return placement(&span.a);
        }
        let (a, b) = (&span.a, &span.b);
        Placement {
            translate: a.translate + (b.translate - a.translate) * u,
            rotation: slerp(a.rotation, b.rotation, span.theta, u),
            scale: a.scale + (b.scale - a.scale) * u,
        }
    }

    /// A box holding `local` placed at every time (see the module doc).
    pub fn swept_bounds(&self, local: &Bounds3) -> Bounds3 {
        let mut out = Bounds3::EMPTY;
        for s in &self.spans {
            let (pa, pb) = (placement(&s.a), placement(&s.b));
            let span_box = if s.theta == 0.0 {
                local
                    .transformed(&pa.affine())
                    .union(&local.transformed(&pb.affine()))
            } else {
                let rho = corners(local)
                    .into_iter()
                    .map(|c| (s.a.scale * c).length().max((s.b.scale * c).length()))
                    .fold(0.0f32, f32::max);
                let ends = Bounds3::new(s.a.translate, s.b.translate);
                Bounds3 {
                    min: ends.min - Vec3::splat(rho),
                    max: ends.max + Vec3::splat(rho),
                }
            };
            out = out.union(&span_box);
        }
        let pad = Vec3::splat(BOUNDS_PAD * out.min.abs().max(out.max.abs()).max_element());
        Bounds3 {
            min: out.min - pad,
            max: out.max + pad,
        }
    }

    /// True when every key scales all three axes alike.
    pub fn is_uniform_scale(&self) -> bool {
        let uniform = |s: Vec3| s.x == s.y && s.y == s.z;
        uniform(self.first.scale) && self.spans.iter().all(|s| uniform(s.b.scale))
    }
}

fn placement(k: &Key) -> Placement {
    Placement {
        translate: k.translate,
        rotation: k.rotation,
        scale: k.scale,
    }
}

/// Slerp from `a` to `b` (on a's side, `theta` apart) at `u` ∈ [0, 1].
#[inline]
fn slerp(a: Quat, b: Quat, theta: f32, u: f32) -> Quat {
    if theta == 0.0 {
        return a;
    }
    if theta < 1e-3 {
        return a.lerp(b, u).normalize();
    }
    let inv_sin = 1.0 / theta.sin();
    let wa = ((1.0 - u) * theta).sin() * inv_sin;
    let wb = (u * theta).sin() * inv_sin;
    (a * wa + b * wb).normalize()
}

fn corners(b: &Bounds3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(time: f32, translate: Vec3, degrees_y: f32, scale: f32) -> Key {
        Key {
            time,
            translate,
            rotation: Quat::from_rotation_y(degrees_y.to_radians()),
            scale: Vec3::splat(scale),
        }
    }

    #[test]
    fn interpolates_linearly_and_holds_outside_the_keys() {
        let k = Keyframes::new(&[
            key(-1.0, Vec3::ZERO, 0.0, 1.0),
            key(1.0, Vec3::new(2.0, 0.0, 0.0), 90.0, 3.0),
        ])
        .unwrap();
        let mid = k.at(0.0);
        assert!((mid.translate - Vec3::X).length() < 1e-6);
        assert!((mid.scale - Vec3::splat(2.0)).length() < 1e-6);
        let expected = Quat::from_rotation_y(45f32.to_radians());
        assert!(mid.rotation.dot(expected).abs() > 1.0 - 1e-6);
        // A quarter of the way: slerp gives 22.5°, at constant angular speed.
        let q = k.at(-0.5).rotation;
        assert!(q.dot(Quat::from_rotation_y(22.5f32.to_radians())).abs() > 1.0 - 1e-6);
        assert_eq!(k.at(-5.0).translate, Vec3::ZERO);
        assert_eq!(k.at(7.0).translate, Vec3::new(2.0, 0.0, 0.0));
        let p = Vec3::new(0.3, -0.2, 0.7);
        assert!((mid.point_to_local(mid.point_to_world(p)) - p).length() < 1e-5);
        assert!(Keyframes::new(&[key(0.0, Vec3::ZERO, 0.0, 1.0)]).is_none());
        assert!(
            Keyframes::new(&[key(1.0, Vec3::ZERO, 0.0, 1.0), key(1.0, Vec3::X, 0.0, 1.0)])
                .is_none()
        );
    }

    #[test]
    fn swept_bounds_hold_every_placement_of_every_corner() {
        let local = Bounds3::new(Vec3::new(-1.0, -0.5, -0.2), Vec3::new(1.0, 0.5, 2.0));
        let k = Keyframes::new(&[
            key(0.0, Vec3::new(3.0, 0.0, 0.0), 0.0, 1.0),
            key(0.5, Vec3::new(3.0, 1.0, 0.0), 0.0, 2.0),
            key(1.0, Vec3::new(-3.0, 1.0, 5.0), 170.0, 0.5),
        ])
        .unwrap();
        let swept = k.swept_bounds(&local);
        for i in 0..=1000 {
            let p = k.at(i as f32 / 1000.0);
            for c in corners(&local) {
                assert!(swept.contains(p.point_to_world(c)), "{i} {c}");
            }
        }
    }
}
