//! The camera as a sensor: the importance it gives each direction, the
//! density of its primary rays' directions, and connecting a scene point to
//! the lens (light tracing, bidirectional path tracing's t = 1).
//!
//! Pixels are sampled with a box filter and the same number of samples each,
//! so over a whole render primary rays leave a lens point with directions of
//! density 1/(A cos³θ) per steradian, where A is the image's area on the
//! plane at unit distance in front of the lens and θ the angle to the optical
//! axis. The importance of a thin lens is We = 1/(A · π r² · cos⁴θ) (1/(A
//! cos⁴θ) for a pinhole), so a point seen along θ at distance d from a lens
//! point drawn uniformly adds We · cosθ / d² / (1/πr²) = 1/(A cos³θ d²)
//! times the radiance it sends, to be divided, like every camera sample, by
//! the samples per pixel: one light path is traced per camera sample.

use super::{Camera, View};
use crate::math::{Vec2, Vec3};
use crate::sampling::warp;

/// A scene point connected to the camera.
#[derive(Clone, Copy, Debug)]
pub struct CameraConnection {
    /// The lens point (the eye for a pinhole) the connection ends at.
    pub lens: Vec3,
    /// Unit direction from the lens point toward the scene point.
    pub direction: Vec3,
    /// Distance from the lens point to the scene point.
    pub distance: f32,
    /// Where the point images on the film, in pixels (x right, y down), inside the image.
    pub raster: Vec2,
    /// 1/(A cos³θ): times the radiance the point sends toward the lens, over
    /// the squared distance, its share of the pixel.
    pub importance: f32,
}

impl Camera {
    /// Area of the image on the plane at unit distance in front of the lens.
    fn film_area(&self) -> f32 {
        let aspect = self.width as f32 / self.height as f32;
        4.0 * self.tan_half_fov * self.tan_half_fov * aspect
    }

    /// Raster position (pixels) where a ray from the eye of `view` along `dir` meets the film,
    /// `None` outside the image or behind the camera.
    fn raster_of(&self, view: &View, dir: Vec3) -> Option<Vec2> {
        let z = dir.dot(view.forward);
        if z <= 0.0 {
            return None;
        }
        let aspect = self.width as f32 / self.height as f32;
        let ndc_x = dir.dot(view.right) / (z * self.tan_half_fov * aspect);
        let ndc_y = dir.dot(view.up) / (z * self.tan_half_fov);
        let raster = Vec2::new(
            (ndc_x + 1.0) * 0.5 * self.width as f32,
            (1.0 - ndc_y) * 0.5 * self.height as f32,
        );
        let inside = raster.x >= 0.0
            && raster.y >= 0.0
            && raster.x < self.width as f32
            && raster.y < self.height as f32;
        inside.then_some(raster)
    }

    /// Solid-angle density with which primary rays at `time` leave their
    /// lens point along `dir`: 1/(A cos³θ) inside the image, 0 outside.
    pub fn direction_pdf(&self, dir: Vec3, time: f32) -> f32 {
        let view = self.view_at(time);
        let cos = dir.dot(view.forward);
        if cos <= 0.0 {
            return 0.0;
        }
        // The film point a lens ray aims at is where the pinhole ray through it lands.
        if self.raster_of(&view, dir).is_none() {
            return 0.0;
        }
        1.0 / (self.film_area() * cos * cos * cos)
    }

    /// Connects scene point `p` to the camera at `time`, through the lens
    /// point drawn from `u_lens` (ignored by a pinhole); `None` when `p`
    /// images outside the film.
    pub fn connect(&self, p: Vec3, time: f32, u_lens: Vec2) -> Option<CameraConnection> {
        let view = self.view_at(time);
        let lens = if self.has_lens() {
            let d = warp::square_to_concentric_disk(u_lens) * self.aperture_radius;
            view.position + view.right * d.x + view.up * d.y
        } else {
            view.position
        };
        let to_p = p - lens;
        let distance = to_p.length();
        if distance <= 0.0 || !distance.is_finite() {
            return None;
        }
        let direction = to_p / distance;
        let cos = direction.dot(view.forward);
        if cos <= 0.0 {
            return None;
        }
        // Every lens ray of one film point crosses the focus plane where the pinhole ray does.
        let through = if self.has_lens() {
            let focus = lens + direction * (self.focus_distance / cos);
            (focus - view.position).normalize()
        } else {
            direction
        };
        let raster = self.raster_of(&view, through)?;
        Some(CameraConnection {
            lens,
            direction,
            distance,
            raster,
            importance: 1.0 / (self.film_area() * cos * cos * cos),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    /// A primary ray's direction images back onto the pixel it was drawn
    /// for, at its sub-pixel offset, with and without a lens.
    #[test]
    fn primary_rays_connect_back_to_their_pixel() {
        let pinhole = Camera::new(Vec3::new(0.5, 1.0, 3.0), Vec3::ZERO, Vec3::Y, 50.0, 40, 30)
            .expect("camera");
        let lens = pinhole.clone().with_lens(0.1, 2.0);
        let mut s = Sampler::from_seed(4);
        for cam in [&pinhole, &lens] {
            for _ in 0..500 {
                let (x, y) = ((s.next_1d() * 40.0) as u32, (s.next_1d() * 30.0) as u32);
                let (u, u_lens) = (s.next_2d(), s.next_2d());
                let ray = cam.generate_lens_ray(x, y, u, u_lens);
                let p = ray.at(0.5 + 3.0 * s.next_1d());
                let c = cam.connect(p, 0.0, u_lens).expect("inside the image");
                let want = Vec2::new(x as f32 + u.x, y as f32 + u.y);
                assert!(
                    (c.raster - want).length() < 2e-3,
                    "{:?} vs {want}",
                    c.raster
                );
                assert!((c.lens - ray.origin).length() < 1e-5);
                assert!((c.direction - ray.direction).length() < 1e-4);
            }
        }
    }

    /// The direction density integrates to one over the image: a Monte Carlo
    /// integral over uniform directions of the hemisphere, at the suite's k.
    #[test]
    fn direction_pdf_integrates_to_one() {
        let cam = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 32, 20).expect("camera");
        let n = 400_000;
        let mut s = Sampler::from_seed(9);
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let local = warp::square_to_uniform_cone(s.next_2d(), 0.0);
            let dir = Vec3::new(local.x, local.y, -local.z);
            let v = (cam.direction_pdf(dir, 0.0) * 2.0 * std::f32::consts::PI) as f64;
            sum += v;
            sum2 += v * v;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!(
            (mean - 1.0).abs() < crate::suite_k::k_sigma(1) * se,
            "{mean} ± {se}"
        );
        // The pdf is the importance's cos⁴ form over cosθ: 1/(A cos³θ) on the axis is 1/A.
        let area = 4.0 * (30f32.to_radians().tan()).powi(2) * 1.6;
        assert!((cam.direction_pdf(-Vec3::Z, 0.0) * area - 1.0).abs() < 1e-5);
    }
}
