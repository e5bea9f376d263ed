//! Lat-long (equirectangular) HDR environment maps, importance-sampled by a
//! 2-D piecewise-constant distribution over texel luminance × sin θ.
//!
//! Convention (in the map's own frame, before `rotation`): texel column u ∈
//! [0, 1) is the azimuth φ = 2πu measured from +X toward +Z, row v ∈ [0, 1)
//! is the polar angle θ = πv from +Y (row 0 is straight up), so
//! `dir = (sinθ cosφ, cosθ, sinθ sinφ)`. With [`Filter::Nearest`] radiance
//! is constant over a texel; with [`Filter::Bilinear`] it is interpolated
//! as Mitsuba 3's `envmap` does: between column centres (x + ½)/width,
//! wrapping in u, and between rows placed from pole to pole (row y at
//! v = y/(height − 1): the first row is the zenith, the last the nadir).
//! The bilinear map is
//! sampled by a piecewise-constant table whose texel weight is the largest
//! luminance among the 3 × 3 texels its interpolation touches, so the
//! density is positive wherever the interpolated radiance is.

use crate::math::color::Rgb;
use crate::math::{Quat, Vec2, Vec3};
use crate::sampling::distribution::Distribution2D;
use std::f32::consts::PI;

/// How radiance varies across a texel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// Constant over the texel.
    #[default]
    Nearest,
    /// Bilinear between column centres and rows from pole to pole (Mitsuba 3's `envmap`).
    Bilinear,
}

/// An environment map with its sampling distribution.
#[derive(Clone, Debug)]
pub struct EnvMap {
    filter: Filter,
    width: usize,
    height: usize,
    /// Row-major texels (row 0 at the zenith), already multiplied by the scale.
    texels: Vec<Rgb>,
    distribution: Distribution2D,
    /// Map frame → world.
    rotation: Quat,
}

/// A direction sampled from an environment map.
#[derive(Clone, Copy, Debug)]
pub struct EnvSample {
    /// World direction toward the sky.
    pub wi: Vec3,
    /// Radiance arriving from `wi`.
    pub radiance: Rgb,
    /// Solid-angle density.
    pub pdf: f32,
}

impl EnvMap {
    /// A map of `width` × `height` texels scaled by `scale` and turned by `rotation`.
    ///
    /// Returns `None` when the map is empty or black everywhere (nothing to sample).
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<Rgb>,
        scale: Rgb,
        rotation: Quat,
    ) -> Option<EnvMap> {
        EnvMap::filtered(width, height, texels, scale, rotation, Filter::Nearest)
    }

    /// [`EnvMap::new`] with radiance filtered by `filter`.
    pub fn filtered(
        width: usize,
        height: usize,
        texels: Vec<Rgb>,
        scale: Rgb,
        rotation: Quat,
        filter: Filter,
    ) -> Option<EnvMap> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return None;
        }
        let texels: Vec<Rgb> = texels.into_iter().map(|t| t * scale).collect();
        let luminance: Vec<f32> = texels.iter().map(|t| t.luminance().max(0.0)).collect();
        let mut weights = Vec::with_capacity(texels.len());
        for (i, &l) in luminance.iter().enumerate() {
            let (x, y) = (i % width, i / width);
            let sin_theta = (PI * (y as f32 + 0.5) / height as f32).sin();
            let l = match filter {
                Filter::Nearest => l,
                Filter::Bilinear => neighbourhood_max(&luminance, width, height, x, y),
            };
            weights.push(l * sin_theta);
        }
        let distribution = Distribution2D::new(&weights, width, height)?;
        Some(EnvMap {
            filter,
            width,
            height,
            texels,
            distribution,
            rotation,
        })
    }

    /// Map coordinates of a world direction.
    fn uv(&self, dir: Vec3) -> Vec2 {
        let d = self.rotation.inverse() * dir;
        // atan2 keeps θ accurate near the poles, where acos(y) loses it.
        let theta = (d.x * d.x + d.z * d.z).sqrt().atan2(d.y);
        let mut phi = d.z.atan2(d.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        Vec2::new(
            (phi / (2.0 * PI)).min(1.0 - f32::EPSILON),
            (theta / PI).min(1.0 - f32::EPSILON),
        )
    }

    /// World direction of map coordinates.
    fn direction(&self, uv: Vec2) -> Vec3 {
        let (sin_t, cos_t) = (PI * uv.y).sin_cos();
        let (sin_p, cos_p) = (2.0 * PI * uv.x).sin_cos();
        self.rotation * Vec3::new(sin_t * cos_p, cos_t, sin_t * sin_p)
    }

    /// Radiance at map coordinates `uv`, filtered.
    fn texel(&self, uv: Vec2) -> Rgb {
        match self.filter {
            Filter::Nearest => {
                let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
                let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
                self.texels[y * self.width + x]
            }
            Filter::Bilinear => self.bilinear(uv),
        }
    }

    /// Bilinear interpolation between column centres (wrapping in u) and
    /// rows placed from pole to pole, Mitsuba's convention.
    fn bilinear(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.width, self.height);
        let fx = uv.x * w as f32 - 0.5;
        let floor_x = fx.floor();
        let tx = fx - floor_x;
        let x0 = (floor_x as isize).rem_euclid(w as isize) as usize;
        let x1 = (x0 + 1) % w;
        let fy = (uv.y * (h - 1) as f32).clamp(0.0, (h - 1) as f32);
        let y0 = (fy as usize).min(h - 1);
        let ty = fy - y0 as f32;
        let y1 = (y0 + 1).min(h - 1);
        let at = |x: usize, y: usize| self.texels[y * w + x];
        // a + (b − a)·t: exact where neighbours are equal (a constant map).
        let lerp = |a: Rgb, b: Rgb, t: f32| a + (b - a) * t;
        let top = lerp(at(x0, y0), at(x1, y0), tx);
        let bottom = lerp(at(x0, y1), at(x1, y1), tx);
        lerp(top, bottom, ty)
    }

    /// The least radiance of any texel, per channel: a floor of every
    /// direction's radiance, filtered or not (a bilinear lookup stays between
    /// its texels).
    pub fn floor(&self) -> Rgb {
        self.texels
            .iter()
            .fold(Rgb::splat(f32::INFINITY), |low, &t| low.min_per_channel(t))
    }

    /// The brightest texel's luminance (over the average's: a sun in the map
    /// makes it hundreds or more, a smooth sky a few).
    pub fn peak_luminance(&self) -> f32 {
        self.texels
            .iter()
            .map(|t| t.luminance())
            .fold(0.0, f32::max)
    }

    /// Radiance averaged over the sphere (each texel weighted by its solid
    /// angle, ∝ sin θ; the texel values, also for a bilinear map).
    pub fn average(&self) -> Rgb {
        let mut sum = [0.0f64; 3];
        let mut weight = 0.0f64;
        for (i, t) in self.texels.iter().enumerate() {
            let sin_theta =
                (std::f64::consts::PI * ((i / self.width) as f64 + 0.5) / self.height as f64).sin();
            sum[0] += t.r as f64 * sin_theta;
            sum[1] += t.g as f64 * sin_theta;
            sum[2] += t.b as f64 * sin_theta;
            weight += sin_theta;
        }
        let w = weight.max(f64::MIN_POSITIVE);
        Rgb::new(
            (sum[0] / w) as f32,
            (sum[1] / w) as f32,
            (sum[2] / w) as f32,
        )
    }

    /// Radiance arriving from world direction `dir` (pointing away from the receiver).
    pub fn radiance(&self, dir: Vec3) -> Rgb {
        self.texel(self.uv(dir))
    }

    /// Solid-angle density with which `sample` picks `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let uv = self.uv(dir);
        let sin_theta = (PI * uv.y).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        // dω = 2π² sinθ du dv.
        self.distribution.pdf(uv) / (2.0 * PI * PI * sin_theta)
    }

    /// Samples a direction in proportion to luminance (times the texel's solid angle).
    pub fn sample(&self, u: Vec2) -> Option<EnvSample> {
        let (uv, pdf_uv) = self.distribution.sample(u);
        let sin_theta = (PI * uv.y).sin();
        if pdf_uv <= 0.0 || sin_theta <= 0.0 {
            return None;
        }
        Some(EnvSample {
            wi: self.direction(uv),
            radiance: self.texel(uv),
            pdf: pdf_uv / (2.0 * PI * PI * sin_theta),
        })
    }
}

/// The largest of `luminance` over texel (x, y) and its eight neighbours
/// (wrapping in x, clamped in y): every texel a bilinear lookup inside
/// texel (x, y) can weigh.
fn neighbourhood_max(luminance: &[f32], width: usize, height: usize, x: usize, y: usize) -> f32 {
    let mut max = 0.0f32;
    for dy in [-1isize, 0, 1] {
        let yy = (y as isize + dy).clamp(0, height as isize - 1) as usize;
        for dx in [width - 1, 0, 1] {
            max = max.max(luminance[yy * width + (x + dx) % width]);
        }
    }
    max
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    #[test]
    fn directions_and_map_coordinates_round_trip() {
        let map = EnvMap::new(
            8,
            4,
            vec![Rgb::WHITE; 32],
            Rgb::WHITE,
            Quat::from_rotation_y(0.7),
        )
        .unwrap();
        let mut s = Sampler::from_seed(3);
        for _ in 0..100 {
            let uv = s.next_2d() * 0.98 + Vec2::splat(0.01);
            let back = map.uv(map.direction(uv));
            assert!((back - uv).length() < 1e-4, "{uv} -> {back}");
        }
        // Row 0 is up, u = 0.25 points along +Z before the rotation.
        let flat = EnvMap::new(8, 4, vec![Rgb::WHITE; 32], Rgb::WHITE, Quat::IDENTITY).unwrap();
        assert!((flat.direction(Vec2::new(0.25, 0.5)) - Vec3::Z).length() < 1e-5);
        assert!(flat.direction(Vec2::new(0.0, 0.0)).y > 0.999);
    }

    #[test]
    fn black_maps_are_refused() {
        assert!(EnvMap::new(2, 2, vec![Rgb::BLACK; 4], Rgb::WHITE, Quat::IDENTITY).is_none());
        assert!(EnvMap::new(2, 2, vec![Rgb::WHITE; 3], Rgb::WHITE, Quat::IDENTITY).is_none());
    }
}
