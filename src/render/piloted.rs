//! The passes of a piloted render (module `adaptive`): the pilot, the first
//! samples of every pixel's stream and part of the image, then image passes
//! of rising level, each pixel's samples fixed by its colour's plan (module
//! `class_plans`) before the pass starts.

use super::adaptive::{
    pilot_spp, spread_share, AdaptiveSettings, AutoChoice, NoiseReport, Plan, Spread, MAX_FACTOR,
};
use super::class_plans::{predicted_gain, ClassPlans};
use super::group::Group;
use super::run::{Piloted, Run};
use super::{Estimator, PassObserver};
use crate::film::PixelSums;
use std::sync::atomic::Ordering;

impl<E: Estimator> Run<'_, E> {
    /// Renders the pilot, then image passes until the plans' goals, the time
    /// budget or a stop request; under the automatic choice, uniform passes
    /// from the pilot on when neither colour's pilot predicts enough gain.
    pub(super) fn piloted_passes(
        &mut self,
        on_pass: Option<PassObserver>,
        mut settings: AdaptiveSettings,
    ) {
        assert!(
            !self.job.estimator.splats() && self.job.estimator.pass_samples().is_none(),
            "adaptive sampling and noise targets take the path tracer's pixel samples only"
        );
        let (cap, pilot) = (self.cap(settings), pilot_spp(self.options.spp));
        let auto = settings.auto && !settings.piloted();
        let Some((gains, mut plans)) = self.plans_from_pilot(pilot, settings, cap, auto) else {
            self.partial = true;
            self.bar.finish_and_clear();
            return;
        };
        if let Some(gains) = gains {
            if !self.choose_spread(&mut plans, gains, pilot) {
                // The pilot's samples are the uniform image's first ones.
                self.spp_done = pilot;
                return self.uniform_passes(on_pass);
            }
            settings.adaptive = true;
        }
        plans.set_goals(|plan| self.goal(plan, settings));
        self.begin(&plans, pilot, settings);
        self.image_passes(&plans, (pilot, cap), on_pass);
        self.bar.finish_and_clear();
    }

    /// Image passes of rising level from the pilot's `pilot` samples per
    /// pixel to the plans' goal, the time budget, a stop request or every
    /// pixel at `cap`.
    fn image_passes(
        &mut self,
        plans: &ClassPlans,
        (pilot, cap): (u32, u32),
        mut on_pass: Option<PassObserver>,
    ) {
        let goal = plans.goal();
        let mut done = vec![pilot; self.job.part.crop.area()];
        let mut level = pilot as f64;
        loop {
            if self.cancel.load(Ordering::Relaxed) {
                self.partial = true;
                break;
            }
            let level_k = level.min(goal);
            let counts = plans.counts(level_k);
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
            self.record(plans, &done);
            if let Some(observe) = on_pass.as_mut() {
                let mut image = self.film.beauty_image();
                image.partial = true;
                observe(&image);
            }
            if level_k >= goal || done.iter().all(|&c| c >= cap) {
                break;
            }
            match self.next_level(plans, level_k, pass_samples, pass_start.elapsed()) {
                Some(next) => level = next,
                None => break,
            }
        }
    }

    /// The two colours' plans from a pilot of `pilot` spp, taken into the
    /// image, with each colour's predicted gain from spreading when `auto`
    /// (None when a stop request cut the pilot short or came while
    /// planning: a stop is looked at between the plans, so that a large
    /// frame's planning answers it soon; nothing is then written, as when
    /// the pilot itself was cut). Spread when adaptive or under the
    /// automatic choice. The gains are judged first, so that at most the
    /// pilot, one judging plan and then the two plans are held at once.
    fn plans_from_pilot(
        &mut self,
        pilot: u32,
        settings: AdaptiveSettings,
        cap: u32,
        auto: bool,
    ) -> Option<(Option<[f64; 2]>, ClassPlans)> {
        let sums = self.pilot(pilot)?;
        let w = self.job.part.crop.width() as usize;
        let spp = self.options.spp;
        let stopped = || self.cancel.load(Ordering::Relaxed);
        let mut gains = [0.0; 2];
        for (c, gain) in gains.iter_mut().enumerate().filter(|_| auto) {
            if stopped() {
                return None;
            }
            *gain = predicted_gain(&sums, w, c, spp, (pilot, cap));
        }
        if stopped() {
            return None;
        }
        let plans = ClassPlans::new(&sums, w, Spread::of(&settings), pilot, cap);
        (!stopped()).then_some((auto.then_some(gains), plans))
    }

    /// The automatic choice, colour by colour: a colour's samples are spread
    /// by its plan in the share [`spread_share`] of its predicted gain (none
    /// below `AUTO_GAIN`, all from `FULL_GAIN`), else kept uniform
    /// (recorded: the mean gain, spread if either colour is). False when
    /// neither colour spreads.
    fn choose_spread(&mut self, plans: &mut ClassPlans, gains: [f64; 2], pilot: u32) -> bool {
        for (c, &gain) in gains.iter().enumerate() {
            plans.spread_by(c, spread_share(gain));
        }
        let spread = gains.iter().any(|&g| spread_share(g) > 0.0);
        self.auto = Some(AutoChoice {
            pilot_spp: pilot,
            gain: 0.5 * (gains[0] + gains[1]),
            spread,
        });
        spread
    }

    /// The level of the next pass: double this one's, or with a time budget
    /// as far as the time left allows at the last pass's rate (`took` for
    /// `pass_samples`); None when the time is spent.
    fn next_level(
        &self,
        plan: &ClassPlans,
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

    /// Records that the pilot of `pilot` spp is done: the image holds its samples.
    fn begin(&mut self, plans: &ClassPlans, pilot: u32, settings: AdaptiveSettings) {
        self.piloted = Some(Piloted {
            max_count: pilot,
            report: NoiseReport {
                pilot_spp: pilot,
                adaptive: settings.adaptive,
                target: settings.noise,
                error: f64::INFINITY,
                min_spp: pilot,
                mean_spp: pilot as f64,
                max_spp: pilot,
            },
        });
        self.record(plans, &vec![pilot; self.job.part.crop.area()]);
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

    /// The level a colour's `plan` aims at: where the noise target is met,
    /// the top for a time budget; under the automatic choice where the image
    /// costs what `spp` uniform samples per pixel would (the pilot's count of
    /// rays and lookups: a spread the user did not ask for takes about the
    /// uniform render's time, not more); else where the samples, the
    /// pilot's among them, make `spp` per pixel on average.
    fn goal(&self, plan: &Plan, settings: AdaptiveSettings) -> f64 {
        if let Some(target) = settings.noise {
            return plan.level_for_noise(target as f64);
        }
        if self.options.time_budget.is_some() {
            return plan.top_level();
        }
        let spp = self.options.spp;
        if settings.auto {
            return plan.level_for_uniform_work(spp);
        }
        plan.level_for_budget(spp as u64 * plan.member_count() as u64)
    }

    /// The pilot: the first `spp` samples of every pixel's stream, added to
    /// the film; their sums (None when a stop request cut it short).
    fn pilot(&mut self, spp: u32) -> Option<Vec<PixelSums>> {
        let start = self.job.part.samples.start;
        let schedule = vec![(start, spp); self.job.part.crop.area()];
        let with_aovs = !self.aovs.is_empty();
        if !self.run_pass(&schedule, self.job.scene.settings.seed, with_aovs) {
            return None;
        }
        self.add_sums(0);
        let mut sums = std::mem::take(&mut self.bufs.sums);
        sums.truncate(self.job.part.crop.area());
        Some(sums)
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
    fn record(&mut self, plan: &ClassPlans, counts: &[u32]) {
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
