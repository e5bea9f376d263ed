//! Mitsuba's binary grid volume (`.vol`), as its `gridvolume` plugin documents it.
//!
//! Little endian: bytes `V`, `O`, `L`, the version byte 3, then 32-bit
//! integers encoding (1: float32), x, y and z resolution and channel count,
//! six float32 of the data's bounding box (xmin, ymin, zmin, xmax, ymax,
//! zmax), and the values, `data[((z·yres + y)·xres + x)·channels + c]`.
//!
//! The header alone fixes the file's length: a file whose length differs is
//! refused before anything is allocated, and the values are then checked
//! against the memory limit, so a damaged or hostile header never sizes an
//! allocation. Every error names the file.
//!
//! Mitsuba looks a grid up trilinearly at `u·res - 0.5` for u in the unit
//! cube (voxel centres at `(i + 0.5)/res`), clamping indices to the edge.
//! [`VolFile::channel_grid`] gives a channel as a [`FloatGrid`] with that
//! lookup: index i of the grid is voxel i, placed at its centre, and one
//! extra layer of edge copies on every side makes brume's trilinear lookup
//! equal the clamped one up to half a voxel beyond the data.

use std::io::Read;
use std::path::{Path, PathBuf};

use glam::{DVec3, IVec3};

use super::{FloatGrid, GridTransform};
use crate::error::{limits, Error, Result};

/// Bytes before the values.
pub const VOL_HEADER_BYTES: u64 = 48;

/// A `.vol` file read into memory.
#[derive(Clone, Debug)]
pub struct VolFile {
    /// Where it was read from (for messages).
    pub path: PathBuf,
    /// Cells along x, y, z.
    pub res: [usize; 3],
    /// Values per cell: 1 or 3.
    pub channels: usize,
    /// The data's bounding box: min and max corners.
    pub bbox: [[f32; 3]; 2],
    /// The values, x fastest then y then z, channels innermost.
    pub data: Vec<f32>,
}

/// An input error about `path`.
fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::Input {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The fields of the 48-byte header.
struct Header {
    res: [usize; 3],
    channels: usize,
    bbox: [[f32; 3]; 2],
}

/// Reads and checks the header bytes.
fn parse_header(path: &Path, h: &[u8; 48]) -> Result<Header> {
    if &h[0..3] != b"VOL" {
        return Err(bad(
            path,
            "not a Mitsuba .vol file (it does not start with 'VOL')",
        ));
    }
    if h[3] != 3 {
        return Err(bad(
            path,
            format!(".vol version {} (brume reads version 3)", h[3]),
        ));
    }
    let int = |at: usize| i32::from_le_bytes(h[at..at + 4].try_into().expect("4 bytes"));
    let float = |at: usize| f32::from_le_bytes(h[at..at + 4].try_into().expect("4 bytes"));
    if int(4) != 1 {
        return Err(bad(
            path,
            format!(".vol encoding {} (brume reads encoding 1, float32)", int(4)),
        ));
    }
    let mut res = [0usize; 3];
    for (a, r) in res.iter_mut().enumerate() {
        let v = int(8 + 4 * a);
        if v <= 0 {
            let axis = ["x", "y", "z"][a];
            return Err(bad(path, format!(".vol {axis} resolution is {v}")));
        }
        *r = v as usize;
    }
    let channels = int(20);
    if channels != 1 && channels != 3 {
        return Err(bad(
            path,
            format!(".vol with {channels} channels (brume reads 1 or 3)"),
        ));
    }
    let mut bbox = [[0.0f32; 3]; 2];
    for (i, v) in bbox.iter_mut().flatten().enumerate() {
        *v = float(24 + 4 * i);
        if !v.is_finite() {
            return Err(bad(path, ".vol bounding box is not finite"));
        }
    }
    Ok(Header {
        res,
        channels: channels as usize,
        bbox,
    })
}

impl VolFile {
    /// Reads `path`: header checked, length checked against it, then the values.
    pub fn read(path: &Path) -> Result<VolFile> {
        let meta = crate::error::regular_file(path).map_err(|p| bad(path, p))?;
        let io = |e: std::io::Error| bad(path, format!("cannot read: {e}"));
        let mut file = std::fs::File::open(path).map_err(io)?;
        let mut h = [0u8; 48];
        if meta.len() < VOL_HEADER_BYTES {
            return Err(bad(
                path,
                format!(
                    "truncated .vol file: {} bytes, shorter than the {VOL_HEADER_BYTES}-byte header",
                    meta.len()
                ),
            ));
        }
        file.read_exact(&mut h).map_err(io)?;
        let header = parse_header(path, &h)?;
        let [x, y, z] = header.res.map(|r| r as u128);
        let values = x * y * z * header.channels as u128;
        let declared = VOL_HEADER_BYTES as u128 + 4 * values;
        if declared != meta.len() as u128 {
            return Err(bad(
                path,
                format!(
                    ".vol header declares {x}×{y}×{z}×{} float32 values ({declared} bytes with the header) \
                     but the file holds {} bytes",
                    header.channels,
                    meta.len()
                ),
            ));
        }
        limits::check(4 * values).map_err(|r| bad(path, format!(".vol values: {r}")))?;
        let mut bytes = vec![0u8; 4 * values as usize];
        file.read_exact(&mut bytes).map_err(io)?;
        let data = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
            .collect();
        Ok(VolFile {
            path: path.to_path_buf(),
            res: header.res,
            channels: header.channels,
            bbox: header.bbox,
            data,
        })
    }

    /// The value of channel `c` at cell (x, y, z).
    pub fn value(&self, x: usize, y: usize, z: usize, c: usize) -> f32 {
        let [rx, ry, _] = self.res;
        self.data[((z * ry + y) * rx + x) * self.channels + c]
    }

    /// The largest value of any channel (the majorant of an unscaled lookup).
    pub fn max_value(&self) -> f32 {
        self.data.iter().fold(0.0f32, |m, &v| m.max(v))
    }

    /// Index → local map: voxel i at its centre in the unit cube, or in the
    /// file's bounding box with `use_grid_bbox`.
    pub fn index_to_local(&self, use_grid_bbox: bool) -> Result<GridTransform> {
        let (lo, hi) = if use_grid_bbox {
            let [lo, hi] = self.bbox.map(|c| DVec3::from_array(c.map(f64::from)));
            if !lo.cmplt(hi).all() {
                return Err(bad(
                    &self.path,
                    ".vol bounding box is empty on some axis (min ≥ max) and use_grid_bbox is set",
                ));
            }
            (lo, hi)
        } else {
            (DVec3::ZERO, DVec3::ONE)
        };
        let res = DVec3::from_array(self.res.map(|r| r as f64));
        let scale = (hi - lo) / res;
        GridTransform::scale_translate("ScaleTranslateMap", scale, lo + 0.5 * scale)
            .ok_or_else(|| bad(&self.path, ".vol bounding box gives a singular placement"))
    }

    /// The index-space box a lookup covers: half a voxel beyond the outer voxel centres.
    pub fn index_box(&self) -> (glam::Vec3, glam::Vec3) {
        let hi = glam::Vec3::from_array(self.res.map(|r| r as f32 - 0.5));
        (glam::Vec3::splat(-0.5), hi)
    }

    /// Channel `c` (or, with `None`, the largest channel per cell) as a grid
    /// with one layer of edge copies around the data (see the module note).
    pub fn channel_grid(&self, c: Option<usize>, transform: GridTransform) -> Result<FloatGrid> {
        let [rx, ry, rz] = self.res;
        let dims = IVec3::new(rx as i32 + 2, ry as i32 + 2, rz as i32 + 2);
        let count = (rx + 2) as u128 * (ry + 2) as u128 * (rz + 2) as u128;
        limits::check(count * 4 * 3).map_err(|r| bad(&self.path, format!(".vol grid: {r}")))?;
        let cell = |x: usize, y: usize, z: usize| match c {
            Some(c) => self.value(x, y, z, c),
            None => {
                (0..self.channels).fold(f32::NEG_INFINITY, |m, c| m.max(self.value(x, y, z, c)))
            }
        };
        let clamp = |i: usize, r: usize| i.saturating_sub(1).min(r - 1);
        let mut values = Vec::with_capacity(count as usize);
        for z in 0..rz + 2 {
            for y in 0..ry + 2 {
                for x in 0..rx + 2 {
                    values.push(cell(clamp(x, rx), clamp(y, ry), clamp(z, rz)));
                }
            }
        }
        let name = self.path.display().to_string();
        FloatGrid::from_dense(&name, IVec3::NEG_ONE, dims, &values, transform)
            .ok_or_else(|| bad(&self.path, "cannot build a grid from the .vol values"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Header bytes for the tests.
    fn header(version: u8, encoding: i32, res: [i32; 3], channels: i32) -> Vec<u8> {
        let mut b = b"VOL".to_vec();
        b.push(version);
        for v in [encoding, res[0], res[1], res[2], channels] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b
    }

    #[test]
    fn header_fields_are_checked() {
        let p = Path::new("t.vol");
        let h = |b: Vec<u8>| -> [u8; 48] { b.try_into().unwrap() };
        assert!(parse_header(p, &h(header(3, 1, [2, 3, 4], 3))).is_ok());
        let bad_cases = [
            (header(2, 1, [2, 3, 4], 1), "version 2"),
            (header(3, 2, [2, 3, 4], 1), "encoding 2"),
            (header(3, 1, [2, 0, 4], 1), "y resolution is 0"),
            (header(3, 1, [2, 3, 4], 6), "6 channels"),
        ];
        for (bytes, words) in bad_cases {
            let e = parse_header(p, &h(bytes)).err().unwrap().to_string();
            assert!(e.starts_with("t.vol: ") && e.contains(words), "{e}");
        }
    }
}
