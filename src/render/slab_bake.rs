//! `brume slab bake`: every recorded line of a light slab estimated in
//! parallel, in passes, under the render's budget, progress and cancellation.

use super::RenderOptions;
use crate::geometry::slab::{LightSlab, Param, SlabHeader};
use crate::integrator::slab_record::{self, RecordSums};
use crate::integrator::Scene;
use crate::math::color::Rgb;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Records estimated between two looks at the stop flag and the progress bar.
const CHUNK: usize = 256;
/// Most samples per line in one pass: a chunk of a pass stays short enough
/// for a stop request to be seen within a second, however large `--spp` is.
const PASS_SAMPLES: u32 = 8;

/// What a bake produced.
pub struct BakeOutput {
    /// The slab, or `None` when the bake was stopped (nothing to write).
    pub slab: Option<LightSlab>,
    /// Samples per line reached.
    pub spp: u32,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Samples that were NaN or infinite and were left out.
    pub nonfinite: u64,
    /// Recorded values beyond the half-float range, clamped to its largest value.
    pub clamped: u64,
}

/// Bytes a bake of `records` lines holds at its peak: per-record sums and
/// counts, then the half-float records.
pub fn bake_peak_bytes(records: u64) -> u128 {
    records as u128 * (6 * 4 + 4 + 12)
}

/// Bakes the box and grid of `header` (its `spp` is replaced by the samples
/// reached) from `scene`: passes of up to 8 samples per line until
/// `options.spp`, or of one sample under a time budget. A stop request drops the pass under way and
/// the bake returns no slab: a slab of fewer samples is never written.
pub fn bake(
    scene: &Scene,
    header: SlabHeader,
    options: &RenderOptions,
    cancel: &AtomicBool,
) -> BakeOutput {
    let start = Instant::now();
    let param = Param::new(header.bounds, header.grid);
    let n = header.grid.records() as usize;
    let mut sums = vec![(Rgb::BLACK, Rgb::BLACK, 0u32, 0u32); n];
    let pass = match options.time_budget {
        Some(_) => 1,
        None => options.spp.min(PASS_SAMPLES),
    };
    let bar = progress_bar(options, n as u64 * options.spp.div_ceil(pass) as u64);
    let pool = super::thread_pool(options);
    let mut spp = 0u32;
    let stopped = pool.install(|| loop {
        if budget_spent(options, spp, start) {
            return false;
        }
        let samples = spp..spp.saturating_add(pass).min(match options.time_budget {
            Some(_) => u32::MAX,
            None => options.spp,
        });
        let context = (scene, &param, header.seed);
        if !bake_pass(context, &mut sums, samples.clone(), (options, &bar, cancel)) {
            return true;
        }
        spp = samples.end;
        bar.set_message(format!("{spp} spp"));
    });
    bar.finish_and_clear();
    let nonfinite = sums.iter().map(|s| s.3 as u64).sum();
    let elapsed = start.elapsed();
    if stopped || spp == 0 {
        return BakeOutput {
            slab: None,
            spp,
            elapsed,
            nonfinite,
            clamped: 0,
        };
    }
    let header = SlabHeader { spp, ..header };
    let (slab, clamped) = LightSlab::from_records(header, |i| {
        let (l, t, count, _) = sums[i as usize];
        let k = 1.0 / count.max(1) as f32;
        (l * k, t * k)
    });
    BakeOutput {
        slab: Some(slab),
        spp,
        elapsed,
        nonfinite,
        clamped,
    }
}

/// Adds the samples `samples` of every line to `sums`, in parallel chunks;
/// false when a stop request cut the pass short (the sums are then unfinished).
fn bake_pass(
    context: (&Scene, &Param, u64),
    sums: &mut [(Rgb, Rgb, u32, u32)],
    samples: std::ops::Range<u32>,
    (options, bar, cancel): (&RenderOptions, &ProgressBar, &AtomicBool),
) -> bool {
    let finished = AtomicBool::new(true);
    sums.par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, chunk)| {
            if cancel.load(Ordering::Relaxed) {
                finished.store(false, Ordering::Relaxed);
                return;
            }
            add_samples(context, c * CHUNK, chunk, samples.clone());
            if options.time_budget.is_none() {
                bar.inc(chunk.len() as u64);
            }
        });
    finished.load(Ordering::Relaxed) && !cancel.load(Ordering::Relaxed)
}

/// The bar of a bake: `steps` record-passes, or a spinner under a time budget.
fn progress_bar(options: &RenderOptions, steps: u64) -> ProgressBar {
    if !options.progress {
        return ProgressBar::hidden();
    }
    let (bar, template) = match options.time_budget {
        Some(_) => (
            ProgressBar::new_spinner(),
            "{spinner} {elapsed_precise} {msg}",
        ),
        None => (
            ProgressBar::new(steps),
            "{bar:40} {percent:>3}% of the lines {elapsed_precise} eta {eta}",
        ),
    };
    bar.set_draw_target(ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// True once the bake has its samples or its time.
fn budget_spent(options: &RenderOptions, spp: u32, start: Instant) -> bool {
    match options.time_budget {
        None => spp >= options.spp,
        Some(budget) => (options.spp_is_cap && spp >= options.spp) || start.elapsed() >= budget,
    }
}

/// Adds samples `samples` of records `first..first + chunk.len()` to their sums.
fn add_samples(
    (scene, param, seed): (&Scene, &Param, u64),
    first: usize,
    chunk: &mut [(Rgb, Rgb, u32, u32)],
    samples: std::ops::Range<u32>,
) {
    let bounds = param.bounds();
    for (k, sum) in chunk.iter_mut().enumerate() {
        let record = (first + k) as u64;
        let line = param.line(record);
        let s: RecordSums =
            slab_record::estimate(scene, &bounds, line, (samples.clone(), seed, record));
        sum.0 += s.radiance;
        sum.1 += s.transmittance;
        sum.2 += s.samples;
        sum.3 += s.nonfinite;
    }
}
