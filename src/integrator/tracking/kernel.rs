//! What tracking reads of a medium at a tentative collision, per medium type.
//!
//! The estimators' loops are generic over [`TrackedMedium`] and entered
//! through [`dispatch!`], so the match on the medium's type happens once per
//! estimator call and each loop is compiled for one concrete medium.

use crate::math::color::Rgb;
use crate::math::Vec3;
use crate::medium::{GridMedium, HeightFog, HomogeneousMedium, MediumProperties, MovingMedium};

/// A medium's coefficients as tracking needs them.
pub(crate) trait TrackedMedium {
    /// Extinction only (shadow rays), at `time` (frames from the frame's time).
    fn sigma_t(&self, p: Vec3, time: f32) -> Rgb;
    /// Everything (free flights), at `time`.
    fn properties(&self, p: Vec3, time: f32) -> MediumProperties;
}

impl TrackedMedium for HomogeneousMedium {
    #[inline]
    fn sigma_t(&self, p: Vec3, _time: f32) -> Rgb {
        if self.region.contains(p) {
            self.sigma_a + self.sigma_s
        } else {
            Rgb::BLACK
        }
    }
    #[inline]
    fn properties(&self, p: Vec3, _time: f32) -> MediumProperties {
        HomogeneousMedium::properties(self, p)
    }
}

impl TrackedMedium for HeightFog {
    #[inline]
    fn sigma_t(&self, p: Vec3, _time: f32) -> Rgb {
        let p = HeightFog::properties(self, p);
        p.sigma_a + p.sigma_s
    }
    #[inline]
    fn properties(&self, p: Vec3, _time: f32) -> MediumProperties {
        HeightFog::properties(self, p)
    }
}

impl TrackedMedium for GridMedium {
    #[inline]
    fn sigma_t(&self, p: Vec3, time: f32) -> Rgb {
        GridMedium::sigma_t_at(self, p, time)
    }
    #[inline]
    fn properties(&self, p: Vec3, time: f32) -> MediumProperties {
        GridMedium::properties_at(self, p, time)
    }
}

impl TrackedMedium for MovingMedium {
    #[inline]
    fn sigma_t(&self, p: Vec3, time: f32) -> Rgb {
        MovingMedium::sigma_t_at(self, p, time)
    }
    #[inline]
    fn properties(&self, p: Vec3, time: f32) -> MediumProperties {
        MovingMedium::properties(self, p, time)
    }
}

/// Evaluates `$body` with `$m` bound to the concrete medium inside `$medium`.
macro_rules! dispatch {
    ($medium:expr, $m:ident => $body:expr) => {
        match $medium {
            crate::medium::Medium::Homogeneous($m) => $body,
            crate::medium::Medium::HeightFog($m) => $body,
            crate::medium::Medium::Grid(g) => {
                let $m: &crate::medium::GridMedium = g;
                $body
            }
            // A shape-masked medium tracks its content over the clipped
            // segments (see medium::interior): collisions fall inside the shape.
            crate::medium::Medium::Interior(i) => match &i.content {
                crate::medium::InteriorContent::Homogeneous($m) => $body,
                crate::medium::InteriorContent::Grid(g) => {
                    let $m: &crate::medium::GridMedium = g;
                    $body
                }
            },
            crate::medium::Medium::Moving(g) => {
                let $m: &crate::medium::MovingMedium = g;
                $body
            }
        }
    };
}
pub(crate) use dispatch;
