//! The OpenVDB file layout above the tree: the file header, metadata maps,
//! grid descriptors and each grid's header (compression flags, metadata,
//! transform). Follows `io/Archive.cc`, `io/GridDescriptor.cc` and
//! `Metadata.cc` of OpenVDB.

use super::bytes::Reader;
use super::error::{FResult, FormatError};
use super::transform::{read_transform, GridTransform};

/// The 8 bytes every VDB file starts with (" BDV" and four zero bytes).
const MAGIC: u64 = 0x5644_4220;
/// Oldest file format brume reads: per-grid compression and per-node metadata bytes.
pub(crate) const MIN_FILE_VERSION: u32 = 222;
/// Separator OpenVDB puts between a grid name and its uniquifying suffix.
const NAME_SUFFIX_SEP: char = '\u{1e}';

/// Metadata entries rendered as text: (name, value).
pub(crate) type Metadata = Vec<(String, String)>;

/// The file header.
#[derive(Debug, Clone)]
pub(crate) struct Header {
    /// File format version (224 for OpenVDB 6–12).
    pub file_version: u32,
    /// Library major and minor version that wrote the file.
    pub library_version: (u32, u32),
}

/// One grid descriptor from the grid list.
#[derive(Debug, Clone)]
pub(crate) struct Descriptor {
    /// Grid name, suffix stripped.
    pub name: String,
    /// Unique name as stored (may carry a suffix for duplicates).
    pub unique_name: String,
    /// Tree type without the `_HalfFloat` suffix, e.g. `Tree_float_5_4_3`.
    pub grid_type: String,
    /// Stored as half floats.
    pub half: bool,
    /// Unique name of the grid whose tree this one shares, if instanced.
    pub instance_parent: Option<String>,
    /// Offset of the grid header.
    pub grid_pos: u64,
    /// Offset of the leaf buffers.
    pub block_pos: u64,
    /// Offset after the grid.
    pub end_pos: u64,
}

/// A grid's header at `grid_pos`: compression, metadata and transform.
#[derive(Debug, Clone)]
pub(crate) struct GridHeader {
    /// Compression flags (ZIP, ACTIVE_MASK, BLOSC).
    pub compression: u32,
    /// Metadata, rendered as text.
    pub metadata: Metadata,
    /// The index↔world transform.
    pub transform: GridTransform,
}

impl GridHeader {
    /// A metadata entry by name.
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.metadata
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// Reads the header and the grid descriptors; returns them and the file-level metadata.
pub(crate) fn read_file(data: &[u8]) -> FResult<(Header, Metadata, Vec<Descriptor>)> {
    let mut r = Reader::at(data, 0)?;
    if data.len() < 8 || r.u64()? != MAGIC {
        return Err(FormatError::corrupt(0, "missing the OpenVDB magic number"));
    }
    let file_version = r.u32()?;
    if file_version < MIN_FILE_VERSION {
        return Err(FormatError::Unsupported(format!(
            "file format version {file_version} (brume reads {MIN_FILE_VERSION} and newer, \
             i.e. files from OpenVDB 3 on)"
        )));
    }
    let library_version = (r.u32()?, r.u32()?);
    let has_offsets = r.u8()? != 0;
    if !has_offsets {
        return Err(FormatError::Unsupported(
            "file without grid offsets (streamed archive)".into(),
        ));
    }
    r.take(36)?; // ASCII UUID
    let file_meta = read_metadata(&mut r)?;
    let at = r.pos();
    let count = r.i32()?;
    if count < 0 {
        return Err(FormatError::corrupt(
            at,
            format!("negative grid count {count}"),
        ));
    }
    // a descriptor is at least three strings and three offsets
    r.check_fits(count as u64, 36, "grid list")?;
    let mut grids = Vec::with_capacity(count as usize);
    for _ in 0..count {
        let d = read_descriptor(&mut r, data.len() as u64)?;
        r.seek(d.end_pos)?;
        grids.push(d);
    }
    let header = Header {
        file_version,
        library_version,
    };
    Ok((header, file_meta, grids))
}

fn read_descriptor(r: &mut Reader, file_len: u64) -> FResult<Descriptor> {
    let at = r.pos();
    let unique_name = r.string()?;
    let name = unique_name
        .split(NAME_SUFFIX_SEP)
        .next()
        .unwrap_or_default()
        .to_string();
    let mut grid_type = r.string()?;
    let half = grid_type.ends_with("_HalfFloat");
    if half {
        grid_type.truncate(grid_type.len() - "_HalfFloat".len());
    }
    let parent = r.string()?;
    let grid_pos = r.i64()?;
    let block_pos = r.i64()?;
    let end_pos = r.i64()?;
    let here = r.pos() as i64;
    let ordered = here <= grid_pos && grid_pos <= block_pos && block_pos <= end_pos;
    if !ordered || end_pos as u64 > file_len {
        return Err(FormatError::corrupt(
            at,
            format!(
                "grid '{name}': offsets grid={grid_pos} blocks={block_pos} end={end_pos} \
                 are out of order or past the end of the file ({file_len} bytes)"
            ),
        ));
    }
    Ok(Descriptor {
        name,
        unique_name,
        grid_type,
        half,
        instance_parent: (!parent.is_empty()).then_some(parent),
        grid_pos: grid_pos as u64,
        block_pos: block_pos as u64,
        end_pos: end_pos as u64,
    })
}

/// Reads a grid's header; leaves the reader at the start of its topology.
pub(crate) fn read_grid_header(r: &mut Reader) -> FResult<GridHeader> {
    let compression = r.u32()?;
    let metadata = read_metadata(r)?;
    let transform = read_transform(r)?;
    Ok(GridHeader {
        compression,
        metadata,
        transform,
    })
}

/// Reads a `MetaMap`: a count, then (name, type name, byte size, value) per entry.
fn read_metadata(r: &mut Reader) -> FResult<Metadata> {
    let count = r.u32()?;
    r.check_fits(count as u64, 12, "metadata")?;
    let mut out = Vec::with_capacity(count as usize);
    for _ in 0..count {
        let name = r.string()?;
        let type_name = r.string()?;
        let at = r.pos();
        let size = r.u32()? as usize;
        let bytes = r.take(size).map_err(|_| {
            FormatError::corrupt(at, format!("metadata '{name}' runs past the end"))
        })?;
        out.push((name, render_meta(&type_name, bytes)));
    }
    Ok(out)
}

/// Renders a metadata value as text for `brume info`.
fn render_meta(type_name: &str, b: &[u8]) -> String {
    let i32s = || {
        b.chunks_exact(4)
            .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]).to_string())
            .collect::<Vec<_>>()
    };
    let f64s = || {
        b.chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])).to_string())
            .collect::<Vec<_>>()
    };
    match (type_name, b.len()) {
        ("string", _) => String::from_utf8_lossy(b).into_owned(),
        ("bool", 1) => (b[0] != 0).to_string(),
        ("int32", 4) => i32s().join(""),
        ("int64", 8) => i64::from_le_bytes(b.try_into().unwrap_or([0; 8])).to_string(),
        ("float", 4) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]).to_string(),
        ("double", 8) => f64s().join(""),
        ("vec3i", 12) => format!("[{}]", i32s().join(", ")),
        ("vec3d", 24) => format!("[{}]", f64s().join(", ")),
        _ => format!("<{type_name}, {} bytes>", b.len()),
    }
}
