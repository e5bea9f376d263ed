//! The majorant grid of a grid medium: the cell size, and the grid over the
//! medium's box (dilated over the shutter when it moves), checked against the
//! memory limit before it is allocated.

use glam::{IVec3, Mat4};

use super::super::majorant_grid::{check_size, MajorantGrid, TooLarge};
use super::super::motion::{self, GridMotion, MotionLookup};
use super::{GridMediumParams, MajorantMode};
use crate::math::{Affine3A, Vec3};
use crate::volume::FloatGrid;

/// Majorant cell size in voxels: about 32 cells along the longest axis, kept within 4..=32.
///
/// On the B3 smoke (73 voxels wide) 4-voxel cells (6 once widened by the trilinear
/// support) cut the null-collision fraction from 0.52 (8-voxel cells) to 0.41 and
/// the tentative collisions by a fifth, for about as many instructions per sample:
/// the DDA steps the smaller cells add cost what the saved lookups did.
pub fn default_cell_size(extent: IVec3) -> i32 {
    (extent.max_element().saturating_add(31) / 32).clamp(4, 32)
}

/// Most null collisions a ray should expect crossing one majorant cell whose
/// bound is the volume's maximum: past it the cells shrink (see `dense_cell_size`).
const MAX_CELL_OPTICAL_DEPTH: f32 = 8.0;

/// Most optical depth one majorant cell should span at the volume's peak
/// extinction where dense cells are walked exactly (grey, still media).
///
/// Finer cells bound σ̄ closer to the density a ray meets, so fewer of its
/// tentative collisions are null, at the cost of more DDA steps. Render
/// time at 64 spp against cell size (2, 3, 4, 6, 8 voxels; BENCHMARKS.md,
/// "Majorant cells for dense media"): the dense cloud (peak 1.6 per voxel)
/// 1.33, 1.35, 1.40, 1.43, 1.52 s; the smoke at 3× its bench density (1.25)
/// 1.32, 1.38, 1.43, 1.50, 1.60 s; the bench smoke itself (0.42) 0.79,
/// 0.79, 0.80, 0.82, 0.85 s: a cell should span at most about 3 at the
/// peak, and never less than 2 voxels (the trilinear support widens every
/// cell by one).
const DENSE_CELL_OPTICAL_DEPTH: f32 = 3.0;

/// Fewest voxels a cell chosen by [`DENSE_CELL_OPTICAL_DEPTH`] spans.
const MIN_DENSE_CELL: i32 = 2;

/// The cell size (voxels) over which the peak extinction `peak_per_voxel`
/// spans at most [`DENSE_CELL_OPTICAL_DEPTH`], at least [`MIN_DENSE_CELL`].
fn exact_walk_cell_size(peak_per_voxel: f32) -> i32 {
    cells_spanning(DENSE_CELL_OPTICAL_DEPTH, peak_per_voxel).max(MIN_DENSE_CELL)
}

/// The most whole voxels over which `peak_per_voxel` adds up to at most
/// `depth` (at most 10⁶; `i32::MAX` where the volume has no extinction).
fn cells_spanning(depth: f32, peak_per_voxel: f32) -> i32 {
    if peak_per_voxel > 0.0 {
        (depth / peak_per_voxel).floor().min(1e6) as i32
    } else {
        i32::MAX
    }
}

/// Most cells a majorant grid may hold (two f32 bounds each, 32 MB).
const MAX_MAJORANT_CELLS: f32 = (1 << 22) as f32;

/// The largest cell size (voxels) over which the volume's peak extinction
/// gives at most `MAX_CELL_OPTICAL_DEPTH` null collisions, within the memory
/// limit of `MAX_MAJORANT_CELLS`.
///
/// Tracking costs σ̄·d steps; a dense volume (`density_scale = 1e6`) over
/// 8-voxel cells would spend ~10⁵ null collisions crossing one mostly empty
/// cell at its edge. Finer cells bound σ̄ near the density itself.
fn dense_cell_size(peak_per_voxel: f32, extent: IVec3) -> i32 {
    let by_depth = cells_spanning(MAX_CELL_OPTICAL_DEPTH, peak_per_voxel);
    let volume = extent.as_vec3().element_product();
    let by_memory = (volume / MAX_MAJORANT_CELLS).cbrt().ceil() as i32;
    by_depth.max(by_memory).max(1)
}

/// World length of one voxel step (the longest axis of index → world after `to_world`).
fn voxel_world_length(grid: &FloatGrid, to_world: &Affine3A) -> f32 {
    let m = Mat4::from(*to_world).as_dmat4() * grid.transform().index_to_world_matrix();
    (0..3)
        .map(|i| m.col(i).truncate().length())
        .fold(0.0, f64::max) as f32
}

/// Majorant cell size in voxels for a grid over the index box `[lo, hi]`.
pub(super) fn choose_cell_size(
    density: &FloatGrid,
    params: &GridMediumParams,
    moving: bool,
    lo: Vec3,
    hi: Vec3,
) -> Vec3 {
    let extent = (hi - lo).as_ivec3().max(IVec3::ONE);
    let peak = density.value_range().1.max(density.background()).max(0.0)
        * (params.sigma_t_scale * params.density_scale).max_channel()
        * voxel_world_length(density, &params.to_world);
    // Dense cells are walked voxel by voxel (`ExactVoxels`) where the medium
    // allows it; only media that always take null collisions need cells
    // shrunk to their density.
    let exact_walks =
        !moving && params.sigma_t_scale.min_channel() == params.sigma_t_scale.max_channel();
    match params.majorant {
        MajorantMode::Grid => Vec3::splat(
            params
                .cell_size
                .unwrap_or_else(|| {
                    let cell = match exact_walks {
                        true => default_cell_size(extent).min(exact_walk_cell_size(peak)),
                        false => default_cell_size(extent).min(dense_cell_size(peak, extent)),
                    };
                    cell.max(memory_cell_size(hi - lo))
                })
                .max(1) as f32,
        ),
        MajorantMode::Global => extent.as_vec3(),
    }
}

/// A grid medium whose majorant grid would be too large to build.
#[derive(Clone, Debug, PartialEq)]
pub struct MajorantTooLarge {
    /// How far (density index voxels per axis) the motion displaces the
    /// medium over the shutter; `None` for a still medium.
    pub motion_radius: Option<Vec3>,
    /// The grid it would need.
    pub grid: TooLarge,
}

/// The smallest cell size (voxels) that keeps a default majorant grid over
/// the index box of `size` voxels within 2²² cells: a sparse grid spanning a huge box gets
/// coarser cells, not a grid beyond memory. Grids whose default cells fit
/// (up to 5000 voxels a side and far beyond) keep them.
fn memory_cell_size(size: Vec3) -> i32 {
    // The grid box is the size plus half a voxel each side (i64: a sparse
    // grid can span more than i32 holds).
    let sides = size.as_i64vec3().max(glam::I64Vec3::ZERO) + glam::I64Vec3::ONE;
    let cells = |c: i64| {
        let d = (sides + glam::I64Vec3::splat(c - 1)) / c;
        d.x as u128 * d.y as u128 * d.z as u128
    };
    // Fewer cells as c grows: the smallest c that fits, by bisection.
    let (mut lo, mut hi) = (1, sides.max_element());
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if cells(mid) <= MAX_MAJORANT_CELLS as u128 {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo.min(i32::MAX as i64) as i32
}

/// A built majorant grid with what tracking needs beside it.
pub(super) struct Majorants {
    /// The motion's lookups; `None` for a still medium.
    pub motion: Option<MotionLookup>,
    /// The grid, dilated over the shutter for a moving medium.
    pub grid: MajorantGrid,
    /// The index box tracking must cover (grown by the dilation).
    pub track: (Vec3, Vec3),
}

/// The majorant grid over the index box `[lo, hi]` of `density` in cells of
/// `cell` voxels, dilated over the shutter by `motion`; with the motion's
/// lookups and the box tracking must cover. Refused before allocating when
/// over the memory limit.
pub(super) fn build_majorants(
    density: &FloatGrid,
    motion: Option<&GridMotion>,
    (params, world_to_index): (&GridMediumParams, &Affine3A),
    (lo, hi): (Vec3, Vec3),
    cell: Vec3,
) -> Result<Majorants, MajorantTooLarge> {
    // Cell faces half-way between voxel centres: the trilinear support of a
    // cell is then cell + 2 voxels per axis, not cell + 3 (majorant_grid).
    let (grid_lo, grid_hi) = (lo - 0.5, hi + 0.5);
    let Some(m) = motion else {
        let still = |grid| MajorantTooLarge {
            motion_radius: None,
            grid,
        };
        check_size(grid_lo, grid_hi, cell).map_err(still)?;
        let grid = MajorantGrid::build(density, grid_lo, grid_hi, cell);
        return Ok(Majorants {
            motion: None,
            grid,
            track: (lo, hi),
        });
    };
    let (lookup, r) = MotionLookup::new(m, &params.to_world, world_to_index);
    let moving = |grid| MajorantTooLarge {
        motion_radius: Some(r),
        grid,
    };
    let k = motion::dilation_cells(r, cell).ok_or_else(|| {
        moving(TooLarge {
            cells: None,
            bytes: None,
            reason: "beyond what a majorant grid can index".into(),
        })
    })?;
    let pad = k.as_vec3() * cell;
    check_size(grid_lo - pad, grid_hi + pad, cell).map_err(moving)?;
    let (grid, pad) = motion::dilated_majorants(density, grid_lo, grid_hi, cell, k);
    Ok(Majorants {
        motion: Some(lookup),
        grid,
        track: (lo - pad, hi + pad),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::GridTransform;

    /// About 32 cells along the longest axis, kept within 4..=32 voxels a cell.
    #[test]
    fn default_cells_span_a_thirty_second_of_the_volume() {
        for (extent, cell) in [(73, 4), (200, 7), (640, 20), (1000, 32), (4000, 32), (8, 4)] {
            assert_eq!(
                default_cell_size(IVec3::new(extent, 5, extent / 2)),
                cell,
                "{extent}"
            );
        }
    }

    /// Dense media get cells of at most 8 expected null collisions at the
    /// peak extinction, unless that would exceed the memory budget of 2²² cells.
    #[test]
    fn dense_cells_follow_the_peak_within_the_memory_budget() {
        assert_eq!(dense_cell_size(2.0, IVec3::splat(100)), 4);
        assert_eq!(dense_cell_size(0.0, IVec3::splat(100)), i32::MAX);
        assert_eq!(dense_cell_size(100.0, IVec3::splat(100)), 1);
        // 4096³ voxels in at most 2²² cells: cells of at least ∛16384 ≈ 25.4 voxels.
        assert_eq!(dense_cell_size(100.0, IVec3::splat(4096)), 26);
    }

    /// A voxel step's world length is the file's voxel size times the scene's
    /// scale, along the axis the placement stretches most.
    #[test]
    fn voxel_world_length_is_the_longest_placed_voxel_edge() {
        let t = GridTransform::scale_translate(
            "UniformScaleMap",
            glam::DVec3::splat(0.05),
            glam::DVec3::ZERO,
        )
        .expect("transform");
        let grid =
            FloatGrid::from_dense("density", IVec3::ZERO, IVec3::new(2, 1, 1), &[1.0, 2.0], t)
                .expect("grid");
        let cases = [
            (Affine3A::IDENTITY, 0.05),
            (Affine3A::from_scale(Vec3::splat(2.0)), 0.1),
            (Affine3A::from_scale(Vec3::new(1.0, 3.0, 0.5)), 0.15),
        ];
        for (to_world, expected) in cases {
            let length = voxel_world_length(&grid, &to_world);
            assert!((length - expected).abs() < 1e-6, "{length} != {expected}");
        }
    }
}
