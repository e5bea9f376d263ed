//! The bootstrap: independent states whose mean luminance estimates the
//! image's brightness b, and from which chains are started in proportion to
//! their luminance (sampling-importance resampling).
//!
//! Sample i has path length 1 + (i mod K) for the K lengths the scene allows,
//! so every length gets ⌊N/K⌋ or ⌈N/K⌉ samples (the scene loader asks for
//! N ≥ K); b is the sum over lengths of each length's mean luminance, and a
//! sample's resampling weight is its luminance over its length's count.
//!
//! A sample's luminance is Rao–Blackwellised over the strategy choice: the
//! mean, over the k + 1 strategies of its length, of the luminance of the
//! state that picks each (`Multiplexed::evaluate_all`, one camera and one
//! light subpath shared by all). That is the multiplexed luminance's
//! expectation given the camera and light numbers, so b keeps its
//! expectation, and a path found by one strategy of k + 1 counts in every
//! sample that finds it instead of one in k + 1, at 1/(k + 1) of the
//! weight: on rare bright paths (lantern_gap's lamp seen through its globe)
//! the variance falls by up to k + 1 for about twice a state's cost. A chain
//! then starts from the resampled sample with a strategy drawn in
//! proportion to its state's luminance (module `chain`).

use super::MltSettings;
use crate::integrator::bdpt::multiplexed::Multiplexed;
use crate::integrator::bdpt::BdptArena;
use crate::integrator::Scene;
use crate::sampling::mix64;
use crate::sampling::primary::PrimarySamples;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Bootstrap samples evaluated between two looks at the stop request.
const BLOCK: u64 = 1 << 14;

/// Bytes the bootstrap keeps per sample (its luminance, then its running weight).
pub const BYTES_PER_SAMPLE: u64 = 16;

/// The bootstrap's result.
#[derive(Clone, Debug)]
pub struct Bootstrap {
    /// Running sums of the resampling weights, one per sample.
    cumulative: Vec<f64>,
    /// Path lengths the scene allows.
    lengths: usize,
    /// The estimate b of the image's mean luminance (the sum of the weights).
    pub brightness: f64,
    /// Its standard error.
    pub std_error: f64,
}

/// Key of the primary-sample state of bootstrap sample `i` under scene seed `seed`.
pub fn key(seed: u64, i: u64) -> u64 {
    mix64(seed.rotate_left(41) ^ mix64(i ^ 0x4D4C_5442_6F6F_7400))
}

impl Bootstrap {
    /// Evaluates `settings.bootstrap_samples` independent states of `scene`
    /// (in parallel, in blocks between which a stop request is honoured:
    /// None when `cancel` stopped it).
    pub fn run(
        scene: &Scene,
        settings: &MltSettings,
        mux: &Multiplexed,
        cancel: &AtomicBool,
    ) -> Option<Bootstrap> {
        let lengths = Multiplexed::max_length(scene);
        let n = settings.bootstrap_samples as u64;
        let seed = scene.settings.seed;
        let init = || {
            let ps = PrimarySamples::new(0, settings.small_step_size, 0.0);
            (ps, BdptArena::new(), vec![0.0; lengths + 1])
        };
        let mut luminance: Vec<f64> = Vec::with_capacity(n as usize);
        for start in (0..n).step_by(BLOCK as usize) {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let block = (start..(start + BLOCK).min(n)).into_par_iter();
            luminance.par_extend(block.map_init(init, |(ps, arena, strategies), i| {
                ps.reseed(key(seed, i));
                let k = 1 + (i % lengths as u64) as usize;
                mux.evaluate_all(scene, k, ps, arena, strategies);
                strategies[..=k].iter().sum::<f64>() / (k + 1) as f64
            }));
        }
        Some(Bootstrap::from_luminance(&luminance, lengths))
    }

    /// An empty bootstrap (no sample, brightness 0): the state of a render
    /// stopped before its bootstrap finished.
    pub fn stopped() -> Bootstrap {
        Bootstrap {
            cumulative: Vec::new(),
            lengths: 1,
            brightness: 0.0,
            std_error: 0.0,
        }
    }

    /// The weights, b and its standard error of samples of these luminances.
    fn from_luminance(luminance: &[f64], lengths: usize) -> Bootstrap {
        let n = luminance.len();
        let count = |k: usize| ((n + lengths - 1 - k) / lengths).max(1) as f64;
        let (mut sum, mut sum2) = (vec![0.0; lengths], vec![0.0; lengths]);
        for (i, &l) in luminance.iter().enumerate() {
            sum[i % lengths] += l;
            sum2[i % lengths] += l * l;
        }
        let mut variance = 0.0;
        for k in 0..lengths {
            let m = count(k);
            let mean = sum[k] / m;
            if m > 1.0 {
                variance += (sum2[k] / m - mean * mean).max(0.0) / (m - 1.0);
            }
        }
        let mut total = 0.0;
        let cumulative = luminance
            .iter()
            .enumerate()
            .map(|(i, &l)| {
                total += l / count(i % lengths);
                total
            })
            .collect();
        Bootstrap {
            cumulative,
            lengths,
            brightness: total,
            std_error: variance.sqrt(),
        }
    }

    /// The sample whose share of the weights holds `u` ∈ [0, 1), and its path length.
    pub fn pick(&self, u: f64) -> (u64, usize) {
        let target = u * self.brightness;
        let i = self.cumulative.partition_point(|&c| c <= target);
        let i = i.min(self.cumulative.len() - 1);
        (i as u64, 1 + i % self.lengths)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// b sums the per-length means, and resampling lands only on samples of positive weight.
    #[test]
    fn brightness_is_the_sum_of_the_per_length_means() {
        // Two lengths; length 1 gets samples 0, 2, 4 and length 2 gets 1, 3.
        let b = Bootstrap::from_luminance(&[3.0, 1.0, 0.0, 0.0, 6.0], 2);
        assert!((b.brightness - (3.0 + 0.5)).abs() < 1e-12);
        // Weights 1, 0.5, 0, 0, 2: cumulative 1, 1.5, 1.5, 1.5, 3.5.
        assert_eq!(b.pick(0.0), (0, 1));
        assert_eq!(b.pick(1.2 / 3.5), (1, 2));
        assert_eq!(b.pick(1.6 / 3.5), (4, 1));
        assert_eq!(b.pick(0.999_999), (4, 1));
        // Variances: length 1 {3, 0, 6} → 9 / 3; length 2 {1, 0} → 0.5 / 2.
        assert!((b.std_error - (3.0f64 + 0.25).sqrt()).abs() < 1e-12);
    }
}
