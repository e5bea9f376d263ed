//! Inputs kept between the frames of a sequence, and between the scene
//! build and the scene hash of one image: a slab file is read once, and each
//! input file's digest computed once, while the file is unchanged.
//!
//! An entry is keyed by the resolved path and stamped with the file's length
//! and modification time: a file edited between frames is read again. An
//! entry the last frame did not use is dropped at the frame's end
//! ([`InputCache::end_frame`]), so a frame-numbered input (`smoke.####.vdb`,
//! a new path every frame) is never held beyond its frame; only inputs whose
//! path does not depend on the frame stay for the whole sequence.

use crate::error::Result;
use crate::geometry::slab::LightSlab;
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// What identifies one version of a file: its length and modification time.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
}

impl Stamp {
    /// The stamp of the file at `path` now; `None` when it cannot be read
    /// (the caller's own read then reports the problem).
    fn of(path: &Path) -> Option<Stamp> {
        let m = std::fs::metadata(path).ok()?;
        Some(Stamp {
            len: m.len(),
            modified: m.modified().ok(),
        })
    }
}

/// One kept value, with the stamp of the file it came from and the frame
/// that last used it.
struct Kept<T> {
    stamp: Stamp,
    value: T,
    used: u64,
}

#[derive(Default)]
struct Entries {
    slabs: HashMap<PathBuf, Kept<Arc<LightSlab>>>,
    digests: HashMap<PathBuf, Kept<u64>>,
    frame: u64,
}

/// Slab files and input digests kept for the frames of one run (a still is
/// a run of one frame). Not shared between threads: a sequence builds and
/// hashes its frames one after another.
#[derive(Default)]
pub struct InputCache {
    entries: RefCell<Entries>,
}

impl InputCache {
    /// An empty cache.
    pub fn new() -> InputCache {
        InputCache::default()
    }

    /// The slab at `path`: the kept one while the file is unchanged, else
    /// `read()` (kept when the file could be stamped).
    pub(crate) fn slab(
        &self,
        path: &Path,
        read: impl FnOnce() -> std::result::Result<LightSlab, String>,
    ) -> std::result::Result<Arc<LightSlab>, String> {
        let stamp = Stamp::of(path);
        let mut e = self.entries.borrow_mut();
        let frame = e.frame;
        if let Some(kept) = e.slabs.get_mut(path).filter(|k| Some(k.stamp) == stamp) {
            kept.used = frame;
            return Ok(kept.value.clone());
        }
        let slab = Arc::new(read()?);
        if let Some(stamp) = stamp {
            let kept = Kept {
                stamp,
                value: slab.clone(),
                used: frame,
            };
            e.slabs.insert(path.to_path_buf(), kept);
        }
        Ok(slab)
    }

    /// The digest of the file at `path`: the kept one while the file is
    /// unchanged; else `hash` of a kept slab's bytes (no second read), or of
    /// `read()`.
    pub fn digest(
        &self,
        path: &Path,
        read: impl FnOnce() -> Result<Vec<u8>>,
        hash: impl Fn(&[u8]) -> u64,
    ) -> Result<u64> {
        let stamp = Stamp::of(path);
        let mut e = self.entries.borrow_mut();
        let frame = e.frame;
        if let Some(kept) = e.digests.get_mut(path).filter(|k| Some(k.stamp) == stamp) {
            kept.used = frame;
            return Ok(kept.value);
        }
        let slab = e.slabs.get(path).filter(|k| Some(k.stamp) == stamp);
        let value = match slab {
            Some(kept) => hash(kept.value.file_bytes()),
            None => hash(&read()?),
        };
        if let Some(stamp) = stamp {
            let kept = Kept {
                stamp,
                value,
                used: frame,
            };
            e.digests.insert(path.to_path_buf(), kept);
        }
        Ok(value)
    }

    /// Ends a frame: drops what it did not use (the inputs of earlier frames
    /// only), keeps the rest for the next frame.
    pub fn end_frame(&self) {
        let mut e = self.entries.borrow_mut();
        let frame = e.frame;
        e.slabs.retain(|_, k| k.used == frame);
        e.digests.retain(|_, k| k.used == frame);
        e.frame += 1;
    }

    /// How many slabs and digests are kept (for tests).
    pub fn kept(&self) -> (usize, usize) {
        let e = self.entries.borrow();
        (e.slabs.len(), e.digests.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::slab::{Grid, SlabHeader};
    use crate::math::color::Rgb;
    use crate::math::{Bounds3, Vec3};

    /// Writes a 2 x 2 slab whose radiance is `level` to `path`.
    fn write_slab(path: &Path, level: f32) {
        let header = SlabHeader {
            bounds: Bounds3::new(Vec3::ZERO, Vec3::ONE),
            grid: Grid {
                spatial: 2,
                angular: 2,
            },
            spp: 1,
            seed: 0,
        };
        let (slab, _) = LightSlab::from_records(header, |_| (Rgb::splat(level), Rgb::WHITE));
        let mut f = std::fs::File::create(path).unwrap();
        slab.write_to(&mut f).unwrap();
    }

    fn read(path: &Path) -> std::result::Result<LightSlab, String> {
        LightSlab::read(path)
    }

    /// An unchanged slab is read once; its digest comes from the kept bytes;
    /// an edited file is read again; what a frame did not use is dropped.
    #[test]
    fn unchanged_slabs_are_kept_and_edited_or_unused_ones_are_not() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.slab"), dir.path().join("b.slab"));
        write_slab(&a, 1.0);
        write_slab(&b, 2.0);
        let cache = InputCache::new();
        let first = cache.slab(&a, || read(&a)).unwrap();
        let again = cache.slab(&a, || panic!("read twice")).unwrap();
        assert!(Arc::ptr_eq(&first, &again));
        let fnv = |d: &[u8]| d.iter().fold(7u64, |h, &x| h.wrapping_mul(31) ^ x as u64);
        let digest = cache
            .digest(&a, || panic!("slab bytes read again"), fnv)
            .unwrap();
        assert_eq!(digest, fnv(&std::fs::read(&a).unwrap()));
        cache.end_frame();
        assert_eq!(cache.kept(), (1, 1), "frame 0 used a.slab");
        cache.slab(&b, || read(&b)).unwrap();
        cache.end_frame();
        assert_eq!(cache.kept(), (1, 0), "frame 1 used b.slab only");
        // An edit (a longer file, so the stamp changes whatever the clock) is read again.
        let mut bytes = std::fs::read(&b).unwrap();
        bytes.push(0);
        std::fs::write(&b, &bytes).unwrap();
        let err = cache.slab(&b, || read(&b)).unwrap_err();
        assert!(err.contains("bytes long"), "{err}");
    }
}
