//! One parallel job over one or more passes of the crop: each work unit is
//! one row of one pass, summed pixel by pixel in sample order by the one
//! thread that runs it; splats are gathered per unit and added to the pass's
//! splat sums in unit order, so nothing depends on the thread count.

use crate::film::{PixelSums, Splat, Splats};
use crate::integrator::aov::{aov_sample, AovPixel};
use crate::integrator::estimator::Estimator;
use crate::integrator::tracking::{take_thread_stats, TrackingStats};
use crate::integrator::Scene;
use crate::sampling::PixelStreams;
use indicatif::ProgressBar;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The buffers of a group of passes, kept across groups so that a render
/// allocates them once.
#[derive(Default)]
pub(super) struct Buffers {
    /// Beauty sums, one `w`×`h` block per pass of the group.
    pub sums: Vec<PixelSums>,
    /// AOV sums in the same layout (empty without AOVs).
    pub aovs: Vec<AovPixel>,
    /// The splats of each unit of a batch.
    units: Vec<Vec<Splat>>,
    /// The splat sums of the group's one pass (splatting estimators only).
    pub pass_splats: Option<Splats>,
}

/// What a group renders: passes of `counts` samples from sample index `first`.
pub(super) struct Group<'a, E> {
    pub scene: &'a Scene,
    pub estimator: &'a E,
    /// Crop size.
    pub w: usize,
    pub h: usize,
    /// Top-left pixel of the crop.
    pub origin: (u32, u32),
    /// Index of the first sample of the first pass.
    pub first: u32,
    /// Samples of each pass (one pass when the estimator splats).
    pub counts: &'a [u32],
    /// Take the AOVs of every sample too.
    pub with_aovs: bool,
    /// The seed of the pixels' streams (the scene's, or a pilot's).
    pub seed: u64,
    /// Each pixel's own (first sample, count) of the group's one pass, row
    /// by row over the crop, instead of `first` and `counts` (adaptive passes).
    pub per_pixel: Option<&'a [(u32, u32)]>,
    pub cancel: &'a AtomicBool,
    pub bar: &'a ProgressBar,
}

/// One work unit: row `y` of pass `k`.
struct Unit<'b> {
    k: usize,
    y: usize,
    sums: &'b mut [PixelSums],
    aovs: Option<&'b mut [AovPixel]>,
}

/// Where each pass starts and how many of its rows are done.
struct Tally {
    firsts: Vec<u32>,
    rows_done: Vec<AtomicUsize>,
}

impl<E: Estimator> Group<'_, E> {
    /// Fills `bufs` for every pass of the group (in pass order); returns how
    /// many leading passes finished every row, and what their rays ran into.
    pub fn render(&self, bufs: &mut Buffers) -> (usize, RayCounts) {
        let n = self.counts.len() * self.w * self.h;
        bufs.sums.clear();
        bufs.sums.resize(n, PixelSums::default());
        bufs.aovs.clear();
        if self.with_aovs {
            bufs.aovs.resize(n, AovPixel::default());
        }
        let tally = Tally {
            firsts: self
                .counts
                .iter()
                .scan(self.first, |next, &c| {
                    let f = *next;
                    *next += c;
                    Some(f)
                })
                .collect(),
            rows_done: self.counts.iter().map(|_| AtomicUsize::new(0)).collect(),
        };
        let mut aov_rows = bufs.aovs.chunks_mut(self.w);
        let units: Vec<Unit> = bufs
            .sums
            .chunks_mut(self.w)
            .enumerate()
            .map(|(item, sums)| Unit {
                k: item / self.h,
                y: item % self.h,
                sums,
                aovs: aov_rows.next(),
            })
            .collect();
        let stats = match bufs.pass_splats.as_mut() {
            None => self.run(units, &tally),
            Some(pass_splats) => self.run_splatting(units, &tally, &mut bufs.units, pass_splats),
        };
        let finished = tally
            .rows_done
            .iter()
            .take_while(|r| r.load(Ordering::Relaxed) == self.h)
            .count();
        (finished, stats)
    }

    /// Runs every unit at once (no splats to keep in order).
    fn run(&self, units: Vec<Unit>, tally: &Tally) -> RayCounts {
        units
            .into_par_iter()
            // Rayon otherwise splits the rows into a few large blocks only
            // (one level per thread) and a thread that finishes its block
            // early finds nothing left to steal: the last pass of a group
            // is often shorter, so its block is cheaper (B4 at 87 spp: 1.80×
            // on two threads, 1.97× with small blocks).
            .with_max_len(4)
            .map_init(
                || (self.estimator.arena(), Vec::new()),
                |(arena, splats), mut unit| self.render_unit(&mut unit, tally, arena, splats),
            )
            .reduce(RayCounts::default, RayCounts::merged)
    }

    /// Runs the units in batches, adding each batch's splats to `pass_splats`
    /// in unit order; the batch size bounds the splats held at once and does
    /// not change the result (the order of additions is the unit order).
    fn run_splatting(
        &self,
        mut units: Vec<Unit>,
        tally: &Tally,
        buffers: &mut Vec<Vec<Splat>>,
        pass_splats: &mut Splats,
    ) -> RayCounts {
        pass_splats.clear();
        let batch = 16 * rayon::current_num_threads().max(1);
        if buffers.len() < batch {
            buffers.resize_with(batch, Vec::new);
        }
        let mut stats = RayCounts::default();
        for chunk in units.chunks_mut(batch) {
            if self.cancel.load(Ordering::Relaxed) {
                break;
            }
            let splats = &mut buffers[..chunk.len()];
            let counts = chunk
                .par_iter_mut()
                .zip(splats.par_iter_mut())
                .with_max_len(1)
                .map_init(
                    || self.estimator.arena(),
                    |arena, (unit, splats)| {
                        splats.clear();
                        self.render_unit(unit, tally, arena, splats)
                    },
                )
                .reduce(RayCounts::default, RayCounts::merged);
            stats.merge(counts);
            for unit_splats in splats.iter() {
                pass_splats.add(unit_splats);
            }
        }
        stats
    }

    /// Renders one row of one pass; a row cut short by `cancel` is not
    /// counted, so its pass is dropped whole.
    fn render_unit(
        &self,
        unit: &mut Unit,
        tally: &Tally,
        arena: &mut E::Arena,
        splats: &mut Vec<Splat>,
    ) -> RayCounts {
        if self.cancel.load(Ordering::Relaxed) {
            return RayCounts::default();
        }
        // A unit runs on one thread from start to end: its counts are the thread's.
        RayCounts::take_thread();
        let (x0, y0) = self.origin;
        let y = y0 + unit.y as u32;
        let pass = (tally.firsts[unit.k], self.counts[unit.k]);
        for (x, px) in unit.sums.iter_mut().enumerate() {
            let aov = unit.aovs.as_deref_mut().map(|a| &mut a[x]);
            let pixel = (x0 + x as u32, y);
            let samples = match self.per_pixel {
                Some(schedule) => schedule[unit.y * self.w + x],
                None => pass,
            };
            if !self.render_pixel(pixel, samples, px, aov, arena, splats) {
                return RayCounts::default();
            }
        }
        tally.rows_done[unit.k].fetch_add(1, Ordering::Relaxed);
        self.bar.inc(1);
        RayCounts::take_thread()
    }

    /// Sums samples `first..first + count` of `pixel` into `px` (and its
    /// AOVs into `aov`); false once `cancel` is set (checked before every
    /// sample, so a stop request is seen within one sample's time).
    #[inline]
    fn render_pixel(
        &self,
        (x, y): (u32, u32),
        (first, count): (u32, u32),
        px: &mut PixelSums,
        mut aov: Option<&mut AovPixel>,
        arena: &mut E::Arena,
        splats: &mut Vec<Splat>,
    ) -> bool {
        let mut sums = PixelSums::default();
        let lookups = crate::integrator::tracking::thread_lookups();
        let rays = crate::geometry::thread_rays();
        let streams = PixelStreams::new(self.scene.settings.sampler, self.seed, x, y);
        for s in first..first + count {
            if self.cancel.load(Ordering::Relaxed) {
                return false;
            }
            let l = self
                .estimator
                .sample(self.scene, (x, y), &streams, s, arena, splats);
            sums.add(l);
            if let Some(a) = aov.as_deref_mut() {
                a.add(&aov_sample(self.scene, x, y, &streams, s));
            }
        }
        sums.lookups = crate::integrator::tracking::thread_lookups() - lookups;
        sums.rays = crate::geometry::thread_rays().wrapping_sub(rays);
        *px = sums;
        true
    }
}

/// What the rays of a render ran into, counted per thread and merged: a
/// render reports its own rays only, whatever else runs in the process.
#[derive(Clone, Copy, Default)]
pub(super) struct RayCounts {
    pub tracking: TrackingStats,
    pub truncated_interiors: u64,
}

impl RayCounts {
    /// Takes (and resets) this thread's counts.
    fn take_thread() -> RayCounts {
        RayCounts {
            tracking: take_thread_stats(),
            truncated_interiors: crate::medium::interior::take_thread_truncated_queries(),
        }
    }

    /// Adds `other`'s counts.
    pub fn merge(&mut self, other: RayCounts) {
        self.tracking.merge(other.tracking);
        self.truncated_interiors += other.truncated_interiors;
    }

    fn merged(mut self, other: RayCounts) -> RayCounts {
        self.merge(other);
        self
    }
}
