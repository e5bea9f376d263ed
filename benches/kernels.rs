//! The hot kernels of the bench scenes (scenes/bench), one criterion group each:
//! BVH closest-hit and shadow rays (rays/s), trilinear lookup (lookups/s), the
//! majorant DDA (cells/s), each transmittance estimator and free-flight
//! sampling (rays/s), and the exact voxel walk of dense cells beside null
//! collisions on the smoke at density_scale 1e6 (rays/s, voxel spans/s):
//! `cargo bench --bench kernels`.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use brume::integrator::tracking::{
    delta_tracking_transmittance, medium_transmittance, ratio_tracking, residual_ratio_tracking,
    sample_free_flight, TransmittanceEstimator,
};
use brume::integrator::Scene;
use brume::math::color::Rgb;
use brume::math::{Affine3A, Ray, Vec3};
use brume::medium::{
    ExactVoxels, GridEmission, GridMedium, GridMediumParams, MajorantMode, Medium, PhaseFunction,
};
use brume::sampling::Sampler;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::sync::Arc;

/// Rays per iteration of every benchmark.
const RAYS: usize = 1024;

fn scene(file: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/bench")
        .join(file);
    brume::scene::load(&path).expect("bench scene")
}

/// Camera rays through a 32×32 grid of pixels spread over the image.
fn camera_rays(scene: &Scene) -> Vec<Ray> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut sampler = Sampler::from_seed(0x5eed);
    (0..RAYS as u32)
        .map(|k| {
            let (x, y) = ((k % 32) * w / 32, (k / 32) * h / 32);
            scene.camera.generate_ray(x, y, sampler.next_2d())
        })
        .collect()
}

fn bvh(c: &mut Criterion) {
    let s = scene("b4_airlight_fog.toml");
    let rays = camera_rays(&s);
    // Shadow rays from the first hits toward the sun (against its travel direction).
    let to_sun = -Vec3::new(0.4, -0.7, -0.6).normalize();
    let shadows: Vec<Ray> = rays
        .iter()
        .filter_map(|r| s.geometry.intersect(r, f32::INFINITY))
        .map(|h| Ray::new(h.p + 1e-3 * h.geometric_normal, to_sun))
        .collect();
    let mut g = c.benchmark_group("bvh b4");
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("closest hit", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| s.geometry.intersect(r, f32::INFINITY).is_some())
                .count()
        })
    });
    g.throughput(Throughput::Elements(shadows.len() as u64));
    g.bench_function("shadow rays", |b| {
        b.iter(|| {
            shadows
                .iter()
                .filter(|r| s.geometry.occluded(r, f32::INFINITY))
                .count()
        })
    });
    g.finish();
}

/// The smoke of B3 and rays through it: camera rays that meet its box.
fn smoke() -> (Scene, Vec<Ray>) {
    let s = scene("b3_vdb_smoke.toml");
    let rays = camera_rays(&s)
        .into_iter()
        .filter(|r| s.media[0].majorants(r, f32::INFINITY).next().is_some())
        .collect();
    (s, rays)
}

fn lookups(c: &mut Criterion) {
    let (s, rays) = smoke();
    let Medium::Grid(m) = &s.media[0] else {
        panic!("B3 has a grid medium")
    };
    // Points along the rays, as tracking visits them.
    let points: Vec<Vec3> = rays
        .iter()
        .flat_map(|r| (0..16).map(move |k| r.at(3.0 + 0.1 * k as f32)))
        .collect();
    let mut g = c.benchmark_group("grid b3");
    g.throughput(Throughput::Elements(points.len() as u64));
    g.bench_function("trilinear density", |b| {
        b.iter(|| points.iter().map(|&p| m.density(black_box(p))).sum::<f32>())
    });
    let cells: usize = rays
        .iter()
        .map(|r| s.media[0].majorants(r, f32::INFINITY).count())
        .sum();
    g.throughput(Throughput::Elements(cells as u64));
    g.bench_function("majorant dda steps", |b| {
        b.iter(|| {
            rays.iter()
                .map(|r| s.media[0].majorants(black_box(r), f32::INFINITY).count())
                .sum::<usize>()
        })
    });
    g.finish();
}

type Estimator = fn(&Medium, &Ray, f32, &mut Sampler) -> Rgb;

fn estimators(c: &mut Criterion) {
    let (s, rays) = smoke();
    let medium = &s.media[0];
    let mut g = c.benchmark_group("transmittance b3");
    g.throughput(Throughput::Elements(rays.len() as u64));
    let auto: Estimator =
        |m, r, t, s| medium_transmittance(m, r, t, TransmittanceEstimator::Auto, s);
    let list: [(&str, Estimator); 4] = [
        ("auto (ratio; exact voxels in dense cells)", auto),
        ("ratio", ratio_tracking),
        ("residual ratio", residual_ratio_tracking),
        ("delta", delta_tracking_transmittance),
    ];
    for (name, f) in list {
        let mut pass = 0u64;
        g.bench_function(name, |b| {
            b.iter(|| {
                pass += 1;
                let mut sampler = Sampler::new(1, 0, 0, pass);
                rays.iter()
                    .map(|r| f(medium, r, f32::INFINITY, &mut sampler).r)
                    .sum::<f32>()
            })
        });
    }
    g.finish();
    let fog = scene("b4_airlight_fog.toml");
    let fog_rays = camera_rays(&fog);
    let mut g = c.benchmark_group("transmittance b4");
    g.throughput(Throughput::Elements(fog_rays.len() as u64));
    g.bench_function("closed form", |b| {
        let mut sampler = Sampler::new(1, 0, 0, 0);
        b.iter(|| {
            fog_rays
                .iter()
                .map(|r| {
                    let m = &fog.media[0];
                    medium_transmittance(m, r, 50.0, TransmittanceEstimator::Auto, &mut sampler).r
                })
                .sum::<f32>()
        })
    });
    g.finish();
}

fn free_flight(c: &mut Criterion) {
    let (s, rays) = smoke();
    let fog = scene("b4_airlight_fog.toml");
    let fog_rays = camera_rays(&fog);
    let mut g = c.benchmark_group("free flight");
    for (name, media, rays) in [
        ("b3 smoke", &s.media, &rays),
        ("b4 fog", &fog.media, &fog_rays),
    ] {
        g.throughput(Throughput::Elements(rays.len() as u64));
        let mut pass = 0u64;
        g.bench_function(name, |b| {
            b.iter(|| {
                pass += 1;
                let mut sampler = Sampler::new(2, 0, 0, pass);
                let mut scattered = 0usize;
                for r in rays.iter() {
                    let (mut beta, mut radiance) = (Rgb::WHITE, Rgb::BLACK);
                    let e = sample_free_flight(
                        media,
                        r,
                        f32::INFINITY,
                        &mut beta,
                        &mut radiance,
                        &mut sampler,
                    );
                    scattered +=
                        matches!(e, brume::integrator::tracking::FreeFlight::Scatter { .. })
                            as usize;
                }
                scattered
            })
        });
    }
    g.finish();
}

/// The smoke plume at density_scale 1e6, albedo 1 (issue 11), walked exactly or by null collisions.
fn dense_smoke(exact: ExactVoxels) -> Medium {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("volumes/smoke_plume.vdb");
    let grid = brume::volume::load_float_grid(&path, "density").expect("smoke_plume.vdb");
    let params = GridMediumParams {
        to_world: Affine3A::IDENTITY,
        density_scale: 1e6,
        sigma_t_scale: Rgb::WHITE,
        albedo: Rgb::WHITE,
        phase: PhaseFunction::Isotropic,
        emission: GridEmission::None,
        majorant: MajorantMode::Grid,
        // Null collisions only: the one-voxel cells the medium would get without exact walks.
        cell_size: (exact == ExactVoxels::Never).then_some(1),
    };
    let mut m = GridMedium::new(grid, params);
    m.set_exact_voxels(exact);
    Medium::Grid(Arc::new(m))
}

/// Rays from (0, 1, 4) toward the plume's box (the reliability scene's view).
fn dense_rays() -> Vec<Ray> {
    let mut sampler = Sampler::from_seed(0xde75e);
    let (lo, hi) = (Vec3::new(0.32, 0.02, 0.32), Vec3::new(1.72, 1.88, 1.70));
    let o = Vec3::new(0.0, 1.0, 4.0);
    (0..RAYS)
        .map(|_| {
            let u = Vec3::new(sampler.next_1d(), sampler.next_1d(), sampler.next_1d());
            Ray::new(o, (lo + (hi - lo) * u - o).normalize())
        })
        .collect()
}

fn dense(c: &mut Criterion) {
    let rays = dense_rays();
    let mut g = c.benchmark_group("dense smoke 1e6");
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    for (name, exact) in [("exact", ExactVoxels::Auto), ("null", ExactVoxels::Never)] {
        let m = dense_smoke(exact);
        let mut pass = 0u64;
        g.bench_function(format!("transmittance {name}"), |b| {
            b.iter(|| {
                pass += 1;
                let mut sampler = Sampler::new(3, 0, 0, pass);
                rays.iter()
                    .map(|r| {
                        medium_transmittance(
                            &m,
                            r,
                            10.0,
                            TransmittanceEstimator::Auto,
                            &mut sampler,
                        )
                        .r
                    })
                    .sum::<f32>()
            })
        });
        let media = [m.clone()];
        g.bench_function(format!("free flight {name}"), |b| {
            b.iter(|| {
                pass += 1;
                let mut sampler = Sampler::new(4, 0, 0, pass);
                rays.iter()
                    .map(|r| {
                        let (mut beta, mut radiance) = (Rgb::WHITE, Rgb::BLACK);
                        let e = sample_free_flight(
                            &media,
                            r,
                            10.0,
                            &mut beta,
                            &mut radiance,
                            &mut sampler,
                        );
                        matches!(e, brume::integrator::tracking::FreeFlight::Scatter { .. })
                            as usize
                    })
                    .sum::<usize>()
            })
        });
    }
    // The walk alone: every voxel span of the rays through the box (corner fetch and cubic).
    let Medium::Grid(m) = dense_smoke(ExactVoxels::Always) else {
        unreachable!()
    };
    let index_rays: Vec<(Vec3, Vec3, f32, f32)> = rays
        .iter()
        .filter_map(|r| {
            let segs = m.majorants(r, 10.0);
            let (o, d) = segs.index_ray();
            let ts: Vec<_> = segs.map(|s| (s.t0, s.t1)).collect();
            Some((o, d, ts.first()?.0, ts.last()?.1))
        })
        .collect();
    let spans: usize = index_rays
        .iter()
        .map(|&(o, d, t0, t1)| m.voxels(o, d, t0, t1).count())
        .sum();
    g.throughput(Throughput::Elements(spans as u64));
    g.bench_function("voxel spans", |b| {
        b.iter(|| {
            index_rays
                .iter()
                .map(|&(o, d, t0, t1)| {
                    m.voxels(black_box(o), d, t0, t1)
                        .map(|s| s.density.integral(1.0))
                        .sum::<f32>()
                })
                .sum::<f32>()
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = bvh, lookups, estimators, free_flight, dense
}
criterion_main!(benches);
