//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009) with
//! volumetric photons (Jensen and Christensen 1998) gathered along eye
//! segments by the beam radiance estimate (Jarosz et al. 2008).
//!
//! Every pass (one sample index, one sample per pixel) first traces
//! `photons` light paths (module `photons`, the bidirectional integrator's
//! light walk) and grids the scattering vertices they leave past their first
//! hit; then each pixel traces one eye path with the path tracer's own loop,
//! which does next-event estimation and gathers emission as always but stops
//! scattering after its first non-Dirac event, where the photons add the
//! indirect and caustic light (module `gather`): on that surface by a disk
//! estimate, and in media along every eye segment before it by the beam
//! estimate. Direct light is next-event estimation's alone; photons carry
//! everything that scattered at least once on the way from the light.
//!
//! The radius shrinks from pass to pass by SPPM's rule
//! r²ᵢ₊₁ = r²ᵢ·(i + α)/(i + 1) (Hachisuka and Jensen 2009 with a pass's
//! photon count fixed; Knaus and Zwicker 2011 show that each pass may then
//! use the same radius everywhere and the image be the plain mean of the
//! passes). So a pixel keeps no state across passes: pass `i` is sample
//! index `i`, the film averages passes like samples, and split renders,
//! checkpoints and `--time` work as for the other integrators. The bias of
//! pass i falls like r²ᵢ ∝ i^(α−1) (first order, r ∝ i^((α−1)/2), where the
//! kernel straddles an edge of the lit region) and its variance grows like
//! 1/r²ᵢ ∝ i^(1−α), so the mean of N passes has variance ∝ N^(−α).

mod gather;
mod grid;
pub mod photons;

use crate::error::limits;
use crate::film::Splat;
use crate::integrator::bdpt::scene_sphere;
use crate::integrator::estimator::{Estimator, Prepared};
use crate::integrator::{li_gathering, Scene};
use crate::light::SceneSphere;
use crate::math::color::Rgb;
use crate::sampling::chi2::ln_gamma;
use crate::sampling::PixelStreams;
use gather::Gatherer;
use photons::{Built, PhotonMap, PHOTON_PEAK_BYTES};
use std::sync::atomic::AtomicBool;
use std::sync::RwLock;

/// Light paths traced per pass unless `integrator.photons` says otherwise.
pub const DEFAULT_PHOTONS: u32 = 100_000;

/// Most light paths per pass (`integrator.photons`). The photons they leave
/// are counted against the memory limit while a pass traces them
/// ([`photons::PHOTON_PEAK_BYTES`] each): a pass over it is refused.
pub const MAX_PHOTONS: u32 = 2_000_000;

/// The default first radius as a fraction of the radius of the sphere
/// around the scene (shapes, camera and point lights).
pub const DEFAULT_RADIUS_FRACTION: f32 = 0.01;

/// The default radius-reduction exponent α (Hachisuka and Jensen's 2/3).
pub const DEFAULT_ALPHA: f32 = 2.0 / 3.0;

/// The photon settings of `[integrator] type = "sppm"`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SppmSettings {
    /// Light paths traced per pass.
    pub photons: u32,
    /// Gather radius of the first pass (`None`: [`DEFAULT_RADIUS_FRACTION`] of the scene's size).
    pub radius: Option<f32>,
    /// Radius-reduction exponent α in (0, 1).
    pub alpha: f32,
}

impl Default for SppmSettings {
    fn default() -> Self {
        SppmSettings {
            photons: DEFAULT_PHOTONS,
            radius: None,
            alpha: DEFAULT_ALPHA,
        }
    }
}

/// The gather radius of pass `pass` (0-based) from first radius `r1`:
/// r²ᵢ₊₁ = r²ᵢ·(i + α)/(i + 1) with i the 1-based pass number, in closed
/// form r²ₙ₊₁ = r²₁·Γ(n + 1 + α) / (Γ(1 + α)·Γ(n + 2)) (no loop over passes).
pub fn pass_radius(r1: f32, alpha: f32, pass: u32) -> f32 {
    let (a, n) = (alpha as f64, pass as f64);
    let log_ratio = ln_gamma(n + 1.0 + a) - ln_gamma(1.0 + a) - ln_gamma(n + 2.0);
    r1 * (0.5 * log_ratio).exp() as f32
}

/// Stochastic progressive photon mapping as the driver's [`Estimator`].
pub struct Sppm {
    photons: u32,
    radius: f32,
    alpha: f32,
    sphere: SceneSphere,
    /// The photons of the pass being rendered (written between passes only).
    map: RwLock<PhotonMap>,
}

impl Sppm {
    /// The estimator for `scene`, its first radius resolved.
    pub fn new(scene: &Scene) -> Sppm {
        let settings = scene.settings.sppm;
        let sphere = scene_sphere(scene);
        Sppm {
            photons: settings.photons,
            radius: settings
                .radius
                .unwrap_or(DEFAULT_RADIUS_FRACTION * sphere.radius),
            alpha: settings.alpha,
            sphere,
            map: RwLock::new(PhotonMap::default()),
        }
    }

    /// The first pass's gather radius (the scene's or the default).
    pub fn first_radius(&self) -> f32 {
        self.radius
    }

    /// Bytes the photon map holds now.
    pub fn map_bytes(&self) -> usize {
        self.map.read().map_or(0, |m| m.bytes())
    }

    /// (surface, volume) photons of the pass last built.
    pub fn photon_counts(&self) -> (usize, usize) {
        self.map.read().map_or((0, 0), |m| {
            (m.surface.positions.len(), m.volume.positions.len())
        })
    }
}

impl Estimator for Sppm {
    /// The photons met along one eye segment.
    type Arena = Vec<(f32, Rgb)>;

    fn arena(&self) -> Self::Arena {
        Vec::new()
    }

    fn splats(&self) -> bool {
        false
    }

    fn pass_samples(&self) -> Option<u32> {
        Some(1)
    }

    fn prepare(&self, scene: &Scene, s: u32, cancel: &AtomicBool) -> Prepared {
        let mut map = self.map.write().unwrap_or_else(|e| e.into_inner());
        if map.pass == Some(s) {
            return Prepared::Ready;
        }
        let limit = match limits::memory_limit() {
            Ok(limit) => limit,
            Err(refusal) => return over_budget(refusal.to_string()),
        };
        let radius = pass_radius(self.radius, self.alpha, s);
        let pass = (s, self.photons, radius);
        match map.build(scene, &self.sphere, pass, (limit.bytes, cancel)) {
            Built::Ready => Prepared::Ready,
            Built::Stopped => Prepared::Stopped,
            Built::OverBudget { photons } => {
                let refusal = limits::Refusal::Exceeded {
                    limit,
                    machine: false,
                };
                over_budget(format!(
                    "pass {}'s {} light paths leave at least {photons} photons, {} at {PHOTON_PEAK_BYTES} bytes each: {refusal}; or lower integrator.photons or integrator.max_depth",
                    s + 1,
                    self.photons,
                    limits::format_bytes(u128::from(photons) * u128::from(PHOTON_PEAK_BYTES)),
                ))
            }
        }
    }

    fn sample(
        &self,
        scene: &Scene,
        (x, y): (u32, u32),
        streams: &PixelStreams,
        s: u32,
        arena: &mut Self::Arena,
        _splats: &mut Vec<Splat>,
    ) -> Rgb {
        let map = self.map.read().unwrap_or_else(|e| e.into_inner());
        assert_eq!(
            map.pass,
            Some(s),
            "sppm: sample {s} taken before its photon pass"
        );
        let mut sampler = streams.sampler(s as u64);
        let time = match scene.settings.shutter {
            Some(_) => scene.settings.sample_time(sampler.time_1d()),
            None => 0.0,
        };
        let ray = scene.camera.sample_ray_at(x, y, time, &mut sampler);
        let mut gatherer = Gatherer {
            map: &map,
            beam: arena,
            radiance: Rgb::BLACK,
        };
        let direct = li_gathering(scene, ray, &mut sampler, &mut gatherer, None);
        direct + gatherer.radiance
    }
}

/// A pass refused for its photons' memory.
fn over_budget(message: String) -> Prepared {
    Prepared::Refused {
        key: "integrator.photons",
        message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The radius follows r²ᵢ₊₁ = r²ᵢ (i + α)/(i + 1) and so falls like i^((α−1)/2).
    #[test]
    fn radius_shrinks_by_the_sppm_rule() {
        let (r1, alpha) = (0.5f32, 2.0 / 3.0);
        let mut r2 = (r1 as f64).powi(2);
        for pass in 0..200u32 {
            if pass > 0 {
                r2 *= (pass as f64 + alpha as f64) / (pass as f64 + 1.0);
            }
            let r = pass_radius(r1, alpha, pass) as f64;
            assert!(
                (r * r / r2 - 1.0).abs() < 1e-5,
                "pass {pass}: {} vs {r2}",
                r * r
            );
        }
        // Asymptotically r² ∝ i^(α−1): the ratio over 10× the passes is 10^(α−1).
        let (a, b) = (
            pass_radius(r1, alpha, 10_000),
            pass_radius(r1, alpha, 100_000),
        );
        let ratio = (b / a).powi(2);
        assert!((ratio - 10f32.powf(alpha - 1.0)).abs() < 1e-3, "{ratio}");
    }
}
