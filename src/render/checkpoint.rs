//! `--checkpoint SECONDS`: rewrite the outputs every so often during a long
//! render, so a crash or a kill loses at most that much work.
//!
//! Each checkpoint goes through the atomic writers of `image_io` (an old
//! file is replaced only by a complete new one) and is marked incomplete
//! (`brume:complete = 0`, `brume:spp` the samples so far); the final write
//! after the render replaces it.

use crate::error::Result;
use crate::film::image_io::{write_exr, write_png_tonemapped, Image};
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
        }
    }

    /// Called after each pass with the image so far (which `render_observed`
    /// marks partial, so the EXR says incomplete): writes it if it is time.
    pub fn pass_done(&mut self, image: &Image) -> Result<bool> {
        if self.last.elapsed() < self.every {
            return Ok(false);
        }
        write_exr(&self.exr, image)?;
        write_png_tonemapped(&self.png, image, self.exposure, self.tonemap)?;
        self.last = Instant::now();
        self.written += 1;
        Ok(true)
    }
}
