//! Looking a ray up in a baked slab: the `type = "slab"` shape.

use super::format::LightSlab;
use super::param::GridPoint;
use crate::math::color::Rgb;
use crate::math::{Affine3A, Bounds3, Ray};
use std::sync::Arc;

/// How a line between the recorded ones is answered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// Quadrilinear interpolation in (u, v, s, t) between the 16 nearest records.
    #[default]
    Quadrilinear,
    /// The nearest record (for comparison).
    Nearest,
}

/// A baked slab placed in a scene.
#[derive(Debug)]
pub struct SlabShape {
    /// Index of the scene shape.
    pub shape: u32,
    /// World to the baking scene's space (the inverse of the shape's transform).
    to_local: Affine3A,
    /// The slab's box in world space (bounds of the placed box).
    world_bounds: Bounds3,
    slab: Arc<LightSlab>,
    filter: Filter,
}

/// What a ray meets at a slab: where it enters and leaves the box, and
/// the recorded light and transmittance of its line.
#[derive(Clone, Copy, Debug)]
pub struct SlabCrossing {
    /// Ray parameter where it enters the box.
    pub t_enter: f32,
    /// Ray parameter where it leaves.
    pub t_exit: f32,
    /// Radiance leaving the box toward the ray's origin, from what is inside it.
    pub radiance: Rgb,
    /// Transmittance across the box along the ray.
    pub transmittance: Rgb,
}

impl SlabShape {
    /// Shape `shape`: `slab` placed by `to_world`, looked up with `filter`.
    pub fn new(shape: u32, slab: Arc<LightSlab>, to_world: Affine3A, filter: Filter) -> SlabShape {
        SlabShape {
            shape,
            to_local: to_world.inverse(),
            world_bounds: slab.header().bounds.transformed(&to_world),
            slab,
            filter,
        }
    }

    /// World-space bounds of the placed box.
    pub fn bounds(&self) -> Bounds3 {
        self.world_bounds
    }

    /// True when `p` (world space) is inside the placed box.
    pub fn contains(&self, p: crate::math::Vec3) -> bool {
        self.slab
            .header()
            .bounds
            .contains(self.to_local.transform_point3(p))
    }

    /// The crossing of `ray` with the box if it enters it (from outside)
    /// before `t_max`; a ray starting inside or on the box is not answered.
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_max: f32) -> Option<SlabCrossing> {
        let o = self.to_local.transform_point3(ray.origin);
        // Not normalised: ray parameters stay the world's.
        let d = self.to_local.transform_vector3(ray.direction);
        let b = self.slab.header().bounds;
        let inv = d.recip();
        let ta = (b.min - o) * inv;
        let tb = (b.max - o) * inv;
        let t_enter = ta.min(tb).max_element();
        let t_exit = ta.max(tb).min_element();
        if !(t_enter > 0.0 && t_enter < t_exit && t_enter < t_max) {
            return None;
        }
        // Light leaves the box toward the origin: the recorded line runs along -d.
        let (radiance, transmittance) = self.lookup(self.slab.param().locate(o, -d));
        Some(SlabCrossing {
            t_enter,
            t_exit,
            radiance,
            transmittance,
        })
    }

    /// The record at `g`, interpolated or nearest.
    #[inline]
    fn lookup(&self, g: GridPoint) -> (Rgb, Rgb) {
        lookup(&self.slab, g, self.filter)
    }
}

/// Radiance and transmittance of `slab` at grid point `g` by `filter`.
#[inline]
pub fn lookup(slab: &LightSlab, g: GridPoint, filter: Filter) -> (Rgb, Rgb) {
    let p = slab.param();
    let grid = p.grid();
    let n = [grid.spatial, grid.spatial, grid.angular, grid.angular];
    match filter {
        Filter::Nearest => {
            let i = std::array::from_fn(|k| g.x[k].round() as u32);
            slab.record(p.index(g.slab, i))
        }
        Filter::Quadrilinear => {
            // The cell's lower corner (the last cell for a point on the far edge) and offsets.
            let i0: [u32; 4] = std::array::from_fn(|k| (g.x[k] as u32).min(n[k] - 2));
            let f: [f32; 4] = std::array::from_fn(|k| g.x[k] - i0[k] as f32);
            let (mut l, mut t) = (Rgb::BLACK, Rgb::BLACK);
            for corner in 0..16u32 {
                let mut w = 1.0;
                let mut i = i0;
                for k in 0..4 {
                    let up = corner >> k & 1 == 1;
                    w *= if up { f[k] } else { 1.0 - f[k] };
                    i[k] += u32::from(up);
                }
                if w == 0.0 {
                    continue;
                }
                let (rl, rt) = slab.record(p.index(g.slab, i));
                l += rl * w;
                t += rt * w;
            }
            (l, t)
        }
    }
}
