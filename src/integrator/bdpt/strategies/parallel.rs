//! Every strategy's images of a whole render, rows in parallel: what
//! `--debug-strategies DIR` writes. The images depend on the seed only:
//! each row's contributions are gathered on one thread in sample order and
//! rows are added in row order, whatever the number of threads.

use super::super::{run, BdptArena, Event};
use super::StrategyImage;
use crate::integrator::Scene;
use crate::math::color::Rgb;
use rayon::prelude::*;

/// f64 sums of one strategy's weighted and unweighted contributions.
struct Sums {
    s: usize,
    t: usize,
    /// Weighted r, g, b then unweighted r, g, b, per pixel of the span it covers.
    pixels: Vec<[f64; 6]>,
}

/// Index of strategy (s, t) in `list`, added with `n` zero pixels when new.
fn slot(list: &mut Vec<Sums>, s: usize, t: usize, n: usize) -> usize {
    match list.iter().position(|e| e.s == s && e.t == t) {
        Some(i) => i,
        None => {
            list.push(Sums {
                s,
                t,
                pixels: vec![[0.0; 6]; n],
            });
            list.len() - 1
        }
    }
}

fn add(p: &mut [f64; 6], weighted: Rgb, unweighted: Rgb) {
    let v = [
        weighted.r,
        weighted.g,
        weighted.b,
        unweighted.r,
        unweighted.g,
        unweighted.b,
    ];
    for (a, b) in p.iter_mut().zip(v) {
        *a += b as f64;
    }
}

/// One light-tracing contribution of a row, landing anywhere on the image.
struct SplatRecord {
    s: usize,
    pixel: usize,
    weighted: Rgb,
    unweighted: Rgb,
}

/// What one row's samples contribute: its camera strategies (row-wide sums)
/// and its splats in the order they were made.
struct Row {
    camera: Vec<Sums>,
    splats: Vec<SplatRecord>,
}

/// Samples `0..spp` of every pixel of row `y`.
fn row(scene: &Scene, y: u32, spp: u32, arena: &mut BdptArena) -> Row {
    let w = scene.camera.width();
    let mut out = Row {
        camera: Vec::new(),
        splats: Vec::new(),
    };
    for x in 0..w {
        let streams = scene.settings.pixel_streams(x, y);
        for index in 0..spp {
            let mut record = |event: Event| match event {
                // The film leaves non-finite values out: so do these images.
                Event::Camera { c, .. } | Event::Splat { c, .. } if !c.weighted.is_finite() => {}
                Event::Camera { s, t, c } => {
                    let i = slot(&mut out.camera, s, t, w as usize);
                    add(
                        &mut out.camera[i].pixels[x as usize],
                        c.weighted,
                        c.unweighted,
                    );
                }
                Event::Splat { s, x, y, c } => out.splats.push(SplatRecord {
                    s,
                    pixel: (y * w + x) as usize,
                    weighted: c.weighted,
                    unweighted: c.unweighted,
                }),
            };
            run(scene, x, y, &streams, index, arena, &mut record);
        }
    }
    out
}

/// Every strategy's images over samples `0..spp` of every pixel, divided by
/// `spp` (the weighted images sum to the render), sorted by (segments, s).
/// Runs in the current rayon pool; holds one row's splats per thread at a time.
pub fn render_strategies(scene: &Scene, spp: u32) -> Vec<StrategyImage> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let n = (w * h) as usize;
    let mut images: Vec<Sums> = Vec::new();
    let rows: Vec<u32> = (0..h).collect();
    for block in rows.chunks(rayon::current_num_threads().max(1)) {
        let done: Vec<Row> = block
            .par_iter()
            .map_init(BdptArena::new, |arena, &y| row(scene, y, spp, arena))
            .collect();
        for (r, &y) in done.iter().zip(block) {
            let start = (y * w) as usize;
            for sums in &r.camera {
                let i = slot(&mut images, sums.s, sums.t, n);
                let span = &mut images[i].pixels[start..start + w as usize];
                for (a, b) in span.iter_mut().zip(&sums.pixels) {
                    for c in 0..6 {
                        a[c] += b[c];
                    }
                }
            }
            for sp in &r.splats {
                let i = slot(&mut images, sp.s, 1, n);
                add(&mut images[i].pixels[sp.pixel], sp.weighted, sp.unweighted);
            }
        }
    }
    let scale = 1.0 / spp.max(1) as f64;
    let rgb = |p: &[f64]| Rgb::new(p[0] as f32, p[1] as f32, p[2] as f32);
    let mut out: Vec<StrategyImage> = images
        .into_iter()
        .map(|im| {
            let mean = |k: usize| -> Vec<Rgb> {
                im.pixels
                    .iter()
                    .map(|p| rgb(&[p[k] * scale, p[k + 1] * scale, p[k + 2] * scale]))
                    .collect()
            };
            StrategyImage {
                s: im.s,
                t: im.t,
                weighted: mean(0),
                unweighted: mean(3),
            }
        })
        .collect();
    out.sort_by_key(|im| (im.s + im.t, im.s));
    out
}
