//! Frame patterns in file names: one run of `#` in a file name
//! (`smoke.####.vdb`, `--out out.####.exr`) stands for the frame number,
//! zero-padded to the run's length. Here, below the scene description and
//! the output-safety rule, because both input sequences and output images
//! are named by them (`scene::animation` resolves frames with them).

use std::path::{Path, PathBuf};

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
pub fn frames_on_disk(pattern: &Path) -> Vec<i64> {
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
