//! Paths as the file system sees them, and whether an output can be written.

use super::Identity;
use std::collections::{HashMap, HashSet};
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

/// The end of `path`'s chain of symbolic links and its metadata (`None`:
/// nothing is there), with one `lstat` for a path that is not a link.
fn resolve(path: &Path) -> (PathBuf, Option<std::fs::Metadata>) {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => match std::fs::read_link(&p) {
                Ok(target) if target.is_absolute() => p = target,
                Ok(target) => p = p.parent().map(|d| d.join(&target)).unwrap_or(target),
                Err(_) => break,
            },
            Ok(m) => return (p, Some(m)),
            Err(_) => return (p, None),
        }
    }
    // A loop of links: what the kernel would say of it.
    let m = std::fs::metadata(&p).ok();
    (p, m)
}

fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

#[cfg(unix)]
fn file_identity(m: &std::fs::Metadata) -> Identity {
    use std::os::unix::fs::MetadataExt;
    Identity::File {
        dev: m.dev(),
        ino: m.ino(),
    }
}

/// What a run has learnt about the folders its files are in, so that a
/// sequence of many frames resolves and probes each folder once.
#[derive(Default)]
pub(super) struct Folders {
    /// Folder as written → its canonical form (`None`: it does not exist).
    canonical: HashMap<PathBuf, Option<PathBuf>>,
    /// Folders found writable.
    probed: HashSet<PathBuf>,
}

impl Folders {
    /// The canonical form of `folder`, if it is a folder.
    pub(super) fn canonical(&mut self, folder: &Path) -> Option<PathBuf> {
        if let Some(known) = self.canonical.get(folder) {
            return known.clone();
        }
        let c = folder.canonicalize().ok().filter(|c| c.is_dir());
        self.canonical.insert(folder.to_path_buf(), c.clone());
        c
    }

    /// The identity of the file `path` names: device and inode if it is
    /// there, else its canonical path (folder resolved, links followed).
    pub(super) fn identity(&mut self, path: &Path) -> Identity {
        let (dest, meta) = resolve(path);
        #[cfg(unix)]
        if let Some(m) = &meta {
            return file_identity(m);
        }
        let _ = meta;
        Identity::Path(self.file(&dest))
    }

    /// The canonical path of `dest` (the end of a link chain).
    pub(super) fn file(&mut self, dest: &Path) -> PathBuf {
        if let Ok(c) = dest.canonicalize() {
            return c;
        }
        match (self.canonical(folder_of(dest)), dest.file_name()) {
            (Some(f), Some(name)) => f.join(name),
            _ => dest.to_path_buf(),
        }
    }

    /// The identity of the output `path`, or why it cannot be written: it
    /// must name a file (not a folder), in a folder that exists and is
    /// writable, replacing nothing but a regular file (a symbolic link is
    /// written through to its target). Each folder is probed once, by
    /// creating and removing a file.
    pub(super) fn output(&mut self, path: &Path) -> Result<Identity, String> {
        let text = path.as_os_str().to_string_lossy();
        if text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR) {
            return Err(if path.is_dir() {
                "is a folder; give a file name inside it".into()
            } else {
                "names a folder that does not exist; give a file name in an existing folder".into()
            });
        }
        let (dest, meta) = resolve(path);
        match &meta {
            Some(m) if m.is_dir() => return Err("is a directory".into()),
            Some(m) if !m.is_file() => {
                return Err(
                    "exists and is not a regular file (a device, FIFO or socket); \
                            brume only replaces regular files"
                        .into(),
                )
            }
            _ => {}
        }
        let written = folder_of(&dest);
        let Some(folder) = self.canonical(written) else {
            return Err(format!("folder {} does not exist", written.display()));
        };
        if !self.probed.contains(&folder) {
            probe(&folder).map_err(|e| format!("cannot be written: {e}"))?;
            self.probed.insert(folder.clone());
        }
        #[cfg(unix)]
        if let Some(m) = &meta {
            return Ok(file_identity(m));
        }
        Ok(Identity::Path(match dest.file_name() {
            Some(name) => folder.join(name),
            None => dest,
        }))
    }
}

/// Creates and removes a new file in `folder`; never opens an existing one.
fn probe(folder: &Path) -> std::io::Result<()> {
    let pid = std::process::id();
    for n in 0..100 {
        let path = folder.join(format!(".brume-probe-{pid}-{n}"));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(_) => return std::fs::remove_file(&path),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(std::io::Error::other("no free name for a probe file"))
}
