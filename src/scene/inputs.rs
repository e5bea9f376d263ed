//! The files a scene reads, each with the key that names it, found from the
//! description alone (nothing is loaded), so that the output-safety rule can
//! see every input of every frame before the first frame is rendered.

use super::animation::{has_pattern, resolve_frame, substitute};
use super::description::{LightDesc, MediumDesc, SceneDesc};
use super::resolve;
use crate::error::Result;
use std::path::{Path, PathBuf};

/// One file a scene reads.
#[derive(Clone, Debug, PartialEq)]
pub struct InputFile {
    /// Where the user named it: `the scene file`, `medium[0].file`, `shape[2].material.albedo.file`, ...
    pub key: String,
    /// The file, resolved against the scene's folder (for a frame, the file of that frame).
    pub path: PathBuf,
    /// The frame pattern it came from (`smoke.####.vdb`), if any.
    pub pattern: Option<PathBuf>,
}

/// The scene file and every file `desc` reads for `frame`, in scene order.
///
/// A frame pattern gives two entries when they differ: the file the frame
/// reads (after `missing_frames`) and the file it looks for first, since an
/// output written there would change what the frame reads.
pub fn files_read(desc: &SceneDesc, scene: &Path, frame: Option<i64>) -> Vec<InputFile> {
    let base = scene.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut out = vec![InputFile {
        key: "the scene file".into(),
        path: scene.to_path_buf(),
        pattern: None,
    }];
    let mut plain = |key: String, file: &Path| {
        out.push(InputFile {
            key,
            path: resolve(&base, file),
            pattern: None,
        })
    };
    for (i, light) in desc.lights.iter().enumerate() {
        if let LightDesc::EnvironmentMap { file, .. } = light {
            plain(format!("light[{i}].file"), file);
        }
    }
    for (i, shape) in desc.shapes.iter().enumerate() {
        if let Some(file) = &shape.file {
            plain(format!("shape[{i}].file"), file);
        }
        for (name, color) in shape.colors() {
            if let Some(file) = color.file() {
                plain(format!("shape[{i}].{name}.file"), file);
            }
        }
    }
    let interiors = desc.shapes.iter().enumerate().filter_map(|(i, s)| {
        s.interior
            .as_ref()
            .map(|m| (format!("shape[{i}].interior.file"), m))
    });
    let media = desc
        .media
        .iter()
        .enumerate()
        .map(|(i, m)| (format!("medium[{i}].file"), m));
    for (key, medium) in media.chain(interiors) {
        if let MediumDesc::Vdb(v) = medium {
            out.extend(frame_files(desc, key, &resolve(&base, &v.file), frame));
        }
    }
    out
}

/// The file of `pattern` a frame reads, and the one it looks for first.
fn frame_files(desc: &SceneDesc, key: String, file: &Path, frame: Option<i64>) -> Vec<InputFile> {
    let entry = |path: PathBuf, pattern: Option<&Path>| InputFile {
        key: key.clone(),
        path,
        pattern: pattern.map(Path::to_path_buf),
    };
    let Some(frame) = frame.filter(|_| has_pattern(file)) else {
        return vec![entry(file.to_path_buf(), None)];
    };
    let a = &desc.animation;
    let wanted = substitute(file, frame.saturating_add(a.frame_offset));
    let mut files = vec![entry(wanted.clone(), Some(file))];
    if let Ok(read) = resolve_frame(file, frame, a.frame_offset, a.missing_frames) {
        if read != wanted {
            files.push(entry(read, Some(file)));
        }
    }
    files
}

/// Adds to `plan` the files the scene in `scene` reads for each of
/// `frames` (`None`: a still), each named by its key and frame, and the
/// sequences its frame patterns name. The scene is read and parsed once.
pub fn add_to_plan(
    plan: &mut crate::output_safety::Plan,
    scene: &Path,
    frames: &[Option<i64>],
) -> Result<()> {
    let text = super::read_scene_text(scene)?;
    let desc = super::parse(&text, scene)?;
    for &frame in frames {
        for file in files_read(&desc, scene, frame) {
            let what = match frame {
                Some(f) => format!("{} of frame {f}", file.key),
                None => file.key.clone(),
            };
            plan.input(&what, &file.path);
            if let Some(pattern) = &file.pattern {
                plan.input_sequence(&file.key, pattern);
            }
        }
    }
    Ok(())
}
