//! Exact voxel integration in grid media (`medium::voxel`, `tracking::exact`)
//! against closed forms: the optical depth of the trilinear field along a ray
//! by fine quadrature of the medium's own lookups, free-flight distances
//! against 1 - exp(-τ(t)), emission against (1 - α)·Le·(1 - T), and the
//! choice between exact walks and null collisions (`ExactVoxels::Auto`).
//! Tolerances are the shared `assert_estimate` (tests/common/stats.rs; fixed seeds).

mod common;

use brume::integrator::tracking::{
    medium_transmittance, take_thread_stats, FreeFlight, MAX_TENTATIVE_COLLISIONS,
};
use brume::integrator::TransmittanceEstimator;
use brume::math::color::Rgb;
use brume::math::{Affine3A, Quat, Ray, Vec3};
use brume::medium::{
    ExactVoxels, GridEmission, GridMedium, GridMediumParams, MajorantMode, Medium, PhaseFunction,
};
use brume::sampling::{mix64, Sampler};
use brume::volume::{FloatGrid, GridTransform};
use common::{assert_estimate, free_flight, Accumulator, Estimate};
use glam::{DVec3, IVec3};
use std::sync::Arc;

/// Voxel size of the test grids.
const H: f32 = 0.05;

fn hash(i: u64) -> f32 {
    (mix64(i) >> 40) as f32 / (1u64 << 24) as f32
}

/// A 24×20×18 grid of noisy values in `[lo, lo + 2)` at a negative origin, voxel `H`.
fn noisy_grid(lo: f32) -> FloatGrid {
    let dims = IVec3::new(24, 20, 18);
    let n = (dims.x * dims.y * dims.z) as u64;
    let values: Vec<f32> = (0..n).map(|i| lo + 2.0 * hash(i + 11)).collect();
    let t = GridTransform::scale_translate("UniformScaleMap", DVec3::splat(H as f64), DVec3::ZERO)
        .expect("transform");
    FloatGrid::from_dense("density", IVec3::new(-7, -3, -9), dims, &values, t).expect("grid")
}

/// A grid medium over `grid`, rotated and moved, with the given exact mode.
fn medium(
    grid: FloatGrid,
    density_scale: f32,
    sigma_t_scale: Rgb,
    emission: GridEmission,
    exact: ExactVoxels,
) -> (Arc<GridMedium>, Medium) {
    let params = GridMediumParams {
        to_world: to_world(),
        density_scale,
        sigma_t_scale,
        albedo: Rgb::splat(0.7),
        phase: PhaseFunction::Isotropic,
        emission,
        majorant: MajorantMode::Grid,
        cell_size: None,
    };
    let mut g = GridMedium::new(grid, params);
    g.set_exact_voxels(exact);
    let g = Arc::new(g);
    (g.clone(), Medium::Grid(g))
}

fn to_world() -> Affine3A {
    Affine3A::from_rotation_translation(
        Quat::from_rotation_y(0.3) * Quat::from_rotation_z(-0.2),
        Vec3::new(0.2, -0.1, 0.3),
    )
}

/// Rays through the grid (world space), each with its length: oblique, axis-aligned in the
/// grid's frame, starting inside, and one along a voxel plane.
fn rays() -> Vec<(Ray, f32)> {
    let m = to_world();
    let centre = Vec3::new(-0.35 + 0.6 * H, 0.35, 0.0);
    let grid_ray = |o: Vec3, d: Vec3, l: f32| {
        (
            Ray::new(m.transform_point3(o), m.transform_vector3(d.normalize())),
            l,
        )
    };
    vec![
        grid_ray(
            centre - Vec3::new(1.0, 0.3, 0.4),
            Vec3::new(1.0, 0.3, 0.4),
            2.5,
        ),
        grid_ray(Vec3::new(-0.6, 0.31, -0.1), Vec3::X, 2.0),
        grid_ray(centre, Vec3::new(-0.2, 0.9, 0.35), 1.0),
        grid_ray(Vec3::new(0.1, -0.5, 0.0), Vec3::Y, 2.0),
    ]
}

/// ∫σt along the ray by the midpoint rule over the medium's own (clamped) lookups.
fn optical_depth(g: &GridMedium, ray: &Ray, t_max: f32) -> Rgb {
    let n = 200_000;
    let dt = t_max as f64 / n as f64;
    let mut sum = 0.0f64;
    for i in 0..n {
        sum += g.density(ray.at(((i as f64 + 0.5) * dt) as f32)) as f64 * dt;
    }
    g.sigma_t_unit() * sum as f32
}

/// The mean of `n` transmittance samples; each must lie in [0, 1] (a
/// product of ratios against a true majorant, with roulette that lifts a
/// weight to at most its threshold), so a test's tolerance never comes
/// from a standard error that wild samples inflated.
fn transmittance(m: &Medium, ray: &Ray, t_max: f32, n: usize) -> Estimate {
    let mut acc = Accumulator::default();
    for i in 0..n {
        let mut sampler = Sampler::new(5, 7, 11, i as u64);
        let tr = medium_transmittance(m, ray, t_max, TransmittanceEstimator::Auto, &mut sampler);
        assert!(
            [tr.r, tr.g, tr.b].iter().all(|c| (0.0..=1.0).contains(c)),
            "sample {i}: {tr:?} outside [0, 1]"
        );
        acc.add(tr);
    }
    acc.estimate()
}

fn want(c: Rgb) -> [f64; 3] {
    [c.r as f64, c.g as f64, c.b as f64]
}

/// Above the roulette threshold the exact walk is deterministic: every channel
/// equals exp(-τ) from quadrature (chromatic σt; rotated grid, 4 rays).
#[test]
fn exact_transmittance_equals_quadrature() {
    let (g, m) = medium(
        noisy_grid(0.0),
        0.6,
        Rgb::new(1.0, 0.5, 2.0),
        GridEmission::None,
        ExactVoxels::Always,
    );
    for (k, (ray, t_max)) in rays().iter().enumerate() {
        let expected = optical_depth(&g, ray, *t_max).exp_neg();
        assert!(
            expected.min_channel() > 0.1,
            "ray {k} must stay above the roulette: {expected:?}"
        );
        let mut sampler = Sampler::new(1, 2, 3, 4);
        let got = medium_transmittance(&m, ray, *t_max, TransmittanceEstimator::Auto, &mut sampler);
        for c in 0..3 {
            assert!(
                (got[c] - expected[c]).abs() <= 2e-5 * expected[c],
                "ray {k} channel {c}: {} vs quadrature {}",
                got[c],
                expected[c]
            );
        }
    }
}

/// Dense rays (T down to 1e-3, Russian roulette on the exact product) and grids
/// with negative values (voxels clamped to 0 take ratio tracking inside the
/// cell): the mean is exp(-τ), in every mode.
#[test]
fn exact_transmittance_with_roulette_and_negative_voxels_is_unbiased() {
    for (lo, scale) in [(0.0, 5.0), (-0.8, 3.0)] {
        for exact in [ExactVoxels::Always, ExactVoxels::Auto] {
            let (g, m) = medium(
                noisy_grid(lo),
                scale,
                Rgb::new(1.0, 0.7, 1.3),
                GridEmission::None,
                exact,
            );
            for (k, (ray, t_max)) in rays().iter().enumerate() {
                let expected = optical_depth(&g, ray, *t_max).exp_neg();
                let est = transmittance(&m, ray, *t_max, 20_000);
                let what = format!("density from {lo}, scale {scale}, {exact:?}, ray {k}");
                assert_estimate(&est, want(expected), &what);
            }
        }
    }
}

/// Free flights through a grey noisy grid, without and with negative voxels,
/// follow the optical depth ([`assert_flights_follow_the_optical_depth`]).
#[test]
fn exact_free_flight_distances_follow_the_optical_depth() {
    for lo in [0.0, -0.8] {
        let (g, m) = medium(
            noisy_grid(lo),
            4.0,
            Rgb::WHITE,
            GridEmission::None,
            ExactVoxels::Always,
        );
        for (k, (ray, t_max)) in rays().iter().enumerate() {
            let cuts = [0.25 * t_max, 0.5 * t_max, *t_max];
            let what = format!("density from {lo}, ray {k}");
            assert_flights_follow_the_optical_depth(&g, &m, ray, *t_max, &cuts, lo < 0.0, &what);
        }
    }
}

/// Clamped cells (a negative corner: null collisions) before dense ones
/// (the exact walk), twice: the exact walk after a null-tracked span starts
/// from a fresh target in the same units, so the flights still follow
/// 1 - exp(-τ(t)) in the dense cells after each clamped stretch.
#[test]
fn free_flights_through_clamped_then_dense_cells_follow_the_optical_depth() {
    let grid = row_grid(16, |x| {
        if x < 4 || (10..12).contains(&x) {
            -0.5
        } else {
            1.0
        }
    });
    // The row spans t in [1, 1.8]: cuts in the first and second dense stretch.
    let cuts = [1.3, 1.45, 1.7];
    along_row_flights(grid, 5.0, ExactVoxels::Always, &cuts, "clamped, dense");
}

/// Free flights in `Auto` through thin cells (null collisions) then dense
/// ones (the exact walk), as the transmittance test below: each kind of
/// cell takes its own method, and the flights follow the optical depth.
#[test]
fn auto_free_flights_through_thin_then_dense_cells_follow_the_optical_depth() {
    let grid = row_grid(160, |x| if x < 156 { 0.002 } else { 1.0 });
    // Thin cells over t in [1, 8.8], dense ones to 9.
    let cuts = [5.0, 8.85, 8.95];
    let stats = along_row_flights(grid, 25.0, ExactVoxels::Auto, &cuts, "thin, dense");
    assert!(
        stats.collisions > 0 && stats.collisions < 20_000 && stats.voxel_steps > 0,
        "{stats:?}"
    );
}

/// 20 000 free flights along `ray`: they pass with weight 1 and probability
/// exp(-τ(t_max)), and scatter before each cut t with probability
/// 1 - exp(-τ(t)), with weight α and σt equal to the lookup at the
/// scattering point. Where `weights_vary` (cells tracked by null collisions)
/// the weighted versions: E[β·pass] = T and E[β/α·scatter before t] = 1 - exp(-τ(t)).
fn assert_flights_follow_the_optical_depth(
    g: &GridMedium,
    m: &Medium,
    ray: &Ray,
    t_max: f32,
    cuts: &[f32],
    weights_vary: bool,
    what: &str,
) {
    let mut before: Vec<Accumulator> = cuts.iter().map(|_| Accumulator::default()).collect();
    let mut passed = Accumulator::default();
    for i in 0..20_000u64 {
        let mut sampler = Sampler::new(9, 8, 7, i);
        let (f, beta, _) = free_flight(std::slice::from_ref(m), ray, t_max, &mut sampler);
        let (t, weight) = match f {
            FreeFlight::Scatter { t, properties, .. } => {
                // The lookups within a few f32 roundings of the point (steep
                // cells change σt by 10⁻⁴ over one rounding of t ≈ 9).
                let sigma_t = (properties.sigma_a + properties.sigma_s).r;
                let near = [1.0 - 2e-6, 1.0, 1.0 + 2e-6].map(|f| g.sigma_t(ray.at(t * f)).r);
                let (lo, hi) = (near[0].min(near[2]), near[0].max(near[2]));
                let slack = 1e-4 * hi.max(1.0);
                assert!(
                    (lo - slack..=hi + slack).contains(&sigma_t),
                    "{what}: σt {sigma_t} at the scattering point, lookups {near:?}"
                );
                if !weights_vary {
                    assert!((beta.r - 0.7).abs() < 1e-6, "{what}: weight {beta:?}");
                }
                passed.add(Rgb::BLACK);
                (t, beta / 0.7)
            }
            FreeFlight::Passed => {
                if !weights_vary {
                    assert_eq!(beta, Rgb::WHITE, "{what}");
                }
                passed.add(beta);
                (f32::INFINITY, Rgb::BLACK)
            }
            FreeFlight::Absorbed => {
                passed.add(Rgb::BLACK);
                (f32::INFINITY, Rgb::BLACK)
            }
        };
        for (acc, &cut) in before.iter_mut().zip(cuts) {
            acc.add(if t < cut { weight } else { Rgb::BLACK });
        }
    }
    let tr = optical_depth(g, ray, t_max).exp_neg();
    assert_estimate(&passed.estimate(), want(tr), &format!("{what}, passing"));
    for (acc, &cut) in before.iter().zip(cuts) {
        let p = Rgb::WHITE - optical_depth(g, ray, cut).exp_neg();
        let what = format!("{what}, P(scatter before {cut})");
        assert_estimate(&acc.estimate(), want(p), &what);
    }
}

/// Constant density σt with constant Le: a free flight from 0 to d collects
/// (1 - α)·Le·(1 - e^(-σt d)) on average (∫ T σa Le), exact or null-collision.
#[test]
fn exact_free_flight_emission_matches_closed_form() {
    let dims = IVec3::new(20, 20, 20);
    let values = vec![1.0f32; (dims.x * dims.y * dims.z) as usize];
    let t = GridTransform::scale_translate("UniformScaleMap", DVec3::splat(H as f64), DVec3::ZERO)
        .expect("transform");
    let le = Rgb::new(2.0, 1.0, 0.5);
    for exact in [ExactVoxels::Always, ExactVoxels::Never] {
        let grid =
            FloatGrid::from_dense("density", IVec3::ZERO, dims, &values, t.clone()).expect("grid");
        let (_, m) = medium(grid, 3.0, Rgb::WHITE, GridEmission::Constant(le), exact);
        // Inside the box of voxel centres (where the density is exactly 1), in world space.
        let o = to_world().transform_point3(Vec3::new(0.1, 0.5, 0.45));
        let d = to_world().transform_vector3(Vec3::new(1.0, 0.2, -0.1).normalize());
        let ray = Ray::new(o, d);
        let len = 0.7f32;
        let mut acc = Accumulator::default();
        for i in 0..20_000u64 {
            let mut sampler = Sampler::new(3, 1, 4, i);
            let (_, _, radiance) = free_flight(std::slice::from_ref(&m), &ray, len, &mut sampler);
            acc.add(radiance);
        }
        let expected = le * 0.3 * (1.0 - (-3.0f32 * len).exp());
        assert_estimate(&acc.estimate(), want(expected), &format!("{exact:?}"));
    }
}

/// Auto walks voxels exactly only where null collisions would be many: a thin
/// grid takes none, a dense one takes no tentative collisions (its voxels are ≥ 0).
#[test]
fn auto_walks_exactly_only_in_dense_cells() {
    let counts = |scale: f32| {
        let (_, m) = medium(
            noisy_grid(0.0),
            scale,
            Rgb::WHITE,
            GridEmission::None,
            ExactVoxels::Auto,
        );
        take_thread_stats();
        for (i, (ray, t_max)) in rays().iter().enumerate() {
            let mut sampler = Sampler::new(2, 2, 2, i as u64);
            medium_transmittance(&m, ray, *t_max, TransmittanceEstimator::Auto, &mut sampler);
            free_flight(std::slice::from_ref(&m), ray, *t_max, &mut sampler);
        }
        take_thread_stats()
    };
    // Voxel 0.05, density < 2: scale 1 gives at most 0.1 collisions per voxel, scale 1000 about 100.
    let thin = counts(1.0);
    assert!(thin.voxel_steps == 0 && thin.collisions > 0, "{thin:?}");
    let dense = counts(1000.0);
    assert!(dense.collisions == 0 && dense.voxel_steps > 0, "{dense:?}");
}

/// Work, not time (issue 11): the smoke plume at density_scale = 1e6, albedo 1,
/// costs medium lookups per sample (tentative collisions plus exact voxel
/// steps, as `brume render` reports them) within a small factor of a
/// homogeneous box of the same σt over the plume's bounds (at most 8×). With
/// null collisions only (before exact walks) it took about 1300 times the
/// homogeneous medium's lookups (4800 per sample against 3.7).
#[test]
fn dense_vdb_costs_about_what_the_homogeneous_medium_costs() {
    use brume::render::{render, RenderOptions};
    use std::sync::atomic::AtomicBool;
    let scene = |medium: &str| {
        let text = common::SceneText::camera([0.0, 1.0, 4.0], [0.0, 0.5, 0.0], [32, 24])
            .point_light([0.0, 3.0, 2.0], 20.0)
            .medium(medium);
        common::scene_from_str(&text.build())
    };
    let vdb = scene(
        "type = \"vdb\"\nfile = \"volumes/smoke_plume.vdb\"\ndensity_scale = 1e6\nalbedo = 1.0",
    );
    let homogeneous = scene(
        "type = \"homogeneous\"\nsigma_t = 1e6\nalbedo = 1.0\n\
         bounds = { type = \"box\", min = [0.31, 0.01, 0.31], max = [1.73, 1.89, 1.69] }",
    );
    let options = RenderOptions {
        spp: 16,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(1),
        progress: false,
    };
    let per_sample = |s: &brume::integrator::Scene| {
        let out = render(s, &options, &AtomicBool::new(false));
        assert_eq!(out.tracking.capped_rays, 0);
        out.tracking.lookups() as f64 / out.samples as f64
    };
    let (v, h) = (per_sample(&vdb), per_sample(&homogeneous));
    assert!(
        h > 1.0,
        "the homogeneous box is in view: {h} lookups per sample"
    );
    // Measured: 4.8× (18 voxel steps per sample against 3.7 collisions: the walk also
    // crosses the empty voxels of the 4-voxel majorant cells on the plume's rim).
    assert!(
        v <= 8.0 * h,
        "VDB {v:.2} lookups per sample, homogeneous {h:.2}"
    );
}

/// A render reports the rays the tracking cap ended, its own and no
/// others: a grid whose one dense voxel sets a global majorant of 10⁶ per
/// unit, tracked by null collisions only (no exact walk), ends every ray
/// through it at the cap, on two threads; the same grid walked exactly caps none.
#[test]
fn a_render_counts_the_rays_it_capped() {
    use brume::render::{render, RenderOptions};
    use std::sync::atomic::AtomicBool;
    let mut scene = common::scene_from_str(
        "[camera]\nposition = [4.0, 1.0, 10.0]\nlook_at = [4.0, 1.0, 0.0]\nfov = 5.0\nresolution = [4, 4]\n\
         [[light]]\ntype = \"point\"\nposition = [4.0, 5.0, 5.0]\nintensity = 1.0\n",
    );
    let options = RenderOptions {
        spp: 1,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(2),
        progress: false,
    };
    for (exact, capped) in [(ExactVoxels::Never, true), (ExactVoxels::Always, false)] {
        let grid = row_grid(16, |x| if x == 15 { 1.0 } else { 1e-6 });
        let params = GridMediumParams {
            to_world: Affine3A::from_scale(Vec3::splat(10.0)),
            density_scale: 1e5,
            sigma_t_scale: Rgb::WHITE,
            albedo: Rgb::splat(0.5),
            phase: PhaseFunction::Isotropic,
            emission: GridEmission::None,
            majorant: MajorantMode::Global,
            cell_size: None,
        };
        let mut g = GridMedium::new(grid, params);
        g.set_exact_voxels(exact);
        scene.media = vec![Medium::Grid(Arc::new(g))];
        let out = render(&scene, &options, &AtomicBool::new(false));
        match capped {
            true => assert!(
                out.tracking.capped_rays >= 16,
                "every camera ray is capped: {:?}",
                out.tracking
            ),
            false => assert_eq!(out.tracking.capped_rays, 0, "{:?}", out.tracking),
        }
    }
}

/// In `Auto` mode one ray can cross thin cells (ratio tracking) and then
/// dense ones (the exact walk): the transmittance is the product over all
/// of them, each segment picking up the weight the previous ones left.
/// A grid thin (density 0.002) for 156 voxels, dense (1) for the last 4, at
/// scale 25: 0.0025 and 1.25 expected collisions a voxel.
#[test]
fn auto_transmittance_through_thin_then_dense_cells_is_unbiased() {
    let grid = row_grid(160, |x| if x < 156 { 0.002 } else { 1.0 });
    let (est, expected, stats) = along_row_samples(grid, 25.0, ExactVoxels::Auto);
    // Both, each where it belongs: a fraction of a null collision a ray in
    // the thin cells, voxel steps in the cells around the dense voxels
    // (tracking those instead would take dozens of collisions a ray).
    assert!(
        stats.collisions > 0 && stats.collisions < ROW_SAMPLES as u64,
        "collisions: {stats:?}"
    );
    assert!(stats.voxel_steps > 0, "voxel steps: {stats:?}");
    assert_estimate(&est, want(expected), "thin then dense cells");
}

/// A grid `len`×4×4 voxels whose values vary along x only (`value(x)`).
fn row_grid(len: i32, value: impl Fn(i32) -> f32) -> FloatGrid {
    let dims = IVec3::new(len, 4, 4);
    let values: Vec<f32> = (0..dims.x * dims.y * dims.z)
        .map(|i| value(i % dims.x))
        .collect();
    let t = GridTransform::scale_translate("UniformScaleMap", DVec3::splat(H as f64), DVec3::ZERO)
        .expect("transform");
    FloatGrid::from_dense("density", IVec3::ZERO, dims, &values, t).expect("grid")
}

/// A world ray along the x rows of a [`row_grid`], between voxel centres, with its length.
fn along_row() -> (Ray, f32) {
    let frame = to_world();
    let ray = Ray::new(
        frame.transform_point3(Vec3::new(-1.0, 1.5 * H, 1.5 * H)),
        frame.transform_vector3(Vec3::X),
    );
    (ray, 10.0)
}

/// The exact walk counts its voxel steps against the same cap as
/// tentative collisions: a ray along a row of 70 000 voxels (density
/// 10⁻⁶, so its transmittance is about 1) is ended at the cap, after
/// exactly the cap's number of voxel steps; a shadow ray returns 0 and is
/// counted once, and a free flight ends the path, instead of walking on.
#[test]
fn an_exact_walk_past_the_step_cap_is_ended() {
    let grid = row_grid(70_000, |_| 1.0);
    let (_, m) = medium(
        grid,
        1e-6,
        Rgb::WHITE,
        GridEmission::None,
        ExactVoxels::Always,
    );
    let (ray, _) = along_row();
    let mut sampler = Sampler::from_seed(3);
    take_thread_stats();
    let tr = medium_transmittance(
        &m,
        &ray,
        f32::INFINITY,
        TransmittanceEstimator::Auto,
        &mut sampler,
    );
    assert_eq!(tr, Rgb::BLACK, "a capped shadow ray returns 0");
    let stats = take_thread_stats();
    assert_eq!(stats.voxel_steps, MAX_TENTATIVE_COLLISIONS as u64);
    assert_eq!(stats.capped_rays, 1);
    let (flight, throughput, _) =
        free_flight(std::slice::from_ref(&m), &ray, f32::INFINITY, &mut sampler);
    assert!(
        matches!(flight, FreeFlight::Absorbed) && throughput == Rgb::BLACK,
        "a capped free flight ends the path: {flight:?}, throughput {throughput:?}"
    );
}

/// Transmittance samples a [`row_grid`] test takes.
const ROW_SAMPLES: usize = 20_000;

/// [`ROW_SAMPLES`] transmittance samples along a [`row_grid`] at
/// `density_scale` (grey σt), the quadrature they should average to, and
/// what they cost.
fn along_row_samples(
    grid: FloatGrid,
    density_scale: f32,
    exact: ExactVoxels,
) -> (Estimate, Rgb, brume::integrator::tracking::TrackingStats) {
    let (g, m) = medium(grid, density_scale, Rgb::WHITE, GridEmission::None, exact);
    let (ray, t_max) = along_row();
    let expected = optical_depth(&g, &ray, t_max).exp_neg();
    take_thread_stats();
    let est = transmittance(&m, &ray, t_max, ROW_SAMPLES);
    (est, expected, take_thread_stats())
}

/// Free flights along a [`row_grid`] at `density_scale` (grey σt), checked
/// by [`assert_flights_follow_the_optical_depth`] at each of `cuts` and at
/// the ray's end (weights may vary: some cells are null-tracked), with what
/// they cost.
fn along_row_flights(
    grid: FloatGrid,
    density_scale: f32,
    exact: ExactVoxels,
    cuts: &[f32],
    what: &str,
) -> brume::integrator::tracking::TrackingStats {
    let (g, m) = medium(grid, density_scale, Rgb::WHITE, GridEmission::None, exact);
    let (ray, t_max) = along_row();
    let cuts: Vec<f32> = cuts.iter().copied().chain([t_max]).collect();
    take_thread_stats();
    assert_flights_follow_the_optical_depth(&g, &m, &ray, t_max, &cuts, true, what);
    take_thread_stats()
}

/// Dense, thin, then dense again (`Auto`): the exact walk of the second
/// dense run starts where that run starts, not where the first one
/// stopped, so the thin cells between them (optical depth about 0.7,
/// ratio-tracked) are not integrated a second time by the walk.
#[test]
fn auto_transmittance_through_dense_thin_dense_cells_is_unbiased() {
    let grid = row_grid(60, |x| if (2..58).contains(&x) { 0.01 } else { 1.0 });
    let (est, expected, stats) = along_row_samples(grid, 25.0, ExactVoxels::Auto);
    assert!(
        stats.collisions > 0,
        "the thin cells are tracked: {stats:?}"
    );
    assert!(stats.voxel_steps > 0, "the dense ones walked: {stats:?}");
    assert_estimate(&est, want(expected), "dense, thin, then dense cells");
}

/// Voxels alternating between 1 and −0.5 along the ray: every cell has a
/// negative corner, so the whole optical depth (about 2.3) lies in spans
/// the clamp makes non-cubic, where ratio tracking reads the density at
/// each tentative collision's own place in the span.
#[test]
fn transmittance_through_clamped_cells_only_is_unbiased() {
    let grid = row_grid(12, |x| if x % 2 == 0 { 1.0 } else { -0.5 });
    let (est, expected, stats) = along_row_samples(grid, 12.0, ExactVoxels::Always);
    assert!(stats.collisions > 0, "the clamped cells are tracked");
    assert_estimate(&est, want(expected), "clamped cells");
}
