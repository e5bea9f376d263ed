//! Per-thread counts of tentative collisions, for the benchmark report.

use std::cell::Cell;

/// Tentative collisions taken by tracking, for the benchmark report.
///
/// `null_sum` adds up 1 - max σt/σ̄ over every tentative collision (free
/// flights and shadow rays): its mean is the null-collision fraction, the
/// share of lookups a tighter majorant would have saved.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackingStats {
    /// Tentative collisions (one medium lookup each).
    pub collisions: u64,
    /// Sum of the null-collision probabilities.
    pub null_sum: f64,
    /// Voxel cells integrated exactly (one corner fetch each; see `medium::voxel`).
    pub voxel_steps: u64,
}

impl TrackingStats {
    /// Mean null-collision probability (0 without collisions).
    pub fn null_fraction(&self) -> f64 {
        if self.collisions == 0 {
            0.0
        } else {
            self.null_sum / self.collisions as f64
        }
    }

    /// Adds another count.
    pub fn merge(&mut self, other: TrackingStats) {
        self.collisions += other.collisions;
        self.null_sum += other.null_sum;
        self.voxel_steps += other.voxel_steps;
    }

    /// Medium lookups of either kind: tentative collisions and exact voxel steps.
    pub fn lookups(&self) -> u64 {
        self.collisions + self.voxel_steps
    }
}

thread_local! {
    // Per thread, so counting costs no shared cache line; flushed once per estimator call.
    static STATS: Cell<(u64, f64, u64)> = const { Cell::new((0, 0.0, 0)) };
}

/// Takes (and resets) this thread's tracking counts.
pub fn take_thread_stats() -> TrackingStats {
    let (collisions, null_sum, voxel_steps) = STATS.with(|s| s.replace((0, 0.0, 0)));
    TrackingStats {
        collisions,
        null_sum,
        voxel_steps,
    }
}

/// Local tally of one estimator call, flushed to the thread's counts on drop.
#[derive(Default)]
pub(super) struct Tally {
    collisions: u32,
    null_sum: f32,
    voxel_steps: u32,
}

impl Tally {
    #[inline]
    pub(super) fn add(&mut self, sigma_t_max: f32, sigma_maj: f32) {
        self.collisions += 1;
        self.null_sum += (1.0 - sigma_t_max / sigma_maj).clamp(0.0, 1.0);
    }

    #[inline]
    pub(super) fn voxel(&mut self) {
        self.voxel_steps += 1;
    }
}

impl Drop for Tally {
    fn drop(&mut self) {
        if self.collisions > 0 || self.voxel_steps > 0 {
            STATS.with(|s| {
                let (n, sum, v) = s.get();
                s.set((
                    n + self.collisions as u64,
                    sum + self.null_sum as f64,
                    v + self.voxel_steps as u64,
                ));
            });
        }
    }
}
