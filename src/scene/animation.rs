//! `[animation]`: frames, frame patterns in file names, and the time scale.
//!
//! ```toml
//! [animation]
//! fps = 24.0                # frames per second: velocities are per second, shutters in frames
//! frame_offset = 0          # a file's frame = the rendered frame + frame_offset
//! missing_frames = "error"  # or "hold" (nearest first/last file) or "repeat" (cycle the files)
//! ```
//!
//! A frame pattern is one run of `#` in a file name (`smoke.####.vdb`): it
//! stands for the frame number zero-padded to the run's length (a longer
//! number is written in full; a negative one as `-001` for `####`). The
//! same pattern names output images (`--out out.####.exr`). Frame lists on
//! the command line are comma-separated numbers and ranges with an optional
//! step: `1-100`, `1,3,7-20:2`.

use serde::Deserialize;
use std::path::{Path, PathBuf};

/// What a frame without a file of its own gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MissingFrames {
    /// An error naming the missing file.
    #[default]
    Error,
    /// Before the first file, the first; after the last, the last.
    Hold,
    /// The files repeat: first, …, last, first, …
    Repeat,
}

/// `[animation]` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationDesc {
    /// Frames per second.
    #[serde(default = "default_fps")]
    pub fps: f32,
    /// Added to the rendered frame to get a file's frame.
    #[serde(default)]
    pub frame_offset: i64,
    /// Behaviour for frames outside the files on disk.
    #[serde(default)]
    pub missing_frames: MissingFrames,
}

impl Default for AnimationDesc {
    fn default() -> Self {
        AnimationDesc {
            fps: default_fps(),
            frame_offset: 0,
            missing_frames: MissingFrames::Error,
        }
    }
}

fn default_fps() -> f32 {
    24.0
}

/// The frame a scene is built for, and how files and time follow it.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    /// The rendered frame (`None`: a still render; patterns are then an error).
    pub frame: Option<i64>,
    /// Camera shutter in frames relative to the frame's time.
    pub shutter: Option<[f32; 2]>,
    /// Frames per second.
    pub fps: f32,
    /// Added to the frame for file names.
    pub frame_offset: i64,
    /// Missing-frame behaviour.
    pub missing: MissingFrames,
}

/// The first `#` run of a path's file name: (prefix, width, suffix), or `None` without one.
fn split_pattern(path: &Path) -> Option<(String, usize, String)> {
    let text = path.to_str()?;
    // only the file name holds a pattern: a '#' in a folder name is just a character
    let name_start = text.rfind('/').map_or(0, |i| i + 1);
    let start = name_start + text[name_start..].find('#')?;
    let width = text[start..].chars().take_while(|&c| c == '#').count();
    Some((
        text[..start].to_string(),
        width,
        text[start + width..].to_string(),
    ))
}

/// Whether a path holds a frame pattern.
pub fn has_pattern(path: &Path) -> bool {
    split_pattern(path).is_some()
}

/// A pattern with the frame written in; a path without a pattern unchanged.
pub fn substitute(path: &Path, frame: i64) -> PathBuf {
    match split_pattern(path) {
        Some((prefix, width, suffix)) => PathBuf::from(format!("{prefix}{frame:0width$}{suffix}")),
        None => path.to_path_buf(),
    }
}

/// The frames that exist on disk for a pattern, sorted.
fn frames_on_disk(pattern: &Path) -> Vec<i64> {
    let Some((prefix, _, suffix)) = split_pattern(pattern) else {
        return Vec::new();
    };
    let prefix_path = Path::new(&prefix);
    let (dir, name_prefix) = if prefix.ends_with('/') || prefix.is_empty() {
        (
            PathBuf::from(if prefix.is_empty() { "." } else { &prefix }),
            String::new(),
        )
    } else {
        let dir = prefix_path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let name = prefix_path
            .file_name()
            .map(|n| n.to_string_lossy().to_string());
        (dir, name.unwrap_or_default())
    };
    let dir = if dir.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        dir
    };
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut frames: Vec<i64> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().to_string();
            let digits = name.strip_prefix(&name_prefix)?.strip_suffix(&suffix)?;
            let ok = !digits.is_empty()
                && digits
                    .trim_start_matches('-')
                    .chars()
                    .all(|c| c.is_ascii_digit());
            ok.then(|| digits.parse().ok()).flatten()
        })
        .collect();
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// Every file of a pattern's sequence on disk: all the files any frame can
/// read through it, whatever the frame offset and `missing_frames`.
pub fn sequence_files(pattern: &Path) -> Vec<PathBuf> {
    frames_on_disk(pattern)
        .into_iter()
        .map(|n| substitute(pattern, n))
        .filter(|p| p.exists())
        .collect()
}

/// The file a pattern names for `frame` (plus the offset), following the
/// missing-frame behaviour; the error names the missing file.
pub fn resolve_frame(
    pattern: &Path,
    frame: i64,
    offset: i64,
    missing: MissingFrames,
) -> Result<PathBuf, String> {
    let wanted = frame + offset;
    let path = substitute(pattern, wanted);
    if path.exists() {
        // There but not readable (a FIFO, device or folder): say what it is, not "missing".
        if let Err(problem) = crate::error::regular_file(&path) {
            return Err(format!("frame {frame}: {}: {problem}", path.display()));
        }
    }
    if path.is_file() || missing == MissingFrames::Error {
        return if path.is_file() {
            Ok(path)
        } else {
            Err(format!("frame {frame}: missing file {}", path.display()))
        };
    }
    let on_disk = frames_on_disk(pattern);
    let (Some(&first), Some(&last)) = (on_disk.first(), on_disk.last()) else {
        return Err(format!(
            "frame {frame}: missing file {}, and no file matches {}",
            path.display(),
            pattern.display()
        ));
    };
    let chosen = match missing {
        MissingFrames::Hold => wanted.clamp(first, last),
        _ => first + (wanted - first).rem_euclid(last - first + 1),
    };
    let held = substitute(pattern, chosen);
    if held.is_file() {
        Ok(held)
    } else {
        Err(format!(
            "frame {frame}: missing file {} (files {first}..{last} exist, with a gap here)",
            held.display()
        ))
    }
}

/// Refuses keyframes written in a form brume does not read (an array of
/// transforms, a `time` key in a transform, `camera.keyframes`) with one
/// line that shows the form it reads: `transform = { keyframes = [...] }`.
pub fn reject_keyframes(value: &toml::Value, path: &str) -> Result<(), (String, String)> {
    const MESSAGE: &str = "write keyframes as transform = { keyframes = [{ time = 0.0, \
        translate = [0.0, 0.0, 0.0] }, { time = 1.0, translate = [1.0, 0.0, 0.0] }] } \
        (times in frames, like camera.shutter)";
    match value {
        toml::Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                reject_keyframes(item, &format!("{path}[{i}]"))?;
            }
        }
        toml::Value::Table(table) => {
            for (key, child) in table {
                let child_path = format!("{path}.{key}");
                let keyed = key == "transform"
                    && (child.is_array()
                        || child.as_table().is_some_and(|t| t.contains_key("time")));
                let camera_keys = path == "camera" && (key == "keyframes" || key == "time");
                if keyed || camera_keys {
                    return Err((child_path, MESSAGE.into()));
                }
                reject_keyframes(child, &child_path)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// Parses a frame list: `1-100`, `1,3,7-20:2`, `-5--1`; in the order written.
pub fn parse_frames(text: &str) -> Result<Vec<i64>, String> {
    let mut out = Vec::new();
    for part in text.split(',').map(str::trim) {
        let (range, step) = match part.split_once(':') {
            Some((r, s)) => {
                let step: i64 = s
                    .parse()
                    .map_err(|_| format!("bad step `{s}` in `{part}`"))?;
                if step <= 0 {
                    return Err(format!("step must be at least 1 in `{part}`"));
                }
                (r, step)
            }
            None => (part, 1),
        };
        // the range dash is the first '-' after a leading digit (so negative frames parse)
        let split = range
            .char_indices()
            .skip(1)
            .find(|&(i, c)| c == '-' && range.as_bytes()[i - 1].is_ascii_digit())
            .map(|(i, _)| i);
        let num = |s: &str| {
            s.trim()
                .parse::<i64>()
                .map_err(|_| format!("bad frame `{s}` in `{part}`"))
        };
        let (a, b) = match split {
            Some(i) => (num(&range[..i])?, num(&range[i + 1..])?),
            None => {
                let f = num(range)?;
                (f, f)
            }
        };
        if b < a {
            return Err(format!("range `{part}` ends before it starts"));
        }
        if (b - a) / step >= 1_000_000 {
            return Err(format!("range `{part}` has more than a million frames"));
        }
        out.extend((a..=b).step_by(step as usize));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_lists_parse_ranges_steps_and_negatives() {
        assert_eq!(parse_frames("1-4").unwrap(), vec![1, 2, 3, 4]);
        assert_eq!(
            parse_frames("1,3,7-20:4").unwrap(),
            vec![1, 3, 7, 11, 15, 19]
        );
        assert_eq!(parse_frames("-2-1").unwrap(), vec![-2, -1, 0, 1]);
        assert_eq!(parse_frames("-3--2").unwrap(), vec![-3, -2]);
        assert_eq!(parse_frames("5").unwrap(), vec![5]);
        for bad in ["", "a", "4-1", "1-5:0", "1-5:x", "1-"] {
            assert!(parse_frames(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn patterns_pad_to_the_run_of_hashes() {
        let p = Path::new("dir/smoke.####.vdb");
        assert!(has_pattern(p));
        assert_eq!(substitute(p, 7), PathBuf::from("dir/smoke.0007.vdb"));
        assert_eq!(substitute(p, 12345), PathBuf::from("dir/smoke.12345.vdb"));
        assert_eq!(substitute(p, -3), PathBuf::from("dir/smoke.-003.vdb"));
        assert_eq!(substitute(Path::new("a#.exr"), 3), PathBuf::from("a3.exr"));
        assert!(!has_pattern(Path::new("still.vdb")));
        assert!(!has_pattern(Path::new("take#2/still.vdb")));
        assert_eq!(
            substitute(Path::new("take#2/f.##.vdb"), 4),
            PathBuf::from("take#2/f.04.vdb")
        );
    }

    #[test]
    fn missing_frames_error_hold_or_repeat() {
        let dir = std::env::temp_dir().join(format!("brume-frames-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for f in [3, 4, 5] {
            std::fs::write(dir.join(format!("v.{f:04}.vdb")), b"x").unwrap();
        }
        let pattern = dir.join("v.####.vdb");
        let name = |f: i64| dir.join(format!("v.{f:04}.vdb"));
        use MissingFrames::*;
        assert_eq!(resolve_frame(&pattern, 4, 0, Error).unwrap(), name(4));
        assert_eq!(resolve_frame(&pattern, 2, 1, Error).unwrap(), name(3));
        let err = resolve_frame(&pattern, 9, 0, Error).unwrap_err();
        assert!(
            err.contains("v.0009.vdb") && err.contains("frame 9"),
            "{err}"
        );
        assert_eq!(resolve_frame(&pattern, 1, 0, Hold).unwrap(), name(3));
        assert_eq!(resolve_frame(&pattern, 9, 0, Hold).unwrap(), name(5));
        // 3 4 5 3 4 5 …: frame 6 is 3, 8 is 5, 2 is 5
        assert_eq!(resolve_frame(&pattern, 6, 0, Repeat).unwrap(), name(3));
        assert_eq!(resolve_frame(&pattern, 8, 0, Repeat).unwrap(), name(5));
        assert_eq!(resolve_frame(&pattern, 2, 0, Repeat).unwrap(), name(5));
        std::fs::remove_file(name(4)).unwrap();
        let err = resolve_frame(&pattern, 4, 0, Hold).unwrap_err();
        assert!(err.contains("v.0004.vdb") && err.contains("gap"), "{err}");
        let err = resolve_frame(&dir.join("w.##.vdb"), 1, 0, Repeat).unwrap_err();
        assert!(err.contains("no file matches"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
