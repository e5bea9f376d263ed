//! Velocity motion blur against closed forms, on media built in code.
//!
//! A homogeneous box of voxels moving at constant velocity: the
//! transmittance along a ray averaged over the shutter equals the 1-D
//! quadrature over the shutter of the closed-form transmittance of the box
//! at each time. The majorant over the shutter is conservative at every
//! tentative collision, and dilation is needed for that.

#[path = "analytic_support/mod.rs"]
mod analytic_support;
#[path = "voxel_box_support/mod.rs"]
mod voxel_box_support;

use std::sync::Arc;

use analytic_support::{assert_estimate, estimate};
use brume::integrator::tracking::{medium_transmittance, TransmittanceEstimator};
use brume::math::{Ray, Vec3};
use brume::medium::{GridMedium, Medium};
use brume::sampling::quadrature::gauss_legendre;
use brume::sampling::Sampler;
use brume::volume::FloatGrid;
use glam::IVec3;
use voxel_box_support::*;

/// The box of voxels 0..=7 on every axis, density 1.
fn box_medium(velocity: Option<(Vec3, [f32; 2])>) -> Medium {
    moving_medium(dense(IVec3::ZERO, IVec3::splat(8), 1.0), 4, velocity)
}

/// A medium over `density` (majorant cells of `cell` voxels), moving at constant `velocity` over a shutter.
fn moving_medium(density: FloatGrid, cell: i32, velocity: Option<(Vec3, [f32; 2])>) -> Medium {
    let motion = velocity.map(|(v, shutter)| constant_velocity(v, shutter));
    Medium::Grid(Arc::new(GridMedium::new_moving(
        density,
        params(cell),
        motion,
    )))
}

#[test]
fn moving_box_transmittance_is_the_shutter_average_of_the_closed_form() {
    // 9.6 m/s is 4 voxels per frame; over the shutter [0, 0.5] the box moves 2 voxels in +x
    let v = Vec3::new(9.6, 0.0, 0.0);
    let shutter = [0.0f32, 0.5];
    let medium = box_medium(Some((v, shutter)));
    let v_index = (v.x / FPS / H) as f64;
    let tau_across = (SIGMA * H * 8.0) as f64; // ∫ of the z profile: 7 + 2·½ voxels
                                               // qx = 8.5 lies outside the still box: only the motion brings density here
    for qx in [8.5f32, 7.5, 3.0] {
        let closed = |t: f64| (-tau_across * profile(qx as f64 - v_index * t)).exp();
        let (a, b) = (shutter[0] as f64, shutter[1] as f64);
        let expected = gauss_legendre(closed, a, b, 64) / (b - a);
        for estimator in [TransmittanceEstimator::Ratio, TransmittanceEstimator::Delta] {
            let est = estimate(40_000, 11, |s: &mut Sampler| {
                let t = shutter[0] + (shutter[1] - shutter[0]) * s.next_1d();
                medium_transmittance(&medium, &ray_at(qx, t), 3.0, estimator, s)
            });
            assert_estimate(&est, [expected; 3], &format!("qx {qx} {estimator:?}"));
        }
    }
}

#[test]
fn zero_velocity_tracks_bit_identically_to_the_still_medium() {
    let still = box_medium(None);
    let zero = box_medium(Some((Vec3::ZERO, [-0.5, 0.5])));
    for i in 0..2000u64 {
        let mut u = Sampler::new(5, 0, 0, i);
        let qx = -2.0 + 12.0 * u.next_1d();
        let t = u.next_1d() - 0.5;
        let (mut a, mut b) = (Sampler::new(9, 1, 1, i), Sampler::new(9, 1, 1, i));
        let ray = ray_at(qx, t);
        let ta = medium_transmittance(&still, &ray, 3.0, TransmittanceEstimator::Ratio, &mut a);
        let tb = medium_transmittance(&zero, &ray, 3.0, TransmittanceEstimator::Ratio, &mut b);
        assert_eq!(ta.r.to_bits(), tb.r.to_bits(), "ray {i}");
    }
}

/// Points along random rays at random times: (points, σt > σ̄ seen, σc > σt seen).
///
/// A point in no majorant segment has σ̄ = 0; the points cover the whole
/// ray, so a medium that reaches beyond its tracked box is caught too.
fn check_majorants(medium: &Medium, shutter: [f32; 2], centre: Vec3, size: f32) -> (u64, u64, u64) {
    let (mut n, mut over, mut under) = (0, 0, 0);
    for i in 0..3000u64 {
        let mut s = Sampler::new(21, 0, 0, i);
        let o = centre + (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5) * 3.0 * size;
        let target = centre + (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5) * size;
        let time = shutter[0] + (shutter[1] - shutter[0]) * s.next_1d();
        let ray = Ray {
            time,
            ..Ray::new(o, (target - o).normalize())
        };
        let segments: Vec<_> = medium.majorants(&ray, f32::INFINITY).collect();
        for _ in 0..64 {
            let t = 3.0 * size * s.next_1d();
            let seg = segments.iter().find(|g| g.t0 <= t && t < g.t1);
            let (maj, control) = seg.map_or((0.0, 0.0), |g| {
                (g.majorant_at(t), g.sigma_control.max_channel())
            });
            let p = medium.properties(ray.at(t), time);
            let sigma_t = p.sigma_a + p.sigma_s;
            n += 1;
            over += (sigma_t.max_channel() > maj) as u64;
            under += (control > sigma_t.min_channel() * (1.0 + 1e-5)) as u64;
        }
    }
    (n, over, under)
}

#[test]
fn the_dilated_majorant_bounds_every_collision_over_the_shutter() {
    // dense on one side (x < 8), light on the other, small cells: the motion
    // carries dense voxels into cells whose still bound is light
    let density = half_dense();
    let v = Vec3::new(9.6, -4.8, 2.4);
    let shutter = [-0.5, 0.5];
    let moving = moving_medium(density, 2, Some((v, shutter)));
    let (n, over, under) = check_majorants(&moving, shutter, Vec3::new(0.8, 0.4, 0.4), 1.6);
    assert!(n > 100_000, "{n} checks");
    assert_eq!((over, under), (0, 0), "{n} checks");
}
