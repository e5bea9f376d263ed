//! Participating media: what a medium is at a point, and its majorants along a ray.
//!
//! A medium answers two questions only (DESIGN.md): its coefficients at a
//! point (`properties`) and majorant segments along a ray (`majorants`),
//! plus, where one exists, its optical depth in closed form. Transmittance
//! and free-flight estimators live in `integrator`, written once over
//! majorant segments.

pub mod blackbody;
pub mod channels;
pub mod grid;
pub mod height_fog;
pub mod homogeneous;
pub mod interior;
pub mod keyframed;
pub mod majorant_grid;
pub mod motion;
pub mod phase;
pub mod region;
pub mod voxel;

pub use channels::{AlbedoGrid, ChannelGrids, RgbGrids};
pub use grid::{
    ExactVoxels, GridEmission, GridMedium, GridMediumParams, MajorantMode, MajorantTooLarge,
};
pub use height_fog::HeightFog;
pub use homogeneous::HomogeneousMedium;
pub use interior::{InteriorContent, InteriorMedium, ShapeMask};
pub use keyframed::MovingMedium;
pub use motion::GridMotion;
pub use phase::{PhaseFunction, PhaseSample};
pub use region::Region;

use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};

/// Coefficients of a medium at one point.
#[derive(Clone, Copy, Debug)]
pub struct MediumProperties {
    /// Absorption coefficient σa (1/m).
    pub sigma_a: Rgb,
    /// Scattering coefficient σs (1/m).
    pub sigma_s: Rgb,
    /// Emitted radiance Le; the source term is σa·Le.
    pub emission: Rgb,
    /// Phase function.
    pub phase: PhaseFunction,
}

/// A stretch `[t0, t1)` of a ray with a scalar majorant σ̄(t) = `sigma_maj`·exp(-`decay`·(t - t0)) ≥ max channel of σt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MajorantSegment {
    /// Start of the segment (ray parameter).
    pub t0: f32,
    /// End of the segment.
    pub t1: f32,
    /// Majorant at `t0`.
    pub sigma_maj: f32,
    /// Exponential decay rate of the majorant along the ray (0 for constant).
    pub decay: f32,
    /// A lower bound of σt over the segment (the control extinction of residual ratio tracking; valid when `decay` is 0).
    pub sigma_control: Rgb,
}

impl MajorantSegment {
    /// The majorant at ray parameter `t` inside the segment.
    #[inline]
    pub fn majorant_at(&self, t: f32) -> f32 {
        if self.decay == 0.0 {
            self.sigma_maj
        } else {
            self.sigma_maj * (-self.decay * (t - self.t0)).exp()
        }
    }
}

/// The majorant segments of one medium along one ray, in increasing t.
#[derive(Clone, Debug)]
pub enum MajorantIter<'a> {
    /// At most one segment.
    Single(Option<MajorantSegment>),
    /// The pieces of a height fog.
    Fog(height_fog::FogSegments),
    /// A DDA over the majorant cells of a grid medium.
    Grid(grid::GridMajorants<'a>),
    /// A medium's segments clipped to the inside of its shape.
    Masked(interior::MaskedMajorants<'a>),
}

impl Iterator for MajorantIter<'_> {
    type Item = MajorantSegment;
    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            MajorantIter::Single(s) => s.take(),
            MajorantIter::Fog(f) => f.next(),
            MajorantIter::Grid(g) => g.next(),
            MajorantIter::Masked(m) => m.next(),
        }
    }
}

/// A participating medium (closed set; large payloads go behind `Arc`).
#[derive(Clone, Debug)]
pub enum Medium {
    /// Constant coefficients inside a region.
    Homogeneous(HomogeneousMedium),
    /// Exponential height fog filling all space.
    HeightFog(HeightFog),
    /// Density from a sparse grid (OpenVDB), tracked over a majorant grid.
    Grid(std::sync::Arc<GridMedium>),
    /// A homogeneous or grid medium inside a closed shape (see [`interior`]).
    Interior(std::sync::Arc<InteriorMedium>),
    /// A medium moved by keyframes (module `keyframed`).
    Moving(std::sync::Arc<MovingMedium>),
}

/// σs/σt per channel; 1 where a channel has no extinction (it absorbs nothing).
fn albedo_of(sigma_a: Rgb, sigma_s: Rgb) -> Rgb {
    let share = |a: f32, s: f32| if a + s > 0.0 { s / (a + s) } else { 1.0 };
    Rgb::new(
        share(sigma_a.r, sigma_s.r),
        share(sigma_a.g, sigma_s.g),
        share(sigma_a.b, sigma_s.b),
    )
}

impl Medium {
    /// The single-scattering albedo σs/σt where it is the same at every point
    /// (`None` for an albedo grid).
    pub fn constant_albedo(&self) -> Option<Rgb> {
        match self {
            Medium::Homogeneous(m) => Some(albedo_of(m.sigma_a, m.sigma_s)),
            Medium::HeightFog(m) => Some(albedo_of(m.sigma_a, m.sigma_s)),
            Medium::Grid(m) => m.constant_albedo(),
            Medium::Interior(m) => match &m.content {
                interior::InteriorContent::Homogeneous(h) => Some(albedo_of(h.sigma_a, h.sigma_s)),
                interior::InteriorContent::Grid(g) => g.constant_albedo(),
            },
            Medium::Moving(m) => m.inner().constant_albedo(),
        }
    }

    /// Coefficients at world point `p` and `time` (frames from the frame time; zero outside the medium).
    ///
    /// Grid media with a velocity grid and keyframed media change with time.
    #[inline]
    pub fn properties(&self, p: Vec3, time: f32) -> MediumProperties {
        match self {
            Medium::Homogeneous(m) => m.properties(p),
            Medium::HeightFog(m) => m.properties(p),
            Medium::Grid(m) => m.properties_at(p, time),
            Medium::Interior(m) => m.properties(p, time),
            Medium::Moving(m) => m.properties(p, time),
        }
    }

    /// Extinction at world point `p` and `time`.
    #[inline]
    pub fn sigma_t_at(&self, p: Vec3, time: f32) -> Rgb {
        match self {
            Medium::Grid(m) => m.sigma_t_at(p, time),
            Medium::Moving(m) => m.sigma_t_at(p, time),
            Medium::Interior(m) => {
                let p = m.properties(p, time);
                p.sigma_a + p.sigma_s
            }
            Medium::Homogeneous(_) | Medium::HeightFog(_) => self.sigma_t(p),
        }
    }

    /// Extinction σa + σs at world point `p` (at time 0): all that tracking a shadow ray needs.
    #[inline]
    pub fn sigma_t(&self, p: Vec3) -> Rgb {
        match self {
            Medium::Homogeneous(m) => {
                let p = m.properties(p);
                p.sigma_a + p.sigma_s
            }
            Medium::HeightFog(m) => {
                let p = m.properties(p);
                p.sigma_a + p.sigma_s
            }
            Medium::Grid(m) => m.sigma_t(p),
            Medium::Interior(m) => {
                let p = m.properties(p, 0.0);
                p.sigma_a + p.sigma_s
            }
            Medium::Moving(m) => m.sigma_t_at(p, 0.0),
        }
    }

    /// Majorant segments along `ray` within `[0, t_max)`.
    #[inline]
    pub fn majorants(&self, ray: &Ray, t_max: f32) -> MajorantIter<'_> {
        match self {
            Medium::Homogeneous(m) => MajorantIter::Single(m.majorant(ray, t_max)),
            Medium::HeightFog(m) => MajorantIter::Fog(m.majorants(ray, t_max)),
            Medium::Grid(m) => MajorantIter::Grid(m.majorants(ray, t_max)),
            Medium::Interior(m) => MajorantIter::Masked(m.majorants(ray, t_max)),
            Medium::Moving(m) => m.majorants(ray, t_max),
        }
    }

    /// Optical depth ∫σt ds over `[t0, t1]` along `ray` when it has a closed form.
    #[inline]
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> Option<Rgb> {
        match self {
            Medium::Homogeneous(m) => Some(m.optical_depth(ray, t0, t1)),
            Medium::HeightFog(m) => Some(m.optical_depth(ray, t0, t1)),
            Medium::Grid(_) => None,
            Medium::Interior(m) => m.optical_depth(ray, t0, t1),
            Medium::Moving(m) => m.optical_depth(ray, t0, t1),
        }
    }

    /// `self` moved by `keys` (`None`: unchanged); `self` must be built in its local frame.
    pub fn moved_by(self, keys: Option<crate::math::keyframes::Keyframes>) -> Medium {
        match keys {
            Some(k) => Medium::Moving(std::sync::Arc::new(MovingMedium::new(self, k))),
            None => self,
        }
    }
}

#[cfg(test)]
mod tests;
