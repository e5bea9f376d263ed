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

use crate::film::frame_pattern::frames_on_disk;
pub use crate::film::frame_pattern::{has_pattern, sequence_files, substitute};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// What a frame without a file of its own gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MissingFrames {
    /// An error naming the missing file.
    #[default]
    Error,
    /// Before the first file, the first; after the last, the last.
    Hold,
    /// The files repeat: first, …, last, first, …
    Repeat,
}

impl<'de> Deserialize<'de> for MissingFrames {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<MissingFrames, D::Error> {
        const ALL: [MissingFrames; 3] = [
            MissingFrames::Error,
            MissingFrames::Hold,
            MissingFrames::Repeat,
        ];
        Ok(ALL[super::messages::one_of(d, &["error", "hold", "repeat"])?])
    }
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
    /// What keyframe times count from: each frame's own time, or frame 0.
    #[serde(default)]
    pub keyframe_time: KeyframeTime,
}

/// What keyframe times are measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum KeyframeTime {
    /// The frame's own time: keys move an object within a frame's shutter.
    #[default]
    Relative,
    /// Frame 0: a key's time is a frame number, so keys move an object
    /// across the frames of a sequence (a camera orbit); a still is frame 0.
    Absolute,
}

impl<'de> Deserialize<'de> for KeyframeTime {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<KeyframeTime, D::Error> {
        const ALL: [KeyframeTime; 2] = [KeyframeTime::Relative, KeyframeTime::Absolute];
        Ok(ALL[super::messages::one_of(d, &["relative", "absolute"])?])
    }
}

impl Default for AnimationDesc {
    fn default() -> Self {
        AnimationDesc {
            fps: default_fps(),
            frame_offset: 0,
            missing_frames: MissingFrames::Error,
            keyframe_time: KeyframeTime::Relative,
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

/// The file a pattern names for `frame` (plus the offset), following the
/// missing-frame behaviour; the error names the missing file.
pub fn resolve_frame(
    pattern: &Path,
    frame: i64,
    offset: i64,
    missing: MissingFrames,
) -> Result<PathBuf, String> {
    let wanted = frame.checked_add(offset).ok_or_else(|| {
        format!(
            "frame {frame}: animation.frame_offset {offset} takes the file's frame number \
             outside the range of frame numbers (64-bit)"
        )
    })?;
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
        _ => repeat(wanted, first, last),
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

/// The frame of `first..=last` that `wanted` falls on when the files repeat.
/// In 128 bits: the period and the offset from `first` can exceed i64 when
/// the files' numbers lie near both of its ends; the result lies in `first..=last`.
fn repeat(wanted: i64, first: i64, last: i64) -> i64 {
    let period = last as i128 - first as i128 + 1;
    let chosen = first as i128 + (wanted as i128 - first as i128).rem_euclid(period);
    chosen as i64
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

/// Most frames one `--frames` list may name.
pub const MAX_FRAMES: usize = 1_000_000;

/// Parses a frame list: `1-100`, `1,3,7-20:2`, `-5--1`; in the order written,
/// at most [`MAX_FRAMES`] frames in all.
pub fn parse_frames(text: &str) -> Result<Vec<i64>, String> {
    let mut out = Vec::new();
    for part in text.split(',').map(str::trim) {
        let (a, b, step) = frame_range(part)?;
        // Counted in 128 bits: b - a overflows i64 for ranges across its limits.
        let count = (b as i128 - a as i128) / step as i128 + 1;
        if out.len() as i128 + count > MAX_FRAMES as i128 {
            return Err(format!(
                "`{text}` names more than {MAX_FRAMES} frames; render the sequence in parts"
            ));
        }
        // Every a + k·step up to b lies in a..=b, so the cast back is exact.
        out.extend((0..count).map(|k| (a as i128 + k * step as i128) as i64));
    }
    Ok(out)
}

/// One comma-separated part of a frame list: (first, last, step).
fn frame_range(part: &str) -> Result<(i64, i64, i64), String> {
    let number = |s: &str, what: &str| {
        let t = s.trim();
        let digits = t.strip_prefix(['-', '+']).unwrap_or(t);
        let parsed = match digits.bytes().all(|b| b.is_ascii_digit()) {
            true => t.parse::<i64>().ok(),
            false => None,
        };
        parsed.ok_or_else(|| {
            format!(
                "`{s}` in `{part}` is not a {what}: expected a whole number \
                 from {} to {}",
                i64::MIN,
                i64::MAX
            )
        })
    };
    let (range, step) = match part.split_once(':') {
        Some((r, s)) => (r, number(s, "step")?),
        None => (part, 1),
    };
    if step <= 0 {
        return Err(format!("the step in `{part}` must be at least 1"));
    }
    // the range dash is the first '-' after a leading digit (so negative frames parse)
    let split = range
        .char_indices()
        .skip(1)
        .find(|&(i, c)| c == '-' && range.as_bytes()[i - 1].is_ascii_digit())
        .map(|(i, _)| i);
    let (a, b) = match split {
        Some(i) => (
            number(&range[..i], "frame")?,
            number(&range[i + 1..], "frame")?,
        ),
        None => {
            let f = number(range, "frame")?;
            (f, f)
        }
    };
    if b < a {
        return Err(format!("range `{part}` ends before it starts"));
    }
    Ok((a, b, step))
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
