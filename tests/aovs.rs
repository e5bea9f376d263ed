//! AOV layers: documented names, closed-form values, a round trip through
//! the exr crate, and a beauty that AOVs leave bit-identical.

mod analytic_support;

use analytic_support::{k_sigma, scene_from_str, SceneText};
use brume::integrator::aov::{aov_sample, Aov};
use brume::math::Vec3;
use brume::render::render_aovs;

/// Channel `name` of a render_aovs result.
fn channel<'a>(layers: &'a [(String, Vec<f32>)], name: &str) -> &'a [f32] {
    &layers.iter().find(|(n, _)| n == name).unwrap().1
}

/// A camera on the +z axis at distance `d` from a large diffuse plane z = 0 facing it.
fn plane_scene(d: f32) -> String {
    SceneText::camera([0.3, -0.2, d], [0.3, -0.2, 0.0], [12, 8])
        .fov(60.0)
        .environment(1.0)
        .quad([0.0; 3], [0.0, 0.0, 1.0], [100.0, 100.0])
        .with("material = { type = \"diffuse\", albedo = [0.2, 0.4, 0.6] }")
        .build()
}

/// Depth is camera-space: every pixel of a plane facing the camera at 3.5 m
/// reads 3.5 (the distance along each ray would grow off-axis); the normal
/// is +z, the albedo the material's, alpha 1, transmittance 1 (no media).
#[test]
fn a_plane_at_a_known_distance_has_exact_depth_normal_and_albedo() {
    let scene = scene_from_str(&plane_scene(3.5));
    let layers = render_aovs(&scene, &Aov::ALL, 4, Some(1));
    for i in 0..12 * 8 {
        assert!(
            (channel(&layers, "depth.Z")[i] - 3.5).abs() < 1e-5,
            "pixel {i}"
        );
        assert_eq!(channel(&layers, "A")[i], 1.0);
        for (c, v) in [("X", 0.0), ("Y", 0.0), ("Z", 1.0)] {
            assert!((channel(&layers, &format!("normal.{c}"))[i] - v).abs() < 1e-6);
        }
        for (c, v) in [("R", 0.2), ("G", 0.4), ("B", 0.6)] {
            assert!((channel(&layers, &format!("albedo.{c}"))[i] - v).abs() < 1e-6);
            assert_eq!(channel(&layers, &format!("transmittance.{c}"))[i], 1.0);
        }
    }
}

/// Every sample's normal is (p − c)/r at the point where its camera ray —
/// the beauty's own — meets the sphere; escaping samples have normal 0.
#[test]
fn sphere_normals_are_the_analytic_normals_of_each_camera_ray() {
    let text = SceneText::camera([0.0, 0.0, 5.0], [0.0; 3], [16, 16])
        .fov(30.0)
        .environment(1.0)
        .sphere([0.2, 0.1, 0.0], 1.0);
    let scene = scene_from_str(&text.build());
    let c = Vec3::new(0.2, 0.1, 0.0);
    let (mut hits, mut misses) = (0, 0);
    for y in 0..16 {
        for x in 0..16 {
            let streams = scene.settings.pixel_streams(x, y);
            for s in 0..4 {
                let ray = scene
                    .camera
                    .generate_ray(x, y, streams.sampler(s as u64).next_2d());
                let a = aov_sample(&scene, x, y, &streams, s);
                // |o + t d − c| = 1: t = −b − √(b² − |o − c|² + 1).
                let oc = ray.origin - c;
                let b = oc.dot(ray.direction);
                let disc = b * b - oc.length_squared() + 1.0;
                if disc <= 1e-4 {
                    if disc < -1e-4 {
                        assert_eq!(a.normal, Vec3::ZERO);
                        assert_eq!(a.depth, None);
                        misses += 1;
                    }
                    continue;
                }
                let p = ray.at(-b - disc.sqrt());
                assert!((a.normal - (p - c)).length() < 1e-3, "{x},{y},{s}");
                hits += 1;
            }
        }
    }
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}

/// A homogeneous slab of thickness L seen through a 2° camera in front of
/// the background: alpha = 1 − e^(−σt L/cos θ) per pixel. Delta tracking
/// makes each sample's transmittance 0 or 1, so the per-pixel standard error
/// is √(p(1−p)/N). Over the same slab the volume albedo (spectral-tracking
/// throughput at the scattering vertex) has mean α(1 − e^(−σt L/cos θ)).
#[test]
fn alpha_and_volume_albedo_of_a_homogeneous_slab_match_their_closed_forms() {
    let (sigma_t, albedo, thickness) = (0.7f64, 0.8f64, 1.5f64);
    let text = SceneText::camera([0.0, 0.0, 10.0], [0.0; 3], [6, 4])
        .fov(2.0)
        .integrator("transmittance = \"delta\"")
        .environment(1.0)
        .medium(&format!(
            "type = \"homogeneous\"\nsigma_t = {sigma_t:?}\nalbedo = {albedo:?}\n\
             bounds = {{ type = \"box\", min = [-50.0, -50.0, {:?}], max = [50.0, 50.0, 0.0] }}",
            -thickness
        ));
    let scene = scene_from_str(&text.build());
    let n = 4000u32;
    let layers = render_aovs(&scene, &[Aov::Alpha, Aov::Albedo, Aov::Normal], n, None);
    // 24 pixels × 3 checks, Šidák-corrected as one family.
    let k = k_sigma(72);
    for y in 0..4u32 {
        for x in 0..6u32 {
            let i = (y * 6 + x) as usize;
            let centre = scene.camera.generate_ray(x, y, glam::Vec2::splat(0.5));
            let cos = (-centre.direction.z) as f64;
            let p = 1.0 - (-sigma_t * thickness / cos).exp();
            let se = (p * (1.0 - p) / n as f64).sqrt();
            let alpha = channel(&layers, "A")[i] as f64;
            assert!(
                (alpha - p).abs() <= k * se,
                "pixel {x},{y}: alpha {alpha} vs {p} ± {se}"
            );
            let a = channel(&layers, "albedo.G")[i] as f64;
            assert!(
                (a - albedo * p).abs() <= k * albedo * se,
                "pixel {x},{y}: albedo {a} vs {}",
                albedo * p
            );
            // The normal of a scattering vertex is the view direction: +z here, weighted by p.
            let nz = channel(&layers, "normal.Z")[i] as f64;
            assert!(
                (nz - p * cos).abs() <= k * se + 1e-3,
                "pixel {x},{y}: normal {nz}"
            );
        }
    }
}

/// `brume render --aovs`: the EXR holds R, G, B and the documented AOV
/// channels, read back by the exr crate, equal to render_aovs; the beauty is
/// bit-identical to a render without AOVs.
#[test]
fn aov_layers_round_trip_and_leave_the_beauty_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("slab.toml");
    let text = format!(
        "{}\n[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.4\nalbedo = 0.7\n\
         bounds = {{ type = \"box\", min = [-1.0, -1.0, 0.5], max = [1.0, 1.0, 1.5] }}\n",
        plane_scene(3.0)
    );
    std::fs::write(&scene_path, &text).unwrap();
    let render = |aovs: &str, out: &str| {
        assert_cmd::Command::cargo_bin("brume")
            .unwrap()
            .current_dir(dir.path())
            .args([
                "render",
                "slab.toml",
                "--spp",
                "8",
                "--quiet",
                "--aovs",
                aovs,
                "--out",
                out,
            ])
            .assert()
            .success();
        brume::film::image_io::read_exr_channels(&dir.path().join(out)).unwrap()
    };
    let (w, h, plain) = render("none", "plain.exr");
    let (w2, h2, with) = render("alpha,depth,normal,albedo,transmittance", "aovs.exr");
    assert_eq!((w, h), (w2, h2));
    // brume.* channels are the film's exact sums and counts (for merge), not layers.
    let names: Vec<&str> = with
        .iter()
        .map(|(n, _)| n.as_str())
        .filter(|n| !n.starts_with("brume."))
        .collect();
    let mut expected = vec!["R", "G", "B"];
    for aov in Aov::ALL {
        expected.extend(aov.channels());
    }
    expected.sort();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(sorted, expected);
    for c in ["R", "G", "B"] {
        let a = &plain.iter().find(|(n, _)| n == c).unwrap().1;
        let b = &with.iter().find(|(n, _)| n == c).unwrap().1;
        assert_eq!(a, b, "beauty channel {c} changed by the AOVs");
    }
    let scene = scene_from_str(&text);
    let direct = render_aovs(&scene, &Aov::ALL, 8, None);
    for (name, values) in &direct {
        let read = &with.iter().find(|(n, _)| n == name).unwrap().1;
        assert_eq!(read, values, "channel {name}");
    }
    // The layers carry information: the slab covers part of the plane.
    let t = channel(&direct, "transmittance.R");
    assert!(t.iter().any(|&v| v < 0.9) && t.contains(&1.0));
}

#[test]
fn unknown_aov_names_are_refused_with_the_key_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(
        &path,
        format!(
            "{}\n[film]\naovs = [\"alpha\", \"sheen\"]\n",
            plane_scene(1.0)
        ),
    )
    .unwrap();
    let out = assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args(["render", "bad.toml", "--quiet"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("film.aovs[1]") && stderr.contains("sheen"),
        "{stderr}"
    );
    assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args(["render", "bad.toml", "--quiet", "--aovs", "alpha,gloss"])
        .assert()
        .code(2);
}

/// A plane seen from behind still gives the normal that faces the camera.
#[test]
fn a_plane_seen_from_behind_has_the_normal_toward_the_camera() {
    let scene = scene_from_str(
        &plane_scene(2.0).replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, -1.0]"),
    );
    let layers = render_aovs(&scene, &[Aov::Normal], 2, Some(1));
    for i in 0..12 * 8 {
        assert!(
            (channel(&layers, "normal.Z")[i] - 1.0).abs() < 1e-6,
            "pixel {i}"
        );
    }
}

/// In a medium of albedo 1 every camera ray scatters at a distance t drawn
/// from σt·e^(−σt t); the depth AOV is camera-space, t·cos α for a ray α off
/// the view axis, so depth / cos α averages 1/σt over a corner pixel's samples.
#[test]
fn a_scattering_point_has_the_camera_space_depth_of_its_distance() {
    let text = SceneText::camera([0.0; 3], [0.0, 0.0, -1.0], [4, 4])
        .fov(70.0)
        .environment(1.0)
        .medium(
            "type = \"homogeneous\"\nsigma_a = 0.0\nsigma_s = 0.5\n\
             bounds = { type = \"box\", min = [-1000.0, -1000.0, -1000.0], max = [1000.0, 1000.0, 1000.0] }",
        );
    let scene = scene_from_str(&text.build());
    let forward = Vec3::new(0.0, 0.0, -1.0);
    let n = 8192;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    let streams = scene.settings.pixel_streams(0, 0);
    for s in 0..n {
        let ray = scene
            .camera
            .generate_ray(0, 0, streams.sampler(s as u64).next_2d());
        let a = aov_sample(&scene, 0, 0, &streams, s);
        let depth = a.depth.expect("every ray scatters");
        let t = (depth / ray.direction.dot(forward)) as f64;
        sum += t;
        sum2 += t * t;
    }
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    assert!(
        (mean - 2.0).abs() < k_sigma(1) * se,
        "mean distance {mean} ± {se}, expected 1/σt = 2"
    );
}
