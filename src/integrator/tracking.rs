//! Null-collision tracking over majorant segments: tentative collisions,
//! free-flight sampling (spectral/decomposition tracking) and transmittance
//! estimators (closed form, delta, ratio and residual ratio tracking).
//!
//! Woodcock et al. 1965 (delta tracking); Novák et al. 2014 (ratio and
//! residual ratio tracking); Kutz et al. 2017 (spectral and decomposition
//! tracking); Miller et al. 2019 (the null-scattering path integral).
//!
//! # Bounded work per ray
//!
//! A ray costs one step per tentative collision, σ̄·d of them on average, so
//! a dense volume (`density_scale = 1e6`) or a loose majorant could make one
//! ray take millions of steps. Three mechanisms bound it:
//!
//! * Dense cells of grid media are walked voxel by voxel with exact optical
//!   depths (module `exact`): about one voxel step per event, however dense.
//!
//! * Russian roulette on the transmittance weight (ratio and residual ratio
//!   tracking): once every channel of the running product is below
//!   [`ROULETTE_THRESHOLD`], the estimate survives with probability
//!   p = max|T| / threshold and is divided by p. Its expectation is unchanged
//!   (p · T/p = T), so the estimator stays unbiased; a shadow ray through a
//!   thick medium ends after the few steps that take T below the threshold
//!   instead of walking on until T underflows.
//! * A hard cap of [`MAX_TENTATIVE_COLLISIONS`] per medium per ray (tentative
//!   collisions and exact voxel steps), for the cases roulette cannot shorten
//!   (free flight through a loose majorant where no exact walk applies).
//!   A ray reaching it is ended, its transmittance or throughput set to zero
//!   (a bias toward dark, in pathological scenes only), and counted: the
//!   render reports how many rays hit the cap, as it reports non-finite
//!   samples. No scene of the test suite comes near it.

use crate::math::color::Rgb;
use crate::math::Ray;
use crate::medium::{HomogeneousMedium, MajorantIter, MajorantSegment, Medium, MediumProperties};
use crate::sampling::Sampler;
use kernel::{dispatch, TrackedMedium};
use stats::Tally;
pub use stats::{take_thread_stats, thread_lookups, TrackingStats};

mod exact;
mod kernel;
mod stats;

/// Below this max channel a transmittance weight plays Russian roulette.
pub const ROULETTE_THRESHOLD: f32 = 0.1;

/// Most tentative collisions one tracker takes along one ray (see the module doc).
pub const MAX_TENTATIVE_COLLISIONS: u32 = 1 << 16;

/// Russian roulette on a tracking weight: false if the weight was killed.
///
/// Unbiased: the survivor is divided by its survival probability.
#[inline]
fn roulette(w: &mut Rgb, sampler: &mut Sampler) -> bool {
    let m = w.map(f32::abs).max_channel();
    if m >= ROULETTE_THRESHOLD {
        return true;
    }
    let p = m / ROULETTE_THRESHOLD;
    if sampler.next_1d() < p {
        *w /= p;
        true
    } else {
        *w = Rgb::BLACK;
        false
    }
}

/// The next tracking position: `next`, or the next float after `t` when a
/// step rounds to nothing (so a tracker always moves on).
#[inline]
fn advance(t: f32, next: f32) -> f32 {
    if next > t {
        next
    } else {
        t.next_up()
    }
}

/// Walks the tentative collisions of one medium along a ray: a Poisson
/// process with rate σ̄(t) given by the medium's majorant segments.
#[derive(Clone, Debug)]
pub struct Tracker<'a> {
    segments: MajorantIter<'a>,
    current: Option<MajorantSegment>,
    t: f32,
    steps: u32,
}

/// One tentative collision: where, and the majorant there.
#[derive(Clone, Copy, Debug)]
pub struct Collision {
    /// Ray parameter.
    pub t: f32,
    /// Majorant σ̄(t).
    pub sigma_maj: f32,
    /// The segment's control extinction (for residual ratio tracking).
    pub sigma_control: Rgb,
}

impl<'a> Tracker<'a> {
    /// Tracks `medium` along `ray` over `[0, t_max)`.
    pub fn new(medium: &'a Medium, ray: &Ray, t_max: f32) -> Tracker<'a> {
        let mut segments = medium.majorants(ray, t_max);
        let current = segments.next();
        let t = current.map_or(f32::INFINITY, |s| s.t0);
        Tracker {
            segments,
            current,
            t,
            steps: 0,
        }
    }

    /// Tracks one segment only.
    fn single(seg: MajorantSegment) -> Tracker<'a> {
        Tracker {
            segments: MajorantIter::Single(None),
            current: Some(seg),
            t: seg.t0,
            steps: 0,
        }
    }

    /// True once the tracker stopped at [`MAX_TENTATIVE_COLLISIONS`].
    pub fn capped(&self) -> bool {
        self.steps > MAX_TENTATIVE_COLLISIONS
    }

    /// Advances to the next tentative collision, or `None` past the last segment.
    pub fn next(&mut self, sampler: &mut Sampler) -> Option<Collision> {
        if self.steps >= MAX_TENTATIVE_COLLISIONS {
            if self.steps == MAX_TENTATIVE_COLLISIONS {
                stats::count_capped_ray();
                self.steps += 1;
            }
            return None;
        }
        self.steps += 1;
        // A ray past its last segment draws nothing.
        self.current?;
        let mut tau = -(1.0 - sampler.next_1d()).ln();
        loop {
            let seg = self.current?;
            let t = self.t.max(seg.t0);
            let sigma = seg.majorant_at(t);
            let length = seg.t1 - t;
            if sigma > 0.0 && length > 0.0 {
                let k = seg.decay;
                if k == 0.0 || k.abs() * length < 1e-4 {
                    // Constant (or nearly constant) majorant: exponential steps. Test k == 0
                    // first: on an unbounded segment 0 · ∞ is NaN.
                    let dt = tau / sigma;
                    if dt < length {
                        self.t = advance(t, t + dt).min(seg.t1);
                        return Some(self.collision(&seg));
                    }
                    tau -= sigma * length;
                } else {
                    // σ̄(t + s) = σ e^{-k s}: ∫0^s = σ (1 - e^{-k s}) / k, inverted in closed form.
                    let available = sigma * (-(-k * length).exp_m1()) / k;
                    if tau < available {
                        let dt = -(1.0 - tau * k / sigma).ln() / k;
                        self.t = advance(t, t + dt).min(seg.t1);
                        return Some(self.collision(&seg));
                    }
                    tau -= available;
                }
            }
            self.current = self.segments.next();
            if let Some(next) = self.current {
                self.t = next.t0;
            }
        }
    }

    fn collision(&self, seg: &MajorantSegment) -> Collision {
        Collision {
            t: self.t,
            sigma_maj: seg.majorant_at(self.t),
            sigma_control: seg.sigma_control,
        }
    }
}

/// Which transmittance estimator shadow rays use for media without a closed form.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TransmittanceEstimator {
    /// Closed form where the medium has one, else ratio tracking.
    #[default]
    Auto,
    /// Delta tracking: 1 if no real collision, else 0 (grey σt only; uses the max channel otherwise).
    Delta,
    /// Ratio tracking: product of null-collision probabilities.
    Ratio,
    /// Residual ratio tracking against the segments' control extinction.
    ResidualRatio,
}

/// Transmittance of one medium over `[0, t_max)` of `ray`.
pub fn medium_transmittance(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    estimator: TransmittanceEstimator,
    sampler: &mut Sampler,
) -> Rgb {
    match estimator {
        TransmittanceEstimator::Auto => match medium {
            Medium::Grid(g) if g.may_walk_exactly(ray, false) => {
                exact::grid_transmittance(g, ray, t_max, sampler)
            }
            _ => match medium.optical_depth(ray, 0.0, t_max) {
                Some(tau) => tau.exp_neg(),
                None => ratio_tracking(medium, ray, t_max, sampler),
            },
        },
        TransmittanceEstimator::Delta => delta_tracking_transmittance(medium, ray, t_max, sampler),
        TransmittanceEstimator::Ratio => ratio_tracking(medium, ray, t_max, sampler),
        TransmittanceEstimator::ResidualRatio => {
            residual_ratio_tracking(medium, ray, t_max, sampler)
        }
    }
}

/// Ratio tracking: T = Π (1 - σt(x_i)/σ̄(x_i)) over tentative collisions, per channel.
pub fn ratio_tracking(medium: &Medium, ray: &Ray, t_max: f32, sampler: &mut Sampler) -> Rgb {
    let tracker = Tracker::new(medium, ray, t_max);
    dispatch!(medium, m => ratio_track(m, tracker, ray, true, sampler))
}

/// The ratio-tracking loop over the collisions of `tracker`, for one concrete
/// medium, with or without Russian roulette.
fn ratio_track<M: TrackedMedium>(
    medium: &M,
    mut tracker: Tracker,
    ray: &Ray,
    with_roulette: bool,
    sampler: &mut Sampler,
) -> Rgb {
    let mut tr = Rgb::WHITE;
    let mut tally = Tally::default();
    while let Some(c) = tracker.next(sampler) {
        let sigma_t = medium.sigma_t(ray.at(c.t), ray.time);
        tally.add(sigma_t.max_channel(), c.sigma_maj);
        tr *= Rgb::WHITE - sigma_t / c.sigma_maj;
        if negligible(tr) || inert(tr, sigma_t) {
            return tr;
        }
        if with_roulette && !roulette(&mut tr, sampler) {
            return Rgb::BLACK;
        }
    }
    if tracker.capped() {
        return Rgb::BLACK;
    }
    tr
}

/// Delta tracking used as a transmittance estimator: 1 until a real collision, then 0.
///
/// Real collisions are decided on the max channel, so this is exact for grey media only.
pub fn delta_tracking_transmittance(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    sampler: &mut Sampler,
) -> Rgb {
    let tracker = Tracker::new(medium, ray, t_max);
    dispatch!(medium, m => delta_track(m, tracker, ray, sampler))
}

fn delta_track<M: TrackedMedium>(
    medium: &M,
    mut tracker: Tracker,
    ray: &Ray,
    sampler: &mut Sampler,
) -> Rgb {
    let mut tally = Tally::default();
    while let Some(c) = tracker.next(sampler) {
        let sigma_t = medium.sigma_t(ray.at(c.t), ray.time).max_channel();
        tally.add(sigma_t, c.sigma_maj);
        if sampler.next_1d() < sigma_t / c.sigma_maj {
            return Rgb::BLACK;
        }
    }
    if tracker.capped() {
        return Rgb::BLACK;
    }
    Rgb::WHITE
}

/// Residual ratio tracking (Novák et al. 2014): the control part σc in closed
/// form, the residual σt - σc by ratio tracking against σ̄ - σc.
pub fn residual_ratio_tracking(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    sampler: &mut Sampler,
) -> Rgb {
    let segments = medium.majorants(ray, t_max);
    dispatch!(medium, m => residual_ratio_track(m, segments, ray, sampler))
}

fn residual_ratio_track<M: TrackedMedium>(
    medium: &M,
    segments: MajorantIter,
    ray: &Ray,
    sampler: &mut Sampler,
) -> Rgb {
    let mut tr = Rgb::WHITE;
    let mut tally = Tally::default();
    let mut steps = 0u32;
    for seg in segments {
        if seg.decay != 0.0 || seg.t1.is_infinite() {
            // No control for varying majorants, and an unbounded segment (a global
            // medium) has nothing left to track once the control is taken out:
            // plain ratio tracking, which knows when to stop.
            tr *= ratio_track(medium, Tracker::single(seg), ray, true, sampler);
            if tr.is_black() {
                return tr;
            }
            continue;
        }
        let control = seg.sigma_control;
        let length = seg.t1 - seg.t0;
        tr *= control.depth_over(length).exp_neg();
        // Residual majorant: σ̄ - min channel of the control keeps every channel's residual ratio ≥ -1.
        let residual_maj = seg.sigma_maj - control.min_channel();
        if residual_maj <= 0.0 {
            continue;
        }
        let mut t = seg.t0;
        loop {
            t += -(1.0 - sampler.next_1d()).ln() / residual_maj;
            if t >= seg.t1 {
                break;
            }
            steps += 1;
            if steps > MAX_TENTATIVE_COLLISIONS {
                stats::count_capped_ray();
                return Rgb::BLACK;
            }
            let residual = medium.sigma_t(ray.at(t), ray.time) - control;
            tally.add(residual.max_channel(), residual_maj);
            tr *= Rgb::WHITE - residual / residual_maj;
            if negligible(tr) {
                return tr;
            }
            if !roulette(&mut tr, sampler) {
                return Rgb::BLACK;
            }
        }
    }
    tr
}

/// True when no channel of a tracking weight is a normal float any more.
///
/// Products of null-collision ratios on a long (or unbounded) segment decay
/// geometrically; near the bottom of the subnormal range `w · q` rounds back
/// to `w` and a loop waiting for an exact zero never ends. Stopping there
/// drops at most 1e-38 of the estimate.
fn negligible(w: Rgb) -> bool {
    w.map(f32::abs).max_channel() < f32::MIN_POSITIVE
}

/// True when the only channels of `w` still non-zero are those where σt is zero.
///
/// Every medium's extinction is a density times a fixed RGB vector (a
/// homogeneous σt, a grid's density × scale, a fog's σ0 × e^(-h/H)), so a
/// channel with σt = 0 at a point where another channel is positive has
/// σt = 0 everywhere in that medium: its remaining collisions are all null
/// and leave those channels unchanged. Stopping then is exact, and it ends
/// tracking along unbounded segments, where it would otherwise never end.
fn inert(w: Rgb, sigma_t: Rgb) -> bool {
    sigma_t.max_channel() > 0.0 && (0..3).all(|c| w[c] == 0.0 || sigma_t[c] == 0.0)
}

/// The outcome of free-flight sampling along a ray segment.
#[derive(Clone, Copy, Debug)]
pub enum FreeFlight {
    /// A real scattering event in medium `medium` at parameter `t`.
    Scatter {
        /// Ray parameter.
        t: f32,
        /// Index of the medium that scattered.
        medium: usize,
        /// Its properties there.
        properties: MediumProperties,
    },
    /// The ray reached `t_max` without scattering.
    Passed,
    /// The path's weight dropped to zero (absorbed).
    Absorbed,
}

/// Most media a single ray can overlap at once.
pub const MAX_OVERLAPPING_MEDIA: usize = 8;

/// Samples the next real scattering event along `ray` in `[0, t_max)` through all `media`.
///
/// Decomposition tracking: each medium runs its own tentative-collision
/// process; the earliest collision is classified with that medium's own
/// coefficients. Spectral tracking (Kutz et al. 2017) picks scatter or null
/// with probabilities proportional to the throughput-weighted coefficients, so
/// chromatic extinction stays unbiased. Emission σa·Le/σ̄ is added to
/// `radiance` (times the throughput) at every tentative collision.
pub fn sample_free_flight(
    media: &[Medium],
    ray: &Ray,
    t_max: f32,
    throughput: &mut Rgb,
    radiance: &mut Rgb,
    sampler: &mut Sampler,
) -> FreeFlight {
    if let [medium] = media {
        // One medium (the common case): no earliest-collision search, no tracker array.
        match medium {
            Medium::Grid(g) if g.may_walk_exactly(ray, true) => {
                return exact::grid_free_flight(g, ray, t_max, throughput, radiance, sampler);
            }
            Medium::Homogeneous(h) => {
                return homogeneous_free_flight(h, ray, t_max, throughput, radiance, sampler);
            }
            _ => {}
        }
        let tracker = Tracker::new(medium, ray, t_max);
        return dispatch!(medium, m => {
            free_flight_one(m, tracker, ray, t_max, throughput, radiance, sampler)
        });
    }
    free_flight_overlapping(media, ray, t_max, throughput, radiance, sampler)
}

/// Decomposition tracking through several media: the earliest of their
/// tentative collisions is classified with its own medium's coefficients.
fn free_flight_overlapping(
    media: &[Medium],
    ray: &Ray,
    t_max: f32,
    throughput: &mut Rgb,
    radiance: &mut Rgb,
    sampler: &mut Sampler,
) -> FreeFlight {
    let mut trackers: [Option<(usize, Tracker, Collision)>; MAX_OVERLAPPING_MEDIA] =
        [const { None }; MAX_OVERLAPPING_MEDIA];
    let mut count = 0;
    for (index, medium) in media.iter().enumerate() {
        let mut tracker = Tracker::new(medium, ray, t_max);
        if let Some(c) = tracker.next(sampler) {
            if count < MAX_OVERLAPPING_MEDIA {
                trackers[count] = Some((index, tracker, c));
                count += 1;
            }
        }
    }
    let mut tally = Tally::default();
    loop {
        let mut best: Option<usize> = None;
        let mut best_t = t_max;
        for (slot, entry) in trackers[..count].iter().enumerate() {
            if let Some((_, _, c)) = entry {
                if c.t < best_t {
                    best_t = c.t;
                    best = Some(slot);
                }
            }
        }
        let Some(slot) = best else {
            return FreeFlight::Passed;
        };
        let (medium_index, tracker, collision) = trackers[slot].as_mut().expect("chosen slot");
        let props = media[*medium_index].properties(ray.at(collision.t), ray.time);
        match collide(&props, collision, throughput, radiance, sampler, &mut tally) {
            Step::Scatter => {
                return FreeFlight::Scatter {
                    t: collision.t,
                    medium: *medium_index,
                    properties: props,
                }
            }
            Step::Absorbed => return FreeFlight::Absorbed,
            Step::Inert => trackers[slot] = None,
            Step::Null => match tracker.next(sampler) {
                Some(c) => *collision = c,
                None if tracker.capped() => {
                    *throughput = Rgb::BLACK;
                    return FreeFlight::Absorbed;
                }
                None => trackers[slot] = None,
            },
        }
    }
}

/// Free-flight sampling through one homogeneous medium: the
/// tentative-collision process of its one majorant segment (σ̄ = max σt,
/// over the region's interval) without a tracker, the same random numbers
/// and arithmetic as [`Tracker::next`] and [`free_flight_one`] take.
///
/// With grey extinction every collision inside the region is real
/// (σ̄ − σt = 0), so a flight costs one exponential step; a chromatic one
/// has null collisions in its lesser channels, classified by spectral
/// tracking as in the general loop, and a collision that rounding puts just
/// outside the region is null and the flight goes on.
fn homogeneous_free_flight(
    medium: &HomogeneousMedium,
    ray: &Ray,
    t_max: f32,
    throughput: &mut Rgb,
    radiance: &mut Rgb,
    sampler: &mut Sampler,
) -> FreeFlight {
    let Some(seg) = medium.majorant(ray, t_max) else {
        return FreeFlight::Passed;
    };
    let mut tally = Tally::default();
    let mut t = seg.t0;
    // Every tentative collision lies inside the region: its coefficients are the medium's own.
    let props = MediumProperties {
        sigma_a: medium.sigma_a,
        sigma_s: medium.sigma_s,
        emission: medium.emission,
        phase: medium.phase,
    };
    for _ in 0..MAX_TENTATIVE_COLLISIONS {
        let tau = -(1.0 - sampler.next_1d()).ln();
        let (sigma, length) = (seg.sigma_maj, seg.t1 - t);
        let dt = tau / sigma;
        if !(sigma > 0.0 && length > 0.0 && dt < length) {
            return FreeFlight::Passed;
        }
        t = advance(t, t + dt).min(seg.t1);
        if t >= t_max {
            return FreeFlight::Passed;
        }
        let collision = Collision {
            t,
            sigma_maj: sigma,
            sigma_control: seg.sigma_control,
        };
        match collide(
            &props, &collision, throughput, radiance, sampler, &mut tally,
        ) {
            Step::Scatter => {
                return FreeFlight::Scatter {
                    t,
                    medium: 0,
                    properties: props,
                }
            }
            Step::Absorbed => return FreeFlight::Absorbed,
            Step::Inert => return FreeFlight::Passed,
            Step::Null => {}
        }
    }
    stats::count_capped_ray();
    *throughput = Rgb::BLACK;
    FreeFlight::Absorbed
}

/// Free-flight sampling through a single medium.
fn free_flight_one<M: TrackedMedium>(
    medium: &M,
    mut tracker: Tracker,
    ray: &Ray,
    t_max: f32,
    throughput: &mut Rgb,
    radiance: &mut Rgb,
    sampler: &mut Sampler,
) -> FreeFlight {
    let mut tally = Tally::default();
    while let Some(collision) = tracker.next(sampler) {
        // As the multi-medium search: a collision clamped onto t_max is not inside.
        if collision.t >= t_max {
            break;
        }
        let props = medium.properties(ray.at(collision.t), ray.time);
        match collide(
            &props, &collision, throughput, radiance, sampler, &mut tally,
        ) {
            Step::Scatter => {
                return FreeFlight::Scatter {
                    t: collision.t,
                    medium: 0,
                    properties: props,
                }
            }
            Step::Absorbed => return FreeFlight::Absorbed,
            Step::Inert => break,
            Step::Null => {}
        }
    }
    if tracker.capped() {
        *throughput = Rgb::BLACK;
        return FreeFlight::Absorbed;
    }
    FreeFlight::Passed
}

/// What one tentative collision of a free flight turned out to be.
enum Step {
    Scatter,
    Absorbed,
    /// Null, and the medium can no longer change the throughput (see `inert`).
    Inert,
    Null,
}

/// Classifies a tentative collision by spectral tracking, updating the throughput and adding emission.
#[inline]
fn collide(
    props: &MediumProperties,
    collision: &Collision,
    throughput: &mut Rgb,
    radiance: &mut Rgb,
    sampler: &mut Sampler,
    tally: &mut Tally,
) -> Step {
    let inv_maj = 1.0 / collision.sigma_maj;
    if !props.emission.is_black() {
        *radiance += *throughput * props.sigma_a * props.emission * inv_maj;
    }
    let sigma_t = props.sigma_a + props.sigma_s;
    tally.add(sigma_t.max_channel(), collision.sigma_maj);
    let w_scatter = *throughput * props.sigma_s * inv_maj;
    let w_null = *throughput * (Rgb::splat(collision.sigma_maj) - sigma_t) * inv_maj;
    let p_scatter_raw = w_scatter.map(f32::abs).average();
    let p_null_raw = w_null.map(f32::abs).average();
    let total = p_scatter_raw + p_null_raw;
    if total < f32::MIN_POSITIVE || !total.is_finite() {
        *throughput = Rgb::BLACK;
        return Step::Absorbed;
    }
    let p_scatter = p_scatter_raw / total;
    if sampler.next_1d() < p_scatter {
        *throughput = w_scatter / p_scatter;
        return Step::Scatter;
    }
    *throughput = w_null / (1.0 - p_scatter);
    if inert(*throughput, sigma_t) {
        Step::Inert
    } else {
        Step::Null
    }
}

/// Ratio tracking against the medium's own majorant multiplied by `scale` ≥ 1.
///
/// A looser majorant leaves the estimator unbiased but raises its variance:
/// for a homogeneous medium over a distance d the second moment is
/// exp(-(2σt - σt²/σ̄) d). The renderer never inflates its majorants; this
/// exists so that tests can check that relation for σ̄ = 1×, 2×, 10× σt.
pub fn ratio_tracking_scaled_majorant(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    scale: f32,
    sampler: &mut Sampler,
) -> Rgb {
    scaled_majorant_tracking(medium, ray, t_max, scale, false, sampler)
}

/// [`ratio_tracking_scaled_majorant`] with the Russian roulette the renderer plays.
pub fn ratio_tracking_scaled_majorant_roulette(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    scale: f32,
    sampler: &mut Sampler,
) -> Rgb {
    scaled_majorant_tracking(medium, ray, t_max, scale, true, sampler)
}

fn scaled_majorant_tracking(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    scale: f32,
    with_roulette: bool,
    sampler: &mut Sampler,
) -> Rgb {
    let mut tr = Rgb::WHITE;
    for seg in medium.majorants(ray, t_max) {
        let inflated = MajorantSegment {
            sigma_maj: seg.sigma_maj * scale.max(1.0),
            ..seg
        };
        tr *= dispatch!(medium, m => {
            ratio_track(m, Tracker::single(inflated), ray, with_roulette, sampler)
        });
    }
    tr
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Affine3A, Bounds3, Quat, Vec3};
    use crate::medium::{PhaseFunction, Region};

    /// The ray from (−1, 0, 0) along +x, which crosses [`unit_box`] over one unit.
    fn across_unit_box() -> Ray {
        Ray::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::X)
    }

    /// A free flight along `ray` through `media` ends the path: absorbed, throughput 0.
    fn assert_flight_ends_the_path(media: &[Medium], ray: &Ray, sampler: &mut Sampler) {
        let (mut throughput, mut radiance) = (Rgb::WHITE, Rgb::BLACK);
        let out = sample_free_flight(
            media,
            ray,
            f32::INFINITY,
            &mut throughput,
            &mut radiance,
            sampler,
        );
        assert!(
            matches!(out, FreeFlight::Absorbed) && throughput == Rgb::BLACK,
            "{} media: {out:?}, throughput {throughput:?}",
            media.len()
        );
    }

    /// A non-emissive homogeneous medium in the box [−½, ½]³.
    fn unit_box(sigma_a: Rgb, sigma_s: Rgb) -> Medium {
        Medium::Homogeneous(HomogeneousMedium {
            sigma_a,
            sigma_s,
            emission: Rgb::BLACK,
            phase: PhaseFunction::Isotropic,
            region: Region::Box {
                world_to_local: Affine3A::IDENTITY,
                local: Bounds3::new(Vec3::splat(-0.5), Vec3::splat(0.5)),
            },
        })
    }

    /// A ray that would take more than [`MAX_TENTATIVE_COLLISIONS`] null
    /// collisions (σ̄ = 10⁶ σt over one unit: about 10⁶) stops at the cap:
    /// ratio tracking returns 0, not the product so far, and the ray is
    /// counted; a ray under the cap is not.
    #[test]
    fn a_ray_past_the_collision_cap_is_ended_and_counted() {
        let medium = unit_box(Rgb::splat(0.5), Rgb::splat(0.5));
        let ray = across_unit_box();
        let mut sampler = crate::sampling::Sampler::from_seed(4);
        take_thread_stats();
        let capped =
            ratio_tracking_scaled_majorant(&medium, &ray, f32::INFINITY, 1e6, &mut sampler);
        let stats = take_thread_stats();
        assert_eq!(stats.collisions, MAX_TENTATIVE_COLLISIONS as u64);
        assert_eq!(stats.capped_rays, 1);
        assert_eq!(
            capped,
            Rgb::BLACK,
            "the product of 65536 ratios is about 0.94, not 0"
        );
        let under = ratio_tracking_scaled_majorant(&medium, &ray, f32::INFINITY, 1e3, &mut sampler);
        assert!(under.max_channel() > 0.0);
        assert_eq!(take_thread_stats().capped_rays, 0);
    }

    /// The counts a render reports: against a majorant 4× the grey σt every
    /// tentative collision is null with probability 1 − σt/σ̄ = ¾, so the
    /// null fraction is ¾ exactly, whatever the number of collisions.
    #[test]
    fn the_null_fraction_is_the_mean_of_one_minus_sigma_t_over_the_majorant() {
        let medium = unit_box(Rgb::splat(0.5), Rgb::splat(0.5));
        let ray = across_unit_box();
        let mut sampler = crate::sampling::Sampler::from_seed(5);
        take_thread_stats();
        for _ in 0..100 {
            ratio_tracking_scaled_majorant(&medium, &ray, f32::INFINITY, 4.0, &mut sampler);
        }
        let stats = take_thread_stats();
        assert!(stats.collisions > 100, "{stats:?}");
        assert!((stats.null_fraction() - 0.75).abs() < 1e-6, "{stats:?}");
    }

    /// Residual ratio tracking takes the control part in closed form and
    /// collides only against the residual majorant σ̄ − min(σc): none at all
    /// through a grey homogeneous medium (σc = σt = σ̄), and a Poisson number
    /// of mean (σ̄ − min σc)·L through a chromatic one. Either way every
    /// estimate is exact, since the residual σt − σc is zero.
    #[test]
    fn residual_ratio_tracking_collides_against_the_residual_majorant_only() {
        let ray = across_unit_box();
        let rays = 4000;
        let mut sampler = crate::sampling::Sampler::from_seed(6);
        for (sigma_a, residual_majorant) in
            [(Rgb::splat(0.5), 0.0), (Rgb::new(0.25, 0.75, 1.25), 1.0)]
        {
            let medium = unit_box(sigma_a, Rgb::splat(0.25));
            let expected = (sigma_a + Rgb::splat(0.25)).map(|s| (-s).exp());
            take_thread_stats();
            for _ in 0..rays {
                let tr = residual_ratio_tracking(&medium, &ray, f32::INFINITY, &mut sampler);
                for c in 0..3 {
                    assert!((tr[c] - expected[c]).abs() < 1e-5, "{tr:?} vs {expected:?}");
                }
            }
            let collisions = take_thread_stats().collisions as f64;
            // Poisson count of mean λ = rays·σ̄r·L; one check at the suite's k.
            let mean = rays as f64 * residual_majorant;
            assert!(
                (collisions - mean).abs() <= crate::suite_k::k_sigma(1) * mean.sqrt(),
                "σa {sigma_a:?}: {collisions} collisions, expected {mean}"
            );
        }
    }

    /// Residual ratio tracking has its own collision count: a segment whose
    /// residual majorant would take about 2·10⁵ collisions (σt = (0, 0, 2·10⁵)
    /// over one unit, so σ̄ − min σc = 2·10⁵) is ended at the cap, returns 0
    /// and is counted, instead of the exact (1, 1, 0) it would reach, after
    /// exactly as many collisions as the tracker allows.
    #[test]
    fn a_residual_ratio_ray_past_the_collision_cap_is_ended_and_counted() {
        let medium = unit_box(Rgb::new(0.0, 0.0, 2e5), Rgb::BLACK);
        let ray = across_unit_box();
        let mut sampler = crate::sampling::Sampler::from_seed(2);
        take_thread_stats();
        let tr = residual_ratio_tracking(&medium, &ray, f32::INFINITY, &mut sampler);
        assert_eq!(tr, Rgb::BLACK);
        let stats = take_thread_stats();
        assert_eq!(stats.capped_rays, 1);
        // The same cap as the tracker's: that many collisions, not one fewer.
        assert_eq!(stats.collisions, MAX_TENTATIVE_COLLISIONS as u64);
    }

    /// Without roulette, the product of null-collision ratios through an
    /// unbounded medium decays geometrically; with ratios above ½ it would
    /// stick at the smallest subnormal instead of reaching 0. Tracking stops
    /// once no channel is a normal float (about 300 collisions for ratios of
    /// ¾), long before the collision cap.
    #[test]
    fn ratio_tracking_stops_once_the_weight_leaves_the_normal_range() {
        let medium = Medium::Homogeneous(HomogeneousMedium {
            sigma_a: Rgb::splat(0.5),
            sigma_s: Rgb::splat(0.5),
            emission: Rgb::BLACK,
            phase: PhaseFunction::Isotropic,
            region: Region::Everywhere,
        });
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let mut sampler = crate::sampling::Sampler::from_seed(8);
        take_thread_stats();
        let tr = ratio_tracking_scaled_majorant(&medium, &ray, f32::INFINITY, 4.0, &mut sampler);
        assert!(tr.max_channel() < f32::MIN_POSITIVE, "{tr:?}");
        let collisions = take_thread_stats().collisions;
        assert!(collisions < 1000, "{collisions} collisions");
    }

    /// Where several media overlap, a tracker stopped by the collision cap
    /// ends the path (throughput 0), as it does through one medium; it is
    /// not dropped as if its medium had been crossed. The capped medium has
    /// σt = (1, 1, 2·10⁵) over one unit: 2·10⁵ collisions, all null in the
    /// first two channels; the other is too thin to collide.
    #[test]
    fn a_capped_tracker_among_overlapping_media_ends_the_path() {
        let ray = across_unit_box();
        let capped = unit_box(Rgb::new(1.0, 1.0, 2e5), Rgb::BLACK);
        let thin = unit_box(Rgb::splat(1e-9), Rgb::BLACK);
        for media in [vec![capped.clone()], vec![capped, thin]] {
            let mut sampler = crate::sampling::Sampler::from_seed(12);
            assert_flight_ends_the_path(&media, &ray, &mut sampler);
        }
    }

    /// Roulette on a tracking weight below the threshold keeps it with
    /// probability max|w| / threshold and divides the survivor by that.
    #[test]
    fn tracking_roulette_survives_in_proportion_to_the_weight() {
        let n = 20_000;
        let mut survived = 0;
        for i in 0..n {
            let mut sampler = crate::sampling::Sampler::new(8, 0, 0, i);
            let mut w = Rgb::new(0.02, -0.05, 0.01);
            if roulette(&mut w, &mut sampler) {
                survived += 1;
                assert_eq!(w, Rgb::new(0.04, -0.1, 0.02));
            } else {
                assert_eq!(w, Rgb::BLACK);
            }
        }
        let mut big = Rgb::splat(0.2);
        assert!(roulette(
            &mut big,
            &mut crate::sampling::Sampler::from_seed(1)
        ));
        assert_eq!(big, Rgb::splat(0.2));
        // One check at the suite's k (tests/common/k_sigma.rs).
        let p = survived as f64 / n as f64;
        assert!(
            (p - 0.5).abs() < crate::suite_k::k_sigma(1) * (0.25 / n as f64).sqrt(),
            "survival {p}"
        );
    }

    /// The homogeneous fast path takes the same random numbers and gives the
    /// same outcome, to the bit, as the general tracker loop, for rays that
    /// start outside, inside and beyond the medium, with absorption, emission
    /// and a surface cutting the flight short, for grey and chromatic
    /// extinction (so every homogeneous medium may take it).
    #[test]
    fn homogeneous_fast_path_matches_the_tracker_loop() {
        for (sigma_a, sigma_s) in [
            (Rgb::splat(0.3), Rgb::splat(0.9)),
            (Rgb::new(0.3, 0.1, 0.6), Rgb::new(0.9, 0.4, 0.2)),
        ] {
            fast_path_matches_the_tracker_loop(sigma_a, sigma_s);
        }
    }

    fn fast_path_matches_the_tracker_loop(sigma_a: Rgb, sigma_s: Rgb) {
        let medium = HomogeneousMedium {
            sigma_a,
            sigma_s,
            emission: Rgb::new(0.2, 0.5, 0.1),
            phase: PhaseFunction::Isotropic,
            region: Region::Box {
                world_to_local: Affine3A::from_rotation_translation(
                    Quat::from_rotation_y(0.4),
                    Vec3::new(0.3, -0.2, 0.1),
                ),
                local: Bounds3::new(Vec3::splat(-1.0), Vec3::new(1.0, 2.0, 1.5)),
            },
        };
        let wrapped = Medium::Homogeneous(medium.clone());
        let mut rng = crate::sampling::Sampler::from_seed(3);
        let mut scatters = 0;
        for i in 0..20_000u64 {
            let o = Vec3::new(rng.next_1d(), rng.next_1d(), rng.next_1d()) * 6.0 - 3.0;
            let d = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
            let ray = Ray::new(o, d);
            let t_max = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let run = |fast: bool| {
                let mut sampler = crate::sampling::Sampler::from_seed(100 + i);
                let (mut tp, mut l) = (Rgb::splat(0.7), Rgb::BLACK);
                let out = if fast {
                    homogeneous_free_flight(&medium, &ray, t_max, &mut tp, &mut l, &mut sampler)
                } else {
                    let tracker = Tracker::new(&wrapped, &ray, t_max);
                    free_flight_one(&medium, tracker, &ray, t_max, &mut tp, &mut l, &mut sampler)
                };
                let key = match out {
                    FreeFlight::Scatter { t, .. } => (0, t.to_bits()),
                    FreeFlight::Passed => (1, 0),
                    FreeFlight::Absorbed => (2, 0),
                };
                (
                    key,
                    tp.to_array().map(f32::to_bits),
                    l.to_array().map(f32::to_bits),
                    sampler.next_1d().to_bits(),
                )
            };
            let fast = run(true);
            assert_eq!(fast, run(false), "σa {sigma_a:?}, σs {sigma_s:?}, ray {i}");
            scatters += (fast.0 .0 == 0) as u32;
        }
        assert!(scatters > 1_000, "{scatters} scatterings");
    }
}
