//! Where a partial image goes: never over a complete image, nor over one
//! that holds more samples, nor over a file brume did not write.

use crate::film::image_io::{brume_header, BrumeHeader};
use std::path::{Path, PathBuf};

/// The file beside `path` that receives a partial image when `path` holds a
/// better one: `NAME.partial.EXT` (`render.exr` → `render.partial.exr`,
/// `seq.0003.png` → `seq.0003.partial.png`, `out` → `out.partial`).
pub fn partial_path(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let name = match path.extension() {
        Some(ext) => format!("{stem}.partial.{}", ext.to_string_lossy()),
        None => format!("{stem}.partial"),
    };
    path.with_file_name(name)
}

/// Where to write a partial image (and its PNG preview), and what was kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// The EXR to write, or `None`: nothing is written.
    pub exr: Option<PathBuf>,
    /// The PNG preview to write (it follows the EXR).
    pub png: Option<PathBuf>,
    /// The files kept because they hold a better image, each described
    /// (`render.exr (a complete image of 64 spp)`).
    pub kept: Vec<String>,
}

impl Placement {
    /// The requested files, for a complete image (which replaces what is there).
    pub fn requested(exr: &Path, png: Option<&Path>) -> Placement {
        Placement {
            exr: Some(exr.to_path_buf()),
            png: png.map(Path::to_path_buf),
            kept: Vec::new(),
        }
    }

    /// One line for the user about the kept files, if any were kept.
    pub fn note(&self) -> Option<String> {
        if self.kept.is_empty() {
            return None;
        }
        let kept = self.kept.join(" and ");
        Some(match &self.exr {
            Some(_) => format!(
                "{kept} kept: a partial image never replaces a complete one or one of more samples"
            ),
            None => format!(
                "partial image not saved: {kept} hold better images (move them away to keep a partial)"
            ),
        })
    }
}

/// Where a partial image of `spp` samples per pixel bound for `exr` (and
/// `png`) is written. It replaces only a missing file or an earlier partial
/// image of at most `spp` samples; otherwise it goes to [`partial_path`]
/// beside it (the PNG likewise, so preview and EXR stay a pair), under the
/// same rule there; when neither may be replaced nothing is written.
pub fn place_partial(exr: &Path, png: Option<&Path>, spp: u32) -> Placement {
    let mut kept = Vec::new();
    for (to_exr, to_png) in [
        (exr.to_path_buf(), png.map(Path::to_path_buf)),
        (partial_path(exr), png.map(partial_path)),
    ] {
        match better_image(&to_exr, spp) {
            None => {
                return Placement {
                    exr: Some(to_exr),
                    png: to_png,
                    kept,
                }
            }
            Some(what) => kept.push(format!("{} ({what})", to_exr.display())),
        }
    }
    Placement {
        exr: None,
        png: None,
        kept,
    }
}

/// What `path` holds if a partial image of `spp` samples must not replace it.
fn better_image(path: &Path, spp: u32) -> Option<String> {
    if std::fs::symlink_metadata(path).is_err() {
        return None;
    }
    match brume_header(path) {
        Some(BrumeHeader {
            complete: false,
            spp: held,
        }) if held <= spp => None,
        Some(BrumeHeader {
            complete: false,
            spp: held,
        }) => Some(format!("a partial image of {held} spp")),
        Some(BrumeHeader {
            complete: true,
            spp: held,
        }) => Some(format!("a complete image of {held} spp")),
        None => Some("a file brume did not write as a partial image".into()),
    }
}
