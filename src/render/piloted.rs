//! The passes of a piloted render (module `adaptive`): the pilot, kept out
//! of the image, then image passes of rising level, each pixel's samples
//! fixed by the plan before the pass starts.

use super::adaptive::{
    pilot_seed, pilot_spp, AdaptiveSettings, AutoChoice, NoiseReport, Plan, Spread, AUTO_GAIN,
    MAX_FACTOR,
};
use super::group::Group;
use super::run::{Piloted, Run};
use super::{Estimator, PassObserver};
use crate::film::PixelSums;
use std::sync::atomic::Ordering;

impl<E: Estimator> Run<'_, E> {
    /// Renders the pilot, then image passes until the plan's goal, the time
    /// budget or a stop request; under the automatic choice, the uniform
    /// passes instead when the pilot predicts too little gain.
    pub(super) fn piloted_passes(
        &mut self,
        mut on_pass: Option<PassObserver>,
        mut settings: AdaptiveSettings,
    ) {
        assert!(
            !self.job.estimator.splats() && self.job.estimator.pass_samples().is_none(),
            "adaptive sampling and noise targets take the path tracer's pixel samples only"
        );
        let (cap, pilot) = (self.cap(settings), pilot_spp(self.options.spp));
        let Some(plan) = self.plan_from_pilot(pilot, settings, cap) else {
            self.partial = true;
            self.bar.finish_and_clear();
            return;
        };
        if settings.auto && !settings.piloted() {
            if !self.choose_spread(&plan, pilot) {
                return self.uniform_passes(on_pass);
            }
            settings.adaptive = true;
        }
        let goal = self.goal(&plan, settings, pilot);
        let n = self.job.part.crop.area();
        self.begin(pilot, n, settings);
        let mut done = vec![0u32; n];
        let mut level = pilot as f64;
        loop {
            if self.cancel.load(Ordering::Relaxed) {
                self.partial = true;
                break;
            }
            let level_k = level.min(goal);
            let counts = plan.counts(level_k);
            let pass_start = std::time::Instant::now();
            if !self.image_pass(&done, &counts) {
                self.partial = true;
                break;
            }
            let pass_samples: u64 = counts
                .iter()
                .zip(&done)
                .map(|(&c, &d)| (c - d) as u64)
                .sum();
            done = counts;
            self.record(&plan, &done);
            if let Some(observe) = on_pass.as_mut() {
                let mut image = self.film.beauty_image();
                image.partial = true;
                observe(&image);
            }
            if level_k >= goal || done.iter().all(|&c| c >= cap) {
                break;
            }
            match self.next_level(&plan, level_k, pass_samples, pass_start.elapsed()) {
                Some(next) => level = next,
                None => break,
            }
        }
        self.bar.finish_and_clear();
    }

    /// The plan from a pilot of `pilot` spp (None when a stop request cut
    /// the pilot short); spread when adaptive or under the automatic choice.
    fn plan_from_pilot(
        &mut self,
        pilot: u32,
        settings: AdaptiveSettings,
        cap: u32,
    ) -> Option<Plan> {
        let pilot_sums = self.pilot(pilot)?;
        let w = self.job.part.crop.width() as usize;
        Some(Plan::new(&pilot_sums, w, Spread::of(&settings), pilot, cap))
    }

    /// The automatic choice: spread the samples by `plan` when its predicted
    /// gain reaches [`AUTO_GAIN`] (recorded either way).
    fn choose_spread(&mut self, plan: &Plan, pilot: u32) -> bool {
        let w = self.job.part.crop.width() as usize;
        let gain = plan.predicted_gain(w, self.options.spp);
        let spread = gain >= AUTO_GAIN;
        self.auto = Some(AutoChoice {
            pilot_spp: pilot,
            gain,
            spread,
        });
        spread
    }

    /// The level of the next pass: double this one's, or with a time budget
    /// as far as the time left allows at the last pass's rate (`took` for
    /// `pass_samples`); None when the time is spent.
    fn next_level(
        &self,
        plan: &Plan,
        level: f64,
        pass_samples: u64,
        took: std::time::Duration,
    ) -> Option<f64> {
        let Some(budget) = self.options.time_budget else {
            return Some(level * 2.0);
        };
        let left = budget.checked_sub(self.start.elapsed())?.as_secs_f64();
        let rate = pass_samples as f64 / took.as_secs_f64().max(1e-6);
        let allowed = (rate * left) as u64;
        let now = plan.total(level);
        let next = plan.level_within(level, 2.0 * level, now + allowed);
        (plan.total(next) > now).then_some(next)
    }

    /// Records that the pilot of `pilot` spp over `n` pixels is done.
    fn begin(&mut self, pilot: u32, n: usize, settings: AdaptiveSettings) {
        self.piloted = Some(Piloted {
            pilot_samples: pilot as u64 * n as u64,
            max_count: 0,
            report: NoiseReport {
                pilot_spp: pilot,
                adaptive: settings.adaptive,
                target: settings.noise,
                error: f64::INFINITY,
                min_spp: 0,
                mean_spp: 0.0,
                max_spp: 0,
            },
        });
    }

    /// The most image samples of a pixel: the spp with a noise target or a
    /// capped time budget, [`MAX_FACTOR`] times the spp when the spp is the
    /// mean to reach, unbounded when a time budget alone bounds the render.
    fn cap(&self, settings: AdaptiveSettings) -> u32 {
        let spp = self.options.spp;
        match (self.options.time_budget, self.options.spp_is_cap) {
            (Some(_), false) => u32::MAX / 2,
            (Some(_), true) => spp,
            (None, _) if settings.noise.is_some() => spp,
            (None, _) => spp.saturating_mul(MAX_FACTOR),
        }
    }

    /// The level the render aims at: where the noise target is met, the top
    /// for a time budget; under the automatic choice where the image costs
    /// what `spp` − pilot uniform samples per pixel would (the pilot's count
    /// of rays and lookups: a spread the user did not ask for takes about
    /// the uniform render's time, not more); else where the image and pilot
    /// samples together make `spp` per pixel on average.
    fn goal(&self, plan: &Plan, settings: AdaptiveSettings, pilot: u32) -> f64 {
        if let Some(target) = settings.noise {
            return plan.level_for_noise(target as f64);
        }
        if self.options.time_budget.is_some() {
            return plan.top_level();
        }
        let image_spp = self.options.spp.saturating_sub(pilot);
        if settings.auto {
            return plan.level_for_uniform_work(image_spp);
        }
        let pixels = self.job.part.crop.area() as u64;
        plan.level_for_budget(image_spp as u64 * pixels)
    }

    /// The pilot's sums: `spp` samples of every pixel from the pilot seed
    /// (None when a stop request cut it short).
    fn pilot(&mut self, spp: u32) -> Option<Vec<PixelSums>> {
        let schedule = vec![(0, spp); self.job.part.crop.area()];
        let finished = self.run_pass(&schedule, pilot_seed(self.job.scene.settings.seed), false);
        finished.then(|| std::mem::take(&mut self.bufs.sums))
    }

    /// Takes samples `done[i]..counts[i]` of every pixel into the film; false
    /// when a stop request cut the pass short (the pass is then dropped).
    fn image_pass(&mut self, done: &[u32], counts: &[u32]) -> bool {
        let start = self.job.part.samples.start;
        let schedule: Vec<(u32, u32)> = done
            .iter()
            .zip(counts)
            .map(|(&d, &c)| (start + d, c - d))
            .collect();
        let with_aovs = !self.aovs.is_empty();
        if !self.run_pass(&schedule, self.job.scene.settings.seed, with_aovs) {
            return false;
        }
        self.add_sums(0);
        true
    }

    /// Runs one pass of per-pixel `schedule` with streams of `seed`.
    fn run_pass(&mut self, schedule: &[(u32, u32)], seed: u64, with_aovs: bool) -> bool {
        let crop = self.job.part.crop;
        let group = Group {
            scene: self.job.scene,
            estimator: self.job.estimator,
            w: crop.width() as usize,
            h: crop.height() as usize,
            origin: (crop.x0, crop.y0),
            first: 0,
            counts: &[0],
            with_aovs,
            seed,
            per_pixel: Some(schedule),
            cancel: self.cancel,
            bar: &self.bar,
        };
        let (finished, rays) = group.render(&mut self.bufs);
        self.rays.merge(rays);
        finished == 1
    }

    /// Updates the report and the progress message after a pass.
    fn record(&mut self, plan: &Plan, counts: &[u32]) {
        let error = plan.error(counts);
        let piloted = self.piloted.as_mut().expect("a piloted render");
        let r = &mut piloted.report;
        r.error = error;
        r.min_spp = counts.iter().copied().min().unwrap_or(0);
        r.max_spp = counts.iter().copied().max().unwrap_or(0);
        r.mean_spp = counts.iter().map(|&c| c as f64).sum::<f64>() / counts.len().max(1) as f64;
        piloted.max_count = r.max_spp;
        self.bar.set_message(format!(
            "{:.1} spp (mean), estimated relative error {:.4}",
            r.mean_spp, r.error
        ));
    }
}
