//! HDR environment maps: sampling against the pdf, the constant-map furnace,
//! and the irradiance a map gives a diffuse plane in closed form.

mod analytic_support;

use analytic_support::common::{assert_pixels_equal, estimate_pixels, scene_from_str};
use analytic_support::SceneText;
use analytic_support::{assert_estimate, estimate_li};
use brume::film::image_io::{write_exr, Image};
use brume::light::envmap::{EnvMap, Filter};
use brume::math::color::Rgb;
use brume::math::{Quat, Ray, Vec3};
use brume::sampling::chi2::{chi2_survival, sidak_alpha};
use brume::sampling::quadrature::gauss_legendre;
use std::f64::consts::PI;
use std::path::Path;

/// A structured test sky: a gradient, a bright "sun" texel block and a dark ground.
fn test_texels(width: usize, height: usize) -> Vec<Rgb> {
    let mut t = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let v = (y as f32 + 0.5) / height as f32;
            let mut c = if v < 0.5 {
                Rgb::new(0.2 + v, 0.4 + v, 1.0)
            } else {
                Rgb::splat(0.05)
            };
            if (x * 5 / width, y * 4 / height) == (1, 1) {
                c = Rgb::new(40.0, 35.0, 30.0);
            }
            t.push(c);
        }
    }
    t
}

fn write_map(dir: &Path, name: &str, width: usize, height: usize, texels: Vec<Rgb>) -> String {
    let path = dir.join(name);
    let image = Image {
        width,
        height,
        pixels: texels,
        spp: 1,
        partial: false,
    };
    write_exr(&path, &image).unwrap();
    path.display().to_string().replace('\\', "/")
}

/// Chi-square of map sampling in direction space, with one bin per texel.
///
/// The bin of a sampled direction is found here from its angles in the map
/// frame (f64); the expected count of a texel is N ∫texel pdf(ω) dω by
/// Gauss–Legendre quadrature over θ and φ with dω = sinθ dθ dφ. This checks
/// the sampler, the pdf and the Jacobian 2π² sinθ between them. (Bins are
/// texels because the pdf is discontinuous at texel edges: cells straddling
/// them would make the quadrature crawl.) Both filters: a bilinear map is
/// sampled by its own table (the neighbourhood maxima).
#[test]
fn map_sampling_follows_its_pdf() {
    let (w, h) = (12, 6);
    let n = 200_000;
    for (k, (rotation, filter)) in [
        (Quat::IDENTITY, Filter::Nearest),
        (
            Quat::from_rotation_x(1.1) * Quat::from_rotation_y(0.4),
            Filter::Nearest,
        ),
        (Quat::IDENTITY, Filter::Bilinear),
        (
            Quat::from_rotation_x(1.1) * Quat::from_rotation_y(0.4),
            Filter::Bilinear,
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let map = EnvMap::filtered(w, h, test_texels(w, h), Rgb::WHITE, rotation, filter).unwrap();
        let mut observed = vec![0.0f64; w * h];
        let mut rng = brume::sampling::Sampler::from_seed(40 + k as u64);
        for _ in 0..n {
            let s = map.sample(rng.next_2d()).expect("a sample");
            assert!((s.pdf - map.pdf(s.wi)).abs() <= 1e-3 * s.pdf, "{s:?}");
            let d = (rotation.inverse() * s.wi).as_dvec3();
            let theta = (d.x * d.x + d.z * d.z).sqrt().atan2(d.y);
            let phi = d.z.atan2(d.x).rem_euclid(2.0 * PI);
            let x = ((phi / (2.0 * PI) * w as f64) as usize).min(w - 1);
            let y = ((theta / PI * h as f64) as usize).min(h - 1);
            observed[y * w + x] += 1.0;
        }
        let (mut statistic, mut dof) = (0.0, 0usize);
        // Texels expecting fewer than 20 samples share one bin.
        let (mut pooled_observed, mut pooled_expected) = (0.0, 0.0);
        for y in 0..h {
            for x in 0..w {
                let expected = n as f64 * texel_probability(&map, rotation, (w, h), (x, y));
                if expected < 20.0 {
                    pooled_observed += observed[y * w + x];
                    pooled_expected += expected;
                    continue;
                }
                statistic += (observed[y * w + x] - expected).powi(2) / expected;
                dof += 1;
            }
        }
        if pooled_expected > 0.0 {
            assert!(
                pooled_expected > 20.0,
                "pooled texels expect {pooled_expected}"
            );
            statistic += (pooled_observed - pooled_expected).powi(2) / pooled_expected;
            dof += 1;
        }
        let p_value = chi2_survival(statistic, dof - 1);
        // Four tests at family-wise level 1%.
        assert!(
            p_value >= sidak_alpha(0.01, 4),
            "rotation {k}: χ² = {statistic}, dof {}, p = {p_value}\n{observed:?}",
            dof - 1
        );
    }
}

/// ∫texel (x, y) pdf(ω) dω by Gauss–Legendre quadrature over θ and φ.
fn texel_probability(
    map: &EnvMap,
    rotation: Quat,
    (w, h): (usize, usize),
    (x, y): (usize, usize),
) -> f64 {
    let (t0, p0) = (PI * y as f64 / h as f64, 2.0 * PI * x as f64 / w as f64);
    gauss_legendre(
        |t| {
            gauss_legendre(
                |p| {
                    let local = Vec3::new(
                        (t.sin() * p.cos()) as f32,
                        t.cos() as f32,
                        (t.sin() * p.sin()) as f32,
                    );
                    map.pdf(rotation * local) as f64 * t.sin()
                },
                p0 + 1e-6,
                p0 + 2.0 * PI / w as f64 - 1e-6,
                1,
            )
        },
        t0 + 1e-6,
        t0 + PI / h as f64 - 1e-6,
        1,
    )
}

/// A sphere of `material` under the light `light` (the keys of its table), in the furnace's view.
fn sphere_scene(light: &str, material: &str) -> String {
    SceneText::furnace_view(8)
        .depths(1000, 1000)
        .light(light)
        .unit_sphere(material)
        .build()
}

#[test]
fn a_constant_map_renders_like_the_constant_environment() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_map(dir.path(), "one.exr", 16, 8, vec![Rgb::WHITE; 128]);
    let white = "{ type = \"diffuse\", albedo = 1.0 }";
    for (scale, rotate, filter) in [
        (1.0, "[0.0, 0.0, 0.0]", "nearest"),
        (2.0, "[30.0, 60.0, 10.0]", "nearest"),
        (2.0, "[30.0, 60.0, 10.0]", "bilinear"),
    ] {
        let light = format!(
            "type = \"environment_map\"\nfile = \"{file}\"\nscale = {scale}\nrotate = {rotate}\nfilter = \"{filter}\""
        );
        let scene = scene_from_str(&sphere_scene(&light, white));
        assert_pixels_equal(&estimate_pixels(&scene, 128), [scale; 3], "map furnace");
    }
    // The same furnace with a glass sphere: the delta lobes see the map only by BSDF sampling.
    let light = format!("type = \"environment_map\"\nfile = \"{file}\"");
    let scene = scene_from_str(&sphere_scene(
        &light,
        "{ type = \"dielectric\", ior = 1.5 }",
    ));
    assert_pixels_equal(&estimate_pixels(&scene, 32), [1.0; 3], "glass in a map");
}

/// Irradiance on a plane with normal +Y from a lat-long map whose rows are
/// bands of θ: each texel adds L Δφ ∫ cosθ sinθ dθ = L Δφ (sin²θ1 − sin²θ0) / 2
/// over the rows above the horizon (`flip` turns the map upside down).
fn plane_irradiance(texels: &[Rgb], width: usize, height: usize, flip: bool) -> [f64; 3] {
    let mut e = [0.0; 3];
    let dphi = 2.0 * PI / width as f64;
    for y in 0..height / 2 {
        let (t0, t1) = (
            PI * y as f64 / height as f64,
            PI * (y + 1) as f64 / height as f64,
        );
        let band = dphi * (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0;
        let row = if flip { height - 1 - y } else { y };
        for x in 0..width {
            let l = texels[row * width + x];
            for (c, ec) in e.iter_mut().enumerate() {
                *ec += l[c] as f64 * band;
            }
        }
    }
    e
}

#[test]
fn a_diffuse_plane_under_a_map_receives_the_closed_form_irradiance() {
    let (w, h) = (20, 10);
    let texels = test_texels(w, h);
    let dir = tempfile::tempdir().unwrap();
    let file = write_map(dir.path(), "sky.exr", w, h, texels.clone());
    let albedo = 0.8;
    for (rotate, scale, flip) in [
        ("[0.0, 0.0, 0.0]", 1.0, false),
        ("[180.0, 0.0, 0.0]", 3.0, true),
    ] {
        let scene = scene_from_str(&format!(
            r#"
            [camera]
            position = [0.0, 1.0, 4.0]
            look_at = [0.0, 0.0, 0.0]
            [integrator]
            # 2, so that the first vertex's light sample is MIS-weighted and the
            # BSDF-sampled ray that escapes to the map carries the other weight.
            max_depth = 2
            [[light]]
            type = "environment_map"
            file = "{file}"
            rotate = {rotate}
            scale = {scale}
            [[shape]]
            type = "quad"
            normal = [0.0, 1.0, 0.0]
            size = [100.0, 100.0]
            material = {{ type = "diffuse", albedo = {albedo} }}
            "#
        ));
        let e = plane_irradiance(&texels, w, h, flip);
        let expected = e.map(|v| albedo / PI * scale * v);
        let ray = Ray::new(
            Vec3::new(0.3, 2.0, 0.1),
            Vec3::new(0.1, -1.0, 0.2).normalize(),
        );
        let est = estimate_li(&scene, ray, 200_000, 8);
        assert_estimate(&est, expected, &format!("plane under map, rotate {rotate}"));
    }
}

#[test]
fn bad_maps_name_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let black = write_map(dir.path(), "black.exr", 4, 2, vec![Rgb::BLACK; 8]);
    let negative = write_map(dir.path(), "neg.exr", 4, 2, vec![Rgb::splat(-1.0); 8]);
    let corrupt = dir.path().join("corrupt.exr");
    std::fs::write(&corrupt, b"not an exr").unwrap();
    let corrupt = corrupt.display().to_string().replace('\\', "/");
    let file = Path::new("map.toml");
    for (light, needle) in [
        ("file = \"missing.exr\"".to_string(), "no such file"),
        (format!("file = \"{black}\""), "black everywhere"),
        (format!("file = \"{negative}\""), "negative"),
        (format!("file = \"{corrupt}\""), "cannot read"),
    ] {
        let text = sphere_scene(
            &format!("type = \"environment_map\"\n{light}"),
            "{ type = \"diffuse\", albedo = 0.5 }",
        );
        let desc = brume::scene::parse(&text, file).unwrap();
        let err = brume::scene::build(&desc, file, Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("{light} accepted"))
            .to_string();
        assert!(
            err.contains("light[0].file") && err.contains(needle),
            "{light}: {err}"
        );
    }
}

/// Unrotated direction of map coordinates (u, v).
fn map_direction(u: f32, v: f32) -> Vec3 {
    let (sin_t, cos_t) = (std::f32::consts::PI * v).sin_cos();
    let (sin_p, cos_p) = (2.0 * std::f32::consts::PI * u).sin_cos();
    Vec3::new(sin_t * cos_p, cos_t, sin_t * sin_p)
}

fn two_texels(width: usize, height: usize, filter: Filter) -> EnvMap {
    let texels = vec![Rgb::splat(1.0), Rgb::splat(3.0)];
    EnvMap::filtered(width, height, texels, Rgb::WHITE, Quat::IDENTITY, filter).unwrap()
}

/// A 2 × 1 map (texels 1 and 3, centres at u = ¼ and ¾) and a 1 × 2 one
/// (rows 1 and 3, centres at v = ¼ and ¾): bilinear equals nearest at the
/// centres, is the mean halfway, wraps across u = 0 and is clamped to the
/// first or last row within half a texel of a pole.
#[test]
fn bilinear_maps_interpolate_between_texel_centres() {
    let (nearest, bilinear) = (
        two_texels(2, 1, Filter::Nearest),
        two_texels(2, 1, Filter::Bilinear),
    );
    for (u, near, bilin) in [
        (0.25, 1.0, 1.0),
        (0.75, 3.0, 3.0),
        (0.45, 1.0, 1.8),
        (0.55, 3.0, 2.2),
        (0.05, 1.0, 1.8),
        (0.95, 3.0, 2.2),
    ] {
        let d = map_direction(u, 0.5);
        let (n, b) = (nearest.radiance(d).g, bilinear.radiance(d).g);
        assert!(
            (n - near).abs() < 1e-3 && (b - bilin).abs() < 1e-3,
            "u = {u}: {n}, {b}"
        );
    }
    let (nearest, bilinear) = (
        two_texels(1, 2, Filter::Nearest),
        two_texels(1, 2, Filter::Bilinear),
    );
    for (v, near, bilin) in [
        // rows from pole to pole: 1 + 2v
        (0.02, 1.0, 1.04),
        (0.1, 1.0, 1.2),
        (0.4, 1.0, 1.8),
        (0.6, 3.0, 2.2),
        (0.9, 3.0, 2.8),
        (0.98, 3.0, 2.96),
    ] {
        let d = map_direction(0.3, v);
        let (n, b) = (nearest.radiance(d).g, bilinear.radiance(d).g);
        assert!(
            (n - near).abs() < 1e-3 && (b - bilin).abs() < 1e-3,
            "v = {v}: {n}, {b}"
        );
    }
}

/// A constant map is the same constant bilinearly filtered, exactly.
#[test]
fn a_bilinear_constant_map_equals_the_nearest_one() {
    let c = Rgb::new(0.3, 1.7, 2.9);
    let rotation = Quat::from_rotation_x(0.3) * Quat::from_rotation_y(1.2);
    let map = |filter| EnvMap::filtered(7, 5, vec![c; 35], Rgb::WHITE, rotation, filter).unwrap();
    let (nearest, bilinear) = (map(Filter::Nearest), map(Filter::Bilinear));
    let mut rng = brume::sampling::Sampler::from_seed(5);
    for _ in 0..2000 {
        let s = bilinear.sample(rng.next_2d()).expect("a sample");
        assert_eq!(s.radiance, c);
        assert_eq!(bilinear.radiance(s.wi), nearest.radiance(s.wi));
        assert_eq!(bilinear.pdf(s.wi), nearest.pdf(s.wi));
    }
}

/// Unbiased: wherever the bilinear radiance of a map with one lit texel is
/// positive (that texel and its neighbours' inner halves), so is the pdf.
#[test]
fn a_bilinear_map_is_sampled_wherever_it_shines() {
    let (w, h) = (6, 4);
    let mut texels = vec![Rgb::BLACK; w * h];
    texels[w + 5] = Rgb::splat(2.0); // row 1, the last column: its neighbours wrap
    let map = EnvMap::filtered(w, h, texels, Rgb::WHITE, Quat::IDENTITY, Filter::Bilinear).unwrap();
    let mut rng = brume::sampling::Sampler::from_seed(9);
    let mut lit = 0;
    for _ in 0..20_000 {
        let uv = rng.next_2d();
        let d = map_direction(uv.x, uv.y.clamp(1e-3, 1.0 - 1e-3));
        if map.radiance(d).g > 0.0 {
            lit += 1;
            assert!(
                map.pdf(d) > 0.0,
                "{uv}: radiance {:?}, pdf 0",
                map.radiance(d)
            );
        }
    }
    // about 2 × 2 texels' worth of the 24
    assert!(lit > 20_000 / 12 / 2, "{lit}");
}

/// `filter` is "nearest" (the default) or "bilinear"; anything else is refused by name.
#[test]
fn the_filter_key_takes_nearest_or_bilinear() {
    let file = Path::new("map.toml");
    for (filter, ok) in [
        ("", true),
        ("filter = \"nearest\"\n", true),
        ("filter = \"bilinear\"\n", true),
        ("filter = \"cubic\"\n", false),
    ] {
        let text = sphere_scene(
            &format!("type = \"environment_map\"\nfile = \"sky.exr\"\n{filter}"),
            "{ type = \"diffuse\", albedo = 0.5 }",
        );
        match brume::scene::parse(&text, file) {
            Ok(_) => assert!(ok, "{filter} accepted"),
            Err(e) => assert!(!ok && e.to_string().contains("filter"), "{filter}: {e}"),
        }
    }
}
