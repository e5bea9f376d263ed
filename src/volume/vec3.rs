//! brume's sparse vector grid: a `vec3s` (or `vec3d`) VDB grid held as three
//! component [`FloatGrid`]s that share one topology, so each component keeps
//! the float grid's storage, statistics and BoxSampler lookup. Velocity
//! grids (`vel`, `v`, as Houdini and Blender write them) load this way.

use glam::{DVec3, IVec3, Vec3};

use super::grid::FloatGrid;
use super::transform::GridTransform;

/// A sparse grid of 3-vectors, one float grid per component.
#[derive(Debug, Clone)]
pub struct Vec3Grid {
    name: String,
    components: [FloatGrid; 3],
}

impl Vec3Grid {
    /// A vector grid from its x, y and z component grids (same transform and topology).
    ///
    /// Returns `None` when the components disagree on transform or active voxels.
    pub fn from_components(name: &str, components: [FloatGrid; 3]) -> Option<Vec3Grid> {
        let [x, y, z] = &components;
        let same = |g: &FloatGrid| {
            g.transform() == x.transform()
                && g.active_voxel_count() == x.active_voxel_count()
                && g.index_bbox_active() == x.index_bbox_active()
        };
        (same(y) && same(z)).then(|| Vec3Grid {
            name: name.to_string(),
            components,
        })
    }

    /// The grid's name in the file.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Component grid `axis` (0 = x, 1 = y, 2 = z).
    pub fn component(&self, axis: usize) -> &FloatGrid {
        &self.components[axis]
    }

    /// The index↔world transform.
    pub fn transform(&self) -> &GridTransform {
        self.components[0].transform()
    }

    /// The background vector.
    pub fn background(&self) -> Vec3 {
        Vec3::from_array(self.components.each_ref().map(FloatGrid::background))
    }

    /// Active voxels (a voxel is active in all components at once).
    pub fn active_voxel_count(&self) -> u64 {
        self.components[0].active_voxel_count()
    }

    /// Number of 8³ leaf bricks.
    pub fn leaf_count(&self) -> usize {
        self.components[0].leaf_count()
    }

    /// Number of active tiles.
    pub fn active_tile_count(&self) -> usize {
        self.components[0].active_tile_count()
    }

    /// Inclusive index bounds of the active voxels.
    pub fn index_bbox_active(&self) -> Option<(IVec3, IVec3)> {
        self.components[0].index_bbox_active()
    }

    /// Per-component smallest and largest active values.
    pub fn component_ranges(&self) -> [(f32, f32); 3] {
        self.components.each_ref().map(FloatGrid::value_range)
    }

    /// Per component, the largest |value| any trilinear lookup can return:
    /// over every stored value (active or not), tile and the background.
    ///
    /// A trilinear value is a convex combination of stored voxel values and
    /// the background, so its magnitude cannot exceed this bound.
    pub fn max_abs_lookup(&self) -> Vec3 {
        Vec3::from_array(self.components.each_ref().map(|g| {
            g.blocks()
                .map(|b| b.min_value.abs().max(b.max_value.abs()))
                .fold(g.background().abs(), f32::max)
        }))
    }

    /// The stored vector at a voxel (OpenVDB `getValue`).
    pub fn value(&self, ijk: IVec3) -> Vec3 {
        Vec3::from_array(self.components.each_ref().map(|g| g.value(ijk)))
    }

    /// Whether a voxel is active.
    pub fn is_active(&self, ijk: IVec3) -> bool {
        self.components[0].is_active(ijk)
    }

    /// Trilinear (BoxSampler) interpolation at an index-space point.
    #[inline]
    pub fn trilinear_index(&self, p: Vec3) -> Vec3 {
        Vec3::new(
            self.components[0].trilinear_index(p),
            self.components[1].trilinear_index(p),
            self.components[2].trilinear_index(p),
        )
    }

    /// Trilinear interpolation at a world-space point, in f64 index arithmetic.
    pub fn trilinear_world(&self, p: DVec3) -> Vec3 {
        let q = self.transform().world_to_index(p);
        Vec3::from_array(self.components.each_ref().map(|g| g.trilinear_index_f64(q)))
    }

    /// Bytes of memory the grid holds.
    pub fn memory_bytes(&self) -> usize {
        self.components.iter().map(FloatGrid::memory_bytes).sum()
    }
}
