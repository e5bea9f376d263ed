//! The Metropolis driver: the bootstrap, then passes of one mutation per
//! pixel over all chains, each pass's splats added to the one film in chain
//! order (so the image does not depend on the thread count).
//!
//! It honours the spp (mutations per pixel) and time budgets, the stop
//! request (looked at every few dozen mutations: a pass cut short is
//! dropped whole), the progress bar and the pass observer (live display,
//! checkpoints). It renders whole frames only: a chain splats anywhere, so
//! a crop or a sample range of a split render has no meaning (the command
//! line refuses them).

use super::{PassObserver, RenderOptions, RenderOutput};
use crate::film::{Film, Provenance, Rect, SampleRange};
use crate::integrator::bdpt::multiplexed::Multiplexed;
use crate::integrator::mlt::bootstrap::Bootstrap;
use crate::integrator::mlt::chain::Chain;
use crate::integrator::mlt::{LengthStats, MltSettings, MltStats};
use crate::integrator::tracking::TrackingStats;
use crate::integrator::Scene;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Renders the whole frame of `scene` by Metropolis light transport with `settings`.
pub(super) fn render(
    scene: &Scene,
    settings: &MltSettings,
    options: &RenderOptions,
    cancel: &AtomicBool,
    on_pass: Option<PassObserver>,
) -> RenderOutput {
    super::thread_pool(options)
        .install(|| Metropolis::new(scene, settings, options, cancel).run(on_pass))
}

/// A Metropolis render between passes.
struct Metropolis<'a> {
    scene: &'a Scene,
    options: &'a RenderOptions,
    cancel: &'a AtomicBool,
    film: Film,
    start: Instant,
    spp_done: u32,
    partial: bool,
    boot: Bootstrap,
    chains: Vec<Chain>,
    mux: Multiplexed,
}

impl<'a> Metropolis<'a> {
    /// The bootstrap done and the chains started (in parallel, each from its own key).
    fn new(
        scene: &'a Scene,
        settings: &MltSettings,
        options: &'a RenderOptions,
        cancel: &'a AtomicBool,
    ) -> Metropolis<'a> {
        let start = Instant::now();
        let mux = Multiplexed::new(scene);
        let pixels = scene.camera.width() as u64 * scene.camera.height() as u64;
        let count = (settings.chains as u64).min(pixels).max(1);
        // Stopped during the bootstrap: no chain starts, the run loop sees the stop.
        let (boot, chains) = match Bootstrap::run(scene, settings, &mux, cancel) {
            Some(boot) => {
                let chains = (0..count)
                    .into_par_iter()
                    .filter_map(|c| Chain::start(scene, settings, &mux, &boot, c))
                    .collect();
                (boot, chains)
            }
            None => (Bootstrap::stopped(), Vec::new()),
        };
        Metropolis {
            scene,
            options,
            cancel,
            film: new_film(scene),
            start,
            spp_done: 0,
            partial: false,
            boot,
            chains,
            mux,
        }
    }

    /// True while the spp or time budget allows another pass (as the other integrators count it).
    fn budget_left(&self) -> bool {
        let (options, done) = (self.options, self.spp_done);
        match options.time_budget {
            Some(t) => {
                (done == 0 || self.start.elapsed() < t)
                    && (!options.spp_is_cap || done < options.spp)
            }
            None => done < options.spp,
        }
    }

    /// Passes until the budget is spent or the stop request, then the output.
    fn run(mut self, mut on_pass: Option<PassObserver>) -> RenderOutput {
        let bar = progress_bar(self.options);
        while self.budget_left() {
            if self.cancel.load(Ordering::Relaxed) || !self.pass() {
                self.partial = true;
                break;
            }
            if let Some(observe) = on_pass.as_mut() {
                let mut image = self.film.beauty_image();
                image.partial = true;
                observe(&image);
            }
            bar.inc(1);
            bar.set_message(format!("{} mutations per pixel", self.spp_done));
        }
        bar.finish_and_clear();
        self.finish()
    }

    /// One mutation per pixel, shared out among the chains; false when stopped.
    fn pass(&mut self) -> bool {
        let pixels = self.film.window.area() as u64;
        let (scene, mux, cancel) = (self.scene, &self.mux, self.cancel);
        let b = self.boot.brightness;
        let n = self.chains.len() as u64;
        let finished = self
            .chains
            .par_iter_mut()
            .enumerate()
            .map(|(c, chain)| {
                let mutations = pixels / n + u64::from((c as u64) < pixels % n);
                chain.run(scene, mux, mutations, b, cancel)
            })
            .collect::<Vec<bool>>();
        if finished.iter().any(|f| !f) {
            return false;
        }
        let splats = self.film.splats.as_mut().expect("an mlt film keeps splats");
        for chain in &self.chains {
            splats.add(chain.splats());
        }
        self.spp_done += 1;
        self.film.provenance.held = vec![SampleRange::new(0, self.spp_done)];
        true
    }

    /// The film with its final provenance, the image and the chains' statistics.
    fn finish(mut self) -> RenderOutput {
        let held = SampleRange::new(0, self.spp_done);
        let requested = match self.partial {
            true => SampleRange::new(0, self.options.spp.max(held.end)),
            false => held,
        };
        let provenance = &mut self.film.provenance;
        provenance.spp_total = requested.end;
        provenance.requested = vec![requested];
        provenance.held = if held.is_empty() { vec![] } else { vec![held] };
        let mut image = self.film.beauty_image();
        image.partial = self.partial;
        let stats = self.stats();
        RenderOutput {
            image,
            nonfinite_samples: stats.nonfinite,
            samples: self.spp_done as u64 * self.film.window.area() as u64,
            film: self.film,
            elapsed: self.start.elapsed(),
            tracking: TrackingStats::default(),
            truncated_interiors: 0,
            mlt: Some(stats),
            noise: None,
            auto: None,
            refused: None,
        }
    }

    /// Acceptance per path length, the bootstrap's brightness and its error.
    fn stats(&self) -> MltStats {
        let mut lengths: Vec<LengthStats> = Vec::new();
        for c in &self.chains {
            let i = match lengths.iter().position(|l| l.length == c.length) {
                Some(i) => i,
                None => {
                    lengths.push(LengthStats {
                        length: c.length,
                        ..LengthStats::default()
                    });
                    lengths.len() - 1
                }
            };
            lengths[i].chains += 1;
            lengths[i].proposed += c.proposed;
            lengths[i].accepted += c.accepted;
        }
        lengths.sort_by_key(|l| l.length);
        MltStats {
            brightness: self.boot.brightness,
            brightness_std_error: self.boot.std_error,
            lengths,
            nonfinite: self.chains.iter().map(|c| c.nonfinite).sum(),
        }
    }
}

/// The empty film of the whole frame: splat sums only (no pixel owns a sample).
fn new_film(scene: &Scene) -> Film {
    let display = (scene.camera.width(), scene.camera.height());
    let provenance = Provenance {
        seed: scene.settings.seed,
        scene_hash: 0,
        spp_total: 0,
        requested: vec![],
        held: vec![],
    };
    let mut film = Film::new(display, Rect::full(display.0, display.1), provenance);
    film.add_splats();
    film
}

fn progress_bar(options: &RenderOptions) -> ProgressBar {
    if !options.progress {
        return ProgressBar::hidden();
    }
    let bar = match options.time_budget {
        Some(_) => ProgressBar::new_spinner(),
        None => ProgressBar::new(options.spp as u64),
    };
    bar.set_draw_target(ProgressDrawTarget::stderr());
    let template = match options.time_budget {
        Some(_) => "{spinner} {elapsed_precise} {msg}",
        None => "{bar:40} {percent:>3}% {elapsed_precise} eta {eta} {msg}",
    };
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}
