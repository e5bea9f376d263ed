//! The one film through the render driver: splats from a test-only
//! splatting estimator land where it sends them, divided by the samples per
//! pixel of the render; they do not depend on the thread count; pieces of a
//! split render carry their splats (also those outside their crop) through
//! the EXR to `merge`; and the film keeps the squares of the beauty samples.

mod common;

use brume::film::{Film, Rect, SampleRange, Splat};
use brume::integrator::Scene;
use brume::math::color::Rgb;
use brume::render::{render_part_with, Estimator, Part, PathTracer, RenderOptions};
use brume::sampling::PixelStreams;
use common::scene_from_str;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

const W: u32 = 12;
const H: u32 = 8;

/// A 12×8 view of a diffuse sphere under a white sky, with `extra` TOML.
fn scene(extra: &str) -> Scene {
    sized_scene((W, H), extra)
}

/// [`scene`] at another resolution.
fn sized_scene((w, h): (u32, u32), extra: &str) -> Scene {
    scene_from_str(&format!(
        r#"
        [camera]
        position = [0.0, 0.0, 3.0]
        look_at = [0.0, 0.0, 0.0]
        fov = 50.0
        resolution = [{w}, {h}]
        [integrator]
        seed = 7
        [[light]]
        type = "environment"
        radiance = 1.0
        [[shape]]
        type = "sphere"
        center = [0.2, 0.0, 0.0]
        radius = 0.8
        material = {{ type = "diffuse", albedo = 0.5 }}
        {extra}
        "#
    ))
}

/// Every sample has radiance `r` (NaN for every fourth sample of the target
/// pixel, so its count falls short of the spp) and splats `c` onto display
/// pixel `target`.
struct ConstantSplatter {
    target: (u32, u32),
    c: f32,
    r: f32,
}

impl Estimator for ConstantSplatter {
    type Arena = ();
    fn arena(&self) {}
    fn splats(&self) -> bool {
        true
    }
    fn sample(
        &self,
        _: &Scene,
        pixel: (u32, u32),
        _: &PixelStreams,
        s: u32,
        _: &mut (),
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        splats.push(Splat {
            x: self.target.0,
            y: self.target.1,
            radiance: Rgb::new(self.c, 2.0 * self.c, 0.0),
        });
        match pixel == self.target && s % 4 == 3 {
            true => Rgb::splat(f32::NAN),
            false => Rgb::splat(self.r),
        }
    }
}

/// The path tracer's radiance, plus two splats per sample whose pixel and
/// value depend on the pixel and sample index; counts its samples in its arena.
struct VaryingSplatter;

impl Estimator for VaryingSplatter {
    type Arena = u64;
    fn arena(&self) -> u64 {
        0
    }
    fn splats(&self) -> bool {
        true
    }
    fn sample(
        &self,
        scene: &Scene,
        (x, y): (u32, u32),
        streams: &PixelStreams,
        s: u32,
        arena: &mut u64,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        *arena += 1;
        let l = PathTracer.sample(scene, (x, y), streams, s, &mut (), splats);
        let (w, h) = (scene.camera.width(), scene.camera.height());
        for k in 0..2 {
            splats.push(Splat {
                x: (x * 7 + s * 3 + k) % w,
                y: (y * 5 + s + k) % h,
                radiance: Rgb::new(spread(x + 3 * y + s + k), l.g * 0.3, 0.1),
            });
        }
        l
    }
}

/// Values over 61 binades: f64 sums of f32 values closer in size are exact
/// in any order, these are not, so the order of additions shows.
fn spread(i: u32) -> f32 {
    (1.0 + 1.0 / (1 + i) as f32) * 2f32.powi((i * 13 % 61) as i32 - 30)
}

fn options(spp: u32, threads: usize) -> RenderOptions {
    RenderOptions {
        spp,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(threads),
        progress: false,
    }
}

/// Renders `part` of `scene` with `estimator` at `spp` samples per pixel of the whole render.
fn render<E: Estimator>(
    scene: &Scene,
    estimator: &E,
    part: Part,
    spp: u32,
    threads: usize,
) -> Film {
    render_part_with(
        scene,
        estimator,
        &options(spp, threads),
        &part,
        &AtomicBool::new(false),
        None,
    )
    .film
}

fn whole(spp: u32) -> Part {
    Part {
        crop: Rect::full(W, H),
        samples: SampleRange::new(0, spp),
    }
}

/// Each of the W·H·spp samples splats c onto the target: the target reads
/// r + W·H·c (the splat sum over the spp, not over its own count of finite
/// samples, which is ¾ of it), every other pixel r. Values are dyadic, so the
/// sums are exact and the test compares bits.
#[test]
fn splats_are_divided_by_the_samples_per_pixel_of_the_render() {
    let scene = scene("");
    let est = ConstantSplatter {
        target: (3, 5),
        c: 0.25,
        r: 0.5,
    };
    // 40 spp: passes of 16, 16 and 8 samples.
    let film = render(&scene, &est, whole(40), 40, 2);
    let image = film.beauty_image();
    for y in 0..H {
        for x in 0..W {
            let v = image.pixels[(y * W + x) as usize];
            let splat = if (x, y) == (3, 5) {
                (W * H) as f32 * 0.25
            } else {
                0.0
            };
            assert_eq!(
                v,
                Rgb::new(0.5 + splat, 0.5 + 2.0 * splat, 0.5),
                "pixel {x},{y}"
            );
        }
    }
    assert_eq!(film.splats.as_ref().unwrap().dropped, 0);
    assert_eq!(film.counts[5 * W as usize + 3], 30);
}

/// 1, 2 and 3 threads give the same film: beauty, squares, AOVs and splat
/// sums, bit for bit. 40 rows: more work units per pass than the driver
/// runs at once with one thread, fewer than with three.
#[test]
fn the_film_does_not_depend_on_the_thread_count() {
    let (w, h) = (6, 40);
    let scene = sized_scene((w, h), "[film]\naovs = [\"alpha\", \"depth\", \"normal\"]");
    let part = Part {
        crop: Rect::full(w, h),
        samples: SampleRange::new(0, 40),
    };
    let films: Vec<Film> = [1, 2, 3]
        .into_iter()
        .map(|t| render(&scene, &VaryingSplatter, part, 40, t))
        .collect();
    assert_eq!(films[0].layers.len(), 4);
    assert!(films[0]
        .splats
        .as_ref()
        .unwrap()
        .sums
        .iter()
        .any(|&s| s > 0.0));
    assert_eq!(films[0], films[1]);
    assert_eq!(films[0], films[2]);
}

/// Writes `film` as `NAME.exr` in `dir` and reads it back, as `brume merge` does.
fn through_exr(dir: &std::path::Path, name: &str, film: &Film) -> (PathBuf, Film) {
    let path = dir.join(format!("{name}.exr"));
    brume::film::image_io::write_film_exr(&path, film).unwrap();
    let back = brume::film::image_io::read_film_exr(&path).unwrap();
    (path, back)
}

/// Crops (whose samples splat onto a pixel of another crop) and sample
/// ranges, written as EXRs and merged: the target reads r + W·H·c as in the
/// single render, bit for bit.
#[test]
fn split_pieces_carry_their_splats_through_merge() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene("");
    let est = ConstantSplatter {
        target: (10, 1),
        c: 0.125,
        r: 0.25,
    };
    let single = render(&scene, &est, whole(32), 32, 2).beauty_image().pixels;
    let crop = |x0, x1, y0, y1| Rect { x0, x1, y0, y1 };
    let crops = [crop(0, 5, 0, 8), crop(5, 12, 0, 3), crop(5, 12, 3, 8)];
    let ranges = [SampleRange::new(0, 5), SampleRange::new(5, 32)];
    let by_crop: Vec<Part> = crops
        .map(|crop| Part {
            crop,
            samples: SampleRange::new(0, 32),
        })
        .into();
    let by_samples: Vec<Part> = ranges
        .map(|samples| Part {
            crop: Rect::full(W, H),
            samples,
        })
        .into();
    for (split, parts) in [("crops", by_crop), ("samples", by_samples)] {
        let pieces: Vec<(PathBuf, Film)> = parts
            .iter()
            .enumerate()
            .map(|(i, part)| {
                let film = render(&scene, &est, *part, 32, 2);
                through_exr(dir.path(), &format!("{split}{i}"), &film)
            })
            .collect();
        let merged = brume::film::merge::merge(&pieces).unwrap().film;
        let (_, merged) = through_exr(dir.path(), &format!("{split}-merged"), &merged);
        assert_eq!(merged.beauty_image().pixels, single, "{split}");
    }
}

/// The film keeps each pixel's sum of squared samples, from which
/// `Film::variance` gives the variance of the pixel's mean.
#[test]
fn the_film_keeps_the_squares_of_the_beauty_samples() {
    let scene = scene("");
    let spp = 24;
    let film = render(&scene, &PathTracer, whole(spp), spp, 2);
    let squares = film.squares.as_ref().unwrap();
    let mut noisy = 0;
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let (mut sum, mut sq) = (0.0f64, 0.0f64);
            for s in 0..spp {
                let v = brume::render::pixel_sample(&scene, x, y, s).g as f64;
                sum += v;
                sq += v * v;
            }
            assert!(
                (squares[3 * i + 1] - sq).abs() <= 1e-12 * sq,
                "pixel {x},{y}"
            );
            let n = spp as f64;
            let expected = (sq - sum * sum / n) / (n - 1.0) / n;
            let var = film.variance(i, 1).unwrap();
            // Rounding of the squares' sum scales with the second moment over n.
            let rounding = 1e-12 * sq / n / n;
            assert!((var - expected).abs() <= rounding, "{var} vs {expected}");
            noisy += (var > 1e3 * rounding) as u32;
        }
    }
    assert!(noisy > 10, "the scene must be noisy ({noisy} pixels)");
}
