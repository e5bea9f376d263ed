//! Render throughput: radiance samples per second on small shipped-style scenes.

use brume::integrator::li;
use brume::sampling::Sampler;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::path::Path;

/// Paths per benchmark iteration: one sample for each of 32×32 pixels.
const PIXELS: u32 = 32;

fn bench_scene(c: &mut Criterion, name: &str, file: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    let scene = brume::scene::load(&path).expect("scene");
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut group = c.benchmark_group("render");
    group.throughput(Throughput::Elements((PIXELS * PIXELS) as u64));
    let mut pass = 0u64;
    group.bench_function(name, |b| {
        b.iter(|| {
            pass += 1;
            let mut sum = 0.0f32;
            for j in 0..PIXELS {
                for i in 0..PIXELS {
                    // Spread the probe pixels over the whole image.
                    let (x, y) = (i * w / PIXELS, j * h / PIXELS);
                    let mut sampler = Sampler::new(0, x, y, pass);
                    let ray = scene.camera.sample_ray(x, y, &mut sampler);
                    sum += li(&scene, ray, &mut sampler).luminance();
                }
            }
            sum
        })
    });
    group.finish();
}

fn benches(c: &mut Criterion) {
    bench_scene(c, "cornell", "scenes/cornell.toml");
}

criterion_group!(render_benches, benches);
criterion_main!(render_benches);
