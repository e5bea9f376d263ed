//! The perspective camera (pinhole or thin lens) and primary ray generation.

use crate::math::keyframes::Keyframes;
use crate::math::{Ray, Vec2, Vec3};
use crate::sampling::{warp, Sampler};
use std::sync::Arc;

mod importance;
mod pixel_filter;

pub use importance::CameraConnection;
pub use pixel_filter::PixelFilter;

/// Which image axis the field of view spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FovAxis {
    /// Across the image height (brume's default).
    #[default]
    Vertical,
    /// Across the image width (the convention of many other renderers).
    Horizontal,
}

/// Where a camera is and how it is turned, at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub position: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// Unit image right.
    pub right: Vec3,
    /// Unit image up.
    pub up: Vec3,
}

/// A perspective camera: a pinhole, or a thin lens focused on a plane.
#[derive(Clone, Debug)]
pub struct Camera {
    /// The camera's view at rest (before `motion`).
    view: View,
    /// Rigid keyframed motion applied to the rest view at a sample's time.
    motion: Option<Arc<Keyframes>>,
    /// tan of half the vertical field of view.
    tan_half_fov: f32,
    /// Lens radius (0 = pinhole).
    aperture_radius: f32,
    /// Distance along `forward` of the plane in focus.
    focus_distance: f32,
    width: u32,
    height: u32,
    /// How a pixel weighs the film around it.
    filter: PixelFilter,
}

impl Camera {
    /// A pinhole camera at `position` looking at `look_at`; `fov_degrees` spans the image height.
    ///
    /// Returns `None` for a degenerate frame (look_at = position, or up parallel to the view).
    pub fn new(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        fov_degrees: f32,
        width: u32,
        height: u32,
    ) -> Option<Camera> {
        let forward = (look_at - position).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        if right.cross(forward).length() < 0.5 {
            return None;
        }
        Some(Camera {
            view: View {
                position,
                forward,
                right,
                up: right.cross(forward),
            },
            motion: None,
            tan_half_fov: (fov_degrees.to_radians() * 0.5).tan(),
            aperture_radius: 0.0,
            focus_distance: 1.0,
            width,
            height,
            filter: PixelFilter::Box,
        })
    }

    /// Unit viewing direction (the camera's optical axis) at rest.
    pub fn forward(&self) -> Vec3 {
        self.view.forward
    }

    /// The same camera moved rigidly by `motion` (keys must not scale).
    pub fn with_motion(mut self, motion: Keyframes) -> Camera {
        self.motion = Some(Arc::new(motion));
        self
    }

    /// True when the camera moves over time.
    pub fn is_moving(&self) -> bool {
        self.motion.is_some()
    }

    /// The view at `time` (frames from the frame's time): the rest view moved by the keyframes.
    #[inline]
    pub fn view_at(&self, time: f32) -> View {
        let Some(motion) = &self.motion else {
            return self.view;
        };
        let m = motion.at(time);
        let v = &self.view;
        View {
            position: m.point_to_world(v.position),
            forward: m.rotation * v.forward,
            right: m.rotation * v.right,
            up: m.rotation * v.up,
        }
    }

    /// The same camera with its field of view measured along `axis` instead of the height.
    pub fn with_fov_axis(mut self, axis: FovAxis) -> Camera {
        if axis == FovAxis::Horizontal {
            // `new` stored tan(fov/2) as the vertical half-extent.
            self.tan_half_fov /= self.width as f32 / self.height as f32;
        }
        self
    }

    /// The same camera with a thin lens of `aperture_radius` focused at `focus_distance`.
    pub fn with_lens(mut self, aperture_radius: f32, focus_distance: f32) -> Camera {
        self.aperture_radius = aperture_radius;
        self.focus_distance = focus_distance;
        self
    }

    /// The same camera with pixels weighing the film by `filter`.
    pub fn with_filter(mut self, filter: PixelFilter) -> Camera {
        self.filter = filter;
        self
    }

    /// The film point of pixel `(x, y)` for `u` ∈ [0,1)², as an offset
    /// from the pixel's corner (the pixel filter's sample).
    #[inline]
    pub fn pixel_offset(&self, x: u32, y: u32, u: Vec2) -> Vec2 {
        self.filter.offset(x, y, (self.width, self.height), u)
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// True when rays need a lens sample (aperture radius above 0).
    pub fn has_lens(&self) -> bool {
        self.aperture_radius > 0.0
    }

    /// The pinhole ray through pixel `(x, y)` at sub-pixel offset `u` ∈ [0,1)² (row 0 at the top).
    pub fn generate_ray(&self, x: u32, y: u32, u: Vec2) -> Ray {
        self.pinhole_ray(&self.view, x, y, u)
    }

    /// [`Camera::generate_ray`] from the view at `time`; the ray carries `time`.
    pub fn generate_ray_at(&self, x: u32, y: u32, u: Vec2, time: f32) -> Ray {
        let mut ray = self.pinhole_ray(&self.view_at(time), x, y, u);
        ray.time = time;
        ray
    }

    fn pinhole_ray(&self, view: &View, x: u32, y: u32, u: Vec2) -> Ray {
        let View {
            position,
            forward,
            right,
            up,
        } = *view;
        let ndc_x = ((x as f32 + u.x) / self.width as f32) * 2.0 - 1.0;
        let ndc_y = 1.0 - ((y as f32 + u.y) / self.height as f32) * 2.0;
        let aspect = self.width as f32 / self.height as f32;
        let dir = forward
            + right * (ndc_x * self.tan_half_fov * aspect)
            + up * (ndc_y * self.tan_half_fov);
        Ray::new(position, dir.normalize())
    }

    /// The ray through pixel `(x, y)` at offset `u` leaving the lens at `u_lens` ∈ [0,1)².
    ///
    /// Every ray of one film point meets the others on the plane at
    /// `focus_distance`, so points there are sharp.
    pub fn generate_lens_ray(&self, x: u32, y: u32, u: Vec2, u_lens: Vec2) -> Ray {
        self.lens_ray(&self.view, x, y, u, u_lens)
    }

    fn lens_ray(&self, view: &View, x: u32, y: u32, u: Vec2, u_lens: Vec2) -> Ray {
        let pinhole = self.pinhole_ray(view, x, y, u);
        if !self.has_lens() {
            return pinhole;
        }
        let focus = pinhole.at(self.focus_distance / pinhole.direction.dot(view.forward));
        let d = warp::square_to_concentric_disk(u_lens) * self.aperture_radius;
        let origin = view.position + view.right * d.x + view.up * d.y;
        Ray::new(origin, (focus - origin).normalize())
    }

    /// A primary ray for pixel `(x, y)` drawn from `sampler`.
    ///
    /// The lens sample is drawn only with an aperture, so a pinhole camera
    /// consumes the same random numbers (and makes the same image) as before lenses existed.
    pub fn sample_ray(&self, x: u32, y: u32, sampler: &mut Sampler) -> Ray {
        self.sample_ray_from(&self.view, x, y, sampler)
    }

    /// [`Camera::sample_ray`] from the view at `time` (the same random numbers); the ray carries `time`.
    ///
    /// A still camera's ray is [`Camera::sample_ray`]'s bit for bit.
    pub fn sample_ray_at(&self, x: u32, y: u32, time: f32, sampler: &mut Sampler) -> Ray {
        let mut ray = if self.motion.is_some() {
            self.sample_ray_from(&self.view_at(time), x, y, sampler)
        } else {
            self.sample_ray_from(&self.view, x, y, sampler)
        };
        ray.time = time;
        ray
    }

    fn sample_ray_from(&self, view: &View, x: u32, y: u32, sampler: &mut Sampler) -> Ray {
        let u = self.pixel_offset(x, y, sampler.next_2d());
        if self.has_lens() {
            self.lens_ray(view, x, y, u, sampler.next_2d())
        } else {
            self.pinhole_ray(view, x, y, u)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_forward_and_corners_span_fov() {
        let cam = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 101, 101).unwrap();
        let r = cam.generate_ray(50, 50, Vec2::splat(0.5));
        assert!((r.direction - -Vec3::Z).length() < 1e-5);
        let top = cam.generate_ray(50, 0, Vec2::new(0.5, 0.0));
        // The top edge is 45° up for a 90° vertical fov.
        assert!((top.direction.y - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-3);
        assert!(Camera::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 40.0, 4, 4).is_none());
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 40.0, 4, 4).is_none());
    }

    #[test]
    fn horizontal_fov_spans_the_width() {
        let cam = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 200, 100)
            .unwrap()
            .with_fov_axis(FovAxis::Horizontal);
        let right_edge = cam.generate_ray(199, 50, Vec2::new(1.0, 0.0));
        // The right edge is 45° off axis; the top edge atan(0.5) up.
        assert!((right_edge.direction.x - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-3);
        let top = cam.generate_ray(100, 0, Vec2::new(0.0, 0.0)).direction;
        assert!((top.y / -top.z - 0.5).abs() < 1e-3, "{top}");
        let vertical = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 200, 100).unwrap();
        let top = vertical.generate_ray(100, 0, Vec2::ZERO).direction;
        assert!((top.y / -top.z - 1.0).abs() < 1e-3, "{top}");
    }

    #[test]
    fn zero_aperture_is_the_pinhole_bit_for_bit() {
        let pinhole =
            Camera::new(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y, 35.0, 64, 48).unwrap();
        let lens = pinhole.clone().with_lens(0.0, 2.5);
        let (mut a, mut b, mut c) = (
            Sampler::from_seed(3),
            Sampler::from_seed(3),
            Sampler::from_seed(3),
        );
        for i in 0..200 {
            let (x, y) = (i % 64, (i * 7) % 48);
            let ra = pinhole.generate_ray(x, y, a.next_2d());
            let rb = lens.sample_ray(x, y, &mut b);
            let rc = lens.generate_lens_ray(x, y, c.next_2d(), Vec2::new(0.9, 0.1));
            assert_eq!(ra.direction, rc.direction);
            assert_eq!(ra.origin, rb.origin);
            assert_eq!(ra.direction, rb.direction);
        }
        // Same stream position afterwards: no lens sample was drawn.
        assert_eq!(a.next_1d(), b.next_1d());
    }

    #[test]
    fn points_on_the_focus_plane_are_sharp_and_others_blur() {
        let focus = 3.0;
        let cam = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 40.0, 32, 32)
            .unwrap()
            .with_lens(0.2, focus);
        let mut s = Sampler::from_seed(5);
        for (x, y) in [(16, 16), (0, 0), (31, 5), (7, 30)] {
            let u = Vec2::new(0.3, 0.8);
            let pinhole = cam.generate_ray(x, y, u);
            let target = pinhole.at(focus / pinhole.direction.dot(-Vec3::Z));
            let mut spread_off_focus = 0.0f32;
            for _ in 0..64 {
                let r = cam.generate_lens_ray(x, y, u, s.next_2d());
                // Where the ray crosses the plane z = -focus.
                let on_plane = r.at((-focus - r.origin.z) / r.direction.z);
                assert!(
                    (on_plane - target).length() < 1e-5,
                    "{on_plane} vs {target}"
                );
                let near = r.at((-1.0 - r.origin.z) / r.direction.z);
                let pin_near = pinhole.at(-1.0 / pinhole.direction.z);
                spread_off_focus = spread_off_focus.max((near - pin_near).length());
            }
            // At z = -1 the lens ray is (1 - 1/3) of the way from its lens point to the focus.
            assert!(spread_off_focus > 0.1, "{spread_off_focus}");
        }
    }
}
