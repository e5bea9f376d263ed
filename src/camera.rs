//! The pinhole camera and primary ray generation.

use crate::math::{Ray, Vec2, Vec3};

/// A pinhole camera with a vertical field of view.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_fov: f32,
    width: u32,
    height: u32,
}

impl Camera {
    /// A camera at `position` looking at `look_at`; `fov_degrees` spans the image height.
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
            position,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov: (fov_degrees.to_radians() * 0.5).tan(),
            width,
            height,
        })
    }

    /// Unit viewing direction (the camera's optical axis).
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The primary ray through pixel `(x, y)` at sub-pixel offset `u` ∈ [0,1)² (row 0 at the top).
    pub fn generate_ray(&self, x: u32, y: u32, u: Vec2) -> Ray {
        let ndc_x = ((x as f32 + u.x) / self.width as f32) * 2.0 - 1.0;
        let ndc_y = 1.0 - ((y as f32 + u.y) / self.height as f32) * 2.0;
        let aspect = self.width as f32 / self.height as f32;
        let dir = self.forward
            + self.right * (ndc_x * self.tan_half_fov * aspect)
            + self.up * (ndc_y * self.tan_half_fov);
        Ray::new(self.position, dir.normalize())
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
}
