//! Training the path guide (`integrator::guiding`) before a guided render:
//! iterations of 1, 2, 4, … samples per pixel over the whole frame, rows
//! traced in parallel in chunks, each row's records deposited in row order.
//! The guide therefore depends on the seed only, never on the thread count,
//! and every piece of a split render trains the same one.

use crate::integrator::guiding::{train_row, Guide, Record, TRAINING_ITERATIONS};
use crate::integrator::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Rows traced between two deposits: bounds the records held at once.
const CHUNK_ROWS: u32 = 16;

/// A guide trained for `scene`, or `None` when `cancel` stopped the training.
/// Runs in the current rayon pool.
pub(super) fn train(scene: &Scene, cancel: &AtomicBool) -> Option<Guide> {
    let mut guide = Guide::new();
    for iteration in 0..TRAINING_ITERATIONS {
        let spp = 1 << iteration;
        // Paths sample from the guide as the last iteration left it, while
        // this one's records go into its building trees (one more copy in memory).
        let frozen = guide.clone();
        let sampling = (iteration > 0).then_some(&frozen);
        let height = scene.camera.height();
        let mut rows: Vec<Vec<Record>> = Vec::new();
        for first in (0..height).step_by(CHUNK_ROWS as usize) {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let last = (first + CHUNK_ROWS).min(height);
            (first..last)
                .into_par_iter()
                .map(|y| {
                    let mut out = Vec::new();
                    train_row(scene, sampling, (y, spp, iteration), &mut out);
                    out
                })
                .collect_into_vec(&mut rows);
            for row in &rows {
                guide.deposit(row);
            }
        }
        guide.finish_iteration(spp);
    }
    Some(guide)
}
