//! Reproducible random streams, warps from the unit square and MIS weights.
//!
//! Every random number is a function of (scene seed, pixel, sample index,
//! dimension): a pixel's stream is a PCG32 generator keyed by the first
//! three, and the dimension is the position in that stream. Renders are
//! therefore identical whatever the thread count or tile order. A `Sobol`
//! sampler ([`Sampler::for_pixel`], module `sobol`) answers its first
//! [`SOBOL_DIMENSIONS`] dimensions from shuffled Sobol' points keyed by the
//! same triple instead, and the PCG stream from there on.
//!
//! One dimension is reserved outside the sequential stream: the camera
//! sample's time ([`Sampler::time_1d`]) is the number at position
//! [`TIME_DIMENSION`] of the same stream, reached by PCG's jump-ahead, so
//! drawing it shifts no other dimension: a scene renders bit-identically
//! with or without a shutter unless something in it moves.

pub mod chi2;
pub mod distribution;
pub mod equiangular;
pub mod primary;
pub mod quadrature;
pub mod sobol;
pub mod warp;

use rand::RngCore;
use rand_pcg::Pcg32;

/// A sampled value with its density and the ready-made Monte Carlo weight.
#[derive(Clone, Copy, Debug)]
pub struct Sample<T> {
    /// The sampled value.
    pub value: T,
    /// Density of the sample with respect to the sampler's measure.
    pub pdf: f32,
    /// The estimator weight `f / pdf` for samplers that know `f`, else `1 / pdf`.
    pub weight: f32,
}

/// SplitMix64 finalizer: a bijective 64-bit mixer used to derive stream keys.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Stream position of the camera sample's time: far beyond what any path consumes
/// (a path of 2^40 numbers would take days), so it never collides with a sequential dimension.
pub const TIME_DIMENSION: u64 = 1 << 40;

/// The hash of pixel `(x, y)` that keys its streams.
#[inline]
fn pixel_hash(x: u32, y: u32) -> u64 {
    mix64(((y as u64) << 32) | x as u64)
}

/// How a pixel's samples draw their first dimensions (`integrator.sampler`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Sobol' points, their index Owen-shuffled and their values shifted,
    /// for the first [`SOBOL_DIMENSIONS`] dimensions (module `sobol`),
    /// independent numbers after them.
    #[default]
    Sobol,
    /// Independent uniform numbers in every dimension.
    Independent,
}

/// Dimensions a `Sobol` sampler draws from shuffled Sobol' points, one or
/// two at a time (free-flight distances, light picks and roulette as well
/// as directions); deeper dimensions take independent numbers. On B4
/// (96×64, 64 spp, variance over 16 seeds), against Sobol' pairs over 12
/// dimensions with independent 1-D draws, the error per sample falls by
/// 12 % at 12 dimensions, 15 % at 20, 16 % at 32 and 21 % at 64; 128 gain
/// nothing more. The keys are hashed once per pixel ([`PixelStreams`]), so
/// 64 cost 1.4 % more instructions there.
pub const SOBOL_DIMENSIONS: u32 = 64;

/// Where a `Sobol` sampler is in its pixel's sample.
#[derive(Clone, Debug)]
struct SobolState<'k> {
    /// The pixel's keys (borrowed from its [`PixelStreams`]: no copy per sample).
    keys: &'k [u64; SOBOL_DIMENSIONS as usize],
    /// The sample index, bit-reversed (what the points are computed from).
    reversed_index: u32,
    dimension: u32,
}

/// What every sample of one pixel shares: its hash and, for a `Sobol`
/// sampler, the keys of each dimension, hashed once for all the samples.
#[derive(Clone, Debug)]
pub struct PixelStreams {
    /// The key of the pixel's PCG streams ([`Sampler::keyed`]).
    pcg_key: u64,
    sobol_keys: Option<[u64; SOBOL_DIMENSIONS as usize]>,
}

impl PixelStreams {
    /// The streams of pixel `(x, y)` under scene seed `seed` for a sampler of `kind`.
    pub fn new(kind: SamplerKind, seed: u64, x: u32, y: u32) -> PixelStreams {
        let pixel = pixel_hash(x, y);
        let sobol_keys = (kind == SamplerKind::Sobol).then(|| {
            let pixel_key = mix64(seed.rotate_left(29) ^ pixel);
            std::array::from_fn(|d| sobol::dimension_key(pixel_key, d as u32))
        });
        PixelStreams {
            pcg_key: mix64(seed ^ pixel),
            sobol_keys,
        }
    }

    /// The stream of sample `sample_index` of this pixel.
    #[inline]
    pub fn sampler(&self, sample_index: u64) -> Sampler<'_> {
        let mut sampler = Sampler::keyed(self.pcg_key, sample_index);
        if let Some(keys) = &self.sobol_keys {
            sampler.source = Source::Sobol(SobolState {
                keys,
                // Sample indices past 2³² wrap: they repeat points, never bias.
                reversed_index: (sample_index as u32).reverse_bits(),
                dimension: 0,
            });
        }
        sampler
    }
}

/// Where a sampler's numbers come from before (or instead of) its PCG stream.
///
/// One enum behind the one branch the Sobol' sampler already took: the
/// path tracer's hot loop pays no more than before for the third source.
#[derive(Debug)]
enum Source<'k> {
    /// The PCG stream alone.
    Pcg,
    /// Shuffled Sobol' points for the first dimensions.
    Sobol(SobolState<'k>),
    /// A Metropolis chain's primary-sample vector (module [`primary`]): every number.
    Primary(&'k mut primary::PrimarySamples),
}

/// The random stream of one (seed, pixel, sample index) triple, or of a Metropolis chain's state.
#[derive(Debug)]
pub struct Sampler<'k> {
    rng: Pcg32,
    source: Source<'k>,
}

impl Sampler<'static> {
    /// The independent stream for sample `sample_index` of pixel `(x, y)` under scene seed `seed`.
    pub fn new(seed: u64, x: u32, y: u32, sample_index: u64) -> Sampler<'static> {
        Sampler::keyed(mix64(seed ^ pixel_hash(x, y)), sample_index)
    }

    /// [`Sampler::new`] from the pixel's key, `mix64(seed ^ pixel_hash(x, y))`.
    fn keyed(pixel_key: u64, sample_index: u64) -> Sampler<'static> {
        let state = mix64(pixel_key ^ mix64(sample_index.wrapping_mul(0xD1B5_4A32_D192_ED03)));
        let stream = mix64(pixel_key.rotate_left(17) ^ sample_index);
        Sampler {
            rng: Pcg32::new(state, stream),
            source: Source::Pcg,
        }
    }

    /// A stream keyed by a single integer, for tests and tools.
    pub fn from_seed(seed: u64) -> Sampler<'static> {
        Sampler::new(seed, 0, 0, 0)
    }
}

impl<'k> Sampler<'k> {
    /// A sampler drawing every number from `state`'s current stream (Metropolis).
    pub fn primary(state: &'k mut primary::PrimarySamples) -> Sampler<'k> {
        Sampler {
            rng: Pcg32::new(0, 0),
            source: Source::Primary(state),
        }
    }

    /// Switches a primary-sample sampler to `stream` (camera, light or
    /// connection, each with its own dimensions); other samplers ignore it.
    #[inline]
    pub fn set_stream(&mut self, stream: primary::Stream) {
        if let Source::Primary(p) = &mut self.source {
            p.set_stream(stream);
        }
    }
}

impl Sampler<'_> {
    /// Next uniform number in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        match &mut self.source {
            Source::Sobol(st) if st.dimension < SOBOL_DIMENSIONS => {
                let key = st.keys[st.dimension as usize];
                st.dimension += 1;
                return sobol::point_1d(st.reversed_index, key);
            }
            Source::Primary(p) => return p.next_1d(),
            _ => {}
        }
        // 24 random mantissa bits: uniform on a grid of 2^-24, never 1.0.
        (self.rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Next number of the PCG stream, whatever the kind.
    #[inline]
    fn independent_1d(&mut self) -> f32 {
        // 24 random mantissa bits: uniform on a grid of 2^-24, never 1.0.
        (self.rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// The uniform number at stream position [`TIME_DIMENSION`], without moving the stream.
    pub fn time_1d(&self) -> f32 {
        let mut rng = self.rng.clone();
        rng.advance(TIME_DIMENSION);
        (rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Next uniform point in [0, 1)².
    #[inline]
    pub fn next_2d(&mut self) -> glam::Vec2 {
        match &mut self.source {
            Source::Sobol(st) if st.dimension + 1 < SOBOL_DIMENSIONS => {
                let d = st.dimension as usize;
                st.dimension += 2;
                let [u, v] = sobol::point_2d(st.reversed_index, st.keys[d], st.keys[d + 1]);
                return glam::Vec2::new(u, v);
            }
            Source::Primary(p) => {
                let u = p.next_1d();
                return glam::Vec2::new(u, p.next_1d());
            }
            _ => {}
        }
        let u = self.independent_1d();
        glam::Vec2::new(u, self.independent_1d())
    }
}

/// Power heuristic (β = 2) weight of strategy f against strategy g.
#[inline]
pub fn power_heuristic(f_pdf: f32, g_pdf: f32) -> f32 {
    if f_pdf.is_infinite() {
        return 1.0;
    }
    // Squared as they are, densities above 1.8e19 (free flight in a medium of
    // σt = 1e20) overflow to inf/inf = NaN; relative to the larger one they cannot.
    let m = f_pdf.max(g_pdf);
    if !(m > 0.0 && m.is_finite()) {
        return 0.0;
    }
    let (f, g) = (f_pdf / m, g_pdf / m);
    f * f / (f * f + g * g)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<f32> = {
            let mut s = Sampler::new(7, 3, 4, 5);
            (0..8).map(|_| s.next_1d()).collect()
        };
        let b: Vec<f32> = {
            let mut s = Sampler::new(7, 3, 4, 5);
            (0..8).map(|_| s.next_1d()).collect()
        };
        let c: Vec<f32> = {
            let mut s = Sampler::new(7, 3, 4, 6);
            (0..8).map(|_| s.next_1d()).collect()
        };
        assert_eq!(a, b);
        assert_ne!(a, c);
        // Every pixel has its own streams: neighbours in x and in y, and far apart.
        let first = |x, y| Sampler::new(7, x, y, 5).rng.next_u64();
        let here = first(3, 4);
        for (x, y) in [(4, 4), (3, 5), (3, 4 + (1 << 20)), (3 + (1 << 20), 4)] {
            assert_ne!(here, first(x, y), "pixel ({x}, {y})");
        }
    }

    #[test]
    fn the_time_dimension_is_the_stream_far_ahead_and_moves_nothing() {
        let mut s = Sampler::new(3, 1, 2, 9);
        let t = s.time_1d();
        let mut reference = Sampler::new(3, 1, 2, 9);
        assert_eq!(s.next_1d(), reference.next_1d());
        // the same number as stepping the stream: checked at a small position
        let mut rng = Sampler::new(3, 1, 2, 9).rng;
        rng.advance(5);
        let mut stepped = Sampler::new(3, 1, 2, 9);
        for _ in 0..5 {
            stepped.next_1d();
        }
        assert_eq!(
            rng.next_u32() >> 8,
            (stepped.next_1d() * 16_777_216.0) as u32
        );
        assert!((0.0..1.0).contains(&t));
        assert_ne!(t, Sampler::new(3, 1, 2, 10).time_1d());
        // Far ahead: no number a path draws (here the first 100 000) is the time's.
        let mut path = Sampler::new(3, 1, 2, 9);
        assert!((0..100_000).all(|_| path.next_1d() != t || t == 0.0));
    }

    /// The first 2ᵐ samples of a `Sobol` pixel are stratified in every one of
    /// its dimensions, whether drawn one or two at a time: 1-D draws into 2ᵐ
    /// strata, pairs into every elementary interval of area 2⁻ᵐ. Past
    /// [`SOBOL_DIMENSIONS`] the draws are the pixel's independent stream.
    #[test]
    fn a_sobol_pixel_stratifies_each_dimension_of_its_first_samples() {
        let m = 6;
        let n = 1usize << m;
        // One 1-D draw, then pairs and singles alternating, to the last Sobol' dimension.
        let pattern: Vec<bool> = std::iter::once(false)
            .chain([true, false].into_iter().cycle())
            .scan(0, |used, pair| {
                *used += if pair { 2 } else { 1 };
                (*used <= SOBOL_DIMENSIONS).then_some(pair)
            })
            .collect();
        let used: u32 = pattern.iter().map(|&p| if p { 2 } else { 1 }).sum();
        assert!(
            used + 1 >= SOBOL_DIMENSIONS,
            "the pattern covers the Sobol' dimensions"
        );
        let streams = PixelStreams::new(SamplerKind::Sobol, 11, 5, 7);
        let mut draws: Vec<Vec<[f32; 2]>> = vec![Vec::new(); pattern.len()];
        for s in 0..n {
            let mut sampler = streams.sampler(s as u64);
            for (k, &pair) in pattern.iter().enumerate() {
                draws[k].push(if pair {
                    sampler.next_2d().to_array()
                } else {
                    [sampler.next_1d(), 0.0]
                });
            }
            for _ in used..SOBOL_DIMENSIONS {
                sampler.next_1d();
            }
            let mut independent = Sampler::new(11, 5, 7, s as u64);
            assert_eq!(sampler.next_1d(), independent.next_1d(), "sample {s}");
        }
        for (k, &pair) in pattern.iter().enumerate() {
            let shapes: Vec<(usize, usize)> = if pair {
                (0..=m).map(|i| (1 << i, 1 << (m - i))).collect()
            } else {
                vec![(n, 1)]
            };
            for (nx, ny) in shapes {
                let mut cells = vec![0; n];
                for p in &draws[k] {
                    cells[(p[0] * nx as f32) as usize * ny + (p[1] * ny as f32) as usize] += 1;
                }
                assert!(cells.iter().all(|&c| c == 1), "draw {k}, {nx}×{ny}");
            }
        }
    }

    /// The 24 + 24 bits of a `Sobol` pair, over the first sample of many
    /// pixels, take every value of every parity: they span all 48 dimensions
    /// of their space over GF(2) (affinely, as differences from one sample).
    /// Each pair's second coordinate has its own shift; with the first's
    /// shift reused, x ⊕ y = (I ⊕ C)·r for the Sobol' point r and the second
    /// dimension's Pascal matrix C, whose rows 0–23 have rank 16: eight
    /// parities of the pair's bits (bit 15 ⊕ bit 23 of x ⊕ y, for one) would
    /// be 0 in every pixel. Uniformity and net tests cannot see that.
    #[test]
    fn the_bits_of_a_sobol_pair_span_their_whole_space_over_pixels() {
        let bits = |v: f32| (v * 16_777_216.0) as u64;
        for dimension in [0, 2, SOBOL_DIMENSIONS - 2] {
            let vectors: Vec<u64> = (0..256)
                .map(|pixel| {
                    let streams = PixelStreams::new(SamplerKind::Sobol, 5, pixel, 3);
                    let mut sampler = streams.sampler(0);
                    for _ in 0..dimension {
                        sampler.next_1d();
                    }
                    let [x, y] = sampler.next_2d().to_array();
                    bits(x) << 24 | bits(y)
                })
                .collect();
            // Gaussian elimination over GF(2) on the differences from the first.
            let mut basis: Vec<u64> = Vec::new();
            for v in vectors.iter().map(|v| v ^ vectors[0]) {
                let reduced = basis.iter().fold(v, |r, b| r.min(r ^ b));
                if reduced != 0 {
                    basis.push(reduced);
                    basis.sort_unstable_by(|a, b| b.cmp(a));
                }
            }
            assert_eq!(basis.len(), 48, "pair at dimension {dimension}");
        }
    }

    /// The keys of pixels, samples and dimensions are independent only if
    /// `mix64` avalanches: flipping any one input bit flips each output bit
    /// with probability ½ (a mixer that only shifts left, say, never lets a
    /// high input bit reach a low output bit).
    #[test]
    fn mix64_flips_each_output_bit_half_the_time_for_each_input_bit() {
        let n = 4096;
        let mut inputs = Sampler::from_seed(9);
        let inputs: Vec<u64> = (0..n)
            .map(|_| ((inputs.rng.next_u32() as u64) << 32) | inputs.rng.next_u32() as u64)
            .collect();
        // 64 × 64 frequencies, each a binomial proportion of n trials.
        let tolerance = crate::suite_k::k_sigma(64 * 64) * (0.25 / n as f64).sqrt();
        for bit in 0..64 {
            let mut flips = [0u32; 64];
            for &x in &inputs {
                let d = mix64(x) ^ mix64(x ^ (1 << bit));
                for (o, f) in flips.iter_mut().enumerate() {
                    *f += ((d >> o) & 1) as u32;
                }
            }
            for (o, &f) in flips.iter().enumerate() {
                let p = f as f64 / n as f64;
                assert!(
                    (p - 0.5).abs() < tolerance,
                    "input bit {bit}, output bit {o}: {p}"
                );
            }
        }
    }

    /// `mix64` is a bijection, so distinct pixels, samples and dimensions get
    /// distinct keys: 2²⁰ consecutive inputs give 2²⁰ distinct outputs (a
    /// mixer that lost ~30 bits on the way would collide hundreds of times).
    #[test]
    fn mix64_gives_distinct_outputs_for_distinct_inputs() {
        let mut outputs: Vec<u64> = (0..1u64 << 20).map(mix64).collect();
        outputs.sort_unstable();
        outputs.dedup();
        assert_eq!(outputs.len(), 1 << 20);
    }

    #[test]
    fn uniform_mean_and_range() {
        let mut s = Sampler::from_seed(1);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let u = s.next_1d();
            assert!((0.0..1.0).contains(&u));
            sum += u as f64;
        }
        // Standard error of the mean of U(0,1) is sqrt(1/12)/sqrt(n).
        let se = (1.0f64 / 12.0).sqrt() / (n as f64).sqrt();
        assert!((sum / n as f64 - 0.5).abs() < crate::suite_k::k_sigma(1) * se);
    }

    #[test]
    fn power_heuristic_sums_to_one() {
        let (a, b) = (0.3, 1.7);
        assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        assert_eq!(power_heuristic(f32::INFINITY, 1.0), 1.0);
        // A strategy the other cannot produce keeps everything, and two that
        // cannot produce the sample share nothing (0, not 0/0).
        assert_eq!(power_heuristic(0.5, 0.0), 1.0);
        assert_eq!(power_heuristic(0.0, 0.5), 0.0);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        // densities whose squares overflow f32
        assert_eq!(power_heuristic(1e20, 1e20), 0.5);
        assert!((power_heuristic(3e38, 1e38) - 0.9).abs() < 1e-6);
        assert!((power_heuristic(1e38, 3e38) - 0.1).abs() < 1e-6);
    }
}
