//! Stochastic progressive photon mapping (`[integrator] type = "sppm"`):
//! closed forms through the whole driver (photon pass, grid, eye pass,
//! radius reduction, film), determinism, and the keys' errors.
//!
//! Each pass is one sample index with its own photon map and radius, and
//! passes are independent, so the spread of a pixel's passes gives the
//! standard error of its mean (module docs of `integrator::sppm`).

mod bdpt_support;
mod beam_support;

use bdpt_support::common::*;
use brume::film::Film;
use brume::integrator::Scene;
use brume::render::{render, RenderOptions};
use std::sync::atomic::AtomicBool;

/// Renders `passes` passes of `scene` on `threads` threads; the film.
fn sppm_film(scene: &Scene, passes: u32, threads: usize) -> Film {
    let options = RenderOptions {
        spp: passes,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(threads),
        progress: false,
    };
    render(scene, &options, &AtomicBool::new(false)).film
}

/// Per-pixel means and standard errors from the spread of the passes.
fn pixels(film: &Film) -> Vec<Estimate> {
    (0..film.counts.len())
        .map(|i| {
            let n = film.counts[i];
            let mean = std::array::from_fn(|c| film.layers[0].sums[3 * i + c] / n as f64);
            let std_error = std::array::from_fn(|c| film.variance(i, c).unwrap_or(0.0).sqrt());
            Estimate {
                mean,
                std_error,
                n: n as usize,
            }
        })
        .collect()
}

/// Prints the image mean and its standard error (for the report and failures).
fn report(what: &str, px: &[Estimate]) {
    let n = px.len() as f64;
    let mean: f64 = px.iter().map(|p| p.mean[1]).sum::<f64>() / n;
    let se = px
        .iter()
        .map(|p| p.std_error[1].powi(2))
        .sum::<f64>()
        .sqrt()
        / n;
    let worst = px.iter().map(|p| p.std_error[1]).fold(0.0, f64::max);
    eprintln!("{what}: image mean {mean:.5} ± {se:.5} (largest pixel se {worst:.4})");
}

const CAMERA_INSIDE: &str = "[camera]\nposition = [0.3, -0.2, 1.7]\nlook_at = [0.0, 0.0, 0.0]\nfov = 70.0\nresolution = [8, 8]\n";

/// Six inward-facing walls bounding [-2, 2]³ that emit 0.5 and reflect half
/// (diffuse albedo 0.5): radiance L = 0.5 + 0.5·L = 1 everywhere, and all
/// but the first bounce off a wall is indirect light, the photons' part.
fn room() -> String {
    let mut walls = String::new();
    for axis in 0..3 {
        for sign in [-1.0f64, 1.0] {
            let (mut center, mut normal) = ([0.0; 3], [0.0; 3]);
            center[axis] = 2.0 * sign;
            normal[axis] = -sign;
            walls += &format!(
                "[[shape]]\ntype = \"quad\"\ncenter = {center:?}\nnormal = {normal:?}\nsize = [4.0, 4.0]\nemission = 0.5\nmaterial = {{ type = \"diffuse\", albedo = 0.5 }}\n"
            );
        }
    }
    walls
}

const WHITE_SPHERE: &str = "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, -0.3, 0.0]\nradius = 0.8\nmaterial = { type = \"diffuse\", albedo = 1.0 }\n";

/// An albedo-1 medium filling the whole room (its box reaches past the walls).
const ROOM_MEDIUM: &str = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.7\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"box\", min = [-2.5, -2.5, -2.5], max = [2.5, 2.5, 2.5] }\n";

/// An albedo-1 medium in a box inside the room: eye segments cross its faces.
const BOX_MEDIUM: &str = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.7\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"box\", min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }\n";

fn room_scene(medium: &str, photons: u32, radius: f32) -> String {
    format!(
        "{CAMERA_INSIDE}[integrator]\ntype = \"sppm\"\nphotons = {photons}\nradius = {radius:?}\nmax_depth = 1000\nrr_depth = 5\nseed = 7\n{}{WHITE_SPHERE}{medium}",
        room()
    )
}

/// The emissive-room furnace (radiance 1 everywhere) with a white diffuse
/// sphere: every pixel is 1. Incident radiance is uniform, so the disk
/// estimate is exact on the sphere (a sphere's area within distance r of one
/// of its points is exactly π r²) and on the walls away from their edges
/// (within r of an edge the photons of the next wall are not counted: a
/// bias on a sliver r/4 of a wall, smaller than the noise at r = 0.05).
/// This pins the photons' throughput, the 1/(π r² M) normalization and
/// the |ng·w| of the surface estimate, beside next-event estimation.
#[test]
fn emissive_room_furnace_surfaces() {
    let scene = scene_from_str(&room_scene("", 20_000, 0.05));
    let film = sppm_film(&scene, 64, 2);
    report("room surfaces", &pixels(&film));
    assert_pixels_equal(&pixels(&film), [1.0; 3], "sppm room furnace, white sphere");
}

/// The same room filled with an albedo-1 medium: the beam radiance estimate
/// along every eye segment plus next-event estimation in the medium give 1
/// everywhere (photons fill the whole room evenly, so a cylinder around an
/// eye ray loses only the sliver cut off by the wall it ends on).
#[test]
fn emissive_room_furnace_medium() {
    let scene = scene_from_str(&room_scene(ROOM_MEDIUM, 20_000, 0.15));
    let film = sppm_film(&scene, 64, 2);
    report("room medium", &pixels(&film));
    assert_pixels_equal(&pixels(&film), [1.0; 3], "sppm room furnace, medium");
}

/// A spotlight reflected by a mirror into fog: every light path from it to
/// the eye scatters at the mirror first, so the beam is photons' light only
/// (beam radiance estimate), and it matches the quadrature of its single
/// scattering (`beam_support`, the scene of `bdpt_beam.rs`).
#[test]
fn mirrored_spot_beam_matches_quadrature() {
    let expected = beam_support::INTENSITY.map(|i| i * beam_support::pixel(16, 4));
    let text = beam_support::scene("type = \"sppm\"\nphotons = 20000\nradius = 0.05");
    let film = sppm_film(&scene_from_str(&text), 2000, 2);
    let px = pixels(&film);
    eprintln!(
        "sppm beam {:?} ± {:?}, quadrature {expected:?}",
        px[0].mean, px[0].std_error
    );
    assert_estimate(&px[0], expected, "sppm mirrored beam");
}

/// A caustic in fog (glass ball under a spot, floor, fog): the film is the
/// same bit for bit on one thread and on two.
#[test]
fn same_image_for_any_thread_count() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/caustic_fog.toml"
    ))
    .expect("scenes/caustic_fog.toml");
    let text = text.replace(
        "[integrator]\n",
        "[integrator]\ntype = \"sppm\"\nphotons = 5000\n",
    );
    let text = text.replace("resolution = [320, 240]", "resolution = [24, 18]");
    let scene = scene_from_str(&text);
    let one = sppm_film(&scene, 3, 1);
    let two = sppm_film(&scene, 3, 2);
    assert!(
        one.layers[0].sums.iter().any(|&v| v > 0.0),
        "a black image proves nothing"
    );
    let bits = |f: &Film| {
        f.layers[0]
            .sums
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
}

/// Bad photon keys name the key as written and say what is expected.
#[test]
fn photon_keys_are_validated_in_the_users_words() {
    let base = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [4, 4]\n[[shape]]\ntype = \"sphere\"\nradius = 1.0\n[[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 2.0]\nintensity = 1.0\n";
    for (integrator, key, says) in [
        (
            "type = \"sppm\"\nalpha = 1.5",
            "integrator.alpha",
            "must be in (0, 1)",
        ),
        (
            "type = \"sppm\"\nphotons = 0",
            "integrator.photons",
            "must be between 1",
        ),
        (
            "type = \"sppm\"\nradius = -0.1",
            "integrator.radius",
            "must be in [1e-9, 1e18], got -0.1",
        ),
        (
            "type = \"photons\"",
            "integrator.type",
            "expected path, bdpt, mlt or sppm",
        ),
    ] {
        let text = format!("{base}[integrator]\n{integrator}\n");
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("test.toml");
        let desc = brume::scene::parse(&text, &file).expect("parse");
        let err = match brume::scene::build(
            &desc,
            &file,
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")),
        ) {
            Ok(_) => panic!("{integrator}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(
            err.contains("test.toml") && err.contains(key) && err.contains(says),
            "{integrator}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

/// The bias table of docs/sppm.md: the image mean of the room furnace with
/// a medium box inside (the kernel straddles the box's faces: a bias of first
/// order in r) after 4, 16, 64 and 256 passes, against its closed form 1.
/// `cargo test --release --test sppm -- --ignored bias_table --nocapture`
#[test]
#[ignore]
fn bias_table() {
    eprintln!("| first radius | passes | radius | image mean − 1 | standard error |");
    eprintln!("|---|---|---|---|---|");
    for r1 in [0.2f32, 0.6] {
        let scene = scene_from_str(&room_scene(BOX_MEDIUM, 10_000, r1));
        for passes in [4u32, 16, 64, 256] {
            let film = sppm_film(&scene, passes, 2);
            let px = pixels(&film);
            let n = px.len() as f64;
            let mean: f64 = px.iter().map(|p| p.mean[1]).sum::<f64>() / n;
            let se = px
                .iter()
                .map(|p| p.std_error[1].powi(2))
                .sum::<f64>()
                .sqrt()
                / n;
            let r = brume::integrator::sppm::pass_radius(r1, 2.0 / 3.0, passes - 1);
            eprintln!(
                "| {r1} | {passes} | {r:.4} | {:+.4} | {se:.4} |",
                mean - 1.0
            );
        }
    }
}

/// A point light beside a camera ray in a global medium with
/// `max_scatter_depth = 1`: single scattering only, all of it next-event
/// estimation's (no photon path is in the path set: a photon needs a second
/// scattering event), so SPPM's eye pass must give the quadrature of
/// ∫0^∞ σs p(θ(t)) I e^(−σt (t + r(t))) / r(t)² dt (as in `analytic_scattering.rs`).
#[test]
fn point_light_single_scattering_matches_quadrature() {
    let (sigma_a, sigma_s, g, intensity) = (0.05f64, 0.25f64, 0.5f64, 10.0f64);
    let light = [3.0f64, 0.8, 0.4];
    let integrand = |t: f64| {
        let d = [t - light[0], -light[1], -light[2]];
        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let cos = -d[0] / r;
        let hg =
            (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * cos).powf(1.5));
        sigma_s * hg * intensity * (-(sigma_a + sigma_s) * (t + r)).exp() / (r * r)
    };
    let quad = |panels: usize| -> f64 {
        let breaks = [0.0, 1.0, 2.0, 2.5, 3.0, 3.5, 4.0, 6.0, 12.0, 50.0, 200.0];
        breaks
            .windows(2)
            .map(|w| brume::sampling::quadrature::gauss_legendre(integrand, w[0], w[1], panels))
            .sum()
    };
    let (coarse, expected) = (quad(50), quad(100));
    assert!(
        (coarse - expected).abs() <= 1e-9 * expected,
        "quadrature converged"
    );
    // A 1×1 camera of 0.001° along the ray: its pixel's rays differ by 1e-5 rad.
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [1.0, 0.0, 0.0]\nfov = 0.001\nresolution = [1, 1]\n\
         [integrator]\ntype = \"sppm\"\nphotons = 200\nmax_scatter_depth = 1\nseed = 3\n\
         [[light]]\ntype = \"point\"\nposition = {light:?}\nintensity = {intensity:?}\n\
         [[medium]]\ntype = \"homogeneous\"\nsigma_a = {sigma_a:?}\nsigma_s = {sigma_s:?}\nphase = {{ type = \"hg\", g = {g:?} }}\nglobal = true\n"
    );
    let film = sppm_film(&scene_from_str(&text), 20_000, 2);
    let px = pixels(&film);
    eprintln!(
        "sppm point light {:?} ± {:?}, quadrature {expected}",
        px[0].mean, px[0].std_error
    );
    assert_estimate(&px[0], [expected; 3], "sppm point-light single scattering");
}

/// Means of `px` (a `w`-pixel-wide image) over blocks of `b`×`b` pixels.
fn regions(px: &[Estimate], w: usize, b: usize) -> Vec<Estimate> {
    let h = px.len() / w;
    let mut out = Vec::new();
    for by in (0..h).step_by(b) {
        for bx in (0..w).step_by(b) {
            let (mut mean, mut var, mut n) = ([0.0; 3], [0.0; 3], 0usize);
            for y in by..(by + b).min(h) {
                for x in bx..(bx + b).min(w) {
                    for c in 0..3 {
                        mean[c] += px[y * w + x].mean[c];
                        var[c] += px[y * w + x].std_error[c].powi(2);
                    }
                    n += 1;
                }
            }
            out.push(Estimate {
                mean: mean.map(|m| m / n as f64),
                std_error: var.map(|v| v.sqrt() / n as f64),
                n,
            });
        }
    }
    out
}

/// The caustic in fog (a spot through a glass ball onto a floor, thin fog):
/// SPPM agrees with BDPT block by block (6×6-pixel blocks of a 36×24 image)
/// wherever BDPT can sample the light: blocks that see the ball are left
/// out, because light seen *through* the ball after passing through it
/// (light–glass–floor or fog–glass–eye) has a diffuse or medium vertex
/// between two Dirac chains, which no BDPT connection reaches from a point
/// light, and photon mapping does (SPPM is 20 % brighter there). At
/// r₁ = 0.02 the kernel's bias (about 0.1·r relative where it straddles an
/// edge, docs/sppm.md) is far below the noise, so no allowance is added.
#[test]
fn caustic_in_fog_agrees_with_bdpt_by_region() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/caustic_fog.toml"
    ))
    .expect("scenes/caustic_fog.toml")
    .replace("resolution = [320, 240]", "resolution = [36, 24]");
    let bdpt = bdpt_support::bdpt_pixels(&scene_from_str(&text), 2048);
    let sppm_text = text.replace(
        "[integrator]\n",
        "[integrator]\ntype = \"sppm\"\nphotons = 20000\nradius = 0.02\n",
    );
    let sppm = pixels(&sppm_film(&scene_from_str(&sppm_text), 512, 2));
    let ball = sees_ball(&scene_from_str(&text), 6);
    let keep = |r: Vec<Estimate>| -> Vec<Estimate> {
        r.into_iter()
            .zip(&ball)
            .filter(|(_, &b)| !b)
            .map(|(e, _)| e)
            .collect()
    };
    let (a, b) = (keep(regions(&sppm, 36, 6)), keep(regions(&bdpt, 36, 6)));
    assert!(a.len() >= 16, "{} blocks left", a.len());
    let mean: Vec<[f64; 3]> = b.iter().map(|e| e.mean).collect();
    let se: Vec<[f64; 3]> = b.iter().map(|e| e.std_error).collect();
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        eprintln!(
            "block {i}: sppm {:.5} ± {:.5}, bdpt {:.5} ± {:.5}",
            x.mean[1], x.std_error[1], y.mean[1], y.std_error[1]
        );
    }
    assert_pixels(&a, &mean, &se, "caustic in fog, sppm vs bdpt by block");
}

/// Per 6×6 block (as [`regions`] orders them): does any of its pixels see shape 0 (the ball)?
fn sees_ball(scene: &Scene, b: u32) -> Vec<bool> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::new();
    for by in (0..h).step_by(b as usize) {
        for bx in (0..w).step_by(b as usize) {
            let mut any = false;
            for y in by..(by + b).min(h) {
                for x in bx..(bx + b).min(w) {
                    for s in 0..16 {
                        let mut sampler = brume::sampling::Sampler::new(1, x, y, s);
                        let ray = scene.camera.sample_ray_at(x, y, 0.0, &mut sampler);
                        let hit = scene.geometry.intersect(&ray, f32::INFINITY);
                        any |= hit.is_some_and(|h| h.shape == 0);
                    }
                }
            }
            out.push(any);
        }
    }
    out
}

/// Photons are counted against the memory limit while a pass traces them:
/// a pass that would hold more stops at once, nothing is written, and the
/// error names the scene key, the limit and the ways past it (exit 2). The
/// same scene within the limit renders.
#[test]
fn photons_over_the_memory_limit_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = dir.path().join("room.toml");
    let text =
        room_scene("", 2_000_000, 0.05).replace("max_depth = 1000", "max_depth = 1000\nspp = 2");
    std::fs::write(&scene, text).expect("write scene");
    let run = |limit: &str, out: &str| {
        bdpt_support::common::cli::brume()
            .arg("render")
            .arg(&scene)
            .args(["--quiet", "--memory-limit", limit, "--out"])
            .arg(dir.path().join(format!("{out}.exr")))
            .arg("--png")
            .arg(dir.path().join(format!("{out}.png")))
            .output()
            .expect("run brume")
    };
    let refused = run("0.05", "small");
    let err = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{err}");
    for says in [
        "room.toml",
        "integrator.photons",
        "pass 1's",
        "memory limit of 50.0 MB",
        "--memory-limit",
    ] {
        assert!(err.contains(says), "missing {says:?}: {err}");
    }
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!dir.path().join("small.exr").exists() && !dir.path().join("small.png").exists());
    let small =
        room_scene("", 2_000, 0.05).replace("max_depth = 1000", "max_depth = 1000\nspp = 2");
    std::fs::write(&scene, small).expect("write scene");
    let fits = run("0.05", "fits");
    assert_eq!(
        fits.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&fits.stderr)
    );
    assert!(dir.path().join("fits.exr").exists());
}

/// The photons' share of a wall pixel in the sphere-less room: walls emit
/// 0.5 and reflect half of an incident radiance of 1, of which 0.5 arrived
/// after scattering at least once (photons' light): 0.5 · 0.5.
const WALL_PHOTON_SHARE: f64 = 0.25;

/// Half the side of the room's square walls.
const WALL_HALF: f64 = 2.0;

/// Area of the disk of radius `r` around (u, v) that lies on the wall
/// [−2, 2]²: ∫ chord(x) dx with x = u + r sin θ (smooth at the disk's ends),
/// by Gauss–Legendre between the angles where the chord meets a wall edge
/// (the integrand's kinks), so the quadrature is exact to rounding.
fn disk_on_wall(u: f64, v: f64, r: f64) -> f64 {
    let chord = |theta: f64| {
        let x = u + r * theta.sin();
        if x.abs() > WALL_HALF {
            return 0.0;
        }
        let h = r * theta.cos();
        let width = ((v + h).min(WALL_HALF) - (v - h).max(-WALL_HALF)).max(0.0);
        width * r * theta.cos()
    };
    let half_pi = std::f64::consts::FRAC_PI_2;
    let mut breaks = vec![-half_pi, half_pi];
    for edge in [-WALL_HALF, WALL_HALF] {
        let (s, c) = ((edge - u) / r, (edge - v).abs() / r);
        if s.abs() < 1.0 {
            breaks.push(s.asin());
        }
        if c < 1.0 {
            breaks.extend([c.acos(), -c.acos()]);
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks
        .windows(2)
        .map(|w| brume::sampling::quadrature::gauss_legendre(chord, w[0], w[1], 4))
        .sum()
}

/// Where each of `rays` camera rays per pixel meets a wall, in that wall's
/// own coordinates (the two axes along it).
fn wall_points(scene: &Scene, rays: u32) -> Vec<(f64, f64)> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            for s in 0..rays {
                let mut sampler = brume::sampling::Sampler::new(99, x, y, s as u64);
                let ray = scene.camera.sample_ray_at(x, y, 0.0, &mut sampler);
                let hit = scene
                    .geometry
                    .intersect(&ray, f32::INFINITY)
                    .expect("closed room");
                let p = hit.p.as_dvec3().to_array();
                let axis = (0..3)
                    .max_by(|&a, &b| p[a].abs().total_cmp(&p[b].abs()))
                    .unwrap();
                out.push((p[(axis + 1) % 3], p[(axis + 2) % 3]));
            }
        }
    }
    out
}

/// The expected image mean of the sphere-less room at gather radius `r`
/// with its standard error over the wall points: 1 − 0.25·(1 − A/(π r²)),
/// A the part of the gather disk on the wall (photons of the neighbouring
/// walls are not the surface's, so a disk across an edge loses its outside).
fn room_mean_at_radius(points: &[(f64, f64)], r: f64) -> (f64, f64) {
    let disk = std::f64::consts::PI * r * r;
    let values: Vec<f64> = points
        .iter()
        .map(|&(u, v)| 1.0 - WALL_PHOTON_SHARE * (1.0 - disk_on_wall(u, v, r) / disk))
        .collect();
    mean_and_se(&values)
}

/// Mean and standard error of independent values.
fn mean_and_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The closed form of the mean of `passes` passes from first radius `r1`:
/// the mean over passes of [`room_mean_at_radius`] at each pass's radius
/// (its standard error: the wall points are the same at every radius, so
/// the errors add, not in quadrature).
fn room_mean_over_passes(points: &[(f64, f64)], r1: f32, passes: u32) -> (f64, f64) {
    let (mut mean, mut se) = (0.0, 0.0);
    for pass in 0..passes {
        let r = brume::integrator::sppm::pass_radius(r1, DEFAULT_ALPHA, pass) as f64;
        let (m, s) = room_mean_at_radius(points, r);
        mean += m / passes as f64;
        se += s / passes as f64;
    }
    (mean, se)
}

use brume::integrator::sppm::DEFAULT_ALPHA;

/// Image means (green) of `seeds` independent renders of `passes` passes.
fn image_means(text: &str, passes: u32, seeds: std::ops::Range<u64>) -> Vec<f64> {
    seeds
        .map(|seed| {
            let scene = scene_from_str(&text.replace("seed = 7", &format!("seed = {seed}")));
            let px = pixels(&sppm_film(&scene, passes, 2));
            px.iter().map(|p| p.mean[1]).sum::<f64>() / px.len() as f64
        })
        .collect()
}

/// The error shrinks as passes grow, at the rate the radius schedule sets.
/// The emissive room without the sphere: every wall pixel's photon share
/// (0.25) is gathered on a disk that loses its part past the wall's edges,
/// so the image mean at radius r has the closed form 1 − 0.25·(1 − A/πr²)
/// averaged over the camera's wall points (`room_mean_at_radius`), and the
/// mean of N passes the average of that over the passes' radii rᵢ. The
/// bias is of first order in r here (the disk straddles edges, docs/sppm.md),
/// so it falls like the mean of rᵢ ∝ N^((α−1)/2), between that and N^(α−1).
/// The renders of N and 4N passes (independent seeds, the spread of their
/// image means giving the standard error: pixels share photons, so the
/// pixels' own errors are not independent) must each match the closed form;
/// the closed forms at 4N with the schedule and with the radius kept at r₁
/// are further apart than the tolerance, so a radius that does not shrink fails.
#[test]
fn error_shrinks_at_the_documented_rate() {
    let (r1, n, seeds) = (0.4f32, 4u32, 16u64);
    let text = room_scene("", 20_000, r1)
        .replace(WHITE_SPHERE, "")
        .replace("resolution = [8, 8]", "resolution = [16, 16]");
    let points = wall_points(&scene_from_str(&text), 64);
    let mut rows = Vec::new();
    for (passes, first_seed) in [(n, 1000u64), (4 * n, 2000)] {
        let (got, se) = mean_and_se(&image_means(&text, passes, first_seed..first_seed + seeds));
        let (want, want_se) = room_mean_over_passes(&points, r1, passes);
        eprintln!(
            "{passes} passes: image mean {got:.5} ± {se:.5} over {seeds} seeds, closed form {want:.5} ± {want_se:.5}"
        );
        rows.push((passes, got, se.hypot(want_se), want));
    }
    let bias = |row: &(u32, f64, f64, f64)| 1.0 - row.3;
    let measured = |row: &(u32, f64, f64, f64)| 1.0 - row.1;
    eprintln!(
        "bias ratio 4N/N: closed form {:.4}, measured {:.4}; first order (mean rᵢ) {:.4}",
        bias(&rows[1]) / bias(&rows[0]),
        measured(&rows[1]) / measured(&rows[0]),
        mean_radius(r1, 4 * n) / mean_radius(r1, n),
    );
    // The test has the power to see a radius that does not shrink.
    let kept = room_mean_at_radius(&points, r1 as f64).0;
    let tolerance = k_sigma(2) * rows[1].2;
    assert!(
        (kept - rows[1].3).abs() > 2.0 * tolerance,
        "a constant radius ({kept:.5}) is within twice the tolerance ({tolerance:.5}) of the schedule's {:.5}",
        rows[1].3
    );
    for (passes, got, se, want) in rows {
        assert_within(got, se, want, 2, &format!("sppm room, {passes} passes"));
    }
}

/// The mean gather radius of the first `passes` passes from `r1`.
fn mean_radius(r1: f32, passes: u32) -> f64 {
    (0..passes)
        .map(|p| brume::integrator::sppm::pass_radius(r1, DEFAULT_ALPHA, p) as f64)
        .sum::<f64>()
        / passes as f64
}

/// `emissive_room_furnace_surfaces` sat at −2.9 σ with its seed 7: the same
/// render over 12 other seeds, their spread giving the standard error (it
/// equals the pooled per-pixel one, 0.0054 per render, so the furnace's
/// error bar is right), is 1 within the noise: the −2.9 σ was chance
/// (docs/testing.md). The walls' edge loss (about −0.003 on wall pixels at
/// r = 0.05, the closed form of `error_shrinks_at_the_documented_rate`) is
/// below this noise.
/// `cargo test --release --test sppm -- --ignored surface_furnace_over_seeds --nocapture`
#[test]
#[ignore]
fn surface_furnace_over_seeds() {
    let means = image_means(&room_scene("", 20_000, 0.05), 64, 100..112);
    let (mean, se) = mean_and_se(&means);
    eprintln!(
        "room surfaces over 12 seeds: {mean:.5} ± {se:.5} (spread per render {:.5})",
        se * 12f64.sqrt()
    );
    assert_within(mean, se, 1.0, 1, "sppm room furnace over 12 seeds");
}
