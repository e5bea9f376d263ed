//! Random-access trilinear lookups on smoke_plume.vdb (ns per lookup):
//! `cargo bench --bench volume_lookup`.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use brume::volume::load_float_grid;
use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;

/// Points spread over the active bounding box (padded by two voxels), from a fixed seed.
fn random_points(lo: Vec3, hi: Vec3, n: usize) -> Vec<Vec3> {
    let mut s = 0x1234_5678_9abc_def0u64;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|_| lo + (hi - lo) * Vec3::new(u(), u(), u()))
        .collect()
}

fn lookups(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("volumes/smoke_plume.vdb");
    let grid = load_float_grid(&path, "density").expect("smoke_plume.vdb");
    let (lo, hi) = grid.index_bbox_active().expect("active voxels");
    let points = random_points(lo.as_vec3() - 2.0, hi.as_vec3() + 2.0, 1 << 16);
    let mask = points.len() - 1;
    let mut i = 0usize;
    c.bench_function("trilinear_index random smoke_plume", |b| {
        b.iter(|| {
            i = (i + 1) & mask;
            black_box(grid.trilinear_index(black_box(points[i])))
        })
    });
    let world: Vec<_> = points
        .iter()
        .map(|p| grid.transform().index_to_world(p.as_dvec3()))
        .collect();
    c.bench_function("trilinear_world random smoke_plume", |b| {
        b.iter(|| {
            i = (i + 1) & mask;
            black_box(grid.trilinear_world(black_box(world[i])))
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = lookups
}
criterion_main!(benches);
