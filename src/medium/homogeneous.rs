//! A medium with constant coefficients inside a region.
//!
//! ```toml
//! [[medium]]
//! type = "homogeneous"
//! sigma_a = [0.01, 0.01, 0.01]
//! sigma_s = [0.2, 0.2, 0.2]
//! phase = { type = "hg", g = 0.6 }
//! bounds = { type = "box", min = [-5.0, 0.0, -5.0], max = [5.0, 3.0, 5.0] }
//! ```

use super::{MajorantSegment, MediumProperties, PhaseFunction, Region};
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};

/// Constant σa, σs, emission and phase inside a region.
#[derive(Clone, Debug)]
pub struct HomogeneousMedium {
    /// Absorption coefficient.
    pub sigma_a: Rgb,
    /// Scattering coefficient.
    pub sigma_s: Rgb,
    /// Emitted radiance (source term σa·Le).
    pub emission: Rgb,
    /// Phase function.
    pub phase: PhaseFunction,
    /// Where the medium is.
    pub region: Region,
}

impl HomogeneousMedium {
    /// Extinction σa + σs.
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// Coefficients at `p` (zero outside the region).
    pub fn properties(&self, p: Vec3) -> MediumProperties {
        let inside = self.region.contains(p);
        let k = if inside { 1.0 } else { 0.0 };
        MediumProperties {
            sigma_a: self.sigma_a * k,
            sigma_s: self.sigma_s * k,
            emission: self.emission,
            phase: self.phase,
        }
    }

    /// The single majorant segment where the ray is inside the region.
    pub fn majorant(&self, ray: &Ray, t_max: f32) -> Option<MajorantSegment> {
        let (t0, t1) = self.region.interval(ray, t_max)?;
        let sigma_t = self.sigma_t();
        Some(MajorantSegment {
            t0,
            t1,
            sigma_maj: sigma_t.max_channel(),
            decay: 0.0,
            sigma_control: sigma_t,
        })
    }

    /// ∫σt over `[t0, t1]` of the ray, counting only the part inside the region.
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> Rgb {
        match self.region.interval(ray, t1) {
            Some((a, b)) if b > t0 => self.sigma_t().depth_over(b - a.max(t0)),
            _ => Rgb::BLACK,
        }
    }
}
