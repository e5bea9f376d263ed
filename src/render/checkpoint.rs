//! `--checkpoint SECONDS`: rewrite the outputs every so often during a long
//! render, so a crash or a kill loses at most that much work.
//!
//! Each checkpoint goes through the atomic writers of `image_io` (an old
//! file is replaced only by a complete new one) and is marked incomplete
//! (`brume:complete = 0`, `brume:spp` the samples so far); the final write
//! after the render replaces it. A checkpoint is a partial image, so it
//! follows `output_safety::place_partial`: when the output holds a complete
//! image (or one of more samples) from an earlier render, checkpoints go to
//! `NAME.partial.exr` / `.png` beside it, which the complete final write
//! then removes.

use crate::error::Result;
use crate::film::image_io::{write_exr, write_png_tonemapped, Image};
use crate::film::output_safety::place_partial;
use crate::film::tonemap::Tonemap;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Writes the image so far when `every` has passed since the last write.
pub struct Checkpoint {
    every: Duration,
    last: Instant,
    exr: PathBuf,
    png: PathBuf,
    exposure: f32,
    tonemap: Tonemap,
    /// Checkpoints written so far.
    pub written: u32,
    /// Files written beside the outputs (not the outputs themselves).
    beside: Vec<PathBuf>,
    noted: bool,
}

impl Checkpoint {
    /// A checkpointer for the render's own outputs, starting its clock now.
    pub fn new(
        every: Duration,
        exr: PathBuf,
        png: PathBuf,
        exposure: f32,
        tonemap: Tonemap,
    ) -> Self {
        Checkpoint {
            every,
            last: Instant::now(),
            exr,
            png,
            exposure,
            tonemap,
            written: 0,
            beside: Vec::new(),
            noted: false,
        }
    }

    /// Called after each pass with the image so far (which `render_observed`
    /// marks partial, so the EXR says incomplete): writes it if it is time.
    pub fn pass_done(&mut self, image: &Image) -> Result<bool> {
        if self.last.elapsed() < self.every {
            return Ok(false);
        }
        let place = place_partial(&self.exr, Some(&self.png), image.spp);
        if let Some(note) = place.note().filter(|_| !self.noted) {
            // Once: the same files are kept at every checkpoint.
            eprintln!("note: --checkpoint: {note}");
            self.noted = true;
        }
        if let Some(exr) = &place.exr {
            write_exr(exr, image)?;
            if *exr != self.exr {
                self.beside.push(exr.clone());
            }
        }
        if let Some(png) = &place.png {
            write_png_tonemapped(png, image, self.exposure, self.tonemap)?;
            if *png != self.png {
                self.beside.push(png.clone());
            }
        }
        self.last = Instant::now();
        self.written += u32::from(place.exr.is_some());
        Ok(place.exr.is_some())
    }

    /// After the complete image is written to the outputs: removes the
    /// checkpoints this render wrote beside them (only those), now stale.
    pub fn remove_stale(&mut self) {
        self.beside.sort();
        self.beside.dedup();
        for path in self.beside.drain(..) {
            let _ = std::fs::remove_file(path);
        }
    }
}
