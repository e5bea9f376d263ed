//! Which light next-event estimation asks: a discrete distribution over the
//! scene's lights, in proportion to their power, with a uniform share.
//!
//! One light is sampled per vertex (one-sample MIS over lights, Veach 1997
//! §9.2.4), so its estimate is divided by the probability of picking it.
//! Every place that weighs a light sample against another strategy (BSDF or
//! phase sampling hitting an area light or escaping to an infinite one,
//! free-flight against equiangular sampling) multiplies the light's density
//! by the same probability, [`LightPick::pmf`].
//!
//! Picking by power puts the samples where the light is: a sun of
//! irradiance 4 beside a sky of radiance 0.1 is asked nine times in ten
//! instead of one in two (the B3 bench scene: a 2.4–4× lower mean squared
//! error per sample than a uniform pick). The uniform share (defensive
//! mixing, Hesterberg 1995) keeps a light the power underrates — a lamp in
//! a room the sun cannot reach — from being starved: no light's probability
//! falls below [`UNIFORM_SHARE`] / N, so no estimate's variance grows by
//! more than N / share over a uniform pick.
//!
//! The path tracer asks a constant or sky environment less than its power
//! says ([`environment_share`]): from a diffuse surface such a sky is
//! sampled with the BSDF's own cosine density, and in a medium the phase
//! function samples a smooth sky at least as well as uniform directions, so
//! the light sample only repeats what the continuation ray already gathers
//! (MIS gives that ray weight 1 when the sky is never asked), while every
//! sample spent on the sky is a sample the sun does not get. Bidirectional
//! strategies keep the pick by power: their light subpaths start from it.

/// The part of the pick that stays uniform over the lights.
pub const UNIFORM_SHARE: f32 = 0.1;

/// The largest share [`environment_share`] gives a sky: the other lights
/// keep at least the uniform share (only light samples find a delta light).
pub const MAX_ENVIRONMENT_SHARE: f32 = 1.0 - 0.5 * UNIFORM_SHARE;

/// The probability with which the path tracer's next-event estimation asks
/// a constant or sky environment of power `environment` beside other lights
/// of total power `rest`: max(0, (E − R) / (E + R)), at most
/// [`MAX_ENVIRONMENT_SHARE`].
///
/// Why: at a diffuse vertex lit by a sky of contribution K and other lights
/// of contribution S, asking the sky with probability p costs the other
/// lights' estimate a variance S² p / (1 − p) (the samples they miss) and
/// gives the sky's a second cosine sample a fraction p of the time, its
/// variance σ² / (1 + p). The sum is least at (1 + p) / (1 − p) = σ / S; with
/// σ ≈ K (a partly hidden sky's visibility, relative deviation about 1) that
/// is p = (K − S) / (K + S), and the powers stand in for K and S. No other
/// light's power (R = 0): the sky nearly always; a sun brighter than the sky
/// (B3, B4, clouds): never, the sky then comes from the continuation rays.
pub fn environment_share(environment: f32, rest: f32) -> f32 {
    let (e, r) = (environment.max(0.0), rest.max(0.0));
    let share = match e + r {
        total if total > 0.0 && total.is_finite() => (e - r) / total,
        _ if r > 0.0 => 0.0,
        _ => 1.0,
    };
    share.clamp(0.0, MAX_ENVIRONMENT_SHARE)
}

/// A discrete distribution over the scene's lights.
#[derive(Clone, Debug, Default)]
pub struct LightPick {
    /// Probability of each light.
    pmf: Vec<f32>,
    /// `cdf[i]` = sum of `pmf[..i]`, `cdf[n]` = 1.
    cdf: Vec<f32>,
}

impl LightPick {
    /// The pick for lights of powers `power` (any non-negative scale; a
    /// non-finite or negative power counts as 0). With no positive power the
    /// pick is uniform.
    pub fn new(power: &[f32]) -> LightPick {
        let n = power.len();
        if n == 0 {
            return LightPick::default();
        }
        let clean: Vec<f64> = power
            .iter()
            .map(|&p| {
                if p.is_finite() && p > 0.0 {
                    p as f64
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = clean.iter().sum();
        let uniform = 1.0 / n as f64;
        let pmf: Vec<f32> = clean
            .iter()
            .map(|&p| match total > 0.0 && total.is_finite() {
                true => (1.0 - UNIFORM_SHARE as f64) * p / total + UNIFORM_SHARE as f64 * uniform,
                false => uniform,
            } as f32)
            .collect();
        LightPick::from_pmf(pmf)
    }

    /// The pick of [`LightPick::new`] except that light `fixed` is asked with
    /// probability `share` (clamped to [0, 1]; the only light is always
    /// asked): the other lights split the rest as `new` splits it among them.
    pub fn with_fixed_share(power: &[f32], fixed: usize, share: f32) -> LightPick {
        if power.len() <= 1 || fixed >= power.len() {
            return LightPick::new(power);
        }
        let share = share.clamp(0.0, 1.0);
        let others: Vec<f32> = (0..power.len())
            .filter(|&i| i != fixed)
            .map(|i| power[i])
            .collect();
        let rest = LightPick::new(&others);
        let pmf = (0..power.len())
            .map(|i| match i.cmp(&fixed) {
                std::cmp::Ordering::Less => (1.0 - share) * rest.pmf[i],
                std::cmp::Ordering::Equal => share,
                std::cmp::Ordering::Greater => (1.0 - share) * rest.pmf[i - 1],
            })
            .collect();
        LightPick::from_pmf(pmf)
    }

    /// The pick with probabilities `pmf` (summing to 1).
    fn from_pmf(pmf: Vec<f32>) -> LightPick {
        let n = pmf.len();
        let mut cdf = Vec::with_capacity(n + 1);
        let mut acc = 0.0f64;
        cdf.push(0.0);
        for &p in &pmf {
            acc += p as f64;
            cdf.push(acc as f32);
        }
        cdf[n] = 1.0;
        LightPick { pmf, cdf }
    }

    /// The light for a uniform number `u` ∈ [0, 1) (`None` with no lights).
    #[inline]
    pub fn sample(&self, u: f32) -> Option<usize> {
        let n = self.pmf.len();
        if n == 0 {
            return None;
        }
        // The last light whose cdf is ≤ u: lights of probability 0 have none.
        Some(
            self.cdf
                .partition_point(|&c| c <= u)
                .saturating_sub(1)
                .min(n - 1),
        )
    }

    /// Probability of picking light `index`.
    #[inline]
    pub fn pmf(&self, index: usize) -> f32 {
        self.pmf[index]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probabilities_follow_power_with_a_uniform_share() {
        let pick = LightPick::new(&[3.0, 1.0, 0.0, f32::NAN]);
        let expected = [0.9 * 0.75 + 0.025, 0.9 * 0.25 + 0.025, 0.025, 0.025];
        for (i, e) in expected.iter().enumerate() {
            assert!(
                (pick.pmf(i) - e).abs() < 1e-6,
                "{i}: {} vs {e}",
                pick.pmf(i)
            );
        }
        let sum: f32 = (0..4).map(|i| pick.pmf(i)).sum();
        assert!((sum - 1.0).abs() < 1e-6);
    }

    /// A fixed share: that light gets exactly it, the others split the rest
    /// by power with the uniform share among them, and sampling never lands
    /// on a light of probability 0 (first, middle or last).
    #[test]
    fn a_fixed_share_leaves_the_rest_to_the_others_by_power() {
        let pick = LightPick::with_fixed_share(&[3.0, 9.0, 1.0], 1, 0.2);
        let rest = [0.9 * 0.75 + 0.05, 0.9 * 0.25 + 0.05];
        let expected = [0.8 * rest[0], 0.2, 0.8 * rest[1]];
        for (i, e) in expected.iter().enumerate() {
            assert!(
                (pick.pmf(i) - e).abs() < 1e-6,
                "{i}: {} vs {e}",
                pick.pmf(i)
            );
        }
        for fixed in 0..3 {
            let pick = LightPick::with_fixed_share(&[3.0, 9.0, 1.0], fixed, 0.0);
            assert_eq!(pick.pmf(fixed), 0.0);
            let n = 10_000;
            let hits = (0..n)
                .filter(|k| pick.sample((*k as f32 + 0.5) / n as f32) == Some(fixed))
                .count();
            assert_eq!(hits, 0, "light {fixed} of probability 0 was picked");
        }
        assert_eq!(LightPick::with_fixed_share(&[2.0, 1.0], 0, 1.5).pmf(0), 1.0);
        assert_eq!(LightPick::with_fixed_share(&[2.0], 0, 0.0).pmf(0), 1.0);
    }

    #[test]
    fn the_sky_is_asked_only_when_it_outshines_the_other_lights() {
        assert_eq!(environment_share(1.0, 0.0), MAX_ENVIRONMENT_SHARE);
        assert_eq!(environment_share(100.0, 1.0), MAX_ENVIRONMENT_SHARE);
        assert_eq!(environment_share(0.314, 4.0), 0.0);
        assert_eq!(environment_share(1.0, 1.0), 0.0);
        assert!((environment_share(3.0, 1.0) - 0.5).abs() < 1e-6);
        assert!((environment_share(9.0, 1.0) - 0.8).abs() < 1e-6);
        assert_eq!(environment_share(0.0, 0.0), MAX_ENVIRONMENT_SHARE);
        assert_eq!(environment_share(f32::INFINITY, 1.0), 0.0);
        assert_eq!(environment_share(f32::NAN, 0.0), MAX_ENVIRONMENT_SHARE);
    }

    #[test]
    fn no_power_at_all_picks_uniformly() {
        let pick = LightPick::new(&[0.0, 0.0]);
        assert_eq!((pick.pmf(0), pick.pmf(1)), (0.5, 0.5));
        assert_eq!(LightPick::new(&[]).sample(0.3), None);
    }

    /// Sampling hits each light with its probability: the fraction of a
    /// uniform grid of u that lands on light i is pmf(i).
    #[test]
    fn sampling_follows_the_pmf() {
        let pick = LightPick::new(&[5.0, 0.0, 2.0, 1.0]);
        let n = 100_000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            counts[pick.sample(u).unwrap()] += 1;
        }
        for (i, &c) in counts.iter().enumerate() {
            let f = c as f32 / n as f32;
            assert!(
                (f - pick.pmf(i)).abs() < 2e-4,
                "{i}: {f} vs {}",
                pick.pmf(i)
            );
        }
        assert_eq!(pick.sample(0.0), Some(0));
        assert_eq!(pick.sample(1.0 - f32::EPSILON / 2.0), Some(3));
    }
}
