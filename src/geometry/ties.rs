//! Boxes handed to the BVH builder, padded so that identical primitives do
//! not stall it.

use crate::math::{Bounds3, Vec3};

/// The largest padding of a primitive's box handed to the BVH builder: a
/// 2^-16 of the scene's extent (a conservative box stays correct).
pub(super) fn tie_breaking_pad(scene: &Bounds3) -> f32 {
    let extent = (scene.max - scene.min).max_element();
    if extent.is_finite() {
        extent * (1.0 / 65536.0)
    } else {
        0.0
    }
}

/// `b` grown by a different fraction of `pad` for each index `k`. The PLOC
/// builder pairs a node with a neighbour only when their merged box is
/// strictly smaller than the other neighbour's: among many identical boxes
/// (a mesh whose faces repeat) it then merges one pair per pass, quadratic
/// time (60 000 copies of one triangle took minutes to load); distinct sizes
/// make about a third of the nodes pair each pass.
pub(super) fn padded(b: Bounds3, k: usize, pad: f32) -> Bounds3 {
    let mut h = (k as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^= h >> 31;
    let grow = pad * (0.5 + 0.5 * (h >> 40) as f32 / (1u64 << 24) as f32);
    Bounds3 {
        min: b.min - Vec3::splat(grow),
        max: b.max + Vec3::splat(grow),
    }
}
