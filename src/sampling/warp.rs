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

    /// The concentric map sends the square's centre to the disk's and the
    /// square's axes (where one of the two ratios is 0/0 or the early return
    /// decides) onto the disk's axes, at their own radius.
    #[test]
    fn the_concentric_map_keeps_centre_and_axes() {
        let cases = [
            ((0.5, 0.5), (0.0, 0.0)),
            ((0.5, 0.75), (0.0, 0.5)),
            ((0.75, 0.5), (0.5, 0.0)),
            ((0.5, 0.0), (0.0, -1.0)),
            ((0.0, 0.5), (-1.0, 0.0)),
        ];
        for ((ux, uy), (x, y)) in cases {
            let d = square_to_concentric_disk(Vec2::new(ux, uy));
            assert!(
                (d - Vec2::new(x, y)).length() < 1e-6,
                "({ux}, {uy}) -> {d}, expected ({x}, {y})"
            );
        }
    }

    /// The concentric map is continuous (its advantage over the polar map):
    /// points of the square 10⁻³ apart, across the diagonals where its two
    /// branches meet, land at most a few 10⁻³ apart on the disk.
    #[test]
    fn the_concentric_map_is_continuous_across_its_branches() {
        let step = 1e-3;
        let n = 200;
        for i in 0..=n {
            for j in 0..=n {
                let u = Vec2::new(i as f32, j as f32) * (1.0 / n as f32) * (1.0 - step);
                let here = square_to_concentric_disk(u);
                for du in [Vec2::new(step, 0.0), Vec2::new(0.0, step)] {
                    let there = square_to_concentric_disk(u + du);
                    // |∂/∂u| ≤ 2·√(1 + π²/16) ≈ 2.54 (o = 2u − 1; r = o_x, θ = π/4·o_y/o_x).
                    assert!(
                        (there - here).length() <= 3.2 * step,
                        "{u} -> {here}, {} -> {there}",
                        u + du
                    );
                }
            }
        }
    }

    /// Uniform barycentrics put a quarter of the samples in each of the four
    /// triangles cut by the edges' midpoints (one per corner, one in the
    /// middle): each half of the square must map onto its own half of the
    /// triangle with the same density.
    #[test]
    fn triangle_samples_fill_the_four_midpoint_triangles_equally() {
        let n = 100_000;
        let mut s = Sampler::from_seed(17);
        let mut counts = [0u32; 4];
        for _ in 0..n {
            let b = square_to_uniform_triangle(s.next_2d());
            let third = 1.0 - b.x - b.y;
            let cell = if b.x > 0.5 {
                0
            } else if b.y > 0.5 {
                1
            } else if third > 0.5 {
                2
            } else {
                3
            };
            counts[cell] += 1;
        }
        // Four binomial proportions at the suite's k (tests/common/k_sigma.rs).
        let tolerance = crate::suite_k::k_sigma(4) * (0.25 * 0.75 / n as f64).sqrt();
        for (cell, &c) in counts.iter().enumerate() {
            let p = c as f64 / n as f64;
            assert!((p - 0.25).abs() < tolerance, "triangle {cell}: {p}");
        }
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
