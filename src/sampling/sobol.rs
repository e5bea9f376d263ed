//! Shuffled Sobol' points for the first dimensions of a pixel's samples
//! (`integrator.sampler = "sobol"`): the index shuffle by nested (Owen)
//! scrambling of Burley 2020, "Practical Hash-based Owen Scrambling",
//! JCGT 9(4), and a random digital shift of each point.
//!
//! Pairs of dimensions take the first two Sobol' dimensions (a (0,2)-sequence
//! in base 2), single dimensions the first (van der Corput). Each pair or
//! single dimension has its own shuffle of the sample index and its own
//! shift, both keyed by the seed, the pixel and the dimension, so that:
//! - each sample is uniform in every dimension and independent across pairs
//!   (the estimator stays unbiased);
//! - the samples `0..2^m` of a pixel form a (0, m, 2)-net in every pair and
//!   are stratified in every single dimension, whatever the key.
//!
//! Nested scrambling: in bit-reversed order, an operation whose output bit k
//! depends only on input bits ≤ k (adding, multiplying by an odd number,
//! xoring with a product by an even number) permutes the binary intervals of
//! the original number within their parents, which is Owen's scrambling
//! with permutations drawn from the hash. Applied to the sample index it
//! maps the first 2ᵐ samples onto an aligned block of 2ᵐ Sobol' points
//! (itself a net). The points themselves are only shifted (xor with a key),
//! which keeps every net property and costs nothing: Owen-scrambling them
//! too would cost four bit reversals a pair for a gain only on smooth
//! integrands (B4 at 96×64: 6 % more instructions, the same error).

/// Burley 2020's Laine–Karras-style hash: output bit k depends only on input bits ≤ k.
#[inline]
fn low_to_high_hash(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

/// The second Sobol' dimension as a function of the *bit-reversed* point
/// index, xored by bytes: `SECOND_OF_REVERSED[b][j]` is the xor of the
/// direction numbers (primitive polynomial x + 1: v₁ = 2⁻¹, vₖ = vₖ₋₁ ⊕ vₖ₋₁/2)
/// of index bits 31 − t for the set bits t of `j << 8b`.
static SECOND_OF_REVERSED: [[u32; 256]; 4] = second_of_reversed_tables();

const fn second_of_reversed_tables() -> [[u32; 256]; 4] {
    let mut directions = [0u32; 32];
    let mut v = 1u32 << 31;
    let mut k = 0;
    while k < 32 {
        // Index bit k sits at bit 31 − k of the reversed index.
        directions[31 - k] = v;
        v ^= v >> 1;
        k += 1;
    }
    let mut tables = [[0u32; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut j = 0;
        while j < 256 {
            let mut x = 0;
            let mut t = 0;
            while t < 8 {
                if j & (1 << t) != 0 {
                    x ^= directions[8 * b + t];
                }
                t += 1;
            }
            tables[b][j] = x;
            j += 1;
        }
        b += 1;
    }
    tables
}

/// The second Sobol' dimension of the point whose bit-reversed index is `r` (four table lookups).
#[inline]
fn sobol_second_of_reversed(r: u32) -> u32 {
    let [b0, b1, b2, b3] = r.to_le_bytes();
    SECOND_OF_REVERSED[0][b0 as usize]
        ^ SECOND_OF_REVERSED[1][b1 as usize]
        ^ SECOND_OF_REVERSED[2][b2 as usize]
        ^ SECOND_OF_REVERSED[3][b3 as usize]
}

/// 32 fraction bits as an f32 in [0, 1) (the top 24 bits, so never 1).
#[inline]
pub fn to_unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// A 64-bit key for (pixel key, dimension), each dimension independent.
#[inline]
pub fn dimension_key(pixel_key: u64, dimension: u32) -> u64 {
    super::mix64(pixel_key ^ (dimension as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The bit-reversed index of the Sobol' point that sample `index` takes in
/// the dimensions keyed by `key`, given `reversed_index` = `index.reverse_bits()`.
///
/// The shuffle is a nested scramble of the index (Burley 2020): it maps the
/// first 2ᵐ sample indices onto one aligned block of 2ᵐ point indices, which
/// is again a (0, m, 2)-net. Its bit-reversed form is what the hash returns,
/// and it is all the points need: the first dimension *is* the reversed index.
#[inline]
fn shuffled_reversed(reversed_index: u32, key: u64) -> u32 {
    low_to_high_hash(reversed_index, key as u32)
}

/// One dimension of sample `index` (given reversed) for the key of (pixel, dimension).
///
/// The point is scrambled by a random digital shift (xor with a key), which
/// keeps every net property: with the shuffle, each sample is uniform and
/// samples of different dimensions are independent.
#[inline]
pub fn point_1d(reversed_index: u32, key: u64) -> f32 {
    to_unit(shuffled_reversed(reversed_index, key) ^ (key >> 32) as u32)
}

/// A pair of dimensions of sample `index` (given reversed): shuffled by the
/// key of (pixel, first dimension), its second coordinate shifted by
/// another independent key (the pixel's key of the second dimension, which
/// a pair uses for nothing else).
#[inline]
pub fn point_2d(reversed_index: u32, key: u64, second_key: u64) -> [f32; 2] {
    let r = shuffled_reversed(reversed_index, key);
    [
        to_unit(r ^ (key >> 32) as u32),
        to_unit(sobol_second_of_reversed(r) ^ (second_key >> 32) as u32),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nested uniform scramble of the bits of `x` (most significant first),
    /// keyed by `seed`: what the shuffle computes, in the natural bit order.
    fn nested_scramble(x: u32, seed: u32) -> u32 {
        low_to_high_hash(x.reverse_bits(), seed).reverse_bits()
    }

    /// The second Sobol' dimension of point `i`, as 32 fraction bits.
    fn sobol_second(i: u32) -> u32 {
        sobol_second_of_reversed(i.reverse_bits())
    }

    /// The unscrambled second dimension of the first points: 0, ½, ¾, ¼, ⅝, ⅛, ⅜, ⅞;
    /// the tables agree with the bit-by-bit definition.
    #[test]
    fn second_dimension_matches_the_known_points() {
        let expected = [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875];
        for (i, &e) in expected.iter().enumerate() {
            assert_eq!(to_unit(sobol_second(i as u32)), e, "point {i}");
        }
        for i in [0u32, 1, 255, 256, 0x1234_5678, u32::MAX] {
            let mut v = 1u32 << 31;
            let (mut bits, mut rest) = (0, i);
            while rest != 0 {
                if rest & 1 != 0 {
                    bits ^= v;
                }
                rest >>= 1;
                v ^= v >> 1;
            }
            assert_eq!(sobol_second(i), bits, "point {i}");
        }
    }

    /// A nested scramble maps the intervals [j/2ᵐ, (j+1)/2ᵐ) one to one, for every m.
    #[test]
    fn nested_scrambles_permute_binary_intervals() {
        for seed in [0u32, 1, 0xdead_beef, 0x1234_5678] {
            for m in [1u32, 3, 6, 10] {
                let n = 1u32 << m;
                let mut seen = vec![false; n as usize];
                for j in 0..n {
                    let x = j << (32 - m);
                    let y = nested_scramble(x, seed) >> (32 - m);
                    assert!(
                        !seen[y as usize],
                        "seed {seed} m {m}: two intervals onto {y}"
                    );
                    seen[y as usize] = true;
                    // Every point of an interval stays in the same image interval.
                    let inside = x | (0x9e37_79b9 >> m);
                    assert_eq!(nested_scramble(inside, seed) >> (32 - m), y);
                }
            }
        }
    }

    /// The shuffle is the nested scramble of the index, in reversed form.
    #[test]
    fn the_shuffle_is_a_nested_scramble_of_the_index() {
        for key in [3u64, 0xfeed_f00d_1234_5678] {
            for i in [0u32, 1, 5, 1000, u32::MAX] {
                assert_eq!(
                    shuffled_reversed(i.reverse_bits(), key),
                    nested_scramble(i, key as u32).reverse_bits()
                );
            }
        }
    }

    /// The first 2ᵐ samples of a pixel: one per stratum of each dimension, and
    /// one per elementary interval of area 2⁻ᵐ of each pair (a (0, m, 2)-net).
    #[test]
    fn first_power_of_two_samples_form_nets() {
        for key in [1u64, 0x0123_4567_89ab_cdef, super::super::mix64(42)] {
            for m in [2u32, 4, 7] {
                let n = 1usize << m;
                let ones: Vec<f32> = (0..n as u32)
                    .map(|i| point_1d(i.reverse_bits(), key))
                    .collect();
                let mut strata = vec![0; n];
                for &u in &ones {
                    assert!((0.0..1.0).contains(&u));
                    strata[(u * n as f32) as usize] += 1;
                }
                assert!(strata.iter().all(|&c| c == 1), "1-D, key {key:x}, m {m}");
                let pairs: Vec<[f32; 2]> = (0..n as u32)
                    .map(|i| point_2d(i.reverse_bits(), key, !key))
                    .collect();
                for kx in 0..=m {
                    let (nx, ny) = (1usize << kx, 1usize << (m - kx));
                    let mut cells = vec![0; n];
                    for p in &pairs {
                        let (cx, cy) = ((p[0] * nx as f32) as usize, (p[1] * ny as f32) as usize);
                        cells[cx * ny + cy] += 1;
                    }
                    assert!(cells.iter().all(|&c| c == 1), "2-D {nx}×{ny}, key {key:x}");
                }
            }
        }
    }

    /// Every dimension of a pixel gets its own key, whatever the pixel's key:
    /// xor with distinct multiples of an odd constant is one to one, and so is
    /// `mix64`. Pixel keys with every bit set or none are the edge cases.
    #[test]
    fn dimension_keys_of_a_pixel_are_distinct() {
        for pixel_key in [0, u64::MAX, 0xaaaa_aaaa_aaaa_aaaa, super::super::mix64(7)] {
            let mut keys: Vec<u64> = (0..1024).map(|d| dimension_key(pixel_key, d)).collect();
            keys.sort_unstable();
            keys.dedup();
            assert_eq!(keys.len(), 1024, "pixel key {pixel_key:x}");
        }
    }

    /// Different keys give different points (the scrambles are keyed), and the
    /// mean over many keys of one sample is ½ in each dimension (uniform marginals).
    #[test]
    fn keys_randomise_each_sample_uniformly() {
        assert_ne!(
            point_2d(3u32.reverse_bits(), 1, 3),
            point_2d(3u32.reverse_bits(), 2, 3)
        );
        let n = 200_000u64;
        let (mut s1, mut s2x, mut s2y) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..n {
            let key = super::super::mix64(k);
            s1 += point_1d(5u32.reverse_bits(), key) as f64;
            let p = point_2d(5u32.reverse_bits(), key, super::super::mix64(key ^ 1));
            s2x += p[0] as f64;
            s2y += p[1] as f64;
        }
        // Standard error of a uniform mean: 1/√(12 n); three checks at the
        // suite's k (tests/common/k_sigma.rs, docs/testing.md).
        let tolerance = crate::suite_k::k_sigma(3) / (12.0 * n as f64).sqrt();
        for (what, s) in [("1-D", s1), ("2-D x", s2x), ("2-D y", s2y)] {
            assert!(
                (s / n as f64 - 0.5).abs() < tolerance,
                "{what}: {}",
                s / n as f64
            );
        }
    }
}
