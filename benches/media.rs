//! Tracking through the smoke plume with the majorant grid vs one global
//! majorant: ratio-tracking transmittance and free-flight sampling (ns per
//! ray), plus steps per ray and the fraction of null collisions, printed
//! once before the timings: `cargo bench --bench media`.

use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use brume::integrator::tracking::{ratio_tracking, sample_free_flight, Tracker};
use brume::math::color::Rgb;
use brume::math::{Affine3A, Ray, Vec3};
use brume::medium::{
    GridEmission, GridMedium, GridMediumParams, MajorantMode, Medium, PhaseFunction,
};
use brume::sampling::Sampler;
use brume::volume::load_float_grid;
use criterion::{criterion_group, criterion_main, Criterion};

/// The smoke medium of scenes/smoke.toml (density_scale 20) with the given majorant.
fn smoke(majorant: MajorantMode, cell_size: Option<i32>) -> Medium {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("volumes/smoke_plume.vdb");
    let grid = load_float_grid(&path, "density").expect("smoke_plume.vdb");
    Medium::Grid(Arc::new(GridMedium::new(
        grid,
        GridMediumParams {
            to_world: Affine3A::IDENTITY,
            density_scale: 20.0,
            sigma_t_scale: Rgb::WHITE,
            albedo: Rgb::splat(0.9),
            phase: PhaseFunction::Isotropic,
            emission: GridEmission::None,
            majorant,
            cell_size,
        },
    )))
}

/// Rays from a sphere of radius 3 around the plume towards random points of its bounding box.
fn rays(n: usize) -> Vec<Ray> {
    let mut sampler = Sampler::from_seed(0x5eed);
    let (lo, hi) = (Vec3::new(0.32, 0.02, 0.32), Vec3::new(1.72, 1.88, 1.70));
    let centre = 0.5 * (lo + hi);
    (0..n)
        .map(|_| {
            let u = sampler.next_2d();
            let z = 1.0 - 2.0 * u.x;
            let r = (1.0 - z * z).sqrt();
            let phi = std::f32::consts::TAU * u.y;
            let origin = centre + 3.0 * Vec3::new(r * phi.cos(), z, r * phi.sin());
            let target =
                lo + (hi - lo) * Vec3::new(sampler.next_1d(), sampler.next_1d(), sampler.next_1d());
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

/// Mean segments, tentative collisions and null fraction of free flights (delta tracking), and ns per ray.
fn stats(medium: &Medium, rays: &[Ray]) -> (f64, f64, f64, f64) {
    let (mut segments, mut steps, mut nulls) = (0usize, 0usize, 0usize);
    let start = Instant::now();
    for (i, ray) in rays.iter().enumerate() {
        let mut sampler = Sampler::new(1, 0, 0, i as u64);
        segments += medium.majorants(ray, f32::INFINITY).count();
        let mut tracker = Tracker::new(medium, ray, f32::INFINITY);
        while let Some(c) = tracker.next(&mut sampler) {
            steps += 1;
            let p = medium.properties(ray.at(c.t), ray.time);
            if sampler.next_1d() < (p.sigma_a + p.sigma_s).max_channel() / c.sigma_maj {
                break;
            }
            nulls += 1;
        }
    }
    let ns = start.elapsed().as_nanos() as f64 / rays.len() as f64;
    let n = rays.len() as f64;
    (
        segments as f64 / n,
        steps as f64 / n,
        nulls as f64 / steps.max(1) as f64,
        ns,
    )
}

fn media(c: &mut Criterion) {
    let rays = rays(4096);
    let configs = [
        ("grid", smoke(MajorantMode::Grid, None)),
        ("global", smoke(MajorantMode::Global, None)),
    ];
    println!(
        "free flight (delta tracking) on smoke_plume.vdb, density_scale 20, {} rays:",
        rays.len()
    );
    println!("  majorant        cells  segments/ray  collisions/ray  null fraction  ns/ray");
    for (name, cell) in [
        ("grid 4", Some(4)),
        ("grid 8", Some(8)),
        ("grid 16", Some(16)),
        ("grid 32", Some(32)),
    ] {
        let m = smoke(MajorantMode::Grid, cell);
        let Medium::Grid(g) = &m else { unreachable!() };
        let (s, k, f, ns) = stats(&m, &rays);
        println!(
            "  {name:<12} {:>8}  {s:>12.2}  {k:>14.2}  {f:>13.3}  {ns:>6.0}",
            g.majorant_grid().dims().element_product()
        );
    }
    let (s, k, f, ns) = stats(&configs[1].1, &rays);
    println!(
        "  {:<12} {:>8}  {s:>12.2}  {k:>14.2}  {f:>13.3}  {ns:>6.0}",
        "global", 1
    );
    for (name, medium) in &configs {
        let mut i = 0usize;
        c.bench_function(&format!("ratio tracking smoke {name}"), |b| {
            b.iter(|| {
                i = (i + 1) % rays.len();
                let mut sampler = Sampler::new(2, 0, 0, i as u64);
                black_box(ratio_tracking(
                    medium,
                    &rays[i],
                    f32::INFINITY,
                    &mut sampler,
                ))
            })
        });
        let mut i = 0usize;
        c.bench_function(&format!("free flight smoke {name}"), |b| {
            b.iter(|| {
                i = (i + 1) % rays.len();
                let mut sampler = Sampler::new(3, 0, 0, i as u64);
                let (mut beta, mut radiance) = (Rgb::WHITE, Rgb::BLACK);
                black_box(sample_free_flight(
                    std::slice::from_ref(medium),
                    &rays[i],
                    f32::INFINITY,
                    &mut beta,
                    &mut radiance,
                    &mut sampler,
                ))
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    targets = media
}
criterion_main!(benches);
