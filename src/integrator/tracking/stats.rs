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
    /// Rays ended by the cap ([`super::MAX_TENTATIVE_COLLISIONS`]).
    pub capped_rays: u64,
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
        self.capped_rays += other.capped_rays;
    }

    /// Medium lookups of either kind: tentative collisions and exact voxel steps.
    pub fn lookups(&self) -> u64 {
        self.collisions + self.voxel_steps
    }
}

const NO_STATS: TrackingStats = TrackingStats {
    collisions: 0,
    null_sum: 0.0,
    voxel_steps: 0,
    capped_rays: 0,
};

thread_local! {
    // Per thread, so counting costs no shared cache line, and a render counts
    // only its own rays (it takes the counts of the threads that rendered it);
    // flushed once per estimator call.
    static STATS: Cell<TrackingStats> = const { Cell::new(NO_STATS) };
}

/// This thread's medium lookups so far (see [`TrackingStats::lookups`]), left in place.
pub fn thread_lookups() -> u64 {
    STATS.with(|s| s.get().lookups())
}

/// Takes (and resets) this thread's tracking counts.
pub fn take_thread_stats() -> TrackingStats {
    STATS.with(|s| s.replace(NO_STATS))
}

/// Counts one ray ended by the cap on this thread (rare: not batched in a [`Tally`]).
pub(super) fn count_capped_ray() {
    STATS.with(|s| {
        let mut stats = s.get();
        stats.capped_rays += 1;
        s.set(stats);
    });
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
                let mut stats = s.get();
                stats.collisions += self.collisions as u64;
                stats.null_sum += self.null_sum as f64;
                stats.voxel_steps += self.voxel_steps as u64;
                s.set(stats);
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A render merges the counts of its rows: every field adds up.
    #[test]
    fn merge_adds_every_count() {
        let mut a = TrackingStats {
            collisions: 3,
            null_sum: 1.25,
            voxel_steps: 7,
            capped_rays: 1,
        };
        a.merge(TrackingStats {
            collisions: 10,
            null_sum: 0.5,
            voxel_steps: 20,
            capped_rays: 2,
        });
        let want = TrackingStats {
            collisions: 13,
            null_sum: 1.75,
            voxel_steps: 27,
            capped_rays: 3,
        };
        assert_eq!(a, want);
    }

    /// The null fraction is the mean null probability, 0 before any collision.
    #[test]
    fn null_fraction_is_the_mean_null_probability() {
        let stats = TrackingStats {
            collisions: 4,
            null_sum: 1.0,
            ..NO_STATS
        };
        assert_eq!(stats.null_fraction(), 0.25);
        assert_eq!(NO_STATS.null_fraction(), 0.0);
    }
}
