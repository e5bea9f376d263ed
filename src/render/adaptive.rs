//! Adaptive sampling and the noise target (`--adaptive`, `--noise`).
//!
//! A piloted render first takes a pilot pass of a few samples in every
//! pixel, the first samples of its ordinary stream, which stay in the
//! image: the pilot estimates each pixel's relative variance per sample.
//! From those estimates alone it fixes, before any other image sample is
//! taken, how many samples each pixel gets at every level of the render
//! ([`Plan::counts`]) and the estimated error of the image at those counts
//! ([`Plan::error`]). The image's samples then come in passes of rising
//! level, each pixel's samples being its first `N` of the ordinary stream.
//!
//! Why the image stays unbiased: a pixel's mean of `N` samples is unbiased
//! when `N` does not depend on those samples' values. Here every count of a
//! pixel — the allocation, the level where the noise target is met, the spp
//! cap — is a function of the pilot samples of the pixels of the other
//! colour of a checkerboard (module `class_plans`), whose streams are
//! independent of the pixel's own, so `E[mean | N] = μ` for every `N`, the
//! pilot's samples among them. (Deciding pass k's counts from the image's
//! own passes < k would not do: a pixel whose first samples came out bright
//! would be given more samples and the early bright ones diluted, an
//! optional stopping bias.) Only a time budget or a stop request ends a
//! render at a level that depends on how long the samples took, as it does
//! for uniform renders.

use crate::film::PixelSums;
pub use crate::integrator::adaptive_settings::{AdaptiveSettings, MAX_NOISE, MIN_SPP};

/// The floor of the relative error's denominator, as a fraction of the
/// pilot image's mean luminance: near-black pixels count by their absolute
/// error against it instead of an unbounded relative one.
pub const FLOOR_FRACTION: f64 = 0.1;

/// Without a noise target, a pixel takes at most this many times the
/// render's spp (the mean the render reaches).
pub const MAX_FACTOR: u32 = 16;

/// With neither `adaptive` nor `noise` given, the samples are spread only
/// when the pilot predicts at least this many times the efficiency of the
/// same samples in every pixel ([`Plan::predicted_gain`]): a margin for a
/// cost model that counts rays and lookups, not time. The pilot's samples
/// are the image's first, so the choice costs nothing when it keeps the
/// image uniform.
pub const AUTO_GAIN: f64 = 1.0;

/// The predicted gain from which the automatic choice spreads a colour's
/// samples in full; between [`AUTO_GAIN`] and it, part of the way
/// ([`spread_share`]): the two colours of the checkerboard (module
/// `class_plans`) predict from different pixels, and an all-or-nothing
/// choice could leave one spread and the other uniform where the gain is
/// marginal, a checkerboard in the noise.
pub const FULL_GAIN: f64 = 1.05;

/// The share of the spread the automatic choice takes at predicted `gain`:
/// 0 below [`AUTO_GAIN`], rising to 1 at [`FULL_GAIN`].
pub fn spread_share(gain: f64) -> f64 {
    ((gain - AUTO_GAIN) / (FULL_GAIN - AUTO_GAIN)).clamp(0.0, 1.0)
}

/// The fewest spp the automatic choice takes a pilot for: its pilot (at
/// least 4 spp) is then at most 1/16 of the samples. Below, 4 samples per
/// pixel estimate too little to spread by, and are too large a share of
/// the image to be held uniform (B3's 29-spp bench runs stay uniform).
pub const AUTO_MIN_SPP: u32 = 64;

/// What the automatic choice (no `adaptive`, no `noise`) made of its pilot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoChoice {
    /// Samples per pixel of the pilot (the first of the image's).
    pub pilot_spp: u32,
    /// The predicted gain ([`Plan::predicted_gain`]).
    pub gain: f64,
    /// True when the samples were spread (gain ≥ [`AUTO_GAIN`] in either colour).
    pub spread: bool,
}

/// Samples per pixel of the pilot of a render of `spp` samples per pixel:
/// 1/16 of them, 4 to 16.
pub fn pilot_spp(spp: u32) -> u32 {
    (spp / 16).clamp(4, 16)
}

/// How a plan spreads the samples over the pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spread {
    /// The same count in every pixel.
    Uniform,
    /// By each pixel's relative variance (over its luminance squared): the
    /// measure of a noise target, whose relative error it minimises.
    Relative,
    /// By each pixel's variance over its luminance (not squared), between
    /// the squared error (which spends the samples on bright pixels) and
    /// the relative one (on dark pixels): without a noise target. Measured
    /// at equal time against the uniform image on the harness scenes: the
    /// smokes 1.06–1.28×, the clouds 1.05–1.18×, where the relative spread
    /// lost up to 0.88× (README, "Adaptive sampling and noise targets").
    Luminance,
}

impl Spread {
    /// The spread of a piloted render with `settings`: none unless adaptive
    /// or the automatic choice; a noise target's is the relative error's.
    pub fn of(settings: &AdaptiveSettings) -> Spread {
        match (settings.noise, settings.adaptive || settings.auto) {
            (_, false) => Spread::Uniform,
            (Some(_), true) => Spread::Relative,
            (None, true) => Spread::Luminance,
        }
    }
}

/// What the pilot says about each pixel, and the counts it implies.
pub struct Plan {
    /// Relative variance per sample of each pixel (luminance-normalised).
    rel_var: Vec<f64>,
    /// Variance per sample of each pixel (the mean over channels) over its
    /// floored luminance (not squared), at least [`unseen_variance`] times
    /// that luminance.
    guarded_lum: Vec<f64>,
    /// Cost of a sample of each pixel, in units of a sample without media
    /// ([`sample_costs`]).
    cost: Vec<f64>,
    /// Allocation density, mean 1 over the members (all 1 when not adaptive).
    density: Vec<f64>,
    /// The pixels the plan is for (the others only lend their estimates to
    /// their neighbours' densities): its totals, work, error and levels
    /// count these alone.
    member: Vec<bool>,
    /// Fewest image samples of any pixel.
    pub min_count: u32,
    /// Most image samples of any pixel (the spp cap).
    pub cap: u32,
}

impl Plan {
    /// The plan of a `w`×`h` crop from its pilot sums, spread by `spread`.
    pub fn new(pilot: &[PixelSums], w: usize, spread: Spread, min_count: u32, cap: u32) -> Plan {
        let all = vec![true; pilot.len()];
        Plan::for_members(&|i| pilot[i], w, spread, (min_count, cap), all)
    }

    /// [`Plan::new`] for the pixels marked in `member` alone, pixel `i`'s
    /// pilot sums being `pilot(i)` (made as asked: no second frame in memory).
    pub fn for_members(
        pilot: &dyn Fn(usize) -> PixelSums,
        w: usize,
        spread: Spread,
        (min_count, cap): (u32, u32),
        member: Vec<bool>,
    ) -> Plan {
        let n = member.len();
        let Variances {
            rel_var,
            guarded_rel,
            guarded_lum,
        } = variances(n, pilot);
        let cost = sample_costs(n, pilot);
        let mut density = match spread {
            Spread::Uniform => vec![1.0; rel_var.len()],
            Spread::Relative => densities(&guarded_rel, &cost, w, |_, _| true),
            Spread::Luminance => densities(&guarded_lum, &cost, w, |_, _| true),
        };
        normalise_over(&mut density, &member);
        Plan {
            rel_var,
            guarded_lum,
            cost,
            density,
            member,
            min_count: min_count.min(cap),
            cap,
        }
    }

    /// How many times more efficient (1 / (error² × cost)) the spread by
    /// [`Spread::Luminance`] is predicted to be than the same count in every
    /// pixel, by its own measure of error (the sum of each pixel's squared
    /// error over its floored luminance), for a render of `spp` samples per
    /// pixel in all, the pilot's among them (no pixel below the pilot's
    /// count), over the members. Each member is judged with the density of
    /// its member neighbours alone (of the 8), independent of its own pilot
    /// samples: with its own, a pilot's noise would vouch for itself and a
    /// scene of even noise would seem to gain. 0 when the pilot saw no variance.
    pub fn predicted_gain(&self, w: usize, spp: u32) -> f64 {
        let others = |i: usize, j: usize| i != j && self.member[j];
        let mut neighbours = densities(&self.guarded_lum, &self.cost, w, others);
        normalise_over(&mut neighbours, &self.member);
        let level = spp.max(1) as f64;
        let counts: Vec<f64> = neighbours
            .iter()
            .map(|d| (level * d).max(self.min_count.max(1) as f64))
            .collect();
        let over = |f: &dyn Fn(usize) -> f64| -> f64 { self.members().map(f).sum() };
        let work = over(&|i| self.cost[i] * counts[i]);
        let uniform_work = over(&|i| self.cost[i]);
        let uniform = over(&|i| self.guarded_lum[i]);
        let spread = over(&|i| self.guarded_lum[i] / counts[i]);
        match uniform > 0.0 && uniform.is_finite() {
            true => uniform * uniform_work / (spread * work),
            false => 0.0,
        }
    }

    /// Pixels of the plan's frame (members or not).
    pub fn pixels(&self) -> usize {
        self.density.len()
    }

    /// The indices of the pixels the plan is for.
    fn members(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.member.len()).filter(|&i| self.member[i])
    }

    /// Pixel `i`'s relative variance per sample.
    pub fn rel_var(&self, i: usize) -> f64 {
        self.rel_var[i]
    }

    /// The densities taken `share` of the way from uniform (1) to the
    /// plan's, then scaled to mean 1 again: 0 gives the same count in every pixel.
    pub fn spread_by(&mut self, share: f64) {
        self.density
            .iter_mut()
            .for_each(|d| *d = 1.0 + share * (*d - 1.0));
        normalise_over(&mut self.density, &self.member);
    }

    /// Image samples of pixel `i` at `level` (a level is about the mean spp).
    #[inline]
    pub fn count(&self, i: usize, level: f64) -> u32 {
        let n = (level * self.density[i]).ceil();
        (n.min(self.cap as f64) as u32).clamp(self.min_count, self.cap)
    }

    /// Image samples of every pixel at `level` (members or not).
    pub fn counts(&self, level: f64) -> Vec<u32> {
        (0..self.density.len())
            .map(|i| self.count(i, level))
            .collect()
    }

    /// Pixels the plan is for.
    pub fn member_count(&self) -> usize {
        self.members().count()
    }

    /// The level at which every member reaches the cap.
    pub fn top_level(&self) -> f64 {
        let least = self
            .members()
            .map(|i| self.density[i])
            .filter(|&d| d > 0.0)
            .fold(f64::INFINITY, f64::min);
        match least.is_finite() {
            true => self.cap as f64 / least + 1.0,
            false => self.cap as f64,
        }
    }

    /// Total samples of the members at `level`.
    pub fn total(&self, level: f64) -> u64 {
        self.members().map(|i| self.count(i, level) as u64).sum()
    }

    /// The estimated relative error of the members when the pixels hold
    /// `counts` samples: sqrt(mean over members of relative variance / count).
    pub fn error(&self, counts: &[u32]) -> f64 {
        let n = self.member_count().max(1) as f64;
        let sum: f64 = self
            .members()
            .map(|i| self.rel_var[i] / counts[i].max(1) as f64)
            .sum();
        (sum / n).sqrt()
    }

    /// The highest level whose total is at most `budget` samples.
    pub fn level_for_budget(&self, budget: u64) -> f64 {
        self.search(|level| self.total(level) <= budget).0
    }

    /// The cost of the image at `level`: each pixel's count times its cost
    /// per sample ([`sample_costs`]).
    pub fn work(&self, level: f64) -> f64 {
        self.members()
            .map(|i| self.count(i, level) as f64 * self.cost[i])
            .sum()
    }

    /// The highest level whose image costs at most what `spp` samples in
    /// every pixel would: a spread toward costly pixels then takes about
    /// the uniform image's time, not more, for the same work.
    pub fn level_for_uniform_work(&self, spp: u32) -> f64 {
        let budget = spp as f64 * self.members().map(|i| self.cost[i]).sum::<f64>();
        self.search(|level| self.work(level) <= budget).0
    }

    /// The lowest level whose estimated error is at most `target` (the top
    /// level when even the cap does not reach it).
    pub fn level_for_noise(&self, target: f64) -> f64 {
        self.search(|level| self.error(&self.counts(level)) > target)
            .1
    }

    /// The levels (lo, hi) around where `ok` turns false in [0, top], `ok`
    /// holding up to some level: `ok(lo)` (or lo = 0), `!ok(hi)` (or hi = top).
    fn search(&self, ok: impl Fn(f64) -> bool) -> (f64, f64) {
        let (mut lo, mut hi) = (0.0, self.top_level());
        if ok(hi) {
            return (hi, hi);
        }
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            match ok(mid) {
                true => lo = mid,
                false => hi = mid,
            }
        }
        (lo, hi)
    }
}

/// Per pixel: v = (1/3)·Σ over channels of the sample variance, and v
/// over max(luminance of the mean, floor)²; the floor is [`FLOOR_FRACTION`]
/// of the mean luminance of all pixels; for the spread, neither is taken
/// below [`unseen_variance`] where a sample traced more than its camera
/// ray: no pilot proves such a pixel exact.
fn variances(n: usize, pilot: &dyn Fn(usize) -> PixelSums) -> Variances {
    let abs_var: Vec<f64> = (0..n)
        .map(|i| {
            let p = pilot(i);
            (0..3).map(|c| sample_variance(&p, c)).sum::<f64>() / 3.0
        })
        .collect();
    let (scale, rel_var) = relative_variances(n, pilot, &abs_var);
    let guarded_rel: Vec<f64> = (0..n)
        .map(pilot)
        .zip(&rel_var)
        .map(|(p, &v)| match p.rays > (p.count + p.nonfinite) as u64 {
            true => v.max(unseen_variance(p.count)),
            // One ray per sample: the camera ray escaped, no event to meet.
            false => v,
        })
        .collect();
    let guarded_lum = guarded_rel
        .iter()
        .zip(&scale)
        .map(|(v, s)| v * s.sqrt())
        .collect();
    Variances {
        rel_var,
        guarded_rel,
        guarded_lum,
    }
}

/// A pilot's variances per pixel (see [`Plan`]'s fields of the same names).
struct Variances {
    rel_var: Vec<f64>,
    guarded_rel: Vec<f64>,
    guarded_lum: Vec<f64>,
}

/// The least relative variance per sample a pixel is taken to have after
/// `n` pilot samples: an event the 9·n samples of its 3×3 neighbourhood
/// never met may still come at a rate of 1/(9n + 2) (Laplace's rule of
/// succession), and a sample that is 0 at that rate and else the mean
/// over 1 − p has a relative variance of p/(1 − p) ≈ p. Without it, the
/// pixels of a sky-lit ground whose pilot met no occluder (most of them)
/// get the fewest samples and carry the image's error.
fn unseen_variance(n: u32) -> f64 {
    1.0 / (9.0 * n as f64 + 2.0)
}

/// Each pixel's max(luminance, floor)² and its variance `abs_var` over it.
fn relative_variances(
    n: usize,
    pilot: &dyn Fn(usize) -> PixelSums,
    abs_var: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let lum: Vec<f64> = (0..n)
        .map(|i| pilot(i).mean().luminance().max(0.0) as f64)
        .collect();
    let mean = lum.iter().sum::<f64>() / lum.len().max(1) as f64;
    let floor = (FLOOR_FRACTION * mean).max(1e-12);
    let scale: Vec<f64> = lum.iter().map(|&y| y.max(floor).powi(2)).collect();
    let rel_var = abs_var.iter().zip(&scale).map(|(v, s)| v / s).collect();
    (scale, rel_var)
}

/// The unbiased sample variance of channel `c` (0 below two samples).
fn sample_variance(p: &PixelSums, c: usize) -> f64 {
    crate::film::variance_of_mean(p.sum[c], p.squares[c], p.count)
        .map_or(0.0, |v| v * p.count as f64)
}

/// Each pixel's cost per sample: its pilot's rays and medium lookups per
/// sample, at least 1. Both are counted, not timed, so the plan (and the
/// image) depends on the seed only; a lookup costs about what a ray does
/// (0.08–0.18 µs per lookup on the bench scenes, 0.07 µs per sample of a
/// camera ray that escapes).
fn sample_costs(n: usize, pilot: &dyn Fn(usize) -> PixelSums) -> Vec<f64> {
    (0..n)
        .map(pilot)
        .map(|p| {
            let work = (p.rays + p.lookups) as f64;
            (work / (p.count + p.nonfinite).max(1) as f64).max(1.0)
        })
        .collect()
}

/// Allocation densities: the square root of each pixel's relative variance
/// over its cost per sample, each averaged over its 3×3 neighbourhood (a
/// pilot of a few samples misses rare paths; neighbours share them), to be
/// scaled to mean 1 ([`normalise_over`]). Minimising (sum of variance / count) × (sum of cost × count)
/// gives counts ∝ sqrt(variance / cost): the most efficient spread.
/// Pixel i's average takes neighbour j (itself too) where `counted(i, j)`.
fn densities(
    rel_var: &[f64],
    cost: &[f64],
    w: usize,
    counted: impl Fn(usize, usize) -> bool,
) -> Vec<f64> {
    let h = rel_var.len() / w.max(1);
    let mut density = vec![0.0; rel_var.len()];
    for y in 0..h {
        for x in 0..w {
            let (mut sum, mut work) = (0.0, 0.0);
            for yy in y.saturating_sub(1)..(y + 2).min(h) {
                for xx in x.saturating_sub(1)..(x + 2).min(w) {
                    if counted(y * w + x, yy * w + xx) {
                        sum += rel_var[yy * w + xx];
                        work += cost[yy * w + xx];
                    }
                }
            }
            density[y * w + x] = match work > 0.0 {
                true => (sum / work).sqrt(),
                false => 0.0,
            };
        }
    }
    density
}

/// Scales `density` to mean 1 over the pixels marked in `member` (all 1
/// when that mean is 0 or not finite).
fn normalise_over(density: &mut [f64], member: &[bool]) {
    let (sum, n) = density
        .iter()
        .zip(member)
        .filter(|(_, &m)| m)
        .fold((0.0, 0usize), |(s, n), (d, _)| (s + d, n + 1));
    let mean = sum / n.max(1) as f64;
    if mean > 0.0 && mean.is_finite() {
        density.iter_mut().for_each(|d| *d /= mean);
    } else {
        density.iter_mut().for_each(|d| *d = 1.0);
    }
}

/// How a piloted render went: for the summary and the EXR header.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseReport {
    /// Samples per pixel of the pilot (the first of the image's).
    pub pilot_spp: u32,
    /// Spread by the pilot's estimates (false: uniform counts).
    pub adaptive: bool,
    /// The noise target, if any.
    pub target: Option<f32>,
    /// The estimated relative error of the image at its final counts.
    pub error: f64,
    /// Fewest, mean and most image samples of a pixel.
    pub min_spp: u32,
    pub mean_spp: f64,
    pub max_spp: u32,
}

impl NoiseReport {
    /// True when a noise target was given and the estimate is above it.
    pub fn target_missed(&self) -> bool {
        self.target.is_some_and(|t| self.error > t as f64)
    }

    /// The `brume:adaptive` header text.
    pub fn header(&self) -> String {
        let target = match self.target {
            Some(t) => format!("; noise target {t}"),
            None => String::new(),
        };
        format!(
            "{}; pilot {} spp, the first of every pixel's stream, in the image; image {}-{} spp \
             per pixel (brume:count), mean {:.3}; estimated relative error {:.6}{target}",
            if self.adaptive { "adaptive" } else { "uniform" },
            self.pilot_spp,
            self.min_spp,
            self.max_spp,
            self.mean_spp,
            self.error
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::color::Rgb;

    fn sums(values: &[f32]) -> PixelSums {
        let mut p = PixelSums::default();
        for &v in values {
            p.add(Rgb::splat(v));
        }
        p
    }

    /// A noisy pixel among flat ones gets more samples; the total at the
    /// budget level stays within the budget.
    #[test]
    fn the_noisy_pixel_gets_the_samples() {
        let flat = sums(&[1.0, 1.0, 1.0, 1.0]);
        let noisy = sums(&[0.0, 4.0, 0.0, 0.0]);
        let mut pilot = vec![flat; 25];
        pilot[12] = noisy;
        let plan = Plan::new(&pilot, 5, Spread::Luminance, 4, 1000);
        let level = plan.level_for_budget(25 * 16);
        let counts = plan.counts(level);
        assert!(counts.iter().map(|&c| c as u64).sum::<u64>() <= 25 * 16);
        assert!(counts[12] > 4 * counts[0], "{counts:?}");
        // The corners are outside the noisy pixel's neighbourhood: the minimum.
        assert_eq!(counts[0], 4);
    }

    /// At the level of equal work a spread toward a costly pixel holds
    /// fewer samples than the uniform image, at most its work, and takes
    /// nearly all of it.
    #[test]
    fn equal_work_spends_what_the_uniform_image_would() {
        let flat = sums(&[1.0, 1.0, 1.0, 1.0]);
        let mut noisy = sums(&[0.0, 4.0, 0.0, 0.0]);
        (noisy.rays, noisy.lookups) = (4, 4 * 15); // cost 16 a sample
        let mut pilot = vec![flat; 25];
        pilot[12] = noisy;
        let plan = Plan::new(&pilot, 5, Spread::Luminance, 4, 1000);
        let uniform = 64.0 * (24.0 + 16.0);
        let level = plan.level_for_uniform_work(64);
        let work = plan.work(level);
        assert!(
            work <= uniform && work > 0.95 * uniform,
            "{work} of {uniform}"
        );
        assert!(plan.total(level) < 25 * 64, "{}", plan.total(level));
        assert!(plan.counts(level)[12] > 64, "{:?}", plan.counts(level));
    }

    /// Uniform plans give every pixel the same count; the error falls as 1/sqrt(n).
    #[test]
    fn a_uniform_plan_and_its_error() {
        let pilot = vec![sums(&[0.0, 2.0, 0.0, 2.0]); 4];
        let plan = Plan::new(&pilot, 2, Spread::Uniform, 4, 1000);
        let counts = plan.counts(64.0);
        assert_eq!(counts, vec![64; 4]);
        // Per-sample variance 4/3, mean 1: relative error sqrt(4/3/64).
        let e = plan.error(&counts);
        assert!((e - (4.0f64 / 3.0 / 64.0).sqrt()).abs() < 1e-12, "{e}");
        let level = plan.level_for_noise(e);
        assert!(plan.error(&plan.counts(level)) <= e);
        assert!(plan.error(&plan.counts(level - 1.0)) > e, "{level}");
    }

    /// A pixel whose samples take more medium lookups gets fewer samples at
    /// the same variance: density ∝ sqrt(variance / cost).
    #[test]
    fn a_costlier_pixel_gets_fewer_samples() {
        let noisy = sums(&[0.0, 2.0, 0.0, 2.0]);
        let mut costly = noisy;
        (costly.rays, costly.lookups) = (4, 4 * 7); // a ray and 7 lookups per sample: cost 8
        let pilot = [noisy, costly];
        let rel_var = variances(2, &|i| pilot[i]).guarded_rel;
        let cost = sample_costs(2, &|i| pilot[i]);
        assert_eq!(cost, vec![1.0, 8.0]);
        // 1×2 pixels: each pixel's neighbourhood is both, so leave the centre out.
        let d = densities(&rel_var, &cost, 2, |i, j| i != j);
        assert!((d[1] / d[0] - 8f64.sqrt()).abs() < 1e-9, "{d:?}");
    }

    /// Bright pixels with the larger noise beside dark ones with the larger
    /// relative noise: the relative spread gives the dark half 5× the
    /// density (25× its relative variance), the squared error would give
    /// it half; the luminance spread sits between (√2.5 ≈ 1.58×), and the
    /// gain it predicts by its own measure is a gain, at most the ideal
    /// allocation's between halves whose measure differs 2.5×:
    /// (1 + 2.5)/2 / ((1 + √2.5)/2)² ≈ 1.0507.
    #[test]
    fn the_luminance_spread_lies_between_the_squared_and_the_relative_error() {
        let w = 16;
        let bright = sums(&[9.0, 11.0, 9.0, 11.0]); // luminance 10, variance 4/3
        let dark = sums(&[0.5, 1.5, 0.5, 1.5]); // luminance 1, variance 1/3
        let pilot: Vec<PixelSums> = (0..w * w)
            .map(|i| if i % w < w / 2 { bright } else { dark })
            .collect();
        let relative = Plan::new(&pilot, w, Spread::Relative, 4, 1 << 20);
        let ratio = relative.density[w - 1] / relative.density[0];
        assert!((ratio - 5.0).abs() < 1e-9, "{ratio}");
        let plan = Plan::new(&pilot, w, Spread::Luminance, 4, 1 << 20);
        let ratio = plan.density[w - 1] / plan.density[0];
        assert!((ratio - 2.5f64.sqrt()).abs() < 1e-9, "{ratio}");
        let gain = plan.predicted_gain(w, 64);
        let ideal = 1.75 / ((1.0 + 2.5f64.sqrt()) / 2.0).powi(2);
        assert!(gain > 1.0 && gain <= ideal, "{gain} vs {ideal}");
    }

    /// The automatic choice's share of the spread ramps from none at
    /// `AUTO_GAIN` to all at `FULL_GAIN`, and a plan spread by a share
    /// lies that far between uniform and its own densities (mean 1).
    #[test]
    fn the_spread_share_ramps_between_the_two_gains() {
        assert_eq!(spread_share(AUTO_GAIN - 0.01), 0.0);
        assert_eq!(spread_share(AUTO_GAIN), 0.0);
        assert!((spread_share(0.5 * (AUTO_GAIN + FULL_GAIN)) - 0.5).abs() < 1e-12);
        assert_eq!(spread_share(FULL_GAIN), 1.0);
        assert_eq!(spread_share(3.0), 1.0);
        let pilot = [sums(&[0.0, 2.0, 0.0, 2.0]), sums(&[1.0; 4])];
        let mut plan = Plan::new(&pilot, 2, Spread::Luminance, 1, 100);
        let full = plan.density.clone();
        plan.spread_by(0.5);
        let expect = |d: f64| 1.0 + 0.5 * (d - 1.0);
        for (d, f) in plan.density.iter().zip(&full) {
            assert!((d - expect(*f)).abs() < 1e-12, "{d} vs {f}");
        }
        plan.spread_by(0.0);
        assert_eq!(plan.density, vec![1.0, 1.0]);
    }

    /// A pilot that saw no variance (every camera ray escaped) predicts no
    /// gain at all: 0, not the NaN of 0/0.
    #[test]
    fn a_pilot_without_variance_predicts_no_gain() {
        let mut exact = sums(&[1.0; 4]);
        exact.rays = 4;
        let plan = Plan::new(&[exact; 9], 3, Spread::Luminance, 4, 1000);
        assert_eq!(plan.predicted_gain(3, 64), 0.0);
    }

    /// A noise target spreads by its own measure, the relative error; an
    /// adaptive render or the automatic choice without one by the variance
    /// over the luminance; neither keeps the count even.
    #[test]
    fn a_noise_target_spreads_by_the_relative_error() {
        let settings = |adaptive, noise, auto| AdaptiveSettings {
            adaptive,
            noise,
            auto,
        };
        assert_eq!(
            Spread::of(&settings(true, Some(0.02), false)),
            Spread::Relative
        );
        assert_eq!(Spread::of(&settings(true, None, false)), Spread::Luminance);
        assert_eq!(Spread::of(&settings(false, None, true)), Spread::Luminance);
        assert_eq!(
            Spread::of(&settings(false, Some(0.02), false)),
            Spread::Uniform
        );
        assert_eq!(Spread::of(&settings(false, None, false)), Spread::Uniform);
    }

    /// A pixel whose samples traced more than the camera ray is never taken
    /// as exact, however alike its pilot samples came out; one whose camera
    /// ray escaped is.
    #[test]
    fn only_an_escaped_camera_ray_is_taken_as_exact() {
        let mut escaped = sums(&[1.0; 4]);
        escaped.rays = 4;
        let mut bounced = escaped;
        bounced.rays = 12;
        let pilot = [escaped, bounced];
        let v = variances(2, &|i| pilot[i]);
        assert_eq!(v.rel_var, vec![0.0, 0.0]);
        assert_eq!(v.guarded_rel, vec![0.0, 1.0 / 38.0]);
        // Luminance 1 is above the floor (0.1 of the mean): the same variance.
        assert_eq!(v.guarded_lum, vec![0.0, 1.0 / 38.0]);
    }

    /// Pseudo-random pilot sums of `n` samples with variance `var` (a
    /// fixed hash, so the test does not depend on a generator).
    fn noisy_pixel(i: usize, n: usize, var: f32) -> PixelSums {
        let values: Vec<f32> = (0..n)
            .map(|k| {
                let h = crate::sampling::mix64((i * 131 + k) as u64);
                let u = (h >> 40) as f32 / (1u64 << 24) as f32;
                1.0 + (12.0 * var).sqrt() * (u - 0.5)
            })
            .collect();
        sums(&values)
    }

    /// Even noise is kept uniform (its pilot estimates scatter, which a
    /// pixel's own estimate would take for a gain); noise confined to a
    /// patch of a dark-free frame is spread, with the predicted gain near
    /// the ideal allocation's.
    #[test]
    fn the_predicted_gain_tells_even_noise_from_a_noisy_patch() {
        let (w, pilot) = (32, 4);
        let even: Vec<PixelSums> = (0..w * w).map(|i| noisy_pixel(i, pilot, 0.5)).collect();
        let plan = Plan::new(&even, w, Spread::Luminance, pilot as u32, 1 << 20);
        let gain = plan.predicted_gain(w, 64);
        // Spreading even noise loses (0.98 here): judged with each pixel's
        // own estimate, the scatter of the estimates would seem a gain.
        assert!(gain < 1.0, "even noise: {gain}");
        // A 8×8 patch of noise in a flat frame: ideal gain w²/8² = 16 at
        // equal samples, less the pilot's uniform samples and the patch's edges.
        let patch: Vec<PixelSums> = (0..w * w)
            .map(|i| match (i % w, i / w) {
                (8..16, 8..16) => noisy_pixel(i, pilot, 0.5),
                _ => sums(&[1.0; 4]),
            })
            .collect();
        let plan = Plan::new(&patch, w, Spread::Luminance, pilot as u32, 1 << 20);
        let gain = plan.predicted_gain(w, 64);
        assert!(gain > 4.0 && gain < 16.0, "noisy patch: {gain}");
    }
}
