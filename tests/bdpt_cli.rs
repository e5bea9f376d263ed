//! `brume render` with `[integrator] type = "bdpt"`: the bidirectional
//! estimator through the one film (splats in the EXR, thread-count
//! independent, split pieces merged with their splats), `--debug-strategies
//! DIR` (refused for the path tracer), and `scenes/mirror_beam.toml`, whose
//! reflected beam only the bidirectional estimator renders.

mod common;

use brume::film::image_io::{read_exr, read_film_exr};
use brume::math::color::Rgb;
use common::cli::{assert_refused, brume};
use common::k_sigma::k_sigma;
use std::path::Path;

/// A diffuse sphere and floor lit by a point light: light tracing (t = 1)
/// lands splats on most pixels.
const SCENE: &str = "[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [12, 8]\n[[light]]\ntype = \"point\"\nposition = [0.0, 3.0, 1.0]\nintensity = 5.0\n[[shape]]\ntype = \"sphere\"\nradius = 1.0\n[[shape]]\ntype = \"quad\"\ncenter = [0.0, -1.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nsize = [6.0, 6.0]\n";

fn write_scene(dir: &Path, kind: &str, spp: u32) -> std::path::PathBuf {
    let scene = dir.join("scene.toml");
    let text = format!("{SCENE}[integrator]\ntype = \"{kind}\"\nspp = {spp}\nseed = 5\n");
    std::fs::write(&scene, text).unwrap();
    scene
}

/// Runs `brume render --quiet SCENE --out dir/NAME.exr --png dir/NAME.png ARGS`; asserts success.
fn render(scene: &Path, name: &str, args: &[&str]) -> std::path::PathBuf {
    let dir = scene.parent().unwrap();
    let exr = dir.join(format!("{name}.exr"));
    let output = brume()
        .args(["render", "--quiet"])
        .arg(scene)
        .arg("--out")
        .arg(&exr)
        .arg("--png")
        .arg(dir.join(format!("{name}.png")))
        .args(args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{name}: {stderr}");
    exr
}

fn pixels(exr: &Path) -> Vec<Rgb> {
    read_exr(exr).unwrap().2
}

/// The same image, bit for bit, on one thread and on two, splats included.
#[test]
fn bdpt_renders_splats_independently_of_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "bdpt", 8);
    let one = render(&scene, "one", &["--threads", "1"]);
    let two = render(&scene, "two", &["--threads", "2"]);
    let film = read_film_exr(&one).unwrap();
    let splats = film.splats.as_ref().expect("a bdpt film keeps its splats");
    assert!(
        splats.sums.iter().filter(|&&v| v > 0.0).count() > 10,
        "light tracing splatted nothing"
    );
    assert!(pixels(&one).iter().any(|p| p.max_channel() > 0.0));
    // Pixels and splat sums, not the files' bytes: the EXR header's attribute order varies from run to run.
    let bits = |exr: &Path| -> Vec<u32> {
        pixels(exr)
            .iter()
            .flat_map(|p| [p.r, p.g, p.b].map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&one), bits(&two), "--threads 1 and --threads 2 differ");
    let splat_bits = |exr: &Path| -> Vec<u64> {
        let film = read_film_exr(exr).unwrap();
        film.splats
            .unwrap()
            .sums
            .iter()
            .map(|v| v.to_bits())
            .collect()
    };
    assert_eq!(splat_bits(&one), splat_bits(&two), "splat sums differ");
}

/// Two sample-range pieces merged give the whole render (splats merged).
#[test]
fn bdpt_pieces_merge_with_their_splats() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "bdpt", 8);
    let whole = render(&scene, "whole", &[]);
    let a = render(&scene, "a", &["--samples", "0..3"]);
    let b = render(&scene, "b", &["--samples", "3..8"]);
    let merged = dir.path().join("merged.exr");
    let output = brume()
        .arg("merge")
        .arg(&a)
        .arg(&b)
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for (i, (m, w)) in pixels(&merged).iter().zip(pixels(&whole)).enumerate() {
        for c in 0..3 {
            // The pieces store f32 means: merging is exact up to that rounding.
            let tol = 1e-5 * w[c].abs().max(1e-3);
            assert!(
                (m[c] - w[c]).abs() <= tol,
                "pixel {i}: merged {m:?}, whole {w:?}"
            );
        }
    }
}

/// The weighted strategy images sum to the render; each (s, t) has both images.
#[test]
fn debug_strategies_writes_images_that_sum_to_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "bdpt", 4);
    let strategies = dir.path().join("strategies");
    let exr = render(
        &scene,
        "beauty",
        &["--debug-strategies", strategies.to_str().unwrap()],
    );
    let beauty = pixels(&exr);
    let mut sum = vec![[0.0f64; 3]; beauty.len()];
    let mut names: Vec<String> = std::fs::read_dir(&strategies)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for name in names.iter().filter(|n| n.ends_with("_weighted.exr")) {
        let partner = name.replace("_weighted", "_unweighted");
        assert!(names.contains(&partner), "{partner} missing: {names:?}");
        for (s, p) in sum.iter_mut().zip(pixels(&strategies.join(name))) {
            for c in 0..3 {
                s[c] += p[c] as f64;
            }
        }
    }
    for expected in [
        "s0_t2_weighted.exr",
        "s1_t2_weighted.exr",
        "s2_t1_weighted.exr",
    ] {
        assert!(names.iter().any(|n| n == expected), "{expected}: {names:?}");
    }
    for (i, (s, b)) in sum.iter().zip(&beauty).enumerate() {
        for c in 0..3 {
            let tol = 1e-4 * (b[c] as f64).abs().max(1e-3);
            assert!(
                (s[c] - b[c] as f64).abs() <= tol,
                "pixel {i}: strategies sum to {s:?}, render {b:?}"
            );
        }
    }
}

#[test]
fn debug_strategies_is_refused_for_the_path_tracer() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "path", 1);
    let exr = dir.path().join("out.exr");
    std::fs::write(&exr, b"precious").unwrap();
    let output = brume()
        .args(["render", "--quiet"])
        .arg(&scene)
        .arg("--out")
        .arg(&exr)
        .arg("--debug-strategies")
        .arg(dir.path().join("strategies"))
        .output()
        .unwrap();
    assert_refused(&output, &["--debug-strategies", "bdpt"], "path tracer");
    assert_eq!(std::fs::read(&exr).unwrap(), b"precious");
    assert!(!dir.path().join("strategies").exists());
}

#[test]
fn unknown_integrator_types_are_scene_errors() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "metropolis", 1);
    let output = brume()
        .args(["render", "--quiet"])
        .arg(&scene)
        .arg("--out")
        .arg(dir.path().join("out.exr"))
        .output()
        .unwrap();
    assert_refused(
        &output,
        &["scene.toml: integrator.type: unknown integrator `metropolis`, expected path, bdpt, mlt or sppm"],
        "unknown type",
    );
}

/// Mean over the middle 8×8 pixels of a 48×32 render of
/// `scenes/mirror_beam.toml` (where the reflected beam rises) by `kind`, per seed.
fn beam_means(kind: &str, seeds: &[u64]) -> Vec<f64> {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mirror_beam.toml"),
    )
    .unwrap()
    .replace("resolution = [240, 160]", "resolution = [48, 32]")
    .replace("type = \"bdpt\"", &format!("type = \"{kind}\""));
    assert!(
        text.contains("[48, 32]") && text.contains(kind),
        "scene changed"
    );
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("mirror_beam.toml");
    std::fs::write(&scene, text).unwrap();
    seeds
        .iter()
        .map(|seed| {
            let exr = render(&scene, "beam", &["--spp", "8", "--seed", &seed.to_string()]);
            let image = pixels(&exr);
            let mut sum = 0.0;
            for y in 12..20 {
                for x in 20..28 {
                    sum += image[y * 48 + x].luminance() as f64;
                }
            }
            sum / 64.0
        })
        .collect()
}

/// Mean and standard error of independent estimates.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The reflected beam: brighter with bdpt than with the path tracer (which
/// only gets the fog's multiple scattering there) by more than k standard
/// errors of the difference, the errors from independent seeds.
#[test]
fn mirror_beam_scene_shows_the_reflected_beam_with_bdpt_only() {
    let seeds = [1, 2, 3, 4, 5, 6];
    let (bdpt, se_b) = mean_se(&beam_means("bdpt", &seeds));
    let (path, se_p) = mean_se(&beam_means("path", &seeds));
    let se = se_b.hypot(se_p);
    let k = k_sigma(1);
    eprintln!("beam region: bdpt {bdpt} ± {se_b}, path {path} ± {se_p}");
    assert!(
        bdpt - path > k * se,
        "bdpt {bdpt} ± {se_b} vs path {path} ± {se_p}: no beam beyond {k} σ"
    );
}
