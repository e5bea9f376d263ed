//! Paths as the file system sees them, and whether an output can be written.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// The file a write to `path` replaces: the end of its chain of symbolic
/// links (even a dangling one), else `path` itself.
pub fn destination(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    // 40 links, as the kernel allows, then give up on a loop.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => match std::fs::read_link(&p) {
                Ok(target) if target.is_absolute() => p = target,
                Ok(target) => p = p.parent().map(|d| d.join(&target)).unwrap_or(target),
                Err(_) => break,
            },
            _ => break,
        }
    }
    p
}

/// A comparable form of `path` (absolute, links resolved), existing or not.
pub fn canonical(path: &Path) -> PathBuf {
    let dest = destination(path);
    if let Ok(c) = dest.canonicalize() {
        return c;
    }
    let folder = match dest.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match (folder.canonicalize(), dest.file_name()) {
        (Ok(f), Some(name)) => f.join(name),
        _ => dest,
    }
}

/// Why `path` cannot be written, if it cannot: it must name a file (not a
/// folder), in a folder that exists and is writable, replacing nothing but a
/// regular file (a symbolic link is written through to its target). Each
/// folder is probed once per run (`probed`), by creating and removing a file.
pub(super) fn check(path: &Path, probed: &mut HashSet<PathBuf>) -> Result<(), String> {
    let text = path.as_os_str().to_string_lossy();
    if text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR) {
        return Err(if path.is_dir() {
            "is a folder; give a file name inside it".into()
        } else {
            "names a folder that does not exist; give a file name in an existing folder".into()
        });
    }
    let dest = destination(path);
    if dest.is_dir() {
        return Err("is a directory".into());
    }
    if let Ok(m) = std::fs::metadata(&dest) {
        if !m.is_file() {
            return Err(
                "exists and is not a regular file (a device, FIFO or socket); brume only replaces regular files"
                    .into(),
            );
        }
    }
    let folder = match dest.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !folder.is_dir() {
        return Err(format!("folder {} does not exist", folder.display()));
    }
    if !probed.insert(folder.clone()) {
        return Ok(());
    }
    let probe = folder.join(format!(".brume-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(format!("cannot be written: {e}")),
    }
}
