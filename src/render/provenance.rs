//! A 64-bit fingerprint of what a render's samples depend on besides the seed
//! and the sample indices: the scene file's bytes, the digest of every file it
//! reads (OBJ meshes, textures, OpenVDB volumes, slabs; [`input_digest`]) and
//! the settings after command-line overrides. Pieces with different
//! fingerprints cannot be merged.
//!
//! Paths are not part of it, so a farm that mounts the scene elsewhere on each
//! machine still produces mergeable pieces. It guards against mistakes, not
//! against an adversary.

use crate::error::{Error, Result};
use crate::integrator::Settings;
use crate::sampling::mix64;
use crate::scene::description::MediumDesc;
use crate::scene::InputCache;
use rayon::prelude::*;
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
    frame_scene_hash_cached(file, settings, (frame, overrides), &InputCache::new())
}

/// [`frame_scene_hash`] taking the digests of unchanged inputs (and the bytes
/// of slabs the scene build read) from `cache`: a sequence hashes each
/// unchanged input once.
pub fn frame_scene_hash_cached(
    file: &Path,
    settings: &Settings,
    (frame, overrides): (Option<i64>, &[crate::scene::Override]),
    cache: &InputCache,
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
        hash.word(cache.digest(&path, || read(&path), input_digest)?);
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

/// Bytes per chunk of [`input_digest`]: chunks are hashed independently
/// (in parallel), so the digest depends on this size, never on the threads.
pub const DIGEST_CHUNK: usize = 1 << 20;
/// Independent lanes per chunk, each taking every fourth 8-byte word.
const LANES: usize = 4;

/// The digest of one input file's bytes (format 2 of the scene hash).
///
/// The bytes are cut into [`DIGEST_CHUNK`]-byte chunks; in each chunk four
/// lanes, started from four constants, take the little-endian words of
/// 32-byte blocks (lane k the k-th word; the last block zero-padded):
/// lane ← mix64(lane ⊕ word). The digest folds the length, then each
/// chunk's four lanes in order, through acc ← mix64(acc ⊕ value), and ends
/// with mix64. Every step is a bijection of the running state for fixed
/// inputs, so changing any one byte (same length) always changes the digest.
/// The lanes are independent chains (four multiplies in flight instead of
/// one) and the chunks independent tasks: a 24 MB slab hashes several times
/// faster than word by word.
pub fn input_digest(data: &[u8]) -> u64 {
    let lanes: Vec<[u64; LANES]> = data.par_chunks(DIGEST_CHUNK).map(chunk_lanes).collect();
    let mut acc = mix64(0x6272_756d_655f_6632 ^ data.len() as u64); // "brume_f2"
    for lane in lanes.iter().flatten() {
        acc = mix64(acc ^ lane);
    }
    mix64(acc)
}

/// The four lanes of one chunk.
fn chunk_lanes(chunk: &[u8]) -> [u64; LANES] {
    let mut lanes = [
        0x243f_6a88_85a3_08d3,
        0x1319_8a2e_0370_7344,
        0xa409_3822_299f_31d0,
        0x082e_fa98_ec4e_6c89,
    ];
    let mut blocks = chunk.chunks_exact(8 * LANES);
    let word = |b: &[u8], k: usize| u64::from_le_bytes(b[8 * k..8 * k + 8].try_into().unwrap());
    for block in &mut blocks {
        for (k, lane) in lanes.iter_mut().enumerate() {
            *lane = mix64(*lane ^ word(block, k));
        }
    }
    let rest = blocks.remainder();
    if !rest.is_empty() {
        let mut last = [0u8; 8 * LANES];
        last[..rest.len()].copy_from_slice(rest);
        for (k, lane) in lanes.iter_mut().enumerate() {
            *lane = mix64(*lane ^ word(&last, k));
        }
    }
    lanes
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

    /// Bytes over three chunks and a partial block, pseudo-random (no two
    /// chunks alike), so a shifted, dropped or reordered word shows.
    fn long_input() -> Vec<u8> {
        (0..3 * DIGEST_CHUNK as u64 + 13)
            .map(|i| (mix64(i) >> 24) as u8)
            .collect()
    }

    /// The digest of five bytes spelled out from its definition (one chunk,
    /// one zero-padded block, the length folded first), and of the long
    /// input pinned: a digest that moves breaks every stored scene hash.
    #[test]
    fn input_digest_matches_its_definition_and_known_value() {
        let seeds = [
            0x243f_6a88_85a3_08d3u64,
            0x1319_8a2e_0370_7344,
            0xa409_3822_299f_31d0,
            0x082e_fa98_ec4e_6c89,
        ];
        let words = [0x05_0403_0201u64, 0, 0, 0];
        let mut acc = mix64(0x6272_756d_655f_6632 ^ 5);
        for k in 0..4 {
            acc = mix64(acc ^ mix64(seeds[k] ^ words[k]));
        }
        assert_eq!(input_digest(&[1, 2, 3, 4, 5]), mix64(acc));
        assert_eq!(input_digest(&[]), mix64(mix64(0x6272_756d_655f_6632)));
        assert_eq!(input_digest(&long_input()), LONG_INPUT_DIGEST);
    }

    /// Format 2's digest of [`long_input`].
    const LONG_INPUT_DIGEST: u64 = 0x7e7a_56ff_3e1e_b9d3;

    /// One byte changed anywhere (first, either side of a chunk boundary,
    /// the padded tail) changes the digest, and so do an appended zero and
    /// two chunks swapped; a one-thread pool gives the same digest.
    #[test]
    fn input_digest_sees_every_byte_and_not_the_threads() {
        let data = long_input();
        let d = input_digest(&data);
        for at in [
            0,
            7,
            DIGEST_CHUNK - 1,
            DIGEST_CHUNK,
            2 * DIGEST_CHUNK + 40,
            data.len() - 1,
        ] {
            let mut changed = data.clone();
            changed[at] ^= 0x10;
            assert_ne!(input_digest(&changed), d, "byte {at} changed");
        }
        let mut longer = data.clone();
        longer.push(0);
        assert_ne!(input_digest(&longer), d);
        let mut swapped = data[DIGEST_CHUNK..2 * DIGEST_CHUNK].to_vec();
        swapped.extend_from_slice(&data[..DIGEST_CHUNK]);
        swapped.extend_from_slice(&data[2 * DIGEST_CHUNK..]);
        assert_ne!(input_digest(&swapped), d);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert_eq!(pool.install(|| input_digest(&data)), d);
    }
}
