//! Reads an OpenVDB 5-4-3 tree: root tiles and children, internal-node child
//! and value masks with their tile values, leaf masks, then the leaf buffers
//! at `block_pos`. Follows `tree/RootNode.h`, `tree/InternalNode.h`,
//! `tree/LeafNode.h` and `readCompressedValues` in `io/Compression.h`.

use glam::IVec3;

use super::bytes::Reader;
use super::codec::{read_chunk, COMPRESS_ACTIVE_MASK};
use super::error::{FResult, FormatError};
use super::grid::{GridBuilder, Tile, LEAF_VOXELS};

/// How one stored value is encoded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Elem {
    /// 32-bit float.
    F32,
    /// 64-bit float, narrowed to f32 at load.
    F64,
    /// Three 32-bit floats (`vec3s`).
    Vec3F32,
    /// Three 64-bit floats (`vec3d`), narrowed to f32 at load.
    Vec3F64,
}

/// Most components a value has (vec3).
pub(crate) const MAX_LANES: usize = 3;

impl Elem {
    /// Bytes of one component.
    fn size(self) -> usize {
        match self {
            Elem::F32 | Elem::Vec3F32 => 4,
            Elem::F64 | Elem::Vec3F64 => 8,
        }
    }

    /// Components per value: 1 for scalars, 3 for vectors.
    pub(crate) fn lanes(self) -> usize {
        match self {
            Elem::F32 | Elem::F64 => 1,
            Elem::Vec3F32 | Elem::Vec3F64 => 3,
        }
    }

    /// Reads one whole value (all its components).
    fn read_value(self, r: &mut Reader) -> FResult<[f32; MAX_LANES]> {
        let mut v = [0.0; MAX_LANES];
        for c in v.iter_mut().take(self.lanes()) {
            *c = self.read(r)?;
        }
        Ok(v)
    }

    /// Reads one component.
    fn read(self, r: &mut Reader) -> FResult<f32> {
        Ok(match self.size() {
            4 => r.f32()?,
            _ => r.f64()? as f32,
        })
    }
}

/// The per-node metadata byte that says which inactive values were omitted.
mod meta {
    pub const NO_MASK_AND_ONE_INACTIVE_VAL: i8 = 2;
    pub const MASK_AND_NO_INACTIVE_VALS: i8 = 3;
    pub const MASK_AND_ONE_INACTIVE_VAL: i8 = 4;
    pub const MASK_AND_TWO_INACTIVE_VALS: i8 = 5;
    pub const NO_MASK_AND_ALL_VALS: i8 = 6;
}

/// State shared while reading one tree. Vector values are split into one
/// builder per component (lane) as they are read; the lanes share topology.
struct TreeReader {
    compression: u32,
    half: bool,
    elem: Elem,
    lanes: usize,
    background: [f32; MAX_LANES],
    raw: Vec<u8>,
    temp: Vec<f32>,
    /// Values of the node being read, interleaved by lane.
    values: Vec<f32>,
    node_values: Vec<f32>,
    out: Vec<GridBuilder>,
}

fn bit(mask: &[u64], n: usize) -> bool {
    mask[n >> 6] >> (n & 63) & 1 == 1
}

fn popcount(mask: &[u64]) -> usize {
    mask.iter().map(|w| w.count_ones() as usize).sum()
}

/// Reads the tree starting at the reader (just after the transform): the
/// background and one builder per component of the value type.
pub(crate) fn read_tree(
    r: &mut Reader,
    block_pos: u64,
    compression: u32,
    half: bool,
    elem: Elem,
) -> FResult<(Vec<f32>, Vec<GridBuilder>)> {
    let at = r.pos();
    let buffer_count = r.i32()?;
    if buffer_count != 1 {
        return Err(FormatError::corrupt(
            at,
            format!("tree has {buffer_count} buffers, expected 1"),
        ));
    }
    let lanes = elem.lanes();
    let background = elem.read_value(r)?;
    let mut t = TreeReader {
        compression,
        half,
        elem,
        lanes,
        background,
        raw: Vec::new(),
        temp: Vec::new(),
        values: Vec::new(),
        node_values: Vec::new(),
        out: (0..lanes).map(|_| GridBuilder::default()).collect(),
    };
    let num_tiles = r.u32()?;
    let num_children = r.u32()?;
    t.read_root_tiles(r, num_tiles)?;
    // a root child is at least its origin and two 4 KiB masks
    r.check_fits(num_children as u64, 12 + 8192, "root children")?;
    let mut children = Vec::with_capacity(num_children as usize);
    for _ in 0..num_children {
        let origin = read_origin(r, 12)?;
        let first_leaf = t.out[0].leaf_origins.len();
        t.read_internal(r, origin, 5)?;
        children.push((origin, first_leaf..t.out[0].leaf_origins.len()));
    }
    // buffers follow the root's std::map order: children sorted by (x, y, z)
    children.sort_by_key(|(o, _)| (o.x, o.y, o.z));
    r.seek(block_pos)?;
    for (_, leaves) in children {
        for leaf in leaves {
            t.read_leaf_buffer(r, leaf)?;
        }
    }
    Ok((background[..lanes].to_vec(), t.out))
}

/// Reads a node origin and checks it is aligned to the node size.
fn read_origin(r: &mut Reader, log2: u32) -> FResult<IVec3> {
    let at = r.pos();
    let o = IVec3::new(r.i32()?, r.i32()?, r.i32()?);
    if (o & IVec3::splat((1 << log2) - 1)) != IVec3::ZERO {
        return Err(FormatError::corrupt(
            at,
            format!("node origin {o} is not a multiple of {}", 1 << log2),
        ));
    }
    Ok(o)
}

impl TreeReader {
    /// The root's tiles: origin, value and active flag each.
    fn read_root_tiles(&mut self, r: &mut Reader, num_tiles: u32) -> FResult<()> {
        let elem = self.elem;
        r.check_fits(
            num_tiles as u64,
            13 + (self.lanes * elem.size()) as u64,
            "root tiles",
        )?;
        for _ in 0..num_tiles {
            let origin = read_origin(r, 12)?;
            let value = elem.read_value(r)?;
            let active = r.u8()? != 0;
            self.push_tile(origin, 12, value, active);
        }
        Ok(())
    }

    fn push_tile(&mut self, origin: IVec3, log2: u32, value: [f32; MAX_LANES], active: bool) {
        for (lane, out) in self.out.iter_mut().enumerate() {
            // inactive tiles equal to the background need no storage: lookups fall through to it
            if active || value[lane] != self.background[lane] {
                out.tiles.push(Tile {
                    origin,
                    log2,
                    value: value[lane],
                    active,
                });
            }
        }
    }

    /// Reads an internal node's topology (log2dim 5 or 4) and its children's.
    fn read_internal(&mut self, r: &mut Reader, origin: IVec3, log2dim: u32) -> FResult<()> {
        let child_log2 = if log2dim == 5 { 7 } else { 3 };
        let n_values = 1usize << (3 * log2dim);
        let mut child_mask = vec![0u64; n_values / 64];
        let mut value_mask = vec![0u64; n_values / 64];
        r.mask(&mut child_mask)?;
        r.mask(&mut value_mask)?;
        let lanes = self.lanes;
        let mut values = std::mem::take(&mut self.node_values);
        values.resize(n_values * lanes, 0.0);
        self.read_compressed_values(r, &mut values[..n_values * lanes], &value_mask)?;
        let dim = 1usize << log2dim;
        let offset = |n: usize| {
            let x = (n >> (2 * log2dim)) as i32;
            let y = ((n >> log2dim) & (dim - 1)) as i32;
            let z = (n & (dim - 1)) as i32;
            origin + (IVec3::new(x, y, z) << child_log2 as i32)
        };
        for (n, value) in values.chunks_exact(lanes).enumerate().take(n_values) {
            if !bit(&child_mask, n) {
                let mut v = [0.0; MAX_LANES];
                v[..lanes].copy_from_slice(value);
                self.push_tile(offset(n), child_log2, v, bit(&value_mask, n));
            }
        }
        self.node_values = values;
        let min_child_bytes = if log2dim == 5 { 1024 } else { 64 };
        r.check_fits(popcount(&child_mask) as u64, min_child_bytes, "child nodes")?;
        for n in (0..n_values).filter(|&n| bit(&child_mask, n)) {
            if log2dim == 5 {
                self.read_internal(r, offset(n), 4)?;
            } else {
                let mut mask = [0u64; 8];
                r.mask(&mut mask)?;
                for (out, &bg) in self.out.iter_mut().zip(&self.background) {
                    out.leaf_origins.push(offset(n));
                    out.leaf_masks.push(mask);
                    let len = out.leaf_values.len();
                    out.leaf_values.resize(len + LEAF_VOXELS, bg);
                }
            }
        }
        Ok(())
    }

    /// Reads one leaf's buffer: its value mask again, then its 512 values.
    fn read_leaf_buffer(&mut self, r: &mut Reader, leaf: usize) -> FResult<()> {
        let mut mask = [0u64; 8];
        r.mask(&mut mask)?;
        let range = leaf * LEAF_VOXELS..(leaf + 1) * LEAF_VOXELS;
        if self.lanes == 1 {
            self.out[0].leaf_masks[leaf] = mask;
            let mut values = std::mem::take(&mut self.out[0].leaf_values);
            let result = self.read_compressed_values(r, &mut values[range], &mask);
            self.out[0].leaf_values = values;
            return result;
        }
        let mut values = std::mem::take(&mut self.values);
        values.resize(LEAF_VOXELS * self.lanes, 0.0);
        let result = self.read_compressed_values(r, &mut values, &mask);
        for (lane, out) in self.out.iter_mut().enumerate() {
            out.leaf_masks[leaf] = mask;
            let dst = &mut out.leaf_values[range.clone()];
            for (d, v) in dst
                .iter_mut()
                .zip(values.iter().skip(lane).step_by(self.lanes))
            {
                *d = *v;
            }
        }
        self.values = values;
        result
    }

    /// The two values of inactive voxels a node's metadata byte implies: read from
    /// the stream (at full precision even in half-float grids) or derived from the background.
    fn inactive_values(
        &self,
        r: &mut Reader,
        metadata: i8,
    ) -> FResult<([f32; MAX_LANES], [f32; MAX_LANES])> {
        let bg = self.background;
        let mut inactive1 = bg;
        let mut inactive0 = if metadata == 0 { bg } else { bg.map(|b| -b) };
        if matches!(
            metadata,
            meta::NO_MASK_AND_ONE_INACTIVE_VAL
                | meta::MASK_AND_ONE_INACTIVE_VAL
                | meta::MASK_AND_TWO_INACTIVE_VALS
        ) {
            inactive0 = self.elem.read_value(r)?;
            if metadata == meta::MASK_AND_TWO_INACTIVE_VALS {
                inactive1 = self.elem.read_value(r)?;
            }
        }
        Ok((inactive0, inactive1))
    }

    /// `io::readCompressedValues`: a metadata byte, optional inactive values
    /// and selection mask, then the (possibly only active) values; `out`
    /// holds `lanes` components per value, interleaved.
    fn read_compressed_values(
        &mut self,
        r: &mut Reader,
        out: &mut [f32],
        value_mask: &[u64],
    ) -> FResult<()> {
        let at = r.pos();
        let metadata = r.u8()? as i8;
        if !(0..=meta::NO_MASK_AND_ALL_VALS).contains(&metadata) {
            return Err(FormatError::corrupt(
                at,
                format!("invalid node compression byte {metadata}"),
            ));
        }
        let lanes = self.lanes;
        let bg = self.background;
        let (inactive0, inactive1) = self.inactive_values(r, metadata)?;
        let n_values = out.len() / lanes;
        let mut selection = vec![0u64; n_values / 64];
        if (meta::MASK_AND_NO_INACTIVE_VALS..=meta::MASK_AND_TWO_INACTIVE_VALS).contains(&metadata)
        {
            r.mask(&mut selection)?;
        }
        let mask_compressed =
            self.compression & COMPRESS_ACTIVE_MASK != 0 && metadata != meta::NO_MASK_AND_ALL_VALS;
        let count = if mask_compressed {
            popcount(value_mask)
        } else {
            n_values
        };
        let mut temp = std::mem::take(&mut self.temp);
        temp.resize(count * lanes, 0.0);
        let result = self.read_values(r, &mut temp);
        if result.is_ok() {
            if count == n_values {
                out.copy_from_slice(&temp);
            } else {
                let mut active = temp.chunks_exact(lanes);
                for (n, v) in out.chunks_exact_mut(lanes).enumerate() {
                    if bit(value_mask, n) {
                        match active.next() {
                            Some(a) => v.copy_from_slice(a),
                            None => v.copy_from_slice(&bg[..lanes]),
                        }
                    } else if bit(&selection, n) {
                        v.copy_from_slice(&inactive1[..lanes]);
                    } else {
                        v.copy_from_slice(&inactive0[..lanes]);
                    }
                }
            }
        }
        self.temp = temp;
        result
    }

    /// `readData` / `HalfReader::read`: `out.len()` components, compressed as a chunk.
    fn read_values(&mut self, r: &mut Reader, out: &mut [f32]) -> FResult<()> {
        if self.half && out.is_empty() {
            // OpenVDB writes nothing at all, not even a size, for an empty half array
            return Ok(());
        }
        let size = if self.half { 2 } else { self.elem.size() };
        self.raw.resize(out.len() * size, 0);
        read_chunk(r, self.compression, &mut self.raw)?;
        let raw = &self.raw;
        match (self.half, self.elem.size()) {
            (true, _) => {
                for (v, b) in out.iter_mut().zip(raw.chunks_exact(2)) {
                    *v = half::f16::from_bits(u16::from_le_bytes([b[0], b[1]])).to_f32();
                }
            }
            (false, 4) => {
                for (v, b) in out.iter_mut().zip(raw.chunks_exact(4)) {
                    *v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                }
            }
            (false, _) => {
                for (v, b) in out.iter_mut().zip(raw.chunks_exact(8)) {
                    let mut a = [0u8; 8];
                    a.copy_from_slice(b);
                    *v = f64::from_le_bytes(a) as f32;
                }
            }
        }
        Ok(())
    }
}
