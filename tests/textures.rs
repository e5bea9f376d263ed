//! Textures seen in renders, against closed forms computed here (in f64,
//! independently of brume's lookup code):
//! - a diffuse quad with an image albedo filling the view under a uniform
//!   environment L = 1 (max_depth 1, nothing else in the scene): every pixel is
//!   albedo(u, v)·L, the pixel-footprint average of the bilinear texture;
//! - an emissive quad with an image texture (PNG and EXR) seen directly:
//!   every pixel is the texture;
//! - the same through an OBJ quad with `vt` coordinates (mirrored on purpose);
//! - a small diffuse receiver under a checkerboard emitter (both NEE and BSDF
//!   sampling see the texture, MIS-combined): its radiance is
//!   (1/π)·Σ_squares L_square·E_square, each square's irradiance by
//!   Lambert's polygon formula.
//!
//! Resolutions are chosen so that no pixel straddles a line through texel
//! centres (the 4 × 2 texture spans 32 × 16 pixels, texel centres on pixel
//! edges): inside a pixel the bilinear texture is then a bilinear function of
//! the image position, whose average over the pixel (the box filter) is its
//! value at the pixel centre.

mod common;

use brume::math::color::Rgb;
use common::{assert_pixels_equal, estimate_pixels, Estimate, SceneText};
use std::path::{Path, PathBuf};

/// The bytes of tests/data/textures/checker4x2.png (row 0 at the top), as in tools/make_textures.py.
const TEXELS: [[[u8; 3]; 4]; 2] = [
    [
        [200, 40, 90],
        [30, 220, 140],
        [120, 60, 250],
        [250, 180, 20],
    ],
    [
        [10, 100, 200],
        [160, 250, 60],
        [90, 10, 30],
        [230, 130, 170],
    ],
];

/// Image size of the renders: 8 × 8 pixels per texel.
const W: u32 = 32;
const H: u32 = 16;

fn srgb_decode(b: u8) -> f64 {
    let v = b as f64 / 255.0;
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear texel (i, j) of the test texture, decoded from sRGB or taken as the byte over 255.
fn texel(i: usize, j: usize, srgb: bool) -> [f64; 3] {
    TEXELS[j][i].map(|b| {
        if srgb {
            srgb_decode(b)
        } else {
            b as f64 / 255.0
        }
    })
}

/// Bilinear lookup of the test texture at (u, v), v up, texel centres at (i + ½)/w.
fn bilinear(u: f64, v: f64, repeat: bool, srgb: bool) -> [f64; 3] {
    let (w, h) = (4i64, 2i64);
    let x = u * w as f64 - 0.5;
    let y = (1.0 - v) * h as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let wrap = |k: i64, n: i64| {
        if repeat {
            k.rem_euclid(n) as usize
        } else {
            k.clamp(0, n - 1) as usize
        }
    };
    let (x0, y0) = (x0 as i64, y0 as i64);
    let mut out = [0.0; 3];
    for (dj, wy) in [(0, 1.0 - fy), (1, fy)] {
        for (di, wx) in [(0, 1.0 - fx), (1, fx)] {
            let t = texel(wrap(x0 + di, w), wrap(y0 + dj, h), srgb);
            for c in 0..3 {
                out[c] += wx * wy * t[c];
            }
        }
    }
    out
}

/// The UV at the centre of pixel (x, y) of a W × H view filled by the quad (u right, v up).
fn pixel_uv(x: u32, y: u32) -> (f64, f64) {
    (
        (x as f64 + 0.5) / W as f64,
        1.0 - (y as f64 + 0.5) / H as f64,
    )
}

/// Expected pixels: `f(u, v)` at every pixel centre, row-major from the top.
fn expected(f: impl Fn(f64, f64) -> [f64; 3]) -> Vec<[f64; 3]> {
    (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (u, v) = pixel_uv(x, y);
            f(u, v)
        })
        .collect()
}

fn assert_image(pixels: &[Estimate], want: &[[f64; 3]], what: &str) {
    let zero = vec![[0.0; 3]; want.len()];
    common::assert_pixels(pixels, want, &zero, what);
}

fn texture_png() -> PathBuf {
    common::data::existing(common::data::crate_root().join("tests/data/textures/checker4x2.png"))
}

/// A camera at z = 1 looking down −Z with a 90° vertical fov over W × H pixels:
/// the view at z = 0 is exactly [−2, 2] × [−1, 1], the quad of `quad()`.
fn camera(max_depth: u32, spp: u32) -> String {
    SceneText::camera([0.0, 0.0, 1.0], [0.0; 3], [W, H])
        .fov(90.0)
        .integrator(&format!("max_depth = {max_depth}\nspp = {spp}"))
        .build()
}

/// A quad at z = 0 facing the camera, u along +X and v along +Y, with `extra` keys.
fn quad(extra: &str) -> String {
    format!(
        r#"
        [[shape]]
        type = "quad"
        center = [0.0, 0.0, 0.0]
        normal = [0.0, 0.0, 1.0]
        u_axis = [1.0, 0.0, 0.0]
        size = [4.0, 2.0]
        {extra}
        "#
    )
}

/// Loads `text` written as `scene.toml` in `dir` (files resolve relative to it).
fn load_in(dir: &Path, text: &str) -> brume::integrator::Scene {
    let file = dir.join("scene.toml");
    std::fs::write(&file, text).unwrap();
    brume::scene::load(&file).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn diffuse_quad_under_a_uniform_sky_reproduces_its_albedo_texture() {
    let png = texture_png();
    let text = format!(
        "{}{}",
        camera(1, 64),
        quad(&format!(
            "material = {{ type = \"diffuse\", albedo = {{ type = \"image\", file = {:?}, wrap = \"clamp\" }} }}\n\
             [[light]]\ntype = \"environment\"\nradiance = 1.0\n",
            png.display().to_string()
        ))
    );
    let scene = common::scene_from_str(&text);
    let pixels = estimate_pixels(&scene, 64);
    // ∫ (albedo/π) cosθ L dω over the upper hemisphere = albedo · L.
    let want = expected(|u, v| bilinear(u, v, false, true));
    assert_image(&pixels, &want, "diffuse albedo texture, clamp");
}

#[test]
fn emissive_quad_seen_directly_shows_its_texture() {
    let png = texture_png();
    let text = format!(
        "{}{}",
        camera(0, 16),
        quad(&format!(
            "material = {{ type = \"diffuse\", albedo = 0.0 }}\n\
             emission = {{ type = \"image\", file = {:?}, scale = [2.0, 1.0, 0.5] }}\n",
            png.display().to_string()
        ))
    );
    let scene = common::scene_from_str(&text);
    let pixels = estimate_pixels(&scene, 16);
    let want = expected(|u, v| {
        let t = bilinear(u, v, true, true);
        [2.0 * t[0], t[1], 0.5 * t[2]]
    });
    assert_image(&pixels, &want, "emission texture, repeat");
}

#[test]
fn exr_emission_is_read_linear_and_png_can_be_declared_linear() {
    let dir = tempfile::tempdir().unwrap();
    // The same bytes over 255 as linear values in an EXR.
    let pixels: Vec<Rgb> = (0..2)
        .flat_map(|j| (0..4).map(move |i| (i, j)))
        .map(|(i, j)| {
            let t = texel(i, j, false);
            Rgb::new(t[0] as f32, t[1] as f32, t[2] as f32)
        })
        .collect();
    let image = brume::film::image_io::Image {
        width: 4,
        height: 2,
        pixels,
        spp: 1,
        partial: false,
    };
    brume::film::image_io::write_exr(&dir.path().join("tex.exr"), &image).unwrap();
    std::fs::copy(texture_png(), dir.path().join("tex.png")).unwrap();
    let want = expected(|u, v| bilinear(u, v, true, false));
    for emission in [
        "{ type = \"image\", file = \"tex.exr\" }",
        "{ type = \"image\", file = \"tex.png\", color_space = \"linear\" }",
    ] {
        let text = format!(
            "{}{}",
            camera(0, 16),
            quad(&format!("emission = {emission}\n"))
        );
        let scene = load_in(dir.path(), &text);
        let pixels = estimate_pixels(&scene, 16);
        // f32 texels: the EXR stores b/255 rounded to f32, within ROUNDING of the f64 value.
        assert_image(&pixels, &want, emission);
    }
}

#[test]
fn obj_quad_uses_its_vt_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(texture_png(), dir.path().join("tex.png")).unwrap();
    // The view's rectangle as two triangles, with u mirrored (u = 1 at x = −2),
    // so that coordinates taken from anything but `vt` show.
    std::fs::write(
        dir.path().join("quad.obj"),
        "v -2 -1 0\nv 2 -1 0\nv 2 1 0\nv -2 1 0\n\
         vt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\n\
         f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
    )
    .unwrap();
    let text = format!(
        "{}[[shape]]\ntype = \"mesh\"\nfile = \"quad.obj\"\n\
         emission = {{ type = \"image\", file = \"tex.png\", wrap = \"clamp\" }}\n",
        camera(0, 16)
    );
    let scene = load_in(dir.path(), &text);
    let pixels = estimate_pixels(&scene, 16);
    let want = expected(|u, v| bilinear(1.0 - u, v, false, true));
    assert_image(&pixels, &want, "OBJ vt, mirrored");
}

/// Irradiance at `p` (normal `n`) from a uniform polygon of radiance 1 (Lambert's formula).
fn polygon_irradiance(p: [f64; 3], n: [f64; 3], corners: &[[f64; 3]]) -> f64 {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |a: [f64; 3]| {
        let l = dot(a, a).sqrt();
        [a[0] / l, a[1] / l, a[2] / l]
    };
    let mut sum = 0.0;
    for k in 0..corners.len() {
        let a = unit(sub(corners[k], p));
        let b = unit(sub(corners[(k + 1) % corners.len()], p));
        let angle = dot(a, b).clamp(-1.0, 1.0).acos();
        sum += angle * dot(unit(cross(a, b)), n);
    }
    // E = L/2 · Σ Θ_k (γ_k · n), signed by the winding; |·| makes it orientation-free.
    0.5 * sum.abs()
}

#[test]
fn receiver_under_a_checkerboard_emitter_sees_each_square_at_its_radiance() {
    // Emitter: the square [−1, 1]² at y = 1 facing down, over a small receiver off its centre.
    let (a, b) = ([4.0, 1.0, 0.5], [0.2, 3.0, 1.0]);
    let p = [0.3, 0.0, -0.2];
    let text = SceneText::camera([0.3, 0.5, -0.2], p, [4, 4])
        .with("up = [0.0, 0.0, 1.0]")
        .fov(0.1)
        .integrator("max_depth = 1")
        .quad(p, [0.0, 1.0, 0.0], [0.01, 0.01])
        .with("material = { type = \"diffuse\", albedo = 1.0 }")
        .quad([0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [2.0, 2.0])
        .with(&format!(
            "u_axis = [1.0, 0.0, 0.0]\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n\
             emission = {{ type = \"checkerboard\", a = {a:?}, b = {b:?}, uv_scale = 1.5 }}"
        ))
        .build();
    let scene = common::scene_from_str(&text);
    // u along +X; v along normal × u = (−Y) × X = +Z. Corner (u, v) = (0, 0) at (−1, 1, −1).
    // uv_scale 1.5: a 3 × 3 board of squares 2/3 wide; square (i, k) has colour a when i + k is even.
    let mut e = [0.0; 3];
    for i in 0..3 {
        for k in 0..3 {
            let x0 = -1.0 + 2.0 * i as f64 / 3.0;
            let z0 = -1.0 + 2.0 * k as f64 / 3.0;
            let s = 2.0 / 3.0;
            let corners = [
                [x0, 1.0, z0],
                [x0 + s, 1.0, z0],
                [x0 + s, 1.0, z0 + s],
                [x0, 1.0, z0 + s],
            ];
            let irr = polygon_irradiance(p, [0.0, 1.0, 0.0], &corners);
            let l = if (i + k) % 2 == 0 { a } else { b };
            for c in 0..3 {
                e[c] += l[c] * irr;
            }
        }
    }
    let want = e.map(|v| v / std::f64::consts::PI);
    let pixels = estimate_pixels(&scene, 2048);
    assert_pixels_equal(&pixels, want, "checkerboard emitter over a receiver");
}

/// The texels of tests/data/mitsuba/ramp4x4.png (8-bit RGB, row 0 at the top).
const RAMP: [[u8; 3]; 16] = [
    [40, 30, 200],
    [90, 30, 160],
    [140, 30, 120],
    [190, 30, 80],
    [40, 90, 170],
    [90, 90, 130],
    [140, 90, 90],
    [190, 90, 50],
    [40, 150, 140],
    [90, 150, 100],
    [140, 150, 60],
    [190, 150, 20],
    [40, 210, 110],
    [90, 210, 70],
    [140, 210, 30],
    [190, 210, 10],
];

/// Mitsuba 3's `bitmap` of ramp4x4.png (`raw`) at five (u, v), as its
/// scalar_rgb variant prints them (`mi.load_dict({'type': 'bitmap', ...}).eval(si)`):
/// mirrored bilinear, mirrored nearest, clamped nearest, repeated nearest.
const MITSUBA_BITMAP: [(&str, &str, [[f32; 3]; 5]); 4] = [
    (
        "mirror",
        "bilinear",
        [
            [0.156863, 0.188235, 0.74902],
            [0.686275, 0.823529, 0.062745],
            [0.294118, 0.423529, 0.521569],
            [0.568627, 0.564706, 0.231373],
            [0.607843, 0.752941, 0.122353],
        ],
    ),
    (
        "mirror",
        "nearest",
        [
            [0.156863, 0.117647, 0.784314],
            [0.745098, 0.823529, 0.039216],
            [0.352941, 0.352941, 0.509804],
            [0.54902, 0.588235, 0.235294],
            [0.54902, 0.823529, 0.117647],
        ],
    ),
    (
        "clamp",
        "nearest",
        [
            [0.156863, 0.117647, 0.784314],
            [0.745098, 0.823529, 0.039216],
            [0.156863, 0.352941, 0.666667],
            [0.745098, 0.117647, 0.313726],
            [0.745098, 0.823529, 0.039216],
        ],
    ),
    (
        "repeat",
        "nearest",
        [
            [0.156863, 0.117647, 0.784314],
            [0.745098, 0.823529, 0.039216],
            [0.54902, 0.352941, 0.352941],
            [0.352941, 0.352941, 0.509804],
            [0.54902, 0.117647, 0.470588],
        ],
    ),
];

/// brume's mirror wrap and nearest filter are Mitsuba's: an image looked up
/// at (u, 1 − v) through `uv_scale = [1, −1]`, `uv_offset = [0, 1]` (Mitsuba's
/// rows run down) gives Mitsuba's bitmap values, inside and outside [0, 1]².
/// Seen failing with the mirror taken as a repeat, and with nearest taken as
/// bilinear.
#[test]
fn mirrored_and_nearest_lookups_match_mitsubas_bitmap() {
    use brume::material::texture::{Filter, Image, Texture, Wrap};
    use brume::math::Vec2;
    let points = [
        (0.1, 0.2),
        (0.8, 0.9),
        (-0.3, 0.45),
        (1.35, -0.6),
        (2.7, 1.2),
    ];
    let texels: Vec<Rgb> = RAMP
        .iter()
        .map(|t| {
            Rgb::new(
                t[0] as f32 / 255.0,
                t[1] as f32 / 255.0,
                t[2] as f32 / 255.0,
            )
        })
        .collect();
    for (wrap, filter, expected) in MITSUBA_BITMAP {
        let wrap_mode = match wrap {
            "mirror" => Wrap::Mirror,
            "clamp" => Wrap::Clamp,
            _ => Wrap::Repeat,
        };
        let texture = Texture::Image {
            image: std::sync::Arc::new(Image::new(4, 4, texels.clone(), wrap_mode).unwrap()),
            scale: Rgb::WHITE,
            uv_scale: Vec2::new(1.0, -1.0),
            uv_offset: Vec2::new(0.0, 1.0),
            filter: match filter {
                "nearest" => Filter::Nearest,
                _ => Filter::Bilinear,
            },
        };
        for ((u, v), want) in points.into_iter().zip(expected) {
            let got = texture.eval(Vec2::new(u, v));
            let got = [got.r, got.g, got.b];
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() < 2e-5,
                    "{wrap} {filter} at ({u}, {v}): {got:?} vs Mitsuba's {want:?}"
                );
            }
        }
    }
}

/// tests/data/mitsuba/ramp4x4.jpg is ramp4x4.png saved as a JPEG (quality
/// 100, no chroma subsampling, by Pillow): decoded, its samples are the
/// PNG's within JPEG's rounding (3/255), row 0 at the top.
#[test]
fn a_jpeg_decodes_to_its_pixels() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba/ramp4x4.jpg");
    let (w, h, pixels) = brume::film::image_io::read_jpeg(&path).unwrap();
    assert_eq!((w, h), (4, 4));
    for (i, (got, want)) in pixels.iter().zip(RAMP).enumerate() {
        for c in 0..3 {
            assert!(
                (got[c] * 255.0 - want[c] as f32).abs() <= 3.0,
                "pixel {i}: {got:?} vs {want:?}"
            );
        }
    }
}
