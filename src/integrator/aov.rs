//! First-vertex AOVs (arbitrary output variables) for compositing and
//! denoising, estimated beside the beauty with random streams of their own.
//!
//! A camera sample takes the same camera ray as the beauty sample of the same
//! (pixel, sample index) — the first two dimensions of the beauty stream —
//! and every further random number from a separate stream, so the beauty is
//! bit-identical with or without AOVs.
//!
//! | AOV | EXR channels | per sample |
//! | --- | --- | --- |
//! | `alpha` | `A` | 1 at a surface; else 1 − T(camera ray to infinity), the channel mean |
//! | `depth` | `depth.Z` | camera-space depth (along the optical axis) of the first vertex |
//! | `normal` | `normal.X/Y/Z` | world-space shading normal facing the camera; `−ray direction` at a medium scattering vertex |
//! | `albedo` | `albedo.R/G/B` | throughput × reflectance at the first surface; the free-flight throughput σs-weighted at a medium vertex |
//! | `transmittance` | `transmittance.R/G/B` | T of the camera ray up to its first surface (or to infinity) |
//!
//! At a medium vertex the albedo is the spectral-tracking throughput after
//! the scattering event, whose mean over the camera ray is
//! ∫ T(t) σs(t) dt (+ T(t_s)·ρ for the surface behind): for a thick
//! homogeneous medium, the single-scattering albedo σs/σt, as Cycles defines
//! its volume denoising albedo. A sample that escapes has normal and albedo
//! 0 and no depth; a pixel whose samples all escape has depth +∞.

use super::tracking::{sample_free_flight, FreeFlight};
use super::Scene;
use crate::material::Material;
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};
use crate::sampling::{PixelStreams, Sampler};

pub use crate::film::aov::Aov;

/// What one camera sample sees at its first vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AovSample {
    /// 1 − transmittance to the background (1 at a surface).
    pub alpha: f32,
    /// Camera-space depth of the first vertex, if there is one.
    pub depth: Option<f32>,
    /// Normal at the first vertex (0 when there is none).
    pub normal: Vec3,
    /// Albedo × throughput at the first vertex.
    pub albedo: Rgb,
    /// Transmittance of the camera ray to its first surface.
    pub transmittance: Rgb,
}

/// Mixed into the scene seed to key the AOV streams apart from the beauty's.
const AOV_STREAM_KEY: u64 = 0x414F_565F_5354_524D;

/// The AOVs of sample `s` of pixel (x, y): the beauty's camera ray (from
/// the beauty's streams of that pixel, `beauty`), the AOV stream.
pub fn aov_sample(scene: &Scene, x: u32, y: u32, beauty: &PixelStreams, s: u32) -> AovSample {
    let seed = scene.settings.seed;
    // The beauty's first two dimensions choose its camera ray (see render::pixel_sample).
    let mut beauty = beauty.sampler(s as u64);
    // The beauty's time too (a reserved stream position): AOVs see the scene as the beauty does.
    let time = match scene.settings.shutter {
        Some(_) => scene.settings.sample_time(beauty.time_1d()),
        None => 0.0,
    };
    let offset = scene.camera.pixel_offset(x, y, beauty.next_2d());
    let ray = scene.camera.generate_ray_at(x, y, offset, time);
    let mut sampler = Sampler::new(seed ^ AOV_STREAM_KEY, x, y, s as u64);
    first_vertex(scene, &ray, &mut sampler)
}

/// Reflectance of a surface for the albedo AOV.
fn reflectance(material: &Material) -> Rgb {
    match *material {
        Material::Diffuse { albedo } | Material::Phong { albedo, .. } => albedo,
        Material::Mirror { reflectance } => reflectance,
        // Clear glass transmits or reflects everything: white, as denoisers expect.
        Material::Dielectric { .. } | Material::ThinDielectric { .. } => Rgb::WHITE,
        Material::Plastic(p) => p.diffuse,
        Material::Conductor { fresnel, .. } => fresnel.eval(1.0),
    }
}

fn first_vertex(scene: &Scene, ray: &Ray, sampler: &mut Sampler) -> AovSample {
    let hit = scene.geometry.intersect(ray, f32::INFINITY);
    let t_surface = hit.map_or(f32::INFINITY, |h| h.t);
    let transmittance = scene.transmittance(ray, t_surface, sampler);
    let alpha = if hit.is_some() {
        1.0
    } else {
        1.0 - transmittance.average()
    };
    let forward = scene.camera.view_at(ray.time).forward;
    let mut out = AovSample {
        alpha,
        depth: None,
        normal: Vec3::ZERO,
        albedo: Rgb::BLACK,
        transmittance,
    };
    let mut throughput = Rgb::WHITE;
    if !scene.media.is_empty() {
        // Emission is not an AOV: the radiance this adds is dropped.
        let mut radiance = Rgb::BLACK;
        let event = sample_free_flight(
            &scene.media,
            ray,
            t_surface,
            &mut throughput,
            &mut radiance,
            sampler,
        );
        match event {
            FreeFlight::Absorbed => return out,
            FreeFlight::Passed => {}
            FreeFlight::Scatter { t, .. } => {
                out.depth = Some(t * ray.direction.dot(forward));
                out.normal = -ray.direction;
                out.albedo = throughput;
                return out;
            }
        }
    }
    if let Some(hit) = hit {
        let wo = -ray.direction;
        out.depth = Some(hit.t * ray.direction.dot(forward));
        out.normal = if hit.shading_normal.dot(wo) >= 0.0 {
            hit.shading_normal
        } else {
            -hit.shading_normal
        };
        out.albedo = throughput * reflectance(&scene.material_at(&hit));
    }
    out
}

/// Running per-pixel sums of AOV samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct AovPixel {
    alpha: f64,
    depth: f64,
    depth_hits: u32,
    normal: [f64; 3],
    albedo: [f64; 3],
    transmittance: [f64; 3],
    count: u32,
}

impl AovPixel {
    /// Adds one sample; a sample with a non-finite value is left out whole.
    pub fn add(&mut self, s: &AovSample) {
        let finite = s.alpha.is_finite()
            && s.depth.is_none_or(f32::is_finite)
            && s.normal.is_finite()
            && s.albedo.is_finite()
            && s.transmittance.is_finite();
        if !finite {
            return;
        }
        self.alpha += s.alpha as f64;
        if let Some(d) = s.depth {
            self.depth += d as f64;
            self.depth_hits += 1;
        }
        for c in 0..3 {
            self.normal[c] += s.normal[c] as f64;
            self.albedo[c] += s.albedo[c] as f64;
            self.transmittance[c] += s.transmittance[c] as f64;
        }
        self.count += 1;
    }

    /// Adds this pixel's sums of `aov` to `sums` (one per channel of
    /// `aov.channels()`) and its denominator to `count`: the samples kept,
    /// or for the depth the samples that met a first vertex.
    pub fn add_into(&self, aov: Aov, sums: &mut [f64], count: &mut u32) {
        let values: &[f64] = match aov {
            Aov::Alpha => std::slice::from_ref(&self.alpha),
            Aov::Depth => std::slice::from_ref(&self.depth),
            Aov::Normal => &self.normal,
            Aov::Albedo => &self.albedo,
            Aov::Transmittance => &self.transmittance,
        };
        for (sum, v) in sums.iter_mut().zip(values) {
            *sum += v;
        }
        *count += match aov {
            Aov::Depth => self.depth_hits,
            _ => self.count,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finite_sample() -> AovSample {
        AovSample {
            alpha: 1.0,
            depth: Some(2.0),
            normal: Vec3::Z,
            albedo: Rgb::splat(0.5),
            transmittance: Rgb::WHITE,
        }
    }

    /// A sample with any one non-finite value is left out whole; a pixel no
    /// sample's ray hit has depth +∞.
    #[test]
    fn a_pixel_drops_samples_with_any_non_finite_value() {
        let mut px = AovPixel::default();
        px.add(&finite_sample());
        let bad = [
            AovSample {
                alpha: f32::NAN,
                ..finite_sample()
            },
            AovSample {
                depth: Some(f32::INFINITY),
                ..finite_sample()
            },
            AovSample {
                normal: Vec3::new(0.0, f32::NAN, 1.0),
                ..finite_sample()
            },
            AovSample {
                albedo: Rgb::new(0.5, f32::INFINITY, 0.5),
                ..finite_sample()
            },
            AovSample {
                transmittance: Rgb::new(f32::NAN, 1.0, 1.0),
                ..finite_sample()
            },
        ];
        for (k, sample) in bad.iter().enumerate() {
            px.add(sample);
            assert_eq!(px.count, 1, "sample {k} was kept");
        }
        for aov in Aov::ALL {
            let (mut sums, mut count) = ([0.0; 3], 0);
            px.add_into(aov, &mut sums, &mut count);
            assert_eq!(count, 1, "{aov:?}");
            assert!(sums.iter().all(|v| v.is_finite()), "{aov:?}: {sums:?}");
        }
    }
}
