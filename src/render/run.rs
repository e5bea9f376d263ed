//! One render from its first pass to its film: groups of passes while the
//! budget lasts, each finished pass added to the film in pass order.

use super::adaptive::{AutoChoice, NoiseReport, AUTO_MIN_SPP};
use super::group::{Buffers, Group, RayCounts};
use super::Refused;
use super::{pass_pixel_bytes, Estimator, Job, PassObserver, RenderOptions, RenderOutput};
use crate::film::{Film, SampleRange};
use crate::integrator::aov::Aov;
use crate::integrator::estimator::Prepared;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A render between passes: the film so far and the buffers of the next group.
pub(super) struct Run<'a, E> {
    pub(super) job: &'a Job<'a, E>,
    pub(super) options: &'a RenderOptions,
    pub(super) cancel: &'a AtomicBool,
    /// The AOV of each film layer after the beauty.
    pub(super) aovs: Vec<Aov>,
    pub(super) film: Film,
    pub(super) bufs: Buffers,
    pub(super) bar: ProgressBar,
    pub(super) start: Instant,
    pub(super) spp_done: u32,
    pub(super) partial: bool,
    /// Why the estimator refused a pass, when it did (the render ends there).
    refused: Option<Refused>,
    pub(super) rays: RayCounts,
    /// A piloted render's samples and estimates (module `adaptive`).
    pub(super) piloted: Option<Piloted>,
    /// What the automatic choice made of its pilot.
    pub(super) auto: Option<AutoChoice>,
}

/// What a piloted render has taken so far.
pub(super) struct Piloted {
    /// Image samples of the pixel that holds the most.
    pub max_count: u32,
    /// The report so far.
    pub report: NoiseReport,
}

impl<'a, E: Estimator> Run<'a, E> {
    /// A render of `job` that has taken no sample yet.
    pub fn new(job: &'a Job<'a, E>, options: &'a RenderOptions, cancel: &'a AtomicBool) -> Self {
        let film = job.new_film();
        let aovs = film.layers[1..].iter().filter_map(|l| l.aov()).collect();
        let mut bufs = Buffers::default();
        if let Some(s) = &film.splats {
            bufs.pass_splats = Some(s.clone());
        }
        Run {
            job,
            options,
            cancel,
            aovs,
            film,
            bufs,
            bar: progress_bar(
                options,
                job.part.crop.height() as u64,
                job.estimator.pass_samples(),
                job.scene.settings.adaptive.piloted() || job.scene.settings.adaptive.auto,
            ),
            start: Instant::now(),
            spp_done: 0,
            partial: false,
            refused: None,
            rays: RayCounts::default(),
            piloted: None,
            auto: None,
        }
    }

    /// True while the spp or time budget allows another pass.
    fn budget_left(&self) -> bool {
        let (options, done) = (self.options, self.spp_done);
        match options.time_budget {
            // A time budget always gets its first pass: no render ends with 0 samples.
            Some(t) => {
                (done == 0 || self.start.elapsed() < t)
                    && (!options.spp_is_cap || done < options.spp)
            }
            None => done < options.spp,
        }
    }

    /// Renders the image: piloted when adaptive sampling or a noise target
    /// was asked for, or when the automatic choice may take a pilot.
    pub fn passes(&mut self, on_pass: Option<PassObserver>) {
        let adaptive = self.job.scene.settings.adaptive;
        if adaptive.piloted() || (adaptive.auto && self.may_pilot()) {
            return self.piloted_passes(on_pass, adaptive);
        }
        self.uniform_passes(on_pass);
    }

    /// True when the automatic choice takes a pilot: a whole frame's pixel
    /// samples from 0 (not a piece of a split render, not splats or
    /// prepared passes), at least [`AUTO_MIN_SPP`] of them.
    fn may_pilot(&self) -> bool {
        let (part, estimator) = (self.job.part, self.job.estimator);
        let whole = super::Part::whole(self.job.scene, self.options.spp);
        part.crop == whole.crop
            && part.samples.start == 0
            && self.options.spp >= AUTO_MIN_SPP
            && !estimator.splats()
            && estimator.pass_samples().is_none()
    }

    /// Renders groups of the same samples in every pixel until the budget is
    /// spent or `cancel` is set.
    pub(super) fn uniform_passes(&mut self, mut on_pass: Option<PassObserver>) {
        let prepared = self.job.estimator.pass_samples();
        let pass_spp = prepared.unwrap_or_else(|| pass_size(self.options));
        let crop = self.job.part.crop;
        let (w, h) = (crop.width() as usize, crop.height() as usize);
        // Observers look at the image after every pass; splats are kept per
        // pass; a prepared pass is prepared for its own samples only.
        let one_pass = on_pass.is_some() || self.job.estimator.splats() || prepared.is_some();
        let group_pixels = GROUP_BYTES / pass_pixel_bytes(!self.aovs.is_empty());
        while self.budget_left() {
            if self.cancel.load(Ordering::Relaxed) {
                self.partial = true;
                break;
            }
            let counts = group_counts(
                self.options,
                pass_spp,
                self.spp_done,
                one_pass,
                w * h,
                group_pixels,
            );
            let first = self.job.part.samples.start + self.spp_done;
            if prepared.is_some() && !self.prepare(first, counts[0]) {
                self.partial = true;
                break;
            }
            let group = Group {
                scene: self.job.scene,
                estimator: self.job.estimator,
                w,
                h,
                origin: (crop.x0, crop.y0),
                first,
                counts: &counts,
                with_aovs: !self.aovs.is_empty(),
                seed: self.job.scene.settings.seed,
                per_pixel: None,
                cancel: self.cancel,
                bar: &self.bar,
            };
            let (finished, rays) = group.render(&mut self.bufs);
            self.rays.merge(rays);
            self.keep_finished(&counts[..finished], &mut on_pass);
            if finished < counts.len() {
                self.partial = true;
                break;
            }
        }
        self.bar.finish_and_clear();
    }

    /// Adds the passes of a group that finished (`counts` of them), showing
    /// each to the observer. A pass cut short is dropped whole, so every pixel
    /// of the image has exactly `spp_done` samples; a pass that finished is
    /// kept even if the stop request came in just after its last row.
    fn keep_finished(&mut self, counts: &[u32], on_pass: &mut Option<PassObserver>) {
        for (k, &count) in counts.iter().enumerate() {
            self.add_pass(k, count);
            if let Some(observe) = on_pass.as_mut() {
                let mut image = self.film.beauty_image();
                image.partial = true;
                observe(&image);
            }
        }
        self.bar.set_message(format!("{} spp", self.spp_done));
    }

    /// Runs the estimator's preparation of samples `first..first + count`;
    /// false when a stop request cut it short or the estimator refused (kept
    /// in `refused`).
    fn prepare(&mut self, first: u32, count: u32) -> bool {
        for s in first..first + count {
            match self.job.estimator.prepare(self.job.scene, s, self.cancel) {
                Prepared::Ready => {}
                Prepared::Stopped => return false,
                Prepared::Refused { key, message } => {
                    self.refused = Some(Refused { key, message });
                    return false;
                }
            }
        }
        true
    }

    /// Adds pass `k` of the group's buffers (`count` samples) to the film.
    fn add_pass(&mut self, k: usize, count: u32) {
        self.add_sums(k);
        self.spp_done += count;
        let start = self.job.part.samples.start;
        self.film.provenance.held = vec![SampleRange::new(start, start + self.spp_done)];
    }

    /// Adds pass `k` of the group's buffers to the film's sums and counts.
    pub(super) fn add_sums(&mut self, k: usize) {
        let film = &mut self.film;
        let n = film.window.area();
        let pass = &self.bufs.sums[k * n..(k + 1) * n];
        let squares = film.squares.as_mut().expect("a render keeps the squares");
        for (i, p) in pass.iter().enumerate() {
            for c in 0..3 {
                film.layers[0].sums[3 * i + c] += p.sum[c];
                squares[3 * i + c] += p.squares[c];
            }
            film.counts[i] += p.count;
            film.nonfinite[i] += p.nonfinite;
        }
        if !self.aovs.is_empty() {
            let aovs = &self.bufs.aovs[k * n..(k + 1) * n];
            for (layer, &aov) in film.layers[1..].iter_mut().zip(&self.aovs) {
                let k = layer.channels.len();
                let counts = layer
                    .counts
                    .as_mut()
                    .expect("AOV layers count their own samples");
                for (i, a) in aovs.iter().enumerate() {
                    a.add_into(aov, &mut layer.sums[i * k..(i + 1) * k], &mut counts[i]);
                }
            }
        }
        if let (Some(to), Some(from)) = (film.splats.as_mut(), self.bufs.pass_splats.as_ref()) {
            to.add_sums(from);
        }
    }

    /// The film with its final provenance, the image and the statistics.
    pub fn finish(mut self) -> RenderOutput {
        let part = self.job.part;
        if let Some(p) = &self.piloted {
            // Each pixel holds the first `counts[i]` of samples 0..max_count (brume:count).
            self.spp_done = p.max_count;
            self.film.adaptive = Some(p.report.header());
        }
        let held = SampleRange::new(part.samples.start, part.samples.start + self.spp_done);
        // A timed render asks for what it reaches; only a stopped one falls short.
        let requested = match self.partial {
            true => SampleRange::new(part.samples.start, part.samples.end.max(held.end)),
            false => held,
        };
        let provenance = &mut self.film.provenance;
        provenance.spp_total = requested.end;
        provenance.requested = vec![requested];
        provenance.held = if held.is_empty() { vec![] } else { vec![held] };
        let mut image = match self.spp_done {
            // Stopped before the first pass: the image is black, and only
            // the exit waits for it (the film's means took 0.4 s at 4096²).
            0 => self.film.black_image(),
            _ => self.film.beauty_image(),
        };
        image.partial = self.partial;
        // The pilot's samples are the image's first (module `class_plans`).
        let samples = match &self.piloted {
            Some(_) => {
                self.film.counts.iter().map(|&n| n as u64).sum::<u64>()
                    + self.film.nonfinite.iter().map(|&n| n as u64).sum::<u64>()
            }
            None => self.spp_done as u64 * part.crop.area() as u64,
        };
        RenderOutput {
            image,
            nonfinite_samples: self.film.nonfinite.iter().map(|&n| n as u64).sum(),
            samples,
            noise: self.piloted.map(|p| p.report),
            auto: self.auto,
            film: self.film,
            elapsed: self.start.elapsed(),
            tracking: self.rays.tracking,
            truncated_interiors: self.rays.truncated_interiors,
            mlt: None,
            refused: self.refused,
        }
    }
}

/// Bytes of pass buffers a group of passes may hold at once.
pub(super) const GROUP_BYTES: usize = 32 << 20;

/// The spp of each pass of the next group: one pass with a time budget or
/// when `one_pass` (an observer looks at the image after every pass, or the
/// estimator splats), otherwise as many as fit in `group_pixels`, so that the
/// threads meet once per group instead of once per pass (each meeting idles
/// all but the slowest thread).
fn group_counts(
    options: &RenderOptions,
    pass_spp: u32,
    spp_done: u32,
    one_pass: bool,
    pixels: usize,
    group_pixels: usize,
) -> Vec<u32> {
    if options.time_budget.is_some() {
        let count = match options.spp_is_cap {
            true => pass_spp.min(options.spp - spp_done),
            false => pass_spp,
        };
        return vec![count];
    }
    let most = if one_pass {
        1
    } else {
        (group_pixels / pixels.max(1)).max(1)
    };
    let mut counts = Vec::new();
    let mut done = spp_done;
    while done < options.spp && counts.len() < most {
        let count = pass_spp.min(options.spp - done);
        counts.push(count);
        done += count;
    }
    counts
}

/// Samples per pass: all at once without a time budget (in chunks for progress), small passes with one.
fn pass_size(options: &RenderOptions) -> u32 {
    match options.time_budget {
        Some(_) => 4,
        None => options.spp.clamp(1, 16),
    }
}

/// The bar of a render of `rows` rows per pass, its passes of `pass_samples`
/// (or [`pass_size`]); a spinner when the length is unknown (timed or piloted).
fn progress_bar(
    options: &RenderOptions,
    rows: u64,
    pass_samples: Option<u32>,
    piloted: bool,
) -> ProgressBar {
    if !options.progress {
        return ProgressBar::hidden();
    }
    let spinner = options.time_budget.is_some() || piloted;
    let bar = match spinner {
        true => ProgressBar::new_spinner(),
        false => {
            let pass = pass_samples.unwrap_or_else(|| pass_size(options));
            ProgressBar::new(rows * options.spp.div_ceil(pass) as u64)
        }
    };
    bar.set_draw_target(ProgressDrawTarget::stderr());
    let template = if spinner {
        "{spinner} {elapsed_precise} {msg}"
    } else {
        "{bar:40} {percent:>3}% {elapsed_precise} eta {eta} {msg}"
    };
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}
