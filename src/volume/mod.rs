//! Reading OpenVDB files into brume's own sparse grid.
//!
//! # Design
//!
//! brume reads the OpenVDB format with its own reader (this module), not
//! through vdb-rs. vdb-rs 0.6 reads half-float grids with BLOSC or ZIP
//! compression wrongly (OpenVDB writes no size prefix for an empty half
//! array, so every later chunk is misread), can abort the process with a
//! huge allocation on such files (an abort that `catch_unwind` cannot stop),
//! panics on AffineMap and ScaleMap transforms, ignores the background value,
//! drops root tiles and never validates the magic number. Those are exactly
//! the files Houdini and Blender write by default, and patching around a
//! library that may abort is not possible, so the whole path is ours:
//!
//! * `bytes`: a bounds-checked cursor; every count and length read from the
//!   file is checked against the bytes left before anything is allocated.
//! * `format`: header, magic number, file and grid metadata, grid
//!   descriptors, per-grid compression flags (`io/Archive.cc`).
//! * `transform`: the linear maps (scale, translation, scale+translation,
//!   affine/unitary); frustum maps are reported as unsupported.
//! * `tree`: root tiles and children, internal-node masks and tile values,
//!   leaf masks and buffers with the per-node compression byte and the
//!   active-mask scheme (`io/Compression.h`), half floats converted exactly
//!   to f32 with the `half` crate.
//! * `codec`: ZIP through flate2 and BLOSC decoded in safe Rust (blosc1 frame,
//!   byte unshuffle, LZ4 blocks), with output sizes fixed in advance.
//! * `grid`: the loaded [`FloatGrid`]: 8³ leaf bricks plus constant tiles,
//!   found through coordinate hash tables, with OpenVDB's `getValue` and
//!   BoxSampler semantics.
//! * `vec3`: the loaded [`Vec3Grid`] of a `vec3s`/`vec3d` grid (velocity):
//!   one float grid per component, split from the interleaved values as the
//!   tree is read.
//!
//! vdb-rs stays a dependency only as an independent cross-check in the tests,
//! on the files it is known to read correctly. The whole file is read into
//! memory once by [`VdbFile::open`]; grids are decoded on request.
//! Float and double grids (5-4-3 trees) load as [`FloatGrid`], vec3s and
//! vec3d grids as [`Vec3Grid`]; any other value type gives
//! [`VolumeError::Unsupported`] naming the grid and type, while the other
//! grids of the file still load.

mod bytes;
mod codec;
mod coord_map;
mod dense;
mod error;
mod format;
mod grid;
mod info;
mod transform;
mod tree;
mod vec3;
mod vol;

use std::path::{Path, PathBuf};

pub use error::VolumeError;
/// For tests that build sparse grids no dense array can hold.
#[cfg(test)]
pub(crate) use grid::GridBuilder;
pub use grid::{Block, FloatGrid, ValueCensus};
pub use info::info_report;
pub use transform::GridTransform;
pub use vec3::Vec3Grid;
pub use vol::{VolFile, VOL_HEADER_BYTES};

use bytes::Reader;
use error::{FResult, FormatError};
use format::{Descriptor, GridHeader, Header};
use tree::Elem;

/// What the grid list of a file says about one grid.
#[derive(Debug, Clone, PartialEq)]
pub struct GridDescriptor {
    /// Grid name.
    pub name: String,
    /// Tree type as stored, without `_HalfFloat` (e.g. `Tree_float_5_4_3`).
    pub grid_type: String,
    /// Value type part of the tree type (e.g. `float`, `vec3s`).
    pub value_type: String,
    /// Values stored as 16-bit half floats.
    pub half: bool,
    /// Name of the grid whose tree this one shares, for instanced grids.
    pub instance_parent: Option<String>,
}

/// An opened VDB file: header and grid list; grids load on request.
#[derive(Debug)]
pub struct VdbFile {
    path: PathBuf,
    data: Vec<u8>,
    header: Header,
    grids: Vec<Descriptor>,
}

/// Largest VDB file read (it is held in memory whole).
pub const MAX_VDB_BYTES: u64 = 64 << 30;

/// Loads one float grid from a file.
pub fn load_float_grid(path: &Path, name: &str) -> Result<FloatGrid, VolumeError> {
    VdbFile::open(path)?.load_float_grid(name)
}

/// Loads one vec3 grid from a file.
pub fn load_vec3_grid(path: &Path, name: &str) -> Result<Vec3Grid, VolumeError> {
    VdbFile::open(path)?.load_vec3_grid(name)
}

/// A grid of either value kind, as `brume info` reports it.
#[derive(Debug, Clone)]
pub enum AnyGrid {
    /// A float or double grid (boxed, like the vector grid, to keep the enum small).
    Float(Box<FloatGrid>),
    /// A vec3s or vec3d grid (boxed: three float grids).
    Vec3(Box<Vec3Grid>),
}

impl VdbFile {
    /// Reads a file's header and grid descriptors (all grids, supported or not).
    ///
    /// Refuses what is not a regular file (a FIFO would block, /dev/zero never
    /// ends) and files larger than [`MAX_VDB_BYTES`] or than the memory limit
    /// ([`crate::error::limits`]), before reading a byte.
    pub fn open(path: &Path) -> Result<VdbFile, VolumeError> {
        let io = |source| VolumeError::Io {
            path: path.to_path_buf(),
            source,
        };
        if let Some(problem) = crate::error::input_file_problem(path, MAX_VDB_BYTES) {
            return Err(io(std::io::Error::other(problem)));
        }
        let mut file = std::fs::File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        // Held whole in memory: the file's length is the allocation.
        if let Err(refusal) = crate::error::limits::check(len as u128) {
            return Err(io(std::io::Error::other(format!(
                "is {}, {refusal}",
                crate::error::limits::format_bytes(len as u128)
            ))));
        }
        let mut data = Vec::new();
        data.try_reserve_exact(len as usize)
            .map_err(|e| io(std::io::Error::other(e)))?;
        std::io::Read::read_to_end(&mut file, &mut data).map_err(io)?;
        VdbFile::from_bytes(path, data)
    }

    /// Reads a VDB file held in memory; `path` only names it in messages.
    pub fn from_bytes(path: &Path, data: Vec<u8>) -> Result<VdbFile, VolumeError> {
        let (header, _file_meta, grids) = format::read_file(&data).map_err(|e| e.for_file(path))?;
        Ok(VdbFile {
            path: path.to_path_buf(),
            data,
            header,
            grids,
        })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// File format version (224 for files from OpenVDB 6 on).
    pub fn file_version(&self) -> u32 {
        self.header.file_version
    }

    /// Major and minor version of the library that wrote the file.
    pub fn library_version(&self) -> (u32, u32) {
        self.header.library_version
    }

    /// Names of all grids, in file order.
    pub fn grid_names(&self) -> Vec<String> {
        self.grids.iter().map(|d| d.name.clone()).collect()
    }

    /// Descriptors of all grids, in file order.
    pub fn grids(&self) -> Vec<GridDescriptor> {
        self.grids
            .iter()
            .map(|d| GridDescriptor {
                name: d.name.clone(),
                grid_type: d.grid_type.clone(),
                value_type: value_type_of(&d.grid_type).to_string(),
                half: d.half,
                instance_parent: d.instance_parent.clone(),
            })
            .collect()
    }

    fn find(&self, name: &str) -> Result<&Descriptor, VolumeError> {
        self.grids
            .iter()
            .find(|d| d.name == name)
            .or_else(|| self.grids.iter().find(|d| d.unique_name == name))
            .ok_or_else(|| VolumeError::GridNotFound {
                path: self.path.clone(),
                grid: name.to_string(),
                available: self.grid_names().join(", "),
            })
    }

    /// Reads a grid's compression flags, metadata and transform.
    pub(crate) fn grid_header(&self, name: &str) -> Result<GridHeader, VolumeError> {
        let d = self.find(name)?;
        self.read_header(d)
            .map(|(h, _)| h)
            .map_err(|e| e.for_grid(&self.path, name))
    }

    fn read_header(&self, d: &Descriptor) -> FResult<(GridHeader, Reader<'_>)> {
        let mut r = Reader::at(&self.data[..d.end_pos as usize], d.grid_pos)?;
        let h = format::read_grid_header(&mut r)?;
        Ok((h, r))
    }

    /// Loads a float (or double) grid by name into a sparse [`FloatGrid`].
    pub fn load_float_grid(&self, name: &str) -> Result<FloatGrid, VolumeError> {
        match self.load_grid(name)? {
            AnyGrid::Float(g) => Ok(*g),
            AnyGrid::Vec3(_) => Err(FormatError::Unsupported(
                "a vec3 grid where a float grid is needed".into(),
            )
            .for_grid(&self.path, name)),
        }
    }

    /// Loads a vec3s (or vec3d) grid by name into a sparse [`Vec3Grid`].
    pub fn load_vec3_grid(&self, name: &str) -> Result<Vec3Grid, VolumeError> {
        match self.load_grid(name)? {
            AnyGrid::Vec3(g) => Ok(*g),
            AnyGrid::Float(_) => Err(FormatError::Unsupported(
                "a float grid where a vec3 grid (vec3s) is needed".into(),
            )
            .for_grid(&self.path, name)),
        }
    }

    /// Loads a grid of any supported value type by name.
    pub fn load_grid(&self, name: &str) -> Result<AnyGrid, VolumeError> {
        let d = self.find(name)?;
        self.load(d).map_err(|e| e.for_grid(&self.path, name))
    }

    fn load(&self, d: &Descriptor) -> FResult<AnyGrid> {
        let elem = elem_of(&d.grid_type)?;
        let (header, reader) = self.read_header(d)?;
        let (tree_desc, compression, mut r) = match &d.instance_parent {
            None => (d, header.compression, reader),
            Some(parent) => {
                let p = self
                    .grids
                    .iter()
                    .find(|g| &g.unique_name == parent)
                    .filter(|p| p.instance_parent.is_none() && p.grid_type == d.grid_type)
                    .ok_or_else(|| {
                        FormatError::Corrupt(format!(
                            "instance of missing or unusable grid '{parent}'"
                        ))
                    })?;
                let (ph, pr) = self.read_header(p)?;
                (p, ph.compression, pr)
            }
        };
        let (background, builders) = tree::read_tree(
            &mut r,
            tree_desc.block_pos,
            compression,
            tree_desc.half,
            elem,
        )?;
        let mut grids = builders
            .into_iter()
            .zip(background)
            .map(|(b, bg)| b.finish(&d.name, bg, header.transform.clone()))
            .collect::<FResult<Vec<FloatGrid>>>()?;
        if grids.len() == 1 {
            return Ok(AnyGrid::Float(Box::new(grids.remove(0))));
        }
        let components: [FloatGrid; 3] = grids
            .try_into()
            .map_err(|_| FormatError::Corrupt("vector grid without three components".into()))?;
        Vec3Grid::from_components(&d.name, components)
            .map(|g| AnyGrid::Vec3(Box::new(g)))
            .ok_or_else(|| FormatError::Corrupt("vector components disagree".into()))
    }
}

/// The value type part of a tree type name: `Tree_float_5_4_3` → `float`.
fn value_type_of(grid_type: &str) -> &str {
    grid_type.split('_').nth(1).unwrap_or(grid_type)
}

/// How a tree type's values are stored, or why brume cannot load it.
fn elem_of(grid_type: &str) -> FResult<Elem> {
    match grid_type {
        "Tree_float_5_4_3" => Ok(Elem::F32),
        "Tree_double_5_4_3" => Ok(Elem::F64),
        "Tree_vec3s_5_4_3" => Ok(Elem::Vec3F32),
        "Tree_vec3d_5_4_3" => Ok(Elem::Vec3F64),
        t if t.ends_with("_5_4_3") => Err(FormatError::Unsupported(format!(
            "value type '{}' (grid type {t}); brume loads float, double, vec3s and vec3d grids",
            value_type_of(t)
        ))),
        t => Err(FormatError::Unsupported(format!(
            "grid type {t}; brume loads float, double, vec3s and vec3d grids with 5-4-3 trees"
        ))),
    }
}
