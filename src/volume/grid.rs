//! brume's sparse float grid: 8³ leaf bricks and constant tiles (8³, 128³ and
//! 4096³ voxels a side, the three tile levels of an OpenVDB 5-4-3 tree),
//! found through coordinate hash tables. Storage grows with the leaves and
//! tiles, not with the bounding box; when the bricks fill their bounding box
//! densely enough, a flat table over it (4 bytes per 8³ brick slot) replaces
//! the hash lookup on the hot path.

use glam::{DVec3, IVec3, Vec3};

use super::coord_map::CoordMap;
use super::error::{FResult, FormatError};
use super::transform::GridTransform;

/// Voxels in a leaf brick.
pub(crate) const LEAF_VOXELS: usize = 512;
/// Marks a brick-table entry that is a tile, not a leaf.
const TILE_FLAG: u32 = 1 << 31;
/// A slot of the flat brick table that holds no leaf and no 8³ tile.
const NO_BRICK: u32 = u32::MAX;
/// Largest flat brick table, in slots (64 MiB).
const MAX_DENSE_SLOTS: usize = 1 << 24;

/// A leaf brick or a tile of constant value, for building majorant grids.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Block {
    /// Lowest voxel of the block (inclusive).
    pub min: IVec3,
    /// Voxels per side: 8 (leaf or 8³ tile), 128 or 4096 (larger tiles).
    pub size: i32,
    /// Smallest value stored in the block (active or not).
    pub min_value: f32,
    /// Largest value stored in the block (active or not).
    pub max_value: f32,
}

/// Counts of the values a grid's lookups can return (every leaf value, active
/// or not, every stored tile and the background), by kind.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ValueCensus {
    /// Values counted (leaf voxels, tiles and the background, each once).
    pub stored: u64,
    /// NaN values.
    pub nan: u64,
    /// +∞ values.
    pub pos_inf: u64,
    /// -∞ values.
    pub neg_inf: u64,
    /// Finite values below zero.
    pub negative: u64,
    /// Largest finite value (-∞ if none).
    pub max_finite: f32,
    /// Smallest finite value (+∞ if none).
    pub min_finite: f32,
}

impl ValueCensus {
    /// NaN and infinite values together.
    pub fn nonfinite(&self) -> u64 {
        self.nan + self.pos_inf + self.neg_inf
    }

    fn add(&mut self, v: f32) {
        self.stored += 1;
        if v.is_nan() {
            self.nan += 1;
        } else if v == f32::INFINITY {
            self.pos_inf += 1;
        } else if v == f32::NEG_INFINITY {
            self.neg_inf += 1;
        } else {
            if v < 0.0 {
                self.negative += 1;
            }
            self.max_finite = self.max_finite.max(v);
            self.min_finite = self.min_finite.min(v);
        }
    }
}

/// A constant region of the tree.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tile {
    /// Lowest voxel.
    pub origin: IVec3,
    /// log2 of the side: 3, 7 or 12.
    pub log2: u32,
    /// The value of every voxel in it.
    pub value: f32,
    /// Whether its voxels are active.
    pub active: bool,
}

/// Leaves and tiles gathered while reading a tree.
#[derive(Debug, Default)]
pub(crate) struct GridBuilder {
    /// Leaf origins (multiples of 8).
    pub leaf_origins: Vec<IVec3>,
    /// Leaf active masks, 512 bits each.
    pub leaf_masks: Vec<[u64; 8]>,
    /// 512 values per leaf, x-major (offset = x·64 + y·8 + z).
    pub leaf_values: Vec<f32>,
    /// Tiles whose value a lookup can return: active ones and those that differ from the background.
    pub tiles: Vec<Tile>,
}

/// A sparse scalar grid loaded from a VDB file; values are f32 in memory.
#[derive(Debug, Clone)]
pub struct FloatGrid {
    name: String,
    background: f32,
    transform: GridTransform,
    leaf_origins: Vec<IVec3>,
    leaf_masks: Vec<[u64; 8]>,
    leaf_values: Vec<f32>,
    leaf_ranges: Vec<(f32, f32)>,
    tiles: Vec<Tile>,
    /// key ijk >> 3: leaf index, or TILE_FLAG | tile index for 8³ tiles.
    bricks: CoordMap,
    /// The same entries over the box of bricks `dense_lo + [0, dense_dims)`, x fastest
    /// (`NO_BRICK` where `bricks` has none); empty when that box is too sparse.
    dense: Vec<u32>,
    dense_lo: IVec3,
    dense_dims: IVec3,
    /// key ijk >> 7: tile index of 128³ tiles.
    mid_tiles: CoordMap,
    /// key ijk >> 12: tile index of 4096³ tiles.
    root_tiles: CoordMap,
    active_voxel_count: u64,
    value_range: (f32, f32),
    bbox: Option<(IVec3, IVec3)>,
}

#[inline]
fn leaf_offset(ijk: IVec3) -> usize {
    (((ijk.x & 7) << 6) | ((ijk.y & 7) << 3) | (ijk.z & 7)) as usize
}

/// Lerp as OpenVDB's BoxSampler does it: a + float((b - a) · w).
#[inline]
fn lerp(a: f32, b: f32, w: f64) -> f32 {
    a + ((b - a) as f64 * w) as f32
}

impl GridBuilder {
    /// Builds the lookup tables and statistics.
    pub(crate) fn finish(
        self,
        name: &str,
        background: f32,
        transform: GridTransform,
    ) -> FResult<FloatGrid> {
        let n_leaves = self.leaf_origins.len();
        let count_of = |log2: u32| self.tiles.iter().filter(|t| t.log2 == log2).count();
        let mut bricks = CoordMap::with_capacity(n_leaves + count_of(3));
        let mut mid_tiles = CoordMap::with_capacity(count_of(7));
        let mut root_tiles = CoordMap::with_capacity(count_of(12));
        let dup = |o: IVec3| FormatError::Corrupt(format!("two nodes claim the voxels at {o}"));
        for (i, &o) in self.leaf_origins.iter().enumerate() {
            if !bricks.insert(o >> 3, i as u32) {
                return Err(dup(o));
            }
        }
        for (i, t) in self.tiles.iter().enumerate() {
            let ok = match t.log2 {
                3 => bricks.insert(t.origin >> 3, TILE_FLAG | i as u32),
                7 => mid_tiles.insert(t.origin >> 7, i as u32),
                _ => root_tiles.insert(t.origin >> 12, i as u32),
            };
            if !ok {
                return Err(dup(t.origin));
            }
        }
        let (dense, dense_lo, dense_dims) =
            dense_brick_table(&bricks, &self.leaf_origins, &self.tiles);
        let mut grid = FloatGrid {
            dense,
            dense_lo,
            dense_dims,
            name: name.to_string(),
            background,
            transform,
            leaf_ranges: Vec::with_capacity(n_leaves),
            leaf_origins: self.leaf_origins,
            leaf_masks: self.leaf_masks,
            leaf_values: self.leaf_values,
            tiles: self.tiles,
            bricks,
            mid_tiles,
            root_tiles,
            active_voxel_count: 0,
            value_range: (background, background),
            bbox: None,
        };
        grid.compute_statistics();
        Ok(grid)
    }
}

/// The flat brick table over the bounding box of the leaves and 8³ tiles, when it
/// holds at most 8 slots per brick (or 64 Ki slots) and `MAX_DENSE_SLOTS` in all.
fn dense_brick_table(
    bricks: &CoordMap,
    leaf_origins: &[IVec3],
    tiles: &[Tile],
) -> (Vec<u32>, IVec3, IVec3) {
    let keys = leaf_origins
        .iter()
        .copied()
        .chain(tiles.iter().filter(|t| t.log2 == 3).map(|t| t.origin))
        .map(|o| o >> 3i32);
    let (mut lo, mut hi, mut n) = (IVec3::MAX, IVec3::MIN, 0usize);
    for k in keys {
        lo = lo.min(k);
        hi = hi.max(k);
        n += 1;
    }
    if n == 0 {
        return (Vec::new(), IVec3::ZERO, IVec3::ZERO);
    }
    let dims = (hi.as_i64vec3() - lo.as_i64vec3()) + glam::I64Vec3::ONE;
    let slots = dims.x.saturating_mul(dims.y).saturating_mul(dims.z) as usize;
    if slots > MAX_DENSE_SLOTS || slots > (8 * n).max(1 << 16) {
        return (Vec::new(), IVec3::ZERO, IVec3::ZERO);
    }
    let dims = dims.as_ivec3();
    let mut table = vec![NO_BRICK; slots];
    for z in 0..dims.z {
        for y in 0..dims.y {
            for x in 0..dims.x {
                if let Some(e) = bricks.get(lo + IVec3::new(x, y, z)) {
                    table[(x + dims.x * (y + dims.y * z)) as usize] = e;
                }
            }
        }
    }
    (table, lo, dims)
}

/// ⌊x⌋ as an integer for |x| < 2³¹ (no libm call).
#[inline]
fn floor_i32(x: Vec3) -> IVec3 {
    let t = x.as_ivec3();
    t - IVec3::select(t.as_vec3().cmpgt(x), IVec3::ONE, IVec3::ZERO)
}

impl FloatGrid {
    /// The brick-table entry of brick `b` (= ijk >> 3): leaf index or TILE_FLAG | tile index.
    #[inline]
    fn brick(&self, b: IVec3) -> Option<u32> {
        if self.dense.is_empty() {
            return self.bricks.get(b);
        }
        let d = b - self.dense_lo;
        if (d.cmpge(IVec3::ZERO) & d.cmplt(self.dense_dims)).all() {
            let e =
                self.dense[(d.x + self.dense_dims.x * (d.y + self.dense_dims.y * d.z)) as usize];
            (e != NO_BRICK).then_some(e)
        } else {
            // The table covers every brick: outside it there are only coarse tiles.
            None
        }
    }

    fn compute_statistics(&mut self) {
        let mut count = 0u64;
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        let (mut bmin, mut bmax) = (IVec3::MAX, IVec3::MIN);
        for (leaf, (&origin, mask)) in self.leaf_origins.iter().zip(&self.leaf_masks).enumerate() {
            let values = &self.leaf_values[leaf * LEAF_VOXELS..(leaf + 1) * LEAF_VOXELS];
            let range = values
                .iter()
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            self.leaf_ranges.push(range);
            for (w, &word) in mask.iter().enumerate() {
                let mut bits = word;
                while bits != 0 {
                    let n = w * 64 + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let v = values[n];
                    lo = lo.min(v);
                    hi = hi.max(v);
                    let ijk =
                        origin + IVec3::new((n >> 6) as i32, ((n >> 3) & 7) as i32, (n & 7) as i32);
                    bmin = bmin.min(ijk);
                    bmax = bmax.max(ijk);
                    count += 1;
                }
            }
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            count += 1u64 << (3 * t.log2);
            lo = lo.min(t.value);
            hi = hi.max(t.value);
            bmin = bmin.min(t.origin);
            bmax = bmax.max(t.origin + IVec3::splat((1 << t.log2) - 1));
        }
        self.active_voxel_count = count;
        if count > 0 {
            self.value_range = (lo, hi);
            self.bbox = Some((bmin, bmax));
        }
    }

    /// The grid's name in the file.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The value of voxels outside every leaf and tile (0 for fog volumes).
    pub fn background(&self) -> f32 {
        self.background
    }

    /// The index↔world transform.
    pub fn transform(&self) -> &GridTransform {
        &self.transform
    }

    /// Active voxels, counting every voxel of an active tile.
    pub fn active_voxel_count(&self) -> u64 {
        self.active_voxel_count
    }

    /// Inclusive index bounds of the active voxels, `None` if there are none.
    pub fn index_bbox_active(&self) -> Option<(IVec3, IVec3)> {
        self.bbox
    }

    /// Smallest and largest active value (the background twice if nothing is active).
    pub fn value_range(&self) -> (f32, f32) {
        self.value_range
    }

    /// Sum of the active values, each tile counted as value × its voxel count.
    pub fn sum_active_values(&self) -> f64 {
        let mut sum = 0.0f64;
        for (leaf, mask) in self.leaf_masks.iter().enumerate() {
            let values = &self.leaf_values[leaf * LEAF_VOXELS..(leaf + 1) * LEAF_VOXELS];
            for (n, &v) in values.iter().enumerate() {
                if mask[n >> 6] >> (n & 63) & 1 == 1 {
                    sum += v as f64;
                }
            }
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            sum += t.value as f64 * (1u64 << (3 * t.log2)) as f64;
        }
        sum
    }

    /// NaN, infinite and negative counts over every value a lookup can return.
    pub fn value_census(&self) -> ValueCensus {
        let mut c = ValueCensus {
            max_finite: f32::NEG_INFINITY,
            min_finite: f32::INFINITY,
            ..ValueCensus::default()
        };
        self.leaf_values.iter().for_each(|&v| c.add(v));
        self.tiles.iter().for_each(|t| c.add(t.value));
        c.add(self.background);
        c
    }

    /// Number of 8³ leaf bricks.
    pub fn leaf_count(&self) -> usize {
        self.leaf_origins.len()
    }

    /// Number of active tiles (any size).
    pub fn active_tile_count(&self) -> usize {
        self.tiles.iter().filter(|t| t.active).count()
    }

    /// Bytes of memory the grid holds.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.name.capacity()
            + self.leaf_origins.capacity() * std::mem::size_of::<IVec3>()
            + self.leaf_masks.capacity() * 64
            + self.leaf_values.capacity() * 4
            + self.leaf_ranges.capacity() * 8
            + self.tiles.capacity() * std::mem::size_of::<Tile>()
            + self.bricks.memory_bytes()
            + self.dense.capacity() * 4
            + self.mid_tiles.memory_bytes()
            + self.root_tiles.memory_bytes()
    }

    /// Every leaf brick and every tile a lookup can return, with its value range.
    pub fn blocks(&self) -> impl Iterator<Item = Block> + '_ {
        let leaves = self
            .leaf_origins
            .iter()
            .zip(&self.leaf_ranges)
            .map(|(&min, &(lo, hi))| Block {
                min,
                size: 8,
                min_value: lo,
                max_value: hi,
            });
        let tiles = self.tiles.iter().map(|t| Block {
            min: t.origin,
            size: 1 << t.log2,
            min_value: t.value,
            max_value: t.value,
        });
        leaves.chain(tiles)
    }

    /// The stored value at a voxel, active or not, as OpenVDB's `getValue`:
    /// leaf value, else tile value, else the background.
    #[inline]
    pub fn value(&self, ijk: IVec3) -> f32 {
        match self.brick(ijk >> 3) {
            Some(e) if e & TILE_FLAG == 0 => {
                self.leaf_values[e as usize * LEAF_VOXELS + leaf_offset(ijk)]
            }
            Some(e) => self.tiles[(e & !TILE_FLAG) as usize].value,
            None => self.coarse_value(ijk),
        }
    }

    /// Whether a voxel is active (in a leaf's active mask or an active tile).
    pub fn is_active(&self, ijk: IVec3) -> bool {
        match self.brick(ijk >> 3) {
            Some(e) if e & TILE_FLAG == 0 => {
                let n = leaf_offset(ijk);
                self.leaf_masks[e as usize][n >> 6] >> (n & 63) & 1 == 1
            }
            Some(e) => self.tiles[(e & !TILE_FLAG) as usize].active,
            None => self
                .mid_tiles
                .get(ijk >> 7)
                .or_else(|| self.root_tiles.get(ijk >> 12))
                .is_some_and(|t| self.tiles[t as usize].active),
        }
    }

    #[inline]
    fn coarse_value(&self, ijk: IVec3) -> f32 {
        if let Some(t) = self.mid_tiles.get(ijk >> 7) {
            return self.tiles[t as usize].value;
        }
        if let Some(t) = self.root_tiles.get(ijk >> 12) {
            return self.tiles[t as usize].value;
        }
        self.background
    }

    /// Trilinear interpolation at an index-space point (voxel centres at
    /// integer ijk), as OpenVDB's BoxSampler.
    ///
    /// The same value as [`Self::trilinear_index_f64`] to the bit (the same
    /// f64 weights and roundings); when the eight corners share one brick (7
    /// points in 8 per axis) it takes one table lookup and reads the leaf
    /// directly.
    #[inline]
    pub fn trilinear_index(&self, p: Vec3) -> f32 {
        if p.is_nan() {
            return self.trilinear_index_f64(p.as_dvec3());
        }
        let p = p.clamp(Vec3::splat(-1.0e9), Vec3::splat(1.0e9));
        let i = floor_i32(p);
        let w = p.as_dvec3() - i.as_dvec3();
        if (i & 7).cmpeq(IVec3::splat(7)).any() {
            // Corners in two or more bricks: the same weights and lerps over a gather.
            let v = self.corners_across_bricks(i);
            let yz = |o: usize| {
                lerp(
                    lerp(v[o], v[o + 1], w.z),
                    lerp(v[o + 2], v[o + 3], w.z),
                    w.y,
                )
            };
            return lerp(yz(0), yz(4), w.x);
        }
        match self.brick(i >> 3i32) {
            Some(e) if e & TILE_FLAG == 0 => {
                let base = e as usize * LEAF_VOXELS + leaf_offset(i);
                let v = &self.leaf_values[base..base + 74];
                let yz = |o: usize| {
                    lerp(
                        lerp(v[o], v[o + 1], w.z),
                        lerp(v[o + 8], v[o + 9], w.z),
                        w.y,
                    )
                };
                lerp(yz(0), yz(64), w.x)
            }
            // Eight equal corners c: every lerp gives c (NaN for an infinite c, as nested).
            Some(e) => {
                let c = self.tiles[(e & !TILE_FLAG) as usize].value;
                lerp(c, c, w.x)
            }
            None => {
                let c = self.coarse_value(i);
                lerp(c, c, w.x)
            }
        }
    }

    /// The eight corner values of voxel cell `i` when they span several bricks
    /// (`i` on the last voxel of its brick along some axis), each brick
    /// resolved once: two table lookups when one axis crosses, four or eight
    /// when more do (at index `4·dx + 2·dy + dz`, as [`Self::corners`]).
    #[inline]
    fn corners_across_bricks(&self, i: IVec3) -> [f32; 8] {
        let b = i >> 3i32;
        let cross = IVec3::select((i & 7).cmpeq(IVec3::splat(7)), IVec3::ONE, IVec3::ZERO);
        // Per touched brick (index 4·x + 2·y + z of its offset): a leaf's value base, or a constant.
        let mut base = [usize::MAX; 8];
        let mut constant = [0.0f32; 8];
        for z in 0..=cross.z {
            for y in 0..=cross.y {
                for x in 0..=cross.x {
                    let k = (4 * x + 2 * y + z) as usize;
                    let brick = b + IVec3::new(x, y, z);
                    match self.brick(brick) {
                        Some(e) if e & TILE_FLAG == 0 => base[k] = e as usize * LEAF_VOXELS,
                        Some(e) => constant[k] = self.tiles[(e & !TILE_FLAG) as usize].value,
                        None => constant[k] = self.coarse_value(brick << 3i32),
                    }
                }
            }
        }
        std::array::from_fn(|n| {
            let d = IVec3::new(n as i32 >> 2, (n as i32 >> 1) & 1, n as i32 & 1);
            let k = ((d & cross) * IVec3::new(4, 2, 1)).element_sum() as usize;
            match base[k] {
                usize::MAX => constant[k],
                start => self.leaf_values[start + leaf_offset(i + d)],
            }
        })
    }

    /// The eight stored values around voxel cell `i` (corners `i + (dx, dy, dz)`,
    /// at index `4·dx + 2·dy + dz`): what a trilinear lookup anywhere in the cell reads.
    ///
    /// One table lookup when the cell lies inside one brick (7 in 8 per axis).
    #[inline]
    pub fn corners(&self, i: IVec3) -> [f32; 8] {
        let i = i.clamp(IVec3::splat(-1_000_000_000), IVec3::splat(1_000_000_000));
        if (i & 7).cmpne(IVec3::splat(7)).all() {
            match self.brick(i >> 3i32) {
                Some(e) if e & TILE_FLAG == 0 => {
                    let base = e as usize * LEAF_VOXELS + leaf_offset(i);
                    let v = &self.leaf_values[base..base + 74];
                    return [v[0], v[1], v[8], v[9], v[64], v[65], v[72], v[73]];
                }
                Some(e) => return [self.tiles[(e & !TILE_FLAG) as usize].value; 8],
                None => return [self.coarse_value(i); 8],
            }
        }
        std::array::from_fn(|n| {
            let n = n as i32;
            self.value(i + IVec3::new(n >> 2, (n >> 1) & 1, n & 1))
        })
    }

    /// Trilinear interpolation at a world-space point.
    pub fn trilinear_world(&self, p: DVec3) -> f32 {
        self.trilinear_index_f64(self.transform.world_to_index(p))
    }

    /// Trilinear interpolation at an index-space point given in f64.
    pub fn trilinear_index_f64(&self, p: DVec3) -> f32 {
        // far outside any tree (|ijk| < 2^31); keeps the corner arithmetic from overflowing
        let p = p.clamp(DVec3::splat(-1.0e9), DVec3::splat(1.0e9));
        let f = p.floor();
        let i = f.as_ivec3();
        let w = p - f;
        // the eight corners span at most 2×2×2 bricks: one table lookup per brick
        let b: IVec3 = i >> 3i32;
        let span = IVec3::select((i & 7).cmpeq(IVec3::splat(7)), IVec3::splat(2), IVec3::ONE);
        let mut entries = [[[None; 2]; 2]; 2];
        for (bx, ex) in entries.iter_mut().enumerate().take(span.x as usize) {
            for (by, ey) in ex.iter_mut().enumerate().take(span.y as usize) {
                for (bz, ez) in ey.iter_mut().enumerate().take(span.z as usize) {
                    *ez = self.brick(b + IVec3::new(bx as i32, by as i32, bz as i32));
                }
            }
        }
        let mut v = [[[0.0f32; 2]; 2]; 2];
        for (dx, vx) in v.iter_mut().enumerate() {
            for (dy, vy) in vx.iter_mut().enumerate() {
                for (dz, vz) in vy.iter_mut().enumerate() {
                    let c = i + IVec3::new(dx as i32, dy as i32, dz as i32);
                    let s = ((c >> 3i32) - b).as_uvec3();
                    *vz = match entries[s.x as usize][s.y as usize][s.z as usize] {
                        Some(e) if e & TILE_FLAG == 0 => {
                            self.leaf_values[e as usize * LEAF_VOXELS + leaf_offset(c)]
                        }
                        Some(e) => self.tiles[(e & !TILE_FLAG) as usize].value,
                        None => self.coarse_value(c),
                    };
                }
            }
        }
        let yz = |vx: &[[f32; 2]; 2]| {
            lerp(
                lerp(vx[0][0], vx[0][1], w.z),
                lerp(vx[1][0], vx[1][1], w.z),
                w.y,
            )
        };
        lerp(yz(&v[0]), yz(&v[1]), w.x)
    }

    /// The nearest voxel's value at an index-space point (OpenVDB PointSampler: floor(p + 0.5)).
    pub fn nearest_index(&self, p: DVec3) -> f32 {
        self.value((p + DVec3::splat(0.5)).floor().as_ivec3())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::GridTransform;

    fn hash(i: u64) -> f32 {
        (crate::sampling::mix64(i) >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A noisy grid with a negative origin, and one with the flat table refused (too sparse).
    fn grids() -> Vec<FloatGrid> {
        let t = GridTransform::scale_translate("ScaleMap", DVec3::ONE, DVec3::ZERO).unwrap();
        let dims = IVec3::new(37, 20, 29);
        let n = (dims.x * dims.y * dims.z) as u64;
        let values: Vec<f32> = (0..n).map(|i| 3.0 * hash(i) - 0.5).collect();
        let dense =
            FloatGrid::from_dense("noise", IVec3::new(-5, 3, -11), dims, &values, t.clone())
                .unwrap();
        assert!(!dense.dense.is_empty());
        let mut sparse = dense.clone();
        sparse.dense = Vec::new();
        vec![dense, sparse]
    }

    /// The fast path and the flat table return exactly what the hash-table path does.
    #[test]
    fn fast_trilinear_matches_the_hash_table_path_bit_for_bit() {
        let g = grids();
        let same = |p: Vec3| {
            let reference = g[1].trilinear_index_f64(p.as_dvec3());
            for v in [
                g[0].trilinear_index(p),
                g[1].trilinear_index(p),
                g[0].trilinear_index_f64(p.as_dvec3()),
            ] {
                assert!(
                    v.to_bits() == reference.to_bits() || v.is_nan() && reference.is_nan(),
                    "at {p}: {v} vs {reference}"
                );
            }
        };
        for i in 0..200_000u64 {
            let u = Vec3::new(hash(3 * i), hash(3 * i + 1), hash(3 * i + 2));
            same(Vec3::new(-9.0, -1.0, -15.0) + u * Vec3::new(47.0, 30.0, 39.0));
        }
        for p in [
            Vec3::splat(-0.25),
            Vec3::new(-1e-12, 7.0, 1e9),
            Vec3::splat(f32::NAN),
        ] {
            same(p);
        }
    }

    /// `corners` reads the same eight values as `value` at every cell, across brick
    /// boundaries, in the flat table and the hash table, and outside the tree.
    #[test]
    fn corners_match_voxel_values() {
        for g in grids() {
            for z in -14..20 {
                for y in 0..25 {
                    for x in -8..34 {
                        let i = IVec3::new(x, y, z);
                        let c = g.corners(i);
                        for (n, &v) in c.iter().enumerate() {
                            let n = n as i32;
                            let o = IVec3::new(n >> 2, (n >> 1) & 1, n & 1);
                            assert_eq!(
                                v.to_bits(),
                                g.value(i + o).to_bits(),
                                "cell {i} corner {o}"
                            );
                        }
                    }
                }
            }
        }
    }
}
