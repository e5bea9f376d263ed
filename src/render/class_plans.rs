//! The pilot's samples kept in the image (module `adaptive`), unbiased: the
//! pixels are coloured as a checkerboard, and every count a pixel gets is a
//! function of the other colour's pilot samples alone.
//!
//! A pixel's mean of `N` samples is unbiased when `N` does not depend on
//! those samples' values. The pilot takes the first samples of every
//! pixel's ordinary stream; a pixel's count then must not depend on its own
//! pilot samples, nor, through a level shared by the image, on those of its
//! own colour. So each colour has its plan ([`Plan`]) made from a frame in
//! which every pixel of that colour is replaced by the pooled pilot of its
//! four edge neighbours (all of the other colour) and every pixel of the
//! other colour keeps its own: that plan's densities, levels, predicted gain
//! and the automatic choice are functions of the other colour's samples, and
//! the streams of different pixels are independent. Each colour's counts
//! come from its own plan at its own goal level.

use super::adaptive::{Plan, Spread};
use crate::film::PixelSums;

/// The colour of pixel `i` of a `w`-wide crop: 0 or 1, a checkerboard.
#[inline]
pub fn colour(i: usize, w: usize) -> usize {
    (i % w + i / w) & 1
}

/// Pixel `i`'s sums in the frame colour `c`'s plan is made from: for a
/// pixel of colour `c`, its edge neighbours' pooled pilot (none: empty
/// sums); for another pixel, its own.
pub fn frame_pixel(pilot: &[PixelSums], w: usize, c: usize, i: usize) -> PixelSums {
    if colour(i, w) != c {
        return pilot[i];
    }
    let h = pilot.len() / w.max(1);
    let (x, y) = (i % w, i / w);
    let mut pooled = PixelSums::default();
    let neighbours = [
        (x > 0).then(|| i - 1),
        (x + 1 < w).then(|| i + 1),
        (y > 0).then(|| i - w),
        (y + 1 < h).then(|| i + w),
    ];
    for j in neighbours.into_iter().flatten() {
        pooled = pooled.pooled(&pilot[j]);
    }
    pooled
}

/// The gain colour `c` of a `w`-wide crop is predicted to make by spreading
/// its samples, for a render of `spp` per pixel whose counts lie in
/// `(min_count, cap)`: [`Plan::predicted_gain`] over the other colour's
/// pixels, each judged by its own pilot against the density of its
/// same-colour neighbours (the diagonal ones). Colour `c`'s plan cannot
/// judge itself: its pixels' estimates are the pooled pilot their densities
/// come from.
pub fn predicted_gain(
    pilot: &[PixelSums],
    w: usize,
    c: usize,
    spp: u32,
    counts: (u32, u32),
) -> f64 {
    let member = (0..pilot.len()).map(|i| colour(i, w) != c).collect();
    let judge = Plan::for_members(&|i| pilot[i], w, Spread::Luminance, counts, member);
    judge.predicted_gain(w, spp)
}

/// The two colours' plans and the level each aims at.
pub struct ClassPlans {
    /// The plan of each colour (indexed by [`colour`]).
    plans: [Plan; 2],
    /// Pixels per row.
    w: usize,
    /// The level each colour's image stops at.
    goals: [f64; 2],
}

impl ClassPlans {
    /// Each colour's plan of a `w`-wide crop from the pilot's sums (see the module doc).
    pub fn new(pilot: &[PixelSums], w: usize, spread: Spread, min_count: u32, cap: u32) -> Self {
        let plan = |c| {
            let member = (0..pilot.len()).map(|i| colour(i, w) == c).collect();
            let frame = |i| frame_pixel(pilot, w, c, i);
            Plan::for_members(&frame, w, spread, (min_count, cap), member)
        };
        ClassPlans {
            plans: [plan(0), plan(1)],
            w,
            goals: [f64::INFINITY; 2],
        }
    }

    /// Colour `c`'s plan.
    pub fn plan(&self, c: usize) -> &Plan {
        &self.plans[c]
    }

    /// Colour `c`'s densities taken `share` of the way from uniform ([`Plan::spread_by`]).
    pub fn spread_by(&mut self, c: usize, share: f64) {
        self.plans[c].spread_by(share);
    }

    /// Fixes each colour's goal level, each from `goal` of its own plan.
    pub fn set_goals(&mut self, goal: impl Fn(&Plan) -> f64) {
        self.goals = [goal(&self.plans[0]), goal(&self.plans[1])];
    }

    /// The level the passes run up to: the higher of the two goals.
    pub fn goal(&self) -> f64 {
        self.goals[0].max(self.goals[1])
    }

    /// Colour `c`'s level when the passes are at `level`: its goal at the
    /// end, the same fraction of it on the way.
    fn level_of(&self, c: usize, level: f64) -> f64 {
        let goal = self.goal();
        match level >= goal {
            true => self.goals[c],
            false => level * (self.goals[c] / goal),
        }
    }

    /// Samples of every pixel at `level` (pilot included).
    pub fn counts(&self, level: f64) -> Vec<u32> {
        let levels = [self.level_of(0, level), self.level_of(1, level)];
        (0..self.plans[0].pixels())
            .map(|i| {
                let c = colour(i, self.w);
                self.plans[c].count(i, levels[c])
            })
            .collect()
    }

    /// Total samples at `level`: each colour's plan counts its own pixels.
    pub fn total(&self, level: f64) -> u64 {
        (0..2)
            .map(|c| self.plans[c].total(self.level_of(c, level)))
            .sum()
    }

    /// The highest level in [lo, hi] whose total is at most `budget` samples (lo if none).
    pub fn level_within(&self, lo: f64, hi: f64, budget: u64) -> f64 {
        if self.total(hi) <= budget {
            return hi;
        }
        let (mut lo, mut hi) = (lo, hi);
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            match self.total(mid) <= budget {
                true => lo = mid,
                false => hi = mid,
            }
        }
        lo
    }

    /// The estimated relative error of the image at `counts`, each pixel's
    /// relative variance taken from its colour's plan.
    pub fn error(&self, counts: &[u32]) -> f64 {
        let n = counts.len().max(1) as f64;
        let sum: f64 = counts
            .iter()
            .enumerate()
            .map(|(i, &k)| self.plans[colour(i, self.w)].rel_var(i) / k.max(1) as f64)
            .sum();
        (sum / n).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::color::Rgb;
    use crate::render::adaptive::AUTO_GAIN;

    /// Pilot sums of a `w`×`h` crop: pixel i's `n` samples are spread about a level of its own.
    fn pilot(w: usize, h: usize, n: u32, seed: u64) -> Vec<PixelSums> {
        pilot_levels(w, h, n, seed, |i| 1.0 + (i % 7) as f32)
    }

    /// Pilot sums of even, heavy-tailed noise: each of a pixel's `n` samples
    /// is 10 with probability 0.1, else 0.5 (a rare bright path, as in a
    /// dense medium), and traced more than its camera ray.
    fn pilot_rare(w: usize, h: usize, n: u32, seed: u64) -> Vec<PixelSums> {
        let mut state = seed;
        (0..w * h)
            .map(|_| {
                let mut p = PixelSums::default();
                for _ in 0..n {
                    state = crate::sampling::mix64(state.wrapping_add(0x9e37_79b9_7f4a_7c15));
                    let u = (state >> 11) as f64 / (1u64 << 53) as f64;
                    p.add(Rgb::splat(if u < 0.1 { 10.0 } else { 0.5 }));
                }
                p.rays = 3 * n as u64;
                p
            })
            .collect()
    }

    /// Pilot sums whose pixel i's samples are uniform on [0, 4·level(i)].
    fn pilot_levels(
        w: usize,
        h: usize,
        n: u32,
        seed: u64,
        level: impl Fn(usize) -> f32,
    ) -> Vec<PixelSums> {
        let mut state = seed;
        let mut next = move || {
            state = crate::sampling::mix64(state.wrapping_add(0x9e37_79b9_7f4a_7c15));
            (state >> 11) as f32 / (1u64 << 53) as f32
        };
        (0..w * h)
            .map(|i| {
                let mut p = PixelSums::default();
                let level = level(i);
                for _ in 0..n {
                    p.add(Rgb::splat(level * 4.0 * next()));
                }
                p.rays = n as u64 * (1 + (i % 3) as u64);
                p.lookups = n as u64 * (i % 5) as u64;
                p.nonfinite = (i % 2) as u32;
                p
            })
            .collect()
    }

    /// No pixel's count moves when its own pilot samples, or any of its
    /// colour's, change: the property that keeps the image unbiased with
    /// the pilot in it (counts from the other colour alone). A plan made
    /// from the whole pilot fails it.
    #[test]
    fn a_pixels_count_does_not_depend_on_its_colours_pilot() {
        let (w, h, n) = (12, 9, 8);
        let base = pilot(w, h, n, 1);
        let other = pilot(w, h, n, 2);
        for c in 0..2 {
            // Colour c's pilot samples redrawn, the other colour's kept.
            let changed: Vec<PixelSums> = (0..w * h)
                .map(|i| if colour(i, w) == c { other[i] } else { base[i] })
                .collect();
            let counts = |p: &[PixelSums]| {
                let mut plans = ClassPlans::new(p, w, Spread::Luminance, n, 1 << 20);
                plans.set_goals(|plan| plan.level_for_uniform_work(64));
                plans.counts(plans.goal())
            };
            let (before, after) = (counts(&base), counts(&changed));
            // Nor does the colour's predicted gain, the automatic choice's ground.
            let gain = |p: &[PixelSums]| predicted_gain(p, w, c, 64, (n, 1 << 20));
            assert_eq!(gain(&base), gain(&changed), "colour {c}'s predicted gain");
            let mut moved_other = false;
            for i in 0..w * h {
                if colour(i, w) == c {
                    assert_eq!(before[i], after[i], "pixel {i} of colour {c}");
                } else {
                    moved_other |= before[i] != after[i];
                }
            }
            // The other colour's counts do follow colour c's samples.
            assert!(moved_other, "colour {c}'s samples moved no count");
        }
    }

    /// Even, heavy-tailed noise: neither colour predicts a gain (0.61–0.83
    /// over seeds 4–13), where the colour's own plan, whose pixels are the
    /// pooled pilot their densities come from, vouches for itself (above
    /// 1); a noisy patch in a flat frame: both colours predict one.
    #[test]
    fn each_colour_is_judged_by_the_other_colours_own_pilot() {
        let (w, h, n) = (32, 32, 8);
        let even = pilot_rare(w, h, n, 4);
        let plans = ClassPlans::new(&even, w, Spread::Luminance, n, 1 << 20);
        for c in 0..2 {
            let gain = predicted_gain(&even, w, c, 64, (n, 1 << 20));
            assert!(gain < AUTO_GAIN, "even noise, colour {c}: {gain}");
            let own = plans.plan(c).predicted_gain(w, 64);
            assert!(
                own > AUTO_GAIN,
                "even noise, colour {c} judging itself: {own}"
            );
        }
        let patch = pilot_levels(w, h, n, 5, |i| match (i % w, i / w) {
            (8..16, 8..16) => 1.0,
            _ => 0.0,
        });
        for c in 0..2 {
            let gain = predicted_gain(&patch, w, c, 64, (n, 1 << 20));
            assert!(gain > 2.0, "noisy patch, colour {c}: {gain}");
        }
    }

    /// Each colour stops at its own goal, the passes at the higher one; on
    /// the way a colour's level is the same fraction of its goal; a colour
    /// spread by a share of 0 takes the same count in every pixel.
    #[test]
    fn each_colour_reaches_its_own_goal() {
        // 3×3: colour 0 holds 5 pixels, colour 1 holds 4.
        let (w, n) = (3, 4);
        let p = pilot(w, 3, n, 6);
        let mut plans = ClassPlans::new(&p, w, Spread::Luminance, n, 1 << 20);
        plans.set_goals(|plan| 10.0 * plan.member_count() as f64);
        assert_eq!(plans.goal(), 50.0);
        let half = plans.counts(25.0);
        let end = plans.counts(plans.goal());
        for i in 0..9 {
            let c = colour(i, w);
            let goal = [50.0, 40.0][c];
            assert_eq!(end[i], plans.plan(c).count(i, goal), "pixel {i}");
            assert_eq!(half[i], plans.plan(c).count(i, 0.5 * goal), "pixel {i}");
        }
        plans.spread_by(1, 0.0);
        let counts = plans.counts(plans.goal());
        let ones: Vec<u32> = (0..9)
            .filter(|&i| colour(i, w) == 1)
            .map(|i| counts[i])
            .collect();
        assert!(ones.iter().all(|&k| k == ones[0]), "{ones:?}");
        let zeros: Vec<u32> = (0..9)
            .filter(|&i| colour(i, w) == 0)
            .map(|i| counts[i])
            .collect();
        assert!(zeros.iter().any(|&k| k != zeros[0]), "{zeros:?}");
    }

    /// The pooled frame: a pixel of the colour is the sum of its edge
    /// neighbours' sums (two at a corner), the others are themselves.
    #[test]
    fn each_colours_frame_pools_the_edge_neighbours() {
        let (w, h) = (3, 2);
        let p = pilot(w, h, 4, 3);
        let f: Vec<PixelSums> = (0..w * h).map(|i| frame_pixel(&p, w, 0, i)).collect();
        // Pixel 0 (colour 0, a corner): its right and lower neighbours.
        assert_eq!(f[0].count, p[1].count + p[3].count);
        assert_eq!(f[0].sum[0], p[1].sum[0] + p[3].sum[0]);
        assert_eq!(f[0].rays, p[1].rays + p[3].rays);
        assert_eq!(f[0].lookups, p[1].lookups + p[3].lookups);
        assert_eq!(f[0].nonfinite, p[1].nonfinite + p[3].nonfinite);
        // Pixel 4 (colour 0, bottom middle): left, right and upper.
        assert_eq!(f[4].sum[1], p[3].sum[1] + p[5].sum[1] + p[1].sum[1]);
        // Pixel 1 (colour 1) keeps its own.
        assert_eq!(f[1].sum[2], p[1].sum[2]);
        assert_eq!(f[1].count, p[1].count);
    }
}
