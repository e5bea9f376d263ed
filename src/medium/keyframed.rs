//! Media moved by keyframed transforms (a box, a sphere or a VDB medium).
//!
//! ```toml
//! [[medium]]
//! type = "homogeneous"
//! sigma_t = 2.0
//! bounds = { type = "box", min = [-0.5, -0.5, -0.5], max = [0.5, 0.5, 0.5] }
//! transform = { keyframes = [
//!     { time = -0.5, translate = [-1.0, 0.0, 0.0] },
//!     { time = 0.5, translate = [1.0, 0.0, 0.0] },
//! ] }
//! ```
//!
//! # Model
//!
//! The inner medium is built in its own (local) frame, as if it had no
//! transform; at time t it is placed by the keyframed map K(t)
//! (`math::keyframes`), so
//!
//! ```text
//! σ(x, t) = σ_local(K(t)⁻¹ x)       (and likewise σa, σs, Le, phase)
//! ```
//!
//! Coefficients stay per unit of world length (a scaled medium grows; its
//! density does not change), as for a still `transform`. A velocity grid,
//! if any, advects the medium in the local frame before K(t) places it.
//!
//! # The majorant: the ray is transformed per time, nothing is swept
//!
//! Every ray of a path carries the camera sample's time t
//! ([`crate::math::Ray::time`]); conditioned on t the medium is a still
//! medium placed by the affine map K(t). [`MovingMedium::majorants`] maps the
//! world ray r(s) = o + s·d to the local ray r'(s) = K(t)⁻¹o + s·L⁻¹d (L the
//! linear part of K(t); the direction is not renormalized), so r'(s) =
//! K(t)⁻¹ r(s) for every parameter s, and hands back the inner medium's
//! majorant segments of r' unchanged.
//!
//! Claim: each segment [s0, s1) with majorant σ̄ satisfies σ(r(s), t) ≤ σ̄
//! for s in it (and the control σc ≤ σ(r(s), t)).
//! Proof. σ(r(s), t) = σ_local(K(t)⁻¹ r(s)) = σ_local(r'(s)). The inner
//! medium's segments bound σ_local along any ray, whatever the length of its
//! direction: a grid's DDA cells and a region's interval are found in the
//! ray's own parameter (the same argument by which a still `transform` with
//! a scale keeps world parameters, `medium::grid`), and the bounds are
//! pointwise bounds of σ_local in the cell. Hence σ_local(r'(s)) ≤ σ̄. ∎
//!
//! Because the ray and every lookup of the path use the same t, and the
//! tracking estimators are unbiased for any still medium under a valid
//! majorant, each path is an unbiased estimate at time t, and the mean over
//! t ~ U(shutter) the shutter average. No bound swept over the shutter is
//! needed (a swept box would only be a looser majorant support); the cost is
//! one keyframe evaluation per ray and one per lookup.

use super::{MajorantIter, Medium, MediumProperties};
use crate::math::color::Rgb;
use crate::math::keyframes::Keyframes;
use crate::math::{Ray, Vec3};

/// An inner medium (in its local frame) placed by keyframes at each time.
#[derive(Clone, Debug)]
pub struct MovingMedium {
    inner: Medium,
    keys: Keyframes,
}

impl MovingMedium {
    /// `inner`, built without a transform, moved by `keys`.
    pub fn new(inner: Medium, keys: Keyframes) -> MovingMedium {
        MovingMedium { inner, keys }
    }

    /// The medium in its local frame.
    pub fn inner(&self) -> &Medium {
        &self.inner
    }

    /// The keyframes that place it.
    pub fn keyframes(&self) -> &Keyframes {
        &self.keys
    }

    /// Coefficients at world point `p` at `time`.
    #[inline]
    pub fn properties(&self, p: Vec3, time: f32) -> MediumProperties {
        let q = self.keys.at(time).point_to_local(p);
        self.inner.properties(q, time)
    }

    /// Extinction at world point `p` at `time`.
    #[inline]
    pub fn sigma_t_at(&self, p: Vec3, time: f32) -> Rgb {
        let q = self.keys.at(time).point_to_local(p);
        self.inner.sigma_t_at(q, time)
    }

    /// Majorant segments of `ray` at its time: the inner medium's along the local ray (module doc).
    #[inline]
    pub fn majorants(&self, ray: &Ray, t_max: f32) -> MajorantIter<'_> {
        let local = self.keys.at(ray.time).ray_to_local(ray);
        self.inner.majorants(&local, t_max)
    }

    /// Optical depth over `[t0, t1]` of `ray` at its time, when the inner medium has a closed form.
    #[inline]
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> Option<Rgb> {
        let local = self.keys.at(ray.time).ray_to_local(ray);
        self.inner.optical_depth(&local, t0, t1)
    }
}
