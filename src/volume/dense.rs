//! Building a [`FloatGrid`] from a dense array in code: procedural volumes
//! for tests and benchmarks, with the same sparse layout a VDB file gives.

use glam::IVec3;

use super::grid::{FloatGrid, GridBuilder, LEAF_VOXELS};
use super::transform::GridTransform;

impl FloatGrid {
    /// A grid holding `values` on the index box `[origin, origin + dims)`, every voxel
    /// active, background 0 elsewhere.
    ///
    /// `values[x + dims.x·(y + dims.y·z)]` is the voxel `origin + (x, y, z)` (x varies
    /// fastest). Returns `None` when a dimension is not positive or `values` has the
    /// wrong length.
    pub fn from_dense(
        name: &str,
        origin: IVec3,
        dims: IVec3,
        values: &[f32],
        transform: GridTransform,
    ) -> Option<FloatGrid> {
        FloatGrid::from_dense_over(name, origin, dims, values, 0.0, transform)
    }

    /// [`FloatGrid::from_dense`] over `background`: the value outside the box,
    /// held (inactive) by the leaf voxels beyond it too, as OpenVDB stores them.
    pub fn from_dense_over(
        name: &str,
        origin: IVec3,
        dims: IVec3,
        values: &[f32],
        background: f32,
        transform: GridTransform,
    ) -> Option<FloatGrid> {
        if dims.min_element() <= 0 {
            return None;
        }
        let count = dims.x as usize * dims.y as usize * dims.z as usize;
        if values.len() != count {
            return None;
        }
        let hi = origin + dims - IVec3::ONE;
        // Leaves are aligned to multiples of 8, as in an OpenVDB tree.
        let (leaf_lo, leaf_hi) = (origin >> 3i32, hi >> 3i32);
        let mut builder = GridBuilder::default();
        for lx in leaf_lo.x..=leaf_hi.x {
            for ly in leaf_lo.y..=leaf_hi.y {
                for lz in leaf_lo.z..=leaf_hi.z {
                    let leaf_origin = IVec3::new(lx, ly, lz) << 3i32;
                    let mut mask = [0u64; 8];
                    let mut leaf = [background; LEAF_VOXELS];
                    for n in 0..LEAF_VOXELS {
                        let local =
                            IVec3::new((n >> 6) as i32, ((n >> 3) & 7) as i32, (n & 7) as i32);
                        let d = leaf_origin + local - origin;
                        if d.cmpge(IVec3::ZERO).all() && d.cmplt(dims).all() {
                            let index = d.x as usize
                                + dims.x as usize * (d.y as usize + dims.y as usize * d.z as usize);
                            leaf[n] = values[index];
                            mask[n >> 6] |= 1 << (n & 63);
                        }
                    }
                    builder.leaf_origins.push(leaf_origin);
                    builder.leaf_masks.push(mask);
                    builder.leaf_values.extend_from_slice(&leaf);
                }
            }
        }
        builder.finish(name, background, transform).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    #[test]
    fn dense_grid_lookups_match_the_array() {
        let dims = IVec3::new(5, 3, 9);
        let origin = IVec3::new(-3, 6, 2);
        let values: Vec<f32> = (0..dims.x * dims.y * dims.z).map(|i| i as f32).collect();
        let t = GridTransform::scale_translate("ScaleMap", DVec3::splat(0.5), DVec3::ZERO).unwrap();
        let g = FloatGrid::from_dense("d", origin, dims, &values, t).unwrap();
        assert_eq!(
            g.index_bbox_active(),
            Some((origin, origin + dims - IVec3::ONE))
        );
        assert_eq!(g.active_voxel_count(), values.len() as u64);
        assert_eq!(
            g.value(origin + IVec3::new(1, 2, 3)),
            (1 + 5 * (2 + 3 * 3)) as f32
        );
        assert_eq!(g.value(origin - IVec3::ONE), 0.0);
        let p = origin.as_vec3() + Vec3::new(1.5, 0.0, 0.0);
        assert_eq!(g.trilinear_index(p), 1.5);
    }
}
