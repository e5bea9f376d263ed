//! Metropolis light transport over the bidirectional strategies:
//! multiplexed primary-sample-space MLT (Kelemen et al. 2002; Hachisuka,
//! Pantaleoni and Jensen 2014), `[integrator] type = "mlt"`.
//!
//! A state is a path length k and a primary-sample vector (module
//! `sampling::primary`); its value is one bidirectional strategy's weighted
//! contribution over the chance of picking it (`bdpt::multiplexed`), and its
//! target the luminance I of that value. A bootstrap of independent states
//! (module `bootstrap`; each sample's I averaged over its length's
//! strategies, the multiplexed I's expectation) estimates b, the image's
//! mean luminance, and starts every chain from a state resampled in
//! proportion to I. Each mutation
//! splats the proposal with weight a·b/I(proposal) and the current state with
//! (1 − a)·b/I(current) (the expected-value form of Metropolis–Hastings, a the
//! acceptance probability), so every pixel is an unbiased estimate once the
//! film divides by the mutations per pixel: resampling from the bootstrap
//! with b from the same samples starts each chain in its stationary
//! distribution. The image's mean luminance equals b exactly.
//!
//! A chain keeps its path length; lengths are chosen in proportion to their
//! share of b by the resampling. Chains are independent and each adds its
//! splats in order, so the image depends on the seed and the image size only,
//! never on the thread count.

pub mod bootstrap;
pub mod chain;

/// Metropolis settings (`[integrator]` keys of `type = "mlt"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MltSettings {
    /// Probability that a mutation draws a whole new state (`large_step_probability`).
    pub large_step_probability: f32,
    /// Standard deviation of a small step in primary sample space (`small_step_size`).
    pub small_step_size: f32,
    /// Independent states of the bootstrap that estimates the image's brightness (`bootstrap_samples`).
    pub bootstrap_samples: u32,
    /// Markov chains run side by side (`chains`; at most one per pixel).
    pub chains: u32,
}

// Validated finite when the scene loads: equality is total.
impl Eq for MltSettings {}

impl Default for MltSettings {
    fn default() -> Self {
        MltSettings {
            large_step_probability: 0.3,
            small_step_size: 0.01,
            bootstrap_samples: 1 << 16,
            chains: 1024,
        }
    }
}

/// How the chains of one length fared.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LengthStats {
    /// Path length in segments.
    pub length: usize,
    /// Chains of this length.
    pub chains: u64,
    /// Mutations proposed.
    pub proposed: u64,
    /// Mutations accepted.
    pub accepted: u64,
}

impl LengthStats {
    /// Accepted over proposed (0 without proposals).
    pub fn acceptance(&self) -> f64 {
        self.accepted as f64 / self.proposed.max(1) as f64
    }
}

/// What a Metropolis render reports beside its image.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MltStats {
    /// The bootstrap's estimate b of the image's mean luminance.
    pub brightness: f64,
    /// Standard error of `brightness`.
    pub brightness_std_error: f64,
    /// Per path length, the chains and their acceptance (lengths with chains only).
    pub lengths: Vec<LengthStats>,
    /// Proposals whose value was NaN or infinite (rejected).
    pub nonfinite: u64,
}

impl MltStats {
    /// Acceptance over all chains.
    pub fn acceptance(&self) -> f64 {
        let (a, p) = self
            .lengths
            .iter()
            .fold((0, 0), |(a, p), l| (a + l.accepted, p + l.proposed));
        a as f64 / p.max(1) as f64
    }
}
