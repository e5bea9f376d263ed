//! The held-out check of issue 34: the shipped VDB smoke plume baked into a
//! light slab and seen from an outside camera the bake never used agrees
//! with path tracing that camera, in the image mean and in its bright
//! regions, with the noise of both sides measured in the test.

mod common;

use brume::math::color::Rgb;
use common::cli::brume;
use common::data::shipped_volume;
use std::path::Path;

/// The plume of `scenes/smoke.toml` without its ground (sun and sky only),
/// with the README's box around it; `{VDB}` is the shipped volume's path.
const PLUME: &str = r#"
[camera]
position = [1.2, 2.9, -3.4]
look_at = [0.0, 0.9, 0.0]
fov = 40.0
resolution = [64, 64]
[integrator]
max_depth = 32
[[light]]
type = "sun"
direction = [-1.0, -1.1, -0.7]
irradiance = [3.0, 2.85, 2.6]
[[light]]
type = "sky"
zenith = [0.25, 0.4, 0.8]
horizon = [0.6, 0.7, 0.8]
ground = [0.1, 0.1, 0.1]
[[medium]]
type = "vdb"
file = "{VDB}"
grid = "density"
density_scale = 20.0
albedo = [0.9, 0.9, 0.9]
phase = { type = "hg", g = 0.3 }
transform = { translate = [-1.02, 0.0, -1.0] }
"#;

/// The box baked (the README's) and a small grid: a few seconds of bake.
const SLAB: &str = "[slab]\nmin = [-0.75, 0.0, -0.72]\nmax = [0.74, 1.92, 0.72]\n\
                    spatial = 24\nangular = 8\n";

/// The same camera and sky looking at the baked slab instead of the medium.
fn view_scene(plume: &str) -> String {
    let head = plume.split("[[medium]]").next().unwrap();
    format!("{head}[[shape]]\ntype = \"slab\"\nfile = \"plume.slab\"\n")
}

/// Runs brume in `dir` and insists that it succeeded.
fn run(dir: &Path, args: &[&str]) {
    let out = brume().current_dir(dir).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "brume {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The grey (channel average) pixels of an EXR.
fn grey(path: &Path) -> Vec<f64> {
    let (_, _, pixels) = brume::film::image_io::read_exr(path).unwrap();
    pixels.iter().map(|p: &Rgb| p.average() as f64).collect()
}

/// Independent estimates of one image (the slab seen through bakes of
/// different seeds, or the path tracer's halves) and the standard error of
/// their average's mean over a region.
struct Estimates {
    images: Vec<Vec<f64>>,
    /// Whether pixels are independent within an image (the path tracer's
    /// are; a slab's are not: neighbouring pixels share records).
    independent_pixels: bool,
}

impl Estimates {
    /// The average image.
    fn average(&self) -> Vec<f64> {
        let n = self.images.len() as f64;
        (0..self.images[0].len())
            .map(|i| self.images.iter().map(|im| im[i]).sum::<f64>() / n)
            .collect()
    }

    /// Mean of the average image over `region`, and its standard error:
    /// from the spread of the images' region means when pixels are
    /// correlated, from the per-pixel spread summed over the region when
    /// they are independent.
    fn region(&self, region: &[usize]) -> (f64, f64) {
        let n = self.images.len() as f64;
        let px = region.len() as f64;
        let means: Vec<f64> = self
            .images
            .iter()
            .map(|im| region.iter().map(|&i| im[i]).sum::<f64>() / px)
            .collect();
        let mean = means.iter().sum::<f64>() / n;
        let avg = self.average();
        let var = if self.independent_pixels {
            let per_pixel: f64 = region
                .iter()
                .map(|&i| {
                    self.images
                        .iter()
                        .map(|im| (im[i] - avg[i]).powi(2))
                        .sum::<f64>()
                })
                .sum();
            per_pixel / (n - 1.0) / n / (px * px)
        } else {
            means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0) / n
        };
        (mean, var.sqrt())
    }
}

/// Renders `scene` (a file in `dir`) at `spp` with `seed` and returns its grey pixels.
fn render(dir: &Path, scene: &str, spp: u32, seed: u32) -> Vec<f64> {
    let out = format!("{scene}.{seed}.exr");
    let (spp, seed) = (spp.to_string(), seed.to_string());
    let args = ["render", "--quiet", scene, "--out", &out, "--spp", &spp];
    run(dir, &[&args[..], &["--seed", &seed]].concat());
    grey(&dir.join(out))
}

/// Bakes of the slab at different seeds, each of 2 samples per line.
const BAKES: u32 = 8;

/// The slab of the plume baked 8 times at 2 samples per line (seeds 1 to
/// 8), each viewed at 4 spp with one view seed: the lookup is linear in the
/// records, so the average view is the view of a 16-sample bake, and the
/// spread of the views measures its noise. The medium path traced at
/// 2 × 128 spp (seeds 1 and 2).
fn images(dir: &Path) -> (Estimates, Estimates) {
    let vdb = shipped_volume("smoke_plume.vdb");
    let plume = PLUME.replace("{VDB}", &vdb.display().to_string());
    std::fs::write(dir.join("bake.toml"), format!("{plume}{SLAB}")).unwrap();
    std::fs::write(dir.join("traced.toml"), &plume).unwrap();
    std::fs::write(dir.join("view.toml"), view_scene(&plume)).unwrap();
    let mut views = Vec::new();
    for seed in 1..=BAKES {
        let seed = seed.to_string();
        let bake = ["slab", "bake", "bake.toml", "--out", "plume.slab"];
        run(
            dir,
            &[&bake[..], &["--quiet", "--spp", "2", "--seed", &seed]].concat(),
        );
        views.push(render(dir, "view.toml", 4, 7));
    }
    let traced = [1, 2].map(|seed| render(dir, "traced.toml", 128, seed));
    let slab = Estimates {
        images: views,
        independent_pixels: false,
    };
    let traced = Estimates {
        images: traced.to_vec(),
        independent_pixels: true,
    };
    (slab, traced)
}

/// Pixels of `reference` in its brightest `fraction`.
fn brightest(reference: &[f64], fraction: f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..reference.len()).collect();
    order.sort_by(|&a, &b| reference[b].total_cmp(&reference[a]));
    order.truncate((reference.len() as f64 * fraction).round() as usize);
    order
}

/// A novel view of the baked plume (behind and above it, where the bake's
/// camera never looked) against path tracing it: the image mean within 3 %
/// and the mean over the reference's brightest 10 % of pixels within 10 %
/// (the issue's bars). Each bar is checked to exceed the k-sigma noise of
/// the difference (the bake's, from the spread of 8 bakes, and the
/// reference's), so a failure is the slab's bias (grid blur, a wrong
/// term), not noise. Measured: image +0.07 % (k-sigma noise 2.7 %),
/// brightest 10 % −5.5 % (k-sigma noise 7.1 %: the grid blurs the peaks).
#[test]
fn baked_vdb_plume_agrees_with_path_tracing_a_novel_view() {
    let dir = tempfile::tempdir().unwrap();
    let (slab, traced) = images(dir.path());
    let all: Vec<usize> = (0..traced.images[0].len()).collect();
    let bright = brightest(&traced.average(), 0.1);
    let k = common::k_sigma(2);
    for (name, region, bar) in [("image", &all, 0.03), ("brightest 10 %", &bright, 0.10)] {
        let (s, s_se) = slab.region(region);
        let (t, t_se) = traced.region(region);
        let noise = k * (s_se.powi(2) + t_se.powi(2)).sqrt() / t;
        let error = s / t - 1.0;
        eprintln!("{name}: slab {s:.5} ± {s_se:.5}, traced {t:.5} ± {t_se:.5}, relative error {error:+.4}, k·noise {noise:.4}");
        assert!(
            noise <= bar,
            "{name}: noise bound {noise:.4} too large for the bar {bar}"
        );
        assert!(
            error.abs() <= bar,
            "{name}: slab mean {s:.5} vs path traced {t:.5} ({error:+.4}, bar {bar})"
        );
    }
}
