//! A coarse grid of density bounds over a sparse volume, walked by a 3D DDA.
//!
//! Each cell holds the largest and smallest density that trilinear lookups
//! can return anywhere in the cell: the bounds of the values stored in the
//! voxels its trilinear support holds, taken per voxel in leaf bricks and per
//! block for tiles and uniform leaves, plus the background value when that
//! support is not entirely covered by bricks and tiles.
//!
//! A lookup at p reads voxels ⌊p⌋ and ⌊p⌋ + 1 per axis, and a lookup meant
//! for a cell may land a little outside it (f32 segment ends, the world →
//! index map), so the support of a cell [a, b) is the voxels from
//! ⌊a − r⌋ to ⌊b + r⌋ + 1 with r = [`ROUNDING_REACH`]. With cell faces on
//! voxel centres (integer a) that is the cell widened by one voxel below and
//! by one above (cell + 3 voxels per axis); with faces half-way between
//! voxel centres, as grid media place them, the reach adds no voxel and the
//! support is cell + 2 voxels: per axis 6 instead of 7 for 4-voxel cells, a
//! tighter bound and fewer null collisions. Only the sparse leaves and tiles are read
//! (`FloatGrid::blocks`), never a dense array of the bounding box. A trilinear
//! value is a convex combination of its eight corner voxels, so it lies
//! between these bounds; the bounds are then widened by a relative 2⁻²⁰ to
//! absorb the rounding of the interpolation.

use glam::{BVec3, I64Vec3, IVec3, Vec3, Vec3A};

use crate::volume::{Block, FloatGrid};

mod dilate;

/// Relative widening of the cell bounds, covering rounding in trilinear lookups.
const ROUNDING_PAD: f32 = 1.0 / (1 << 20) as f32;

/// How far (voxels) outside its cell a lookup meant for the cell may land
/// and still be bounded by it (below ½, so that half-voxel-aligned cells
/// need no extra voxel).
pub const ROUNDING_REACH: f32 = 0.375;

/// ⌊a / b⌋ per component (b > 0).
fn div_floor(a: I64Vec3, b: I64Vec3) -> I64Vec3 {
    I64Vec3::new(
        a.x.div_euclid(b.x),
        a.y.div_euclid(b.y),
        a.z.div_euclid(b.z),
    )
}

/// ⌈a / b⌉ per component (b > 0).
fn div_ceil(a: I64Vec3, b: I64Vec3) -> I64Vec3 {
    -div_floor(-a, b)
}

/// Voxels in a box of `size` (0 when empty).
fn volume(size: I64Vec3) -> u128 {
    let s = size.max(I64Vec3::ZERO);
    s.x as u128 * s.y as u128 * s.z as u128
}

/// Bytes per cell a majorant grid holds at its peak: two f32 bounds and a
/// u64 coverage count while it is built (it is dilated in place).
pub const PEAK_BYTES_PER_CELL: u128 = 16;

/// A majorant grid too large to build: cells per axis (`None` when not even
/// that is finite) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct TooLarge {
    /// Cells along each axis.
    pub cells: Option<[u64; 3]>,
    /// Bytes it would hold at its peak.
    pub bytes: Option<u128>,
    /// The limit it is over.
    pub reason: String,
}

impl std::fmt::Display for TooLarge {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match (self.cells, self.bytes) {
            (Some([x, y, z]), Some(b)) => write!(
                f,
                "{x}x{y}x{z} cells ({}), {}",
                crate::error::limits::format_bytes(b),
                self.reason
            ),
            _ => write!(f, "more cells than can be counted, {}", self.reason),
        }
    }
}

/// Cells per axis of the grid [`MajorantGrid::build`] makes over `[lo, hi]`
/// in cells of `cell` voxels, checked before it is allocated: each axis and
/// the total indexable in i32, the bytes within the memory limit.
pub fn check_size(lo: Vec3, hi: Vec3, cell: Vec3) -> Result<IVec3, TooLarge> {
    let dims = ((hi - lo) / cell).ceil().max(Vec3::ONE);
    let finite = dims.is_finite() && dims.max_element() < i32::MAX as f32;
    let Some(cells) = finite.then(|| dims.to_array().map(|d| d as u64)) else {
        return Err(TooLarge {
            cells: None,
            bytes: None,
            reason: "beyond what a majorant grid can index".into(),
        });
    };
    let total = cells.iter().map(|&c| c as u128).product::<u128>();
    let bytes = total * PEAK_BYTES_PER_CELL;
    let too_large = |reason: String| TooLarge {
        cells: Some(cells),
        bytes: Some(bytes),
        reason,
    };
    if total > i32::MAX as u128 {
        return Err(too_large(format!(
            "more than the {} cells a majorant grid can index",
            i32::MAX
        )));
    }
    crate::error::limits::check(bytes).map_err(|refusal| too_large(refusal.to_string()))?;
    Ok(dims.as_ivec3())
}

/// Density bounds over a dense grid of coarse cells in index space.
#[derive(Clone, Debug)]
pub struct MajorantGrid {
    /// Index-space position of the corner of cell (0, 0, 0).
    origin: Vec3,
    /// Cell size in voxels along each axis.
    cell: Vec3,
    /// Number of cells along each axis.
    dims: IVec3,
    /// Largest density per cell (≥ 0).
    max: Vec<f32>,
    /// Smallest density per cell (≥ 0).
    min: Vec<f32>,
}

impl MajorantGrid {
    /// Bounds of `grid`'s (clamped to ≥ 0) density over the index box `[lo, hi]`, in cells of `cell` voxels.
    ///
    /// `cell` holds whole numbers of voxels; equal to the box extent it gives one global bound.
    pub fn build(grid: &FloatGrid, lo: Vec3, hi: Vec3, cell: Vec3) -> MajorantGrid {
        let dims = ((hi - lo) / cell).ceil().as_ivec3().max(IVec3::ONE);
        let n = (dims.x * dims.y * dims.z) as usize;
        let layout = CellLayout::new(lo, cell, dims);
        let mut bounds = CellBounds {
            max: vec![f32::NEG_INFINITY; n],
            min: vec![f32::INFINITY; n],
            covered: vec![0u64; n],
        };
        for block in grid.blocks() {
            let per_voxel = block.size == 8 && block.min_value != block.max_value;
            layout.cover_block(&block, per_voxel, &mut bounds);
            if per_voxel {
                // Leaf bricks vary inside: bound each cell by the voxels its support holds.
                layout.bound_brick_voxels(grid, &block, &mut bounds);
            }
        }
        let (max, min) = bounds.finish(grid.background(), layout.support_volume());
        MajorantGrid {
            origin: lo,
            cell,
            dims,
            max,
            min,
        }
    }

    /// Index-space box the cells cover: `origin` to `origin + dims · cell`.
    pub fn extent(&self) -> (Vec3, Vec3) {
        (self.origin, self.origin + self.dims.as_vec3() * self.cell)
    }

    /// Cell size in voxels along each axis.
    pub fn cell_size(&self) -> Vec3 {
        self.cell
    }

    /// Number of cells along each axis.
    pub fn dims(&self) -> IVec3 {
        self.dims
    }

    /// (min, max) density bound of cell `c`.
    #[inline]
    pub fn bounds(&self, c: IVec3) -> (f32, f32) {
        let i = (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize;
        (self.min[i], self.max[i])
    }

    /// Largest bound over all cells.
    pub fn global_max(&self) -> f32 {
        self.max.iter().copied().fold(0.0, f32::max)
    }

    /// Starts a DDA walk of the index-space ray `o + t·d` over `[t0, t1]` (already clipped to the grid).
    pub fn walk(&self, o: Vec3, d: Vec3, t0: f32, t1: f32) -> Dda {
        // All three axes in SIMD lanes (one walk per free flight and shadow ray).
        let (o, d) = (Vec3A::from(o), Vec3A::from(d));
        let (origin, size) = (Vec3A::from(self.origin), Vec3A::from(self.cell));
        let g = (o + d * t0 - origin) / size;
        let cell = g
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, self.dims - IVec3::ONE);
        let ahead = d.cmpge(Vec3A::ZERO).bitmask();
        let ahead = BVec3::new(ahead & 1 != 0, ahead & 2 != 0, ahead & 4 != 0);
        let step = IVec3::select(ahead, IVec3::ONE, IVec3::NEG_ONE);
        let boundary = cell + IVec3::select(ahead, IVec3::ONE, IVec3::ZERO);
        let plane = origin + boundary.as_vec3a() * size;
        let moving = d.cmpne(Vec3A::ZERO);
        let t_next = Vec3A::select(moving, (plane - o) / d, Vec3A::INFINITY);
        let t_delta = Vec3A::select(moving, size / d.abs(), Vec3A::INFINITY);
        Dda {
            cell,
            step,
            t: t0,
            t_end: t1,
            t_next: t_next.into(),
            t_delta: t_delta.into(),
        }
    }
}

/// State of a 3D DDA (Amanatides & Woo 1987) over the cells of a [`MajorantGrid`].
#[derive(Clone, Copy, Debug)]
pub struct Dda {
    cell: IVec3,
    step: IVec3,
    t: f32,
    t_end: f32,
    t_next: Vec3,
    t_delta: Vec3,
}

impl Dda {
    /// The next cell crossed: `(cell, t0, t1)`, or `None` past the end.
    #[inline]
    pub fn next_cell(&mut self, dims: IVec3) -> Option<(IVec3, f32, f32)> {
        if self.t >= self.t_end {
            return None;
        }
        let axis = if self.t_next.x < self.t_next.y {
            if self.t_next.x < self.t_next.z {
                0
            } else {
                2
            }
        } else if self.t_next.y < self.t_next.z {
            1
        } else {
            2
        };
        let cell = self.cell;
        let t0 = self.t;
        let t1 = self.t_next[axis].min(self.t_end);
        self.t = t1;
        self.cell[axis] += self.step[axis];
        self.t_next[axis] += self.t_delta[axis];
        if self.cell[axis] < 0 || self.cell[axis] >= dims[axis] {
            self.t = self.t_end;
        }
        Some((cell, t0, t1.max(t0)))
    }
}

/// Per-cell density bounds while a majorant grid is built, with the number
/// of voxels of each cell's support that blocks cover.
struct CellBounds {
    max: Vec<f32>,
    min: Vec<f32>,
    covered: Vec<u64>,
}

impl CellBounds {
    /// The final (max, min) per cell: the background where blocks leave part of
    /// a support uncovered, clamped to ≥ 0 and padded against rounding.
    fn finish(mut self, background: f32, support_volume: Option<u64>) -> (Vec<f32>, Vec<f32>) {
        for i in 0..self.max.len() {
            // Bricks and tiles are disjoint: less coverage than the support means background voxels.
            if support_volume.is_none_or(|s| self.covered[i] < s) {
                self.max[i] = self.max[i].max(background);
                self.min[i] = self.min[i].min(background);
            }
            self.max[i] = self.max[i].max(0.0) * (1.0 + ROUNDING_PAD);
            self.min[i] = self.min[i].max(0.0) * (1.0 - ROUNDING_PAD);
        }
        (self.max, self.min)
    }
}

/// Where each cell's voxel support lies, in i64 index arithmetic: a sparse
/// grid may hold voxels at both ends of the i32 range, whose differences
/// overflow i32.
struct CellLayout {
    dims: IVec3,
    cell_i: I64Vec3,
    /// Voxel support of cell c: [first + c·cell, first + c·cell + span) per
    /// axis (module doc), the same span for every cell as cells are whole voxels.
    first: I64Vec3,
    span: I64Vec3,
    last: I64Vec3,
}

impl CellLayout {
    fn new(lo: Vec3, cell: Vec3, dims: IVec3) -> CellLayout {
        let cell_i = cell.ceil().as_i64vec3();
        let first = (lo - ROUNDING_REACH).floor().as_i64vec3();
        let span = (lo + ROUNDING_REACH).floor().as_i64vec3() - first + cell_i + I64Vec3::splat(2);
        CellLayout {
            dims,
            cell_i,
            first,
            span,
            last: dims.as_i64vec3() - I64Vec3::ONE,
        }
    }

    /// Voxels in one cell's support; `None` beyond u64 (cells of millions of
    /// voxels): never known covered.
    fn support_volume(&self) -> Option<u64> {
        u64::try_from(volume(self.span)).ok()
    }

    fn index(&self, x: i64, y: i64, z: i64) -> usize {
        (x + self.dims.x as i64 * (y + self.dims.y as i64 * z)) as usize
    }

    /// Adds `block`'s voxel count to every cell whose support meets it, and
    /// (unless its voxels are bounded one by one) its value range.
    fn cover_block(&self, block: &Block, per_voxel: bool, bounds: &mut CellBounds) {
        let b_lo = block.min.as_i64vec3();
        let b_hi = b_lo + I64Vec3::splat(block.size as i64 - 1);
        let c_lo =
            div_floor(b_lo - self.first - self.span + I64Vec3::ONE, self.cell_i).max(I64Vec3::ZERO);
        let c_hi = div_floor(b_hi - self.first, self.cell_i).min(self.last);
        for z in c_lo.z..=c_hi.z {
            for y in c_lo.y..=c_hi.y {
                for x in c_lo.x..=c_hi.x {
                    let s_lo = self.first + I64Vec3::new(x, y, z) * self.cell_i;
                    let s_hi = s_lo + self.span - I64Vec3::ONE;
                    let overlap = volume(s_hi.min(b_hi) - s_lo.max(b_lo) + I64Vec3::ONE);
                    if overlap == 0 {
                        continue;
                    }
                    let i = self.index(x, y, z);
                    if !per_voxel {
                        bounds.max[i] = bounds.max[i].max(block.max_value);
                        bounds.min[i] = bounds.min[i].min(block.min_value);
                    }
                    bounds.covered[i] =
                        bounds.covered[i].saturating_add(overlap.min(u64::MAX as u128) as u64);
                }
            }
        }
    }

    /// Bounds every cell by each voxel of the 8³ brick `block` its support holds.
    fn bound_brick_voxels(&self, grid: &FloatGrid, block: &Block, bounds: &mut CellBounds) {
        let b_lo = block.min.as_i64vec3();
        for v in 0..512 {
            let local = IVec3::new(v >> 6, (v >> 3) & 7, v & 7);
            let value = grid.value(block.min + local);
            let rel = b_lo + local.as_i64vec3() - self.first;
            let c0 = div_ceil(rel - self.span + I64Vec3::ONE, self.cell_i).max(I64Vec3::ZERO);
            let c1 = div_floor(rel, self.cell_i).min(self.last);
            for z in c0.z..=c1.z {
                for y in c0.y..=c1.y {
                    for x in c0.x..=c1.x {
                        let i = self.index(x, y, z);
                        bounds.max[i] = bounds.max[i].max(value);
                        bounds.min[i] = bounds.min[i].min(value);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::GridTransform;
    use glam::DVec3;

    fn hash(i: u64) -> f32 {
        let z = crate::sampling::mix64(i);
        (z >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A noisy grid with an unaligned, negative origin and some negative values.
    fn noisy_grid() -> FloatGrid {
        let dims = IVec3::new(37, 20, 29);
        let n = (dims.x * dims.y * dims.z) as u64;
        let values: Vec<f32> = (0..n).map(|i| 3.0 * hash(i) - 0.5).collect();
        let t = GridTransform::scale_translate("ScaleMap", DVec3::ONE, DVec3::ZERO).unwrap();
        FloatGrid::from_dense("noise", IVec3::new(-5, 3, -11), dims, &values, t).unwrap()
    }

    /// Every trilinear value in a cell lies within the cell's bounds.
    #[test]
    fn cell_bounds_hold_for_trilinear_lookups() {
        let grid = noisy_grid();
        let (lo, hi) = grid.index_bbox_active().unwrap();
        let (lo, hi) = ((lo - IVec3::ONE).as_vec3(), (hi + IVec3::ONE).as_vec3());
        let m = MajorantGrid::build(&grid, lo, hi, Vec3::splat(8.0));
        for i in 0..200_000u64 {
            let u = Vec3::new(hash(3 * i + 7), hash(3 * i + 8), hash(3 * i + 9));
            let p = lo + (hi - lo) * u;
            let c = ((p - lo) / 8.0)
                .floor()
                .as_ivec3()
                .min(m.dims() - IVec3::ONE);
            let (min, max) = m.bounds(c);
            let v = grid.trilinear_index(p).max(0.0);
            assert!(v <= max && v >= min, "{v} outside [{min}, {max}] at {p}");
        }
    }

    /// The cells a segment of `o + t·d` over `[t0, t1]` crosses, checked: the
    /// segments are contiguous from `t0`, each (but for slivers) holds its cell,
    /// every cell lies in the grid; returns the cells and where the last ends.
    fn walk_and_check(m: &MajorantGrid, o: Vec3, d: Vec3, t0: f32, t1: f32) -> (Vec<IVec3>, f32) {
        let (lo, _) = m.extent();
        let mut dda = m.walk(o, d, t0, t1);
        let (mut t, mut cells) = (t0, Vec::new());
        while let Some((c, a, b)) = dda.next_cell(m.dims()) {
            assert!((a - t).abs() < 1e-4 && b >= a, "[{a}, {b}] after {t}");
            assert!(c.cmpge(IVec3::ZERO).all() && c.cmplt(m.dims()).all(), "{c}");
            if b - a > 1e-3 {
                let mid = (o + d * (0.5 * (a + b)) - lo) / m.cell_size();
                assert_eq!(mid.floor().as_ivec3(), c, "[{a}, {b}] from {o} along {d}");
            }
            cells.push(c);
            t = b;
        }
        (cells, t)
    }

    /// A grid away from the index origin, whose box is not a whole number of
    /// cells: its extent is whole cells from the box's corner, its global bound
    /// the largest cell bound, and walks that start anywhere in it (on its far
    /// faces too, as a ray entering from above does) start in the cell of their
    /// first point and end where they leave the grid, from t = 0 or from a
    /// later start of a ray that begins outside.
    #[test]
    fn walks_start_in_the_cell_of_their_first_point() {
        let (lo, hi) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(20.0, 10.0, 30.0));
        let m = MajorantGrid::build(&noisy_grid(), lo, hi, Vec3::splat(8.0));
        assert_eq!(m.dims(), IVec3::new(3, 1, 4));
        assert_eq!(m.extent(), (lo, Vec3::new(25.0, 10.0, 35.0)));
        let mut largest = 0.0f32;
        for x in 0..3 {
            for z in 0..4 {
                largest = largest.max(m.bounds(IVec3::new(x, 0, z)).1);
            }
        }
        assert!(largest > 2.0 && m.global_max() == largest);
        let (_, top) = m.extent();
        for i in 0..200u64 {
            let u = Vec3::new(hash(6 * i), hash(6 * i + 1), hash(6 * i + 2));
            let o = lo + (top - lo) * u;
            let v = Vec3::new(hash(6 * i + 3), hash(6 * i + 4), hash(6 * i + 5));
            let d = (2.0 * v - 1.0).normalize();
            // where the ray leaves the box (slabs), from t = 0 inside it
            let exit = (Vec3::select(d.cmpgt(Vec3::ZERO), top, lo) - o) / d;
            let t1 = exit.min_element();
            let (_, end) = walk_and_check(&m, o, d, 0.0, t1);
            assert!((end - t1).abs() < 1e-3, "ends at {end}, not {t1}");
            // The same walk from a ray starting s behind (a ray entering the grid from outside).
            let s = 3.0 + 10.0 * hash(1_000_000 + i);
            let (_, end) = walk_and_check(&m, o - d * s, d, s, s + t1);
            assert!((end - s - t1).abs() < 1e-3, "ends at {end}, not {}", s + t1);
        }
        // entering through the far faces, going down each axis in turn; asked to
        // go on past the grid, a walk stops where it leaves the grid
        for a in 0..3 {
            let mut o = 0.5 * (lo + top);
            o[a] = top[a];
            let mut d = Vec3::ZERO;
            d[a] = -1.0;
            let (cells, end) = walk_and_check(&m, o, d, 0.0, top[a] - lo[a] + 20.0);
            assert_eq!(cells[0][a], m.dims()[a] - 1, "axis {a}");
            assert_eq!(cells.len() as i32, m.dims()[a], "axis {a}");
            assert_eq!(end, top[a] - lo[a], "axis {a}");
        }
    }

    /// DDA segments are contiguous, cover the interval and hold their cell.
    #[test]
    fn dda_segments_tile_the_ray() {
        let m = MajorantGrid::build(
            &noisy_grid(),
            Vec3::ZERO,
            Vec3::splat(40.0),
            Vec3::splat(8.0),
        );
        let o = Vec3::new(-3.0, 1.5, 2.5);
        let d = Vec3::new(0.9, 0.35, 0.2);
        let (t0, t1) = (3.5, 45.0);
        let (_, t) = walk_and_check(&m, o, d, t0, t1);
        assert!((t - t1).abs() < 1e-3 || t < t1 && (o + d * t).max_element() >= 40.0 - 1e-3);
    }
}
