//! The free-flight factors of bidirectional MIS densities in media.
//!
//! Subpaths take their free flights with the path tracer's own tracking
//! (spectral and decomposition tracking over majorants, exact voxel walks),
//! whose density of reaching a point has no closed form in a heterogeneous
//! medium; connections estimate transmittance with any unbiased estimator.
//! MIS weights need not be those densities: any weights that are functions
//! of the path alone and sum to one over the strategies that can sample it
//! keep every estimator unbiased (Veach 1997, §9.2; the same freedom Miller,
//! Georgiev and Jarosz 2019 use when they weigh null-scattering paths).
//! So the weights see a deterministic surrogate of each free flight: the
//! density exp(−τ̃) of passing a segment and σ̃t·exp(−τ̃) of stopping at a
//! medium point, with τ̃ the optical depth of the segment — closed form
//! where the medium has one, else the extinction at the midpoint of each
//! majorant cell the segment crosses times its length — taken in the
//! channel where it is smallest, and σ̃t the extinction's channel mean.
//!
//! A surrogate built from the true optical depth is the density a grey
//! medium's delta tracking has, so the weights are the classical ones
//! (Veach 1997 ch. 10 with media, Pauly et al. 2000) wherever the medium is
//! homogeneous and grey, and close to them elsewhere. Taking the smallest
//! channel keeps a surrogate positive wherever some channel's light gets
//! through: a strategy that can sample a path is never weighed as if it
//! could not. Because estimates of the true densities would make the
//! weights random, their sum would be one only on average, which biases.
//!
//! A segment's τ̃ is computed from its lexicographically smaller end, so
//! both directions give the same number and the weights sum to one exactly.

use super::positive;
use crate::integrator::Scene;
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};
use crate::medium::Medium;

/// `exp(−τ̃)`, the surrogate density of crossing a segment of surrogate depth `tau`.
#[inline]
pub(super) fn transmittance(tau: f32) -> f32 {
    (-tau).exp()
}

/// The surrogate free-flight quantities of one scene at one time.
#[derive(Clone, Copy)]
pub(super) struct Surrogate<'a> {
    scene: &'a Scene,
    time: f32,
}

impl<'a> Surrogate<'a> {
    /// The surrogate of `scene` for paths at `time`.
    pub(super) fn new(scene: &'a Scene, time: f32) -> Surrogate<'a> {
        Surrogate { scene, time }
    }

    /// True when the scene has no media (every surrogate is 1).
    #[inline]
    pub(super) fn vacuum(&self) -> bool {
        self.scene.media.is_empty()
    }

    /// Surrogate optical depth of the segment between `a` and `b`.
    pub(super) fn depth(&self, a: Vec3, b: Vec3) -> f32 {
        if self.vacuum() {
            return 0.0;
        }
        let (from, to) = if a.to_array() <= b.to_array() {
            (a, b)
        } else {
            (b, a)
        };
        let d = to - from;
        let length = d.length();
        if length == 0.0 {
            return 0.0;
        }
        self.depth_along(&self.ray(from, d / length), length)
    }

    /// Surrogate optical depth from `p` to infinity along `dir`.
    pub(super) fn depth_to_infinity(&self, p: Vec3, dir: Vec3) -> f32 {
        if self.vacuum() {
            return 0.0;
        }
        self.depth_along(&self.ray(p, dir), f32::INFINITY)
    }

    /// Surrogate extinction at medium point `p`: the channel mean of σt summed over the media.
    pub(super) fn sigma_t(&self, p: Vec3) -> f32 {
        self.scene
            .media
            .iter()
            .map(|m| m.sigma_t_at(p, self.time).average())
            .sum()
    }

    fn ray(&self, origin: Vec3, direction: Vec3) -> Ray {
        let mut ray = Ray::new(origin, direction);
        ray.time = self.time;
        ray
    }

    /// Surrogate depth over `[0, t_max)` of `ray` through every medium, in the smallest channel.
    fn depth_along(&self, ray: &Ray, t_max: f32) -> f32 {
        let mut tau = Rgb::BLACK;
        for medium in &self.scene.media {
            tau += match medium.optical_depth(ray, 0.0, t_max) {
                Some(closed) => closed,
                None => midpoint_depth(medium, ray, t_max, self.time),
            };
        }
        let min = tau.min_channel();
        if min.is_nan() {
            f32::INFINITY
        } else {
            min
        }
    }
}

/// Optical depth by the midpoint rule over the majorant cells of `medium`
/// along `ray` (each cell's σt at its middle times its length, per channel);
/// an unbounded cell is infinitely deep in the channels where σt is not zero
/// (a medium's σt is a density times one colour, so those are zero throughout).
fn midpoint_depth(medium: &Medium, ray: &Ray, t_max: f32, time: f32) -> Rgb {
    let mut tau = Rgb::BLACK;
    for seg in medium.majorants(ray, t_max) {
        let t1 = seg.t1.min(t_max);
        let length = t1 - seg.t0;
        if !positive(length) || seg.sigma_maj <= 0.0 {
            continue;
        }
        if !length.is_finite() {
            let sigma = medium.sigma_t_at(ray.at(seg.t0), time);
            return tau + sigma.map(|s| if s > 0.0 { f32::INFINITY } else { 0.0 });
        }
        let sigma = medium.sigma_t_at(ray.at(0.5 * (seg.t0 + t1)), time);
        tau += sigma * length;
    }
    tau
}
