//! A 64-bit fingerprint of what a render's samples depend on besides the seed
//! and the sample indices: the scene file's bytes, the bytes of every file it
//! reads (OBJ meshes, OpenVDB volumes) and the settings after command-line
//! overrides. Pieces with different fingerprints cannot be merged.
//!
//! Paths are not part of it, so a farm that mounts the scene elsewhere on each
//! machine still produces mergeable pieces. It guards against mistakes, not
//! against an adversary.

use crate::error::{Error, Result};
use crate::integrator::Settings;
use crate::sampling::mix64;
use crate::scene::description::MediumDesc;
use std::path::{Path, PathBuf};

/// Fingerprint of the scene in `file` rendered with `settings` (seed and spp left out).
pub fn scene_hash(file: &Path, settings: &Settings) -> Result<u64> {
    frame_scene_hash(file, settings, None, &[])
}

/// [`scene_hash`] of one frame of a sequence (the frame's own files, and the
/// frame number) with the `--set` values applied (and hashed: pieces rendered
/// with different values must not merge).
pub fn frame_scene_hash(
    file: &Path,
    settings: &Settings,
    frame: Option<i64>,
    overrides: &[crate::scene::Override],
) -> Result<u64> {
    let read = |path: &Path| {
        let problem = |message: String| Error::Input {
            path: path.to_path_buf(),
            message: format!("cannot read for the scene hash: {message}"),
        };
        crate::error::regular_file(path).map_err(problem)?;
        std::fs::read(path).map_err(|e| problem(e.to_string()))
    };
    let text = read(file)?;
    let mut hash = Hasher::new();
    hash.bytes(&text);
    let desc = if crate::scene::mitsuba::is_mitsuba(file) {
        // Included XML files are part of the scene too.
        let defaults = crate::scene::mitsuba_defaults(overrides);
        let imported = crate::scene::mitsuba::import(file, defaults)?;
        for included in imported.files.iter().skip(1) {
            hash.bytes(&read(included)?);
        }
        imported.desc
    } else {
        crate::scene::parse_with_overrides(&String::from_utf8_lossy(&text), file, overrides)?
    };
    for o in overrides {
        hash.bytes(o.to_string().as_bytes());
    }
    let base = file.parent().map(Path::to_path_buf).unwrap_or_default();
    for path in files_read(&desc, &base, frame) {
        hash.bytes(&read(&path)?);
    }
    if let Some(frame) = frame {
        hash.bytes(&frame.to_le_bytes());
    }
    let mut s = *settings;
    s.seed = 0;
    s.spp = 0;
    hash.bytes(format!("{s:?}").as_bytes());
    Ok(hash.finish())
}

/// The files a scene reads (for `frame`, frame patterns resolved), in scene order.
fn files_read(
    desc: &crate::scene::description::SceneDesc,
    base: &Path,
    frame: Option<i64>,
) -> Vec<PathBuf> {
    use crate::scene::animation::{has_pattern, resolve_frame};
    let resolve = |p: &Path| {
        let path = crate::scene::resolve(base, p);
        match frame {
            Some(f) if has_pattern(&path) => {
                let a = &desc.animation;
                resolve_frame(&path, f, a.frame_offset, a.missing_frames).unwrap_or(path)
            }
            _ => path,
        }
    };
    let meshes = desc.shapes.iter().filter_map(|s| s.file.as_deref());
    let volumes = desc.media.iter().filter_map(|m| match m {
        MediumDesc::Vdb(vdb) => Some(vdb.file.as_path()),
        _ => None,
    });
    let textures = desc.shapes.iter().flat_map(|s| s.texture_files());
    meshes.chain(textures).chain(volumes).map(resolve).collect()
}

/// Word-at-a-time hashing through the SplitMix64 finalizer, length-prefixed per input.
struct Hasher(u64);

impl Hasher {
    fn new() -> Hasher {
        Hasher(0x6272_756d_655f_7631) // "brume_v1"
    }

    fn word(&mut self, w: u64) {
        self.0 = mix64(self.0 ^ mix64(w));
    }

    fn bytes(&mut self, data: &[u8]) {
        self.word(data.len() as u64);
        let mut chunks = data.chunks_exact(8);
        for c in &mut chunks {
            self.word(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let mut tail = [0u8; 8];
        tail[..chunks.remainder().len()].copy_from_slice(chunks.remainder());
        self.word(u64::from_le_bytes(tail));
    }

    fn finish(&self) -> u64 {
        mix64(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_byte_and_its_position_count() {
        let h = |data: &[&[u8]]| {
            let mut hash = Hasher::new();
            data.iter().for_each(|d| hash.bytes(d));
            hash.finish()
        };
        assert_ne!(h(&[b"abc"]), h(&[b"abd"]));
        assert_ne!(h(&[b"ab", b"c"]), h(&[b"a", b"bc"]));
        assert_ne!(h(&[b"abcdefgh1"]), h(&[b"abcdefgh2"]));
        assert_ne!(h(&[b""]), h(&[b"\0"]));
        assert_eq!(h(&[b"scene"]), h(&[b"scene"]));
    }
}
