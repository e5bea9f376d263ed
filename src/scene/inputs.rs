//! The files a scene reads, each with the key that names it, found from the
//! description alone (nothing is loaded), so that the output-safety rule can
//! see the inputs of every frame before the first frame is rendered.

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
    /// The file, resolved against the scene's folder (for a frame, the file it reads).
    pub path: PathBuf,
    /// The frame pattern it came from (`smoke.####.vdb`), if any.
    pub pattern: Option<PathBuf>,
}

/// The scene file and every file `desc` reads for `frame`, in scene order
/// (a frame pattern resolved for `frame`; left as the pattern for a still).
pub fn files_read(desc: &SceneDesc, scene: &Path, frame: Option<i64>) -> Vec<InputFile> {
    let base = scene.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut out = vec![InputFile {
        key: "the scene file".into(),
        path: scene.to_path_buf(),
        pattern: None,
    }];
    let mut add = |key: String, file: &Path| {
        let file = resolve(&base, file);
        let pattern = has_pattern(&file).then(|| file.clone());
        let path = match (frame, &pattern) {
            (Some(f), Some(p)) => {
                let a = &desc.animation;
                resolve_frame(p, f, a.frame_offset, a.missing_frames)
                    .unwrap_or_else(|_| substitute(p, f.saturating_add(a.frame_offset)))
            }
            _ => file,
        };
        out.push(InputFile { key, path, pattern });
    };
    for (i, light) in desc.lights.iter().enumerate() {
        if let LightDesc::EnvironmentMap { file, .. } = light {
            add(format!("light[{i}].file"), file);
        }
    }
    for (i, shape) in desc.shapes.iter().enumerate() {
        if let Some(file) = &shape.file {
            add(format!("shape[{i}].file"), file);
        }
        for (name, color) in shape.colors() {
            if let Some(file) = color.file() {
                add(format!("shape[{i}].{name}.file"), file);
            }
        }
        if let Some(MediumDesc::Vdb(v)) = &shape.interior {
            add(format!("shape[{i}].interior.file"), &v.file);
        }
        if let Some(MediumDesc::Vol(v)) = &shape.interior {
            add_vol(&mut add, &format!("shape[{i}].interior"), v);
        }
    }
    for (i, medium) in desc.media.iter().enumerate() {
        if let MediumDesc::Vdb(v) = medium {
            add(format!("medium[{i}].file"), &v.file);
        }
        if let MediumDesc::Vol(v) = medium {
            add_vol(&mut add, &format!("medium[{i}]"), v);
        }
    }
    out
}

/// The `.vol` files of a `type = "vol"` medium at `field`.
fn add_vol(add: &mut impl FnMut(String, &Path), field: &str, v: &super::description::VolDesc) {
    add(format!("{field}.sigma_t_file"), &v.sigma_t_file);
    if let Some(a) = &v.albedo_file {
        add(format!("{field}.albedo_file"), a);
    }
}

/// Adds to `plan` every file the scene in `scene` reads, for any frame:
/// each named by its key, a frame pattern as the whole sequence on disk
/// (see `Plan::input_sequence`). The scene is read and parsed once.
pub fn add_to_plan(
    plan: &mut crate::film::output_safety::Plan,
    scene: &Path,
    overrides: &[super::Override],
) -> Result<()> {
    if super::mitsuba::is_mitsuba(scene) {
        let imported = super::mitsuba::import(scene, super::mitsuba_defaults(overrides))?;
        for (i, file) in imported.files.iter().enumerate().skip(1) {
            plan.input(&format!("included XML file {i}"), file);
        }
        for file in files_read(&imported.desc, scene, None) {
            plan.input(&file.key, &file.path);
        }
        return Ok(());
    }
    let text = super::read_scene_text(scene)?;
    let desc = super::parse_with_overrides(&text, scene, overrides)?;
    for file in files_read(&desc, scene, None) {
        match &file.pattern {
            Some(pattern) => plan.input_sequence(&file.key, pattern),
            None => plan.input(&file.key, &file.path),
        };
    }
    Ok(())
}
