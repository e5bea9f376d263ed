//! Bad textures: every case exits with code 2 and prints one error line
//! naming the scene file, the key path as written and, for files, the
//! texture or OBJ file; never a panic, never a touched output.

mod common;

use common::cli::assert_scene_refused;
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image as ExrImage, Layer as ExrLayer,
    LayerAttributes, SmallVec, WritableImage,
};
use std::path::Path;

const HEAD: &str =
    "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [4, 4]\n\
    [[light]]\ntype = \"environment\"\nradiance = 1.0\n";

/// A quad whose `key` (e.g. `emission`, `material`) is `value`.
fn quad(key: &str, value: &str) -> String {
    format!(
        "{HEAD}[[shape]]\ntype = \"quad\"\nnormal = [0.0, 0.0, 1.0]\nsize = [1.0, 1.0]\n{key} = {value}\n"
    )
}

/// A unit sphere with `uv_axes = axes`.
fn sphere(axes: &str) -> String {
    format!("{HEAD}[[shape]]\ntype = \"sphere\"\nradius = 1.0\nuv_axes = {axes}\n")
}

fn albedo(texture: &str) -> String {
    quad(
        "material",
        &format!("{{ type = \"diffuse\", albedo = {texture} }}"),
    )
}

/// Writes an 8-bit RGBA PNG of 2 × 1 pixels with the given alphas.
fn write_rgba_png(path: &Path, alpha: [u8; 2]) {
    let file = std::fs::File::create(path).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), 2, 1);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer
        .write_image_data(&[10, 20, 30, alpha[0], 40, 50, 60, alpha[1]])
        .unwrap();
}

/// Writes a 2 × 2 EXR with the named float channels.
fn write_exr(path: &Path, channels: &[(&str, [f32; 4])]) {
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .iter()
        .map(|(name, v)| AnyChannel::new(*name, FlatSamples::F32(v.to_vec())))
        .collect();
    let layer = ExrLayer::new(
        (2, 2),
        LayerAttributes::named(""),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(list),
    );
    ExrImage::from_layer(layer).write().to_file(path).unwrap();
}

/// Files the cases refer to, in the scene's folder.
fn setup(dir: &Path) {
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/textures/checker4x2.png"),
        dir.join("good.png"),
    )
    .unwrap();
    std::fs::write(dir.join("corrupt.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    std::fs::write(dir.join("picture.jpg"), b"JFIF").unwrap();
    std::fs::write(dir.join("picture.tif"), b"II*\0").unwrap();
    let jpeg =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba/ramp4x4.jpg"))
            .unwrap();
    std::fs::write(dir.join("truncated.jpg"), &jpeg[..jpeg.len() / 2]).unwrap();
    // The same file declaring 60000 x 60000 pixels in its frame header (SOF0).
    let mut bomb = jpeg.clone();
    let sof = bomb
        .windows(2)
        .position(|w| w == [0xff, 0xc0])
        .expect("a baseline JPEG");
    bomb[sof + 5..sof + 9].copy_from_slice(&[0xea, 0x60, 0xea, 0x60]);
    std::fs::write(dir.join("bomb.jpg"), bomb).unwrap();
    write_rgba_png(&dir.join("opaque.png"), [255, 255]);
    write_rgba_png(&dir.join("cutout.png"), [255, 0]);
    write_exr(
        &dir.join("negative.exr"),
        &[
            ("R", [1.0; 4]),
            ("G", [1.0, -0.5, 1.0, 1.0]),
            ("B", [1.0; 4]),
        ],
    );
    write_exr(&dir.join("depth.exr"), &[("Z", [1.0; 4])]);
    write_exr(&dir.join("bright.exr"), &[("Y", [0.5, 2.0, 0.5, 0.5])]);
    std::fs::write(dir.join("flat.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
}

/// (name, scene text, texts the error must contain).
fn cases() -> Vec<(&'static str, String, Vec<&'static str>)> {
    let img = |extra: &str| format!("{{ type = \"image\", file = \"good.png\"{extra} }}");
    vec![
        ("missing file", albedo("{ type = \"image\", file = \"nope.png\" }"), vec!["shape[0].material.albedo.file", "nope.png"]),
        ("no file key", albedo("{ type = \"image\" }"), vec!["shape[0].material.albedo.file", "missing"]),
        ("corrupt png", quad("emission", "{ type = \"image\", file = \"corrupt.png\" }"), vec!["shape[0].emission.file", "corrupt.png"]),
        ("not a jpeg", albedo("{ type = \"image\", file = \"picture.jpg\" }"), vec!["shape[0].material.albedo.file", "picture.jpg", "not a JPEG image"]),
        ("not png, jpeg, exr or hdr", albedo("{ type = \"image\", file = \"picture.tif\" }"), vec!["shape[0].material.albedo.file", "picture.tif", ".png, .jpg"]),
        ("truncated jpeg", albedo("{ type = \"image\", file = \"truncated.jpg\" }"), vec!["shape[0].material.albedo.file", "truncated.jpg"]),
        ("jpeg declaring 60000x60000", albedo("{ type = \"image\", file = \"bomb.jpg\" }"), vec!["shape[0].material.albedo.file", "bomb.jpg", "60000x60000", "at least"]),
        ("a folder", albedo("{ type = \"image\", file = \".\" }"), vec!["shape[0].material.albedo.file"]),
        ("unknown texture type", albedo("{ type = \"noise\" }"), vec!["shape[0].material.albedo.type", "noise"]),
        ("missing type", albedo("{ file = \"good.png\" }"), vec!["shape[0].material.albedo", "type"]),
        ("unknown key", albedo(&img(", repeat = true")), vec!["shape[0].material.albedo", "repeat"]),
        ("key of the other type", albedo("{ type = \"checkerboard\", a = 0.1, b = 0.9, file = \"good.png\" }"), vec!["shape[0].material.albedo.file", "checkerboard"]),
        ("bad wrap", albedo(&img(", wrap = \"tile\"")), vec!["shape[0].material.albedo.wrap", "tile"]),
        ("bad filter", albedo(&img(", filter = \"cubic\"")), vec!["shape[0].material.albedo.filter", "cubic"]),
        ("filter on a checkerboard", albedo("{ type = \"checkerboard\", a = 0.1, b = 0.9, filter = \"nearest\" }"), vec!["shape[0].material.albedo.filter", "checkerboard"]),
        ("nan uv_offset", albedo(&img(", uv_offset = [0.5, nan]")), vec!["shape[0].material.albedo.uv_offset[1]"]),
        ("bad colour space", albedo(&img(", color_space = \"aces\"")), vec!["shape[0].material.albedo.color_space", "aces"]),
        ("srgb exr", quad("emission", "{ type = \"image\", file = \"bright.exr\", color_space = \"srgb\" }"), vec!["shape[0].emission.color_space", "PNG and JPEG only"]),
        ("a string", albedo("\"good.png\""), vec!["shape[0].material.albedo", "texture table"]),
        ("negative checker colour", quad("emission", "{ type = \"checkerboard\", a = -1.0, b = 1.0 }"), vec!["shape[0].emission.a", "negative"]),
        ("nan checker channel", quad("emission", "{ type = \"checkerboard\", a = [1.0, nan, 1.0], b = 1.0 }"), vec!["shape[0].emission.a[1]"]),
        ("missing checker colour", quad("emission", "{ type = \"checkerboard\", a = 1.0 }"), vec!["shape[0].emission.b", "missing"]),
        ("checker albedo above one", albedo("{ type = \"checkerboard\", a = 0.5, b = 1.5 }"), vec!["shape[0].material.albedo.b"]),
        ("albedo texels above one", albedo(&img(", scale = 5.0")), vec!["shape[0].material.albedo.file", "above 1"]),
        ("exr albedo above one", albedo("{ type = \"image\", file = \"bright.exr\" }"), vec!["shape[0].material.albedo.file", "texel (1, 0)"]),
        ("negative scale", quad("emission", &img(", scale = -1.0")), vec!["shape[0].emission.scale"]),
        ("zero uv_scale", albedo(&img(", uv_scale = 0.0")), vec!["shape[0].material.albedo.uv_scale"]),
        ("infinite uv_scale channel", albedo(&img(", uv_scale = [1.0, inf]")), vec!["shape[0].material.albedo.uv_scale[1]"]),
        ("transparent png", quad("emission", "{ type = \"image\", file = \"cutout.png\" }"), vec!["shape[0].emission.file", "cutout.png", "alpha"]),
        ("negative exr texel", quad("emission", "{ type = \"image\", file = \"negative.exr\" }"), vec!["shape[0].emission.file", "negative.exr", "texel (1, 0)"]),
        ("exr without colour channels", quad("emission", "{ type = \"image\", file = \"depth.exr\" }"), vec!["shape[0].emission.file", "depth.exr", "R, G and B"]),
        ("textured mesh without vt", format!("{HEAD}[[shape]]\ntype = \"mesh\"\nfile = \"flat.obj\"\nmaterial = {{ type = \"diffuse\", albedo = {} }}\n", img("")), vec!["shape[0].material.albedo", "flat.obj", "vt"]),
        ("textured mesh emission without vt", format!("{HEAD}[[shape]]\ntype = \"mesh\"\nfile = \"flat.obj\"\nemission = {{ type = \"checkerboard\", a = 1.0, b = 2.0 }}\n"), vec!["shape[0].emission", "flat.obj", "vt"]),
        ("zero uv_axes pole", sphere("{ pole = [0.0, 0.0, 0.0], seam = [1.0, 0.0, 0.0] }"), vec!["shape[0].uv_axes.pole", "zero"]),
        ("slanted uv_axes seam", sphere("{ pole = [0.0, 1.0, 0.0], seam = [1.0, 0.5, 0.0] }"), vec!["shape[0].uv_axes.seam", "perpendicular"]),
        ("nan uv_axes seam", sphere("{ pole = [0.0, 1.0, 0.0], seam = [nan, 0.0, 0.0] }"), vec!["shape[0].uv_axes.seam[0]"]),
        ("uv_axes without a seam", sphere("{ pole = [0.0, 1.0, 0.0] }"), vec!["shape[0].uv_axes", "seam"]),
        ("unknown face_uv", format!("{HEAD}[[shape]]\ntype = \"box\"\nsize = [1.0, 1.0, 1.0]\nface_uv = \"pbrt\"\n"), vec!["shape[0].face_uv", "pbrt"]),
        ("face_uv on a sphere", sphere("{ pole = [0.0, 1.0, 0.0], seam = [1.0, 0.0, 0.0] }\nface_uv = \"mitsuba\""), vec!["shape[0].face_uv", "sphere"]),
        ("uv_axes on a quad", quad("uv_axes", "{ pole = [0.0, 1.0, 0.0], seam = [1.0, 0.0, 0.0] }"), vec!["shape[0].uv_axes", "quad"]),
        ("uv_axes on a moving sphere", format!("{HEAD}[[shape]]\ntype = \"sphere\"\nradius = 1.0\nuv_axes = {{ pole = [0.0, 1.0, 0.0], seam = [1.0, 0.0, 0.0] }}\ntransform = {{ keyframes = [{{ time = 0.0 }}, {{ time = 1.0, translate = [1.0, 0.0, 0.0] }}] }}\n"), vec!["shape[0].uv_axes", "moving"]),
        ("textured mirror", quad("material", "{ type = \"mirror\", reflectance = { type = \"image\", file = \"nope.png\" } }"), vec!["shape[0].material.reflectance.file"]),
        ("textured conductor f0", quad("material", "{ type = \"conductor\", f0 = { type = \"checkerboard\", a = 0.5, b = 2.0 } }"), vec!["shape[0].material.f0.b"]),
    ]
}

#[test]
fn every_bad_texture_gives_one_clear_error_line_and_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let none: [&str; 0] = [];
    for (i, (name, text, culprits)) in cases().iter().enumerate() {
        let file = format!("case{i}.toml");
        assert_scene_refused(dir.path(), &file, text, &none, culprits, name);
    }
}

#[test]
fn good_textures_of_every_channel_layout_load() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    for (key, value) in [
        ("emission", "{ type = \"image\", file = \"opaque.png\" }"),
        ("emission", "{ type = \"image\", file = \"bright.exr\", wrap = \"clamp\" }"),
        ("emission", "{ type = \"checkerboard\", a = 1.0, b = [0.0, 2.0, 3.0], uv_scale = [2.0, 3.0] }"),
        ("material", "{ type = \"phong\", exponent = 10.0, albedo = { type = \"image\", file = \"good.png\" } }"),
        ("material", "{ type = \"conductor\", alpha = 0.2, f0 = { type = \"image\", file = \"good.png\" } }"),
    ] {
        let file = dir.path().join("ok.toml");
        std::fs::write(&file, quad(key, value)).unwrap();
        let loaded = brume::scene::load_with_inputs(&file).unwrap_or_else(|e| panic!("{value}: {e}"));
        assert!(loaded.warnings.is_empty(), "{value}: {:?}", loaded.warnings);
        if let Some(name) = value.split('"').nth(3).filter(|n| n.contains('.')) {
            assert!(
                loaded.inputs.iter().any(|p| p.ends_with(name)),
                "{value}: texture not listed among the inputs {:?}",
                loaded.inputs
            );
        }
    }
}
