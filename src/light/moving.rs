//! Area lights on shapes moved by keyframes, sampled at the path's time.
//!
//! Such a light keeps its primitives (and its sphere, if it is one) in the
//! shape's local frame. At time t the shape is placed by a similarity
//! x ↦ T + R·(s·x) (emissive moving shapes must scale uniformly; the scene
//! refuses others). A similarity maps solid angles seen from p onto solid
//! angles seen from its local image p' = K(t)⁻¹p unchanged, scales
//! distances by s and turns directions by R. So the light is sampled from
//! p' by its still sampler, and the sample's direction is turned by R and
//! its distance scaled by s; its solid-angle pdf and radiance carry over.
//! The pdf of a hit (for MIS) is the still pdf of the hit's local image
//! seen from p'. Sampling and hit see the shape at the same time t (the
//! path's), which keeps next-event estimation and emission hits one
//! consistent pair of strategies.

use super::{Light, LightSample};
use crate::geometry::MovingShape;
use crate::math::{Vec2, Vec3};

/// A sample of moving `light` (on `shape`) from world point `p` at `time`.
pub(super) fn sample(
    light: &Light,
    shape: &MovingShape,
    p: Vec3,
    u: Vec2,
    time: f32,
) -> Option<LightSample> {
    let m = shape.placement(time);
    let local = light.sample_area(m.point_to_local(p), u, shape.local())?;
    Some(LightSample {
        wi: (m.rotation * local.wi).normalize(),
        distance: local.distance * m.scale.x,
        normal: (m.rotation * local.normal).normalize_or_zero(),
        ..local
    })
}

/// The solid-angle pdf from `p` of the point `hit_p` (normal `n`) of moving `light` at `time`.
pub(super) fn area_pdf(
    light: &Light,
    shape: &MovingShape,
    p: Vec3,
    hit_p: Vec3,
    n: Vec3,
    time: f32,
) -> f32 {
    let m = shape.placement(time);
    light.area_pdf(
        m.point_to_local(p),
        m.point_to_local(hit_p),
        m.rotation.inverse() * n,
    )
}
