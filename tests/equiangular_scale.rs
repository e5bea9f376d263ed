//! Equiangular sampling is active on unbounded segments whatever the scene's
//! units: a point light in a global medium, scaled by k (lengths × k,
//! coefficients ÷ k, intensity × k²), gives the same radiance at every k, and
//! equiangular sampling lowers its standard error at every k.

mod common;

use brume::math::{Ray, Vec3};
use common::*;

/// A point light in a global scattering medium, every length × `k`.
fn scene_text(k: f64, equiangular: bool) -> String {
    SceneText::view([0.0, 0.0, 4.0 * k], [0.0; 3])
        .integrator(&format!(
            "max_depth = 8\nmax_scatter_depth = 1\nequiangular = {equiangular}"
        ))
        .point_light([0.0, 0.3 * k, 0.0], 2.0 * k * k)
        .medium(&format!(
            "type = \"homogeneous\"\nsigma_a = {:?}\nsigma_s = {:?}\n\
             phase = {{ type = \"hg\", g = 0.4 }}\nglobal = true",
            0.05 / k,
            0.2 / k
        ))
        .build()
}

#[test]
fn point_light_in_a_global_medium_is_scale_invariant() {
    let scales = [1e-2, 1.0, 1e2, 1e4];
    let mut estimates = Vec::new();
    for (i, &k) in scales.iter().enumerate() {
        let ray = Ray::new(Vec3::new(-5.0 * k as f32, 0.0, 0.0), Vec3::X);
        let with = estimate_ray(
            &scene_from_str(&scene_text(k, true)),
            ray,
            20_000,
            30 + i as u64,
        );
        let without = estimate_ray(
            &scene_from_str(&scene_text(k, false)),
            ray,
            20_000,
            40 + i as u64,
        );
        eprintln!(
            "scale {k}: equiangular {:.6} ± {:.6}, free flight {:.6} ± {:.6}",
            with.mean[0], with.std_error[0], without.mean[0], without.std_error[0]
        );
        assert!(
            with.std_error[0] < 0.5 * without.std_error[0],
            "scale {k}: equiangular standard error {} not below half of free flight's {}",
            with.std_error[0],
            without.std_error[0]
        );
        assert_same(
            &with,
            &without,
            &format!("scale {k}: with vs without equiangular"),
        );
        estimates.push(with);
    }
    let base = estimates[0];
    for (k, e) in scales.iter().zip(&estimates) {
        assert_same(e, &base, &format!("scale {k} vs scale {}", scales[0]));
    }
}
