//! One Markov chain: its state, its own random numbers for the acceptance
//! test, and the splats of the mutations of the current pass.

use super::bootstrap::{self, Bootstrap};
use super::MltSettings;
use crate::film::Splat;
use crate::integrator::bdpt::multiplexed::{Multiplexed, PathSample};
use crate::integrator::bdpt::BdptArena;
use crate::integrator::Scene;
use crate::sampling::primary::{PrimarySamples, Stream};
use crate::sampling::{mix64, Sampler};
use rand::RngCore;
use rand_pcg::Pcg32;
use std::sync::atomic::{AtomicBool, Ordering};

/// Mutations between two looks at the stop request.
const CANCEL_CHECK: u64 = 64;

/// A chain between mutations.
#[derive(Debug)]
pub struct Chain {
    state: PrimarySamples,
    rng: Pcg32,
    /// Path length in segments, fixed for the chain.
    pub length: usize,
    current: PathSample,
    current_luminance: f64,
    /// Splat weight the current state gathered from rejected proposals, not yet splatted.
    pending: f64,
    /// Mutations proposed and accepted so far.
    pub proposed: u64,
    /// Mutations accepted so far.
    pub accepted: u64,
    /// Proposals whose value was NaN or infinite.
    pub nonfinite: u64,
    splats: Vec<Splat>,
    arena: BdptArena,
}

impl Chain {
    /// Chain `index` of `scene`, started from a bootstrap sample resampled by luminance;
    /// None when the bootstrap found no light (b = 0).
    pub fn start(
        scene: &Scene,
        settings: &MltSettings,
        mux: &Multiplexed,
        boot: &Bootstrap,
        index: u64,
    ) -> Option<Chain> {
        if boot.brightness.is_nan() || boot.brightness <= 0.0 {
            return None;
        }
        let seed = scene.settings.seed;
        let chain_key = mix64(seed ^ mix64(index ^ 0x4D4C_5443_6861_696E));
        let mut rng = Pcg32::new(chain_key, mix64(chain_key));
        let (sample, length) = boot.pick(uniform(&mut rng));
        let mut state = PrimarySamples::new(
            bootstrap::key(seed, sample),
            settings.small_step_size,
            settings.large_step_probability,
        );
        let mut arena = BdptArena::new();
        let strategy = pick_strategy(scene, mux, (&mut state, &mut arena), length, &mut rng);
        // The bootstrap's sample with that strategy: its luminance is the positive one it had there.
        state.rewind();
        let current = mux.evaluate(scene, length, &mut Sampler::primary(&mut state), &mut arena)?;
        debug_assert!(luminance(&current) == strategy);
        state.accept();
        let current_luminance = luminance(&current);
        (current_luminance > 0.0).then_some(Chain {
            state,
            rng,
            length,
            current,
            current_luminance,
            pending: 0.0,
            proposed: 0,
            accepted: 0,
            nonfinite: 0,
            splats: Vec::new(),
            arena,
        })
    }

    /// Runs `mutations` mutations, replacing the chain's splats by theirs
    /// (scaled by `brightness`); false when `cancel` stopped it first.
    pub fn run(
        &mut self,
        scene: &Scene,
        mux: &Multiplexed,
        mutations: u64,
        brightness: f64,
        cancel: &AtomicBool,
    ) -> bool {
        self.splats.clear();
        for m in 0..mutations {
            if m % CANCEL_CHECK == 0 && cancel.load(Ordering::Relaxed) {
                return false;
            }
            self.mutate(scene, mux, brightness);
        }
        self.flush(brightness);
        true
    }

    /// The splats of the last [`Chain::run`], in the order they were made.
    pub fn splats(&self) -> &[Splat] {
        &self.splats
    }

    /// One Metropolis–Hastings step with both states splatted by their expected weights.
    fn mutate(&mut self, scene: &Scene, mux: &Multiplexed, brightness: f64) {
        self.state.start_iteration();
        let mut sampler = Sampler::primary(&mut self.state);
        let proposal = mux.evaluate(scene, self.length, &mut sampler, &mut self.arena);
        let proposal = match proposal {
            Some(p) if !p.radiance.is_finite() => {
                self.nonfinite += 1;
                None
            }
            p => p,
        };
        let proposed_luminance = proposal.as_ref().map_or(0.0, luminance);
        let accept = (proposed_luminance / self.current_luminance).min(1.0);
        self.proposed += 1;
        if let Some(p) = proposal.filter(|_| proposed_luminance > 0.0) {
            push(
                &mut self.splats,
                &p,
                accept * brightness / proposed_luminance,
            );
        }
        self.pending += 1.0 - accept;
        match proposal {
            Some(p) if uniform(&mut self.rng) < accept => {
                self.flush(brightness);
                self.current = p;
                self.current_luminance = proposed_luminance;
                self.state.accept();
                self.accepted += 1;
            }
            _ => self.state.reject(),
        }
    }

    /// Splats the weight the current state gathered.
    fn flush(&mut self, brightness: f64) {
        if self.pending > 0.0 {
            let w = self.pending * brightness / self.current_luminance;
            push(&mut self.splats, &self.current, w);
        }
        self.pending = 0.0;
    }
}

/// Makes `state` (a bootstrap sample's key, not yet evaluated) the state of
/// one of its `length`'s strategies, drawn in proportion to their states'
/// luminances, and returns that luminance. Picking the sample by its mean
/// luminance over strategies, then the strategy so, then the strategy number
/// uniformly within its bin, draws the multiplexed state in proportion to
/// its luminance, as resampling the multiplexed bootstrap did.
fn pick_strategy(
    scene: &Scene,
    mux: &Multiplexed,
    (state, arena): (&mut PrimarySamples, &mut BdptArena),
    length: usize,
    rng: &mut Pcg32,
) -> f64 {
    let n = length + 1;
    let mut strategies = vec![0.0; n];
    mux.evaluate_all(scene, length, state, arena, &mut strategies);
    let i = pick_index(&strategies, uniform(rng));
    // Uniform within bin i of the pick evaluate makes (t − 1 = ⌊u·n⌋ in
    // f32): drawn again in the rare case rounding carried it to the next bin.
    let u = loop {
        let u = ((i as f64 + uniform(rng)) / n as f64) as f32;
        if (u * n as f32) as usize == i {
            break u;
        }
    };
    state.set(Stream::Connection, 0, u);
    strategies[i]
}

/// The index of `weights` (non-negative, one positive) whose share of their sum holds `u` ∈ [0, 1).
fn pick_index(weights: &[f64], u: f64) -> usize {
    let target = u * weights.iter().sum::<f64>();
    let mut below = 0.0;
    for (i, &w) in weights.iter().enumerate() {
        below += w;
        if w > 0.0 && target < below {
            return i;
        }
    }
    // Rounding left `target` at the sum: the last positive weight.
    weights.iter().rposition(|&w| w > 0.0).unwrap_or(0)
}

/// The target of a state: the luminance of its radiance.
fn luminance(p: &PathSample) -> f64 {
    p.radiance.luminance().max(0.0) as f64
}

fn push(splats: &mut Vec<Splat>, p: &PathSample, weight: f64) {
    splats.push(Splat {
        x: p.x,
        y: p.y,
        radiance: p.radiance * weight as f32,
    });
}

/// A uniform number in [0, 1) with 53 bits.
fn uniform(rng: &mut Pcg32) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
}

#[cfg(test)]
mod tests {
    use super::pick_index;

    /// A chain starts on strategy i with probability weight i over the sum, never on a zero weight.
    #[test]
    fn strategies_are_picked_in_proportion_to_their_luminance() {
        let w = [0.0, 1.0, 0.0, 3.0];
        assert_eq!(pick_index(&w, 0.0), 1);
        assert_eq!(pick_index(&w, 0.249), 1);
        assert_eq!(pick_index(&w, 0.251), 3);
        assert_eq!(pick_index(&w, 0.999_999), 3);
        assert_eq!(pick_index(&[2.0, 0.0], 0.75), 0);
    }
}
