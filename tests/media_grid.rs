//! Grid (VDB) media against closed forms: the constant-density box against
//! the homogeneous medium, a procedural linear ramp against
//! T = exp(-(a d + b d²/2)), every transmittance estimator and free-flight
//! sampling, with the majorant grid and with one global majorant.
//! Tolerances are the shared `assert_estimate` (tests/common/stats.rs; fixed seeds).

mod common;

use brume::integrator::tracking::{medium_transmittance, FreeFlight};
use brume::integrator::TransmittanceEstimator;
use brume::math::color::Rgb;
use brume::math::{Affine3A, Bounds3, Quat, Ray, Vec3};
use brume::medium::{
    GridEmission, GridMedium, GridMediumParams, HomogeneousMedium, MajorantMode, Medium,
    PhaseFunction, Region,
};
use brume::sampling::Sampler;
use brume::volume::{FloatGrid, GridTransform};
use common::{assert_estimate, free_flight, scene_from_str, Accumulator, Estimate, SceneText};
use glam::{DVec3, IVec3};
use std::sync::Arc;

const ESTIMATORS: [TransmittanceEstimator; 3] = [
    TransmittanceEstimator::Delta,
    TransmittanceEstimator::Ratio,
    TransmittanceEstimator::ResidualRatio,
];

/// Mean transmittance of `n` independent estimates.
fn transmittance(
    m: &Medium,
    ray: &Ray,
    t_max: f32,
    e: TransmittanceEstimator,
    n: usize,
) -> Estimate {
    let mut acc = Accumulator::default();
    for i in 0..n {
        let mut sampler = Sampler::new(17, 3, 5, i as u64);
        acc.add(medium_transmittance(m, ray, t_max, e, &mut sampler));
    }
    acc.estimate()
}

/// Mean weight of free flights that pass `t_max` (spectral tracking): also T.
fn free_flight_transmittance(m: &Medium, ray: &Ray, t_max: f32, n: usize) -> Estimate {
    let mut acc = Accumulator::default();
    for i in 0..n {
        let mut sampler = Sampler::new(29, 1, 2, i as u64);
        let (flight, beta, _) = free_flight(std::slice::from_ref(m), ray, t_max, &mut sampler);
        acc.add(match flight {
            FreeFlight::Passed => beta,
            _ => Rgb::BLACK,
        });
    }
    acc.estimate()
}

fn assert_close(e: &Estimate, expected: Rgb, what: &str) {
    let want = [expected.r as f64, expected.g as f64, expected.b as f64];
    assert_estimate(e, want, what);
}

/// Every estimator and free flight on every ray agree with `expected(ray, t_max)`.
fn check_all(
    m: &Medium,
    rays: &[(Ray, f32)],
    expected: impl Fn(&Ray, f32) -> Rgb,
    grey: bool,
    what: &str,
) {
    for (k, (ray, t_max)) in rays.iter().enumerate() {
        let want = expected(ray, *t_max);
        for e in ESTIMATORS {
            // Delta tracking decides real collisions on the max channel: grey media only.
            if e == TransmittanceEstimator::Delta && !grey {
                continue;
            }
            let est = transmittance(m, ray, *t_max, e, 20_000);
            assert_close(&est, want, &format!("{what} ray {k} {e:?}"));
        }
        let est = free_flight_transmittance(m, ray, *t_max, 20_000);
        assert_close(&est, want, &format!("{what} ray {k} free flight"));
    }
}

fn vdb_box(file: &str, majorant: &str, sigma_t_scale: &str) -> Medium {
    let text = SceneText::view([0.0, 0.0, 4.0], [0.0; 3]).medium(&format!(
        "type = \"vdb\"\nfile = \"tests/data/volumes/{file}\"\ndensity_scale = 2.0\n\
         sigma_t_scale = {sigma_t_scale}\nalbedo = 0.6\nmajorant = \"{majorant}\""
    ));
    let scene = scene_from_str(&text.build());
    scene.media[0].clone()
}

/// Rays through the unit box: axis-aligned, oblique, starting inside, ending
/// inside, missing. Each crosses the one-voxel trilinear fall-off only through
/// a face (never an edge), where it integrates like a step at the half voxel.
fn box_rays() -> Vec<(Ray, f32)> {
    let c = 15.5 / 32.0;
    let oblique = Vec3::new(1.0, 0.25, 0.35).normalize();
    vec![
        (Ray::new(Vec3::new(-1.0, c, c), Vec3::X), 3.0),
        (Ray::new(Vec3::new(0.3, -1.0, 0.7), Vec3::Y), 3.0),
        (Ray::new(Vec3::splat(c) - 2.0 * oblique, oblique), 4.0),
        (
            Ray::new(
                Vec3::new(0.3, 0.6, 0.5),
                Vec3::new(-0.3, 0.5, 0.8).normalize(),
            ),
            2.0,
        ),
        (Ray::new(Vec3::new(-0.5, 0.4, 0.45), Vec3::X), 1.0),
        (Ray::new(Vec3::new(0.5, 2.0, 0.5), Vec3::X), 3.0),
    ]
}

/// The homogeneous medium with the same σt: a box from -0.5 to 31.5 voxels.
fn homogeneous_box(sigma_t: Rgb) -> HomogeneousMedium {
    HomogeneousMedium {
        sigma_a: sigma_t * 0.4,
        sigma_s: sigma_t * 0.6,
        emission: Rgb::BLACK,
        phase: PhaseFunction::Isotropic,
        region: Region::Box {
            world_to_local: Affine3A::IDENTITY,
            local: Bounds3::new(Vec3::splat(-0.5 / 32.0), Vec3::splat(31.5 / 32.0)),
        },
    }
}

#[test]
fn constant_box_matches_homogeneous_transmittance() {
    for file in ["homogeneous_box.vdb", "homogeneous_box_tiles.vdb"] {
        for majorant in ["grid", "global"] {
            let m = vdb_box(file, majorant, "1.0");
            let h = homogeneous_box(Rgb::splat(2.0));
            let expected = |r: &Ray, t: f32| h.optical_depth(r, 0.0, t).exp_neg();
            check_all(
                &m,
                &box_rays(),
                expected,
                true,
                &format!("{file} {majorant}"),
            );
        }
    }
}

#[test]
fn chromatic_constant_box_matches_homogeneous_transmittance() {
    for majorant in ["grid", "global"] {
        let m = vdb_box("homogeneous_box.vdb", majorant, "[1.0, 0.25, 3.0]");
        let h = homogeneous_box(Rgb::new(2.0, 0.5, 6.0));
        let expected = |r: &Ray, t: f32| h.optical_depth(r, 0.0, t).exp_neg();
        check_all(
            &m,
            &box_rays(),
            expected,
            false,
            &format!("chromatic {majorant}"),
        );
    }
}

/// Density a + b·x on a 64×16×16 grid of voxel 1/16, placed by `to_world`.
fn ramp_medium(a: f32, b: f32, to_world: Affine3A, majorant: MajorantMode) -> Medium {
    let h = 1.0 / 16.0;
    let dims = IVec3::new(64, 16, 16);
    let mut values = Vec::new();
    for _z in 0..dims.z {
        for _y in 0..dims.y {
            for x in 0..dims.x {
                values.push(a + b * x as f32 * h);
            }
        }
    }
    let transform =
        GridTransform::scale_translate("UniformScaleMap", DVec3::splat(h as f64), DVec3::ZERO)
            .expect("transform");
    let grid =
        FloatGrid::from_dense("density", IVec3::ZERO, dims, &values, transform).expect("grid");
    let params = GridMediumParams {
        to_world,
        density_scale: 1.0,
        sigma_t_scale: Rgb::WHITE,
        albedo: Rgb::splat(0.8),
        phase: PhaseFunction::Isotropic,
        emission: GridEmission::None,
        majorant,
        cell_size: None,
    };
    Medium::Grid(Arc::new(GridMedium::new(grid, params)))
}

#[test]
fn linear_ramp_matches_closed_form() {
    let (a, b) = (0.05f32, 0.1f32);
    let s = 1.5f32;
    let to_world = Affine3A::from_scale_rotation_translation(
        Vec3::splat(s),
        Quat::from_rotation_y(0.4) * Quat::from_rotation_x(-0.2),
        Vec3::new(1.0, -2.0, 0.5),
    );
    // (start, unit direction, length) in the grid's own space, all inside the voxel-centre box.
    let local = [
        (Vec3::new(0.5, 0.5, 0.5), Vec3::X, 3.0f32),
        (
            Vec3::new(0.3, 0.2, 0.7),
            Vec3::new(1.0, 0.3, -0.25).normalize(),
            2.5,
        ),
        (
            Vec3::new(3.5, 0.4, 0.4),
            Vec3::new(-1.0, 0.1, 0.15).normalize(),
            3.0,
        ),
    ];
    // Outside the box of voxel centres, [0, 63h] × [0, 15h]², trilinear lookups fade
    // towards the background and σ is no longer a + b·x: the box is convex, so
    // both ends inside keep the whole ray inside.
    let centres = Bounds3::new(Vec3::ZERO, Vec3::new(63.0, 15.0, 15.0) / 16.0);
    for (k, &(q0, u, l)) in local.iter().enumerate() {
        for p in [q0, q0 + u * l] {
            assert!(
                (centres.min.cmple(p) & p.cmple(centres.max)).all(),
                "ray {k} leaves the voxel-centre box at {p}"
            );
        }
    }
    let rays: Vec<(Ray, f32)> = local
        .iter()
        .map(|&(q0, u, l)| {
            let d = to_world.transform_vector3(u).normalize();
            (Ray::new(to_world.transform_point3(q0), d), s * l)
        })
        .collect();
    // σ(t) = a + b·x(t), x(t) = q0.x + u.x·t/s along the world ray.
    let expected = |ray: &Ray, d: f32| {
        let q0 = to_world.inverse().transform_point3(ray.origin);
        let ux = to_world.inverse().transform_vector3(ray.direction).x;
        Rgb::splat((-((a + b * q0.x) * d + b * ux * d * d / 2.0)).exp())
    };
    for mode in [MajorantMode::Grid, MajorantMode::Global] {
        let m = ramp_medium(a, b, to_world, mode);
        check_all(&m, &rays, expected, true, &format!("ramp {mode:?}"));
    }
}

/// Sample variance of one estimator's transmittance on a ray (mean over channels).
fn variance(m: &Medium, ray: &Ray, e: TransmittanceEstimator, n: usize) -> f64 {
    let est = transmittance(m, ray, f32::INFINITY, e, n);
    (0..3)
        .map(|c| est.std_error[c].powi(2) * n as f64)
        .sum::<f64>()
        / 3.0
}

/// Ratio tracking has lower variance than delta tracking on the same rays through the smoke plume.
#[test]
fn ratio_tracking_beats_delta_tracking_variance() {
    let text = SceneText::view([0.0, 0.0, 4.0], [0.0; 3])
        .medium("type = \"vdb\"\nfile = \"volumes/smoke_plume.vdb\"\ndensity_scale = 4.0");
    let scene = scene_from_str(&text.build());
    let m = &scene.media[0];
    let (mut var_delta, mut var_ratio) = (0.0, 0.0);
    for (o, d) in [
        (Vec3::new(-1.0, 0.5, 1.0), Vec3::X),
        (Vec3::new(1.0, 0.8, -1.0), Vec3::Z),
        (
            Vec3::new(-1.0, -0.5, -1.0),
            Vec3::new(1.0, 1.0, 1.0).normalize(),
        ),
        (Vec3::new(1.0, 3.0, 1.0), -Vec3::Y),
    ] {
        let ray = Ray::new(o, d);
        var_delta += variance(m, &ray, TransmittanceEstimator::Delta, 20_000);
        var_ratio += variance(m, &ray, TransmittanceEstimator::Ratio, 20_000);
    }
    // Sample variances of 80k estimates are within a few per cent; ask for a clear factor.
    assert!(var_delta > 0.0, "the rays must cross the smoke");
    assert!(
        var_ratio < 0.8 * var_delta,
        "ratio variance {var_ratio} vs delta {var_delta}"
    );
}
