//! Warps from the unit square to common domains, each with its density.

use crate::math::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Uniform direction on the unit sphere.
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    crate::math::spherical_direction(z, 2.0 * PI * u.y)
}

/// Density of `square_to_uniform_sphere` (per steradian).
pub fn uniform_sphere_pdf() -> f32 {
    0.25 * FRAC_1_PI
}

/// Uniform point on the unit disk (Shirley–Chiu concentric map).
pub fn square_to_concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, std::f32::consts::FRAC_PI_4 * (o.y / o.x))
    } else {
        (
            o.y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (o.x / o.y),
        )
    };
    let (s, c) = theta.sin_cos();
    Vec2::new(r * c, r * s)
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method).
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of `square_to_cosine_hemisphere` for a local direction.
pub fn cosine_hemisphere_pdf(local: Vec3) -> f32 {
    local.z.max(0.0) * FRAC_1_PI
}

/// Uniform direction inside a cone of half-angle `acos(cos_max)` around +z.
pub fn square_to_uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_theta = 1.0 - u.x * (1.0 - cos_max);
    crate::math::spherical_direction(cos_theta, 2.0 * PI * u.y)
}

/// Density of `square_to_uniform_cone` (per steradian) inside the cone.
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Uniform barycentric coordinates (b1, b2) on a triangle.
pub fn square_to_uniform_triangle(u: Vec2) -> Vec2 {
    // Heitz 2019 low-distortion map: area preserving, no square root.
    if u.y > u.x {
        let b0 = u.x / 2.0;
        let b1 = u.y - b0;
        Vec2::new(b0, b1)
    } else {
        let b1 = u.y / 2.0;
        let b0 = u.x - b1;
        Vec2::new(b0, b1)
    }
}

/// Exponential free-flight distance with rate `sigma` for uniform `u` in [0, 1).
#[inline]
pub fn sample_exponential(u: f32, sigma: f32) -> f32 {
    -(1.0 - u).ln() / sigma
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    /// Monte Carlo integral of `pdf` over the sphere with uniform sphere samples.
    fn sphere_integral(pdf: impl Fn(Vec3) -> f32) -> f64 {
        let mut s = Sampler::from_seed(11);
        let n = 400_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let d = square_to_uniform_sphere(s.next_2d());
            sum += (pdf(d) / uniform_sphere_pdf()) as f64;
        }
        sum / n as f64
    }

    #[test]
    fn densities_integrate_to_one() {
        // Standard error of these estimates is below 0.005 for n = 4e5; 0.02 is > 4σ.
        assert!((sphere_integral(|_| uniform_sphere_pdf()) - 1.0).abs() < 1e-6);
        assert!((sphere_integral(cosine_hemisphere_pdf) - 1.0).abs() < 0.02);
        let cos_max = 0.8;
        let cone = |d: Vec3| {
            if d.z >= cos_max {
                uniform_cone_pdf(cos_max)
            } else {
                0.0
            }
        };
        assert!((sphere_integral(cone) - 1.0).abs() < 0.03);
    }

    #[test]
    fn warps_land_in_their_domains() {
        let mut s = Sampler::from_seed(3);
        for _ in 0..10_000 {
            let u = s.next_2d();
            assert!((square_to_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
            assert!(square_to_concentric_disk(u).length() <= 1.0 + 1e-6);
            let h = square_to_cosine_hemisphere(u);
            assert!(h.z >= 0.0 && (h.length() - 1.0).abs() < 1e-4);
            assert!(square_to_uniform_cone(u, 0.9).z >= 0.9 - 1e-6);
            let b = square_to_uniform_triangle(u);
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
        }
    }
}
