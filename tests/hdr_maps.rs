//! Radiance `.hdr` (RGBE) images as environment maps and textures: one
//! generator writes the same map as EXR and as `.hdr` (run-length encoded and
//! flat), which must read and render equal within RGBE's quantisation; and
//! damaged files are refused through the command line with one line.

#[path = "common/mod.rs"]
mod common;

use brume::film::image_io::{read_exr, read_hdr, write_exr, Image};
use brume::math::color::Rgb;
use common::cli::{assert_refused, brume};
use common::scene_from_str;
use std::path::Path;

/// A map with smooth gradients, runs of equal pixels and a bright block,
/// spanning several exponents.
fn texels(width: usize, height: usize) -> Vec<Rgb> {
    (0..width * height)
        .map(|i| {
            let (x, y) = ((i % width) as f32, (i / width) as f32);
            if y < 2.0 {
                Rgb::new(0.25, 0.5, 1.0) // runs
            } else if (x as usize / 8, y as usize / 4) == (1, 1) {
                Rgb::new(40.0, 35.0, 30.0)
            } else {
                Rgb::new(0.01 + x / 30.0, 0.3 + y / 10.0, 2.0 + (x * y).sin())
            }
        })
        .collect()
}

/// RGBE of one pixel as Radiance's `setcolr` writes it (mantissas truncated).
fn rgbe(c: Rgb) -> [u8; 4] {
    let m = c.max_channel();
    if m < 1e-32 {
        return [0; 4];
    }
    let e = m.log2().floor() as i32 + 1; // m = f·2^e, f in [0.5, 1)
    let scale = 256.0 / (e as f32).exp2();
    let q = |v: f32| (v * scale).floor().clamp(0.0, 255.0) as u8;
    [q(c.r), q(c.g), q(c.b), (e + 128) as u8]
}

/// Runs of one component: (count > 128 | byte) for repeats of 3 or more, else literals.
fn rle_component(bytes: &[u8], out: &mut Vec<u8>) {
    let mut i = 0;
    while i < bytes.len() {
        let run = bytes[i..]
            .iter()
            .take(127)
            .take_while(|&&b| b == bytes[i])
            .count();
        if run >= 3 {
            out.extend([128 + run as u8, bytes[i]]);
            i += run;
            continue;
        }
        let start = i;
        while i < bytes.len() && i - start < 128 {
            let ahead = bytes[i..]
                .iter()
                .take(3)
                .take_while(|&&b| b == bytes[i])
                .count();
            if ahead >= 3 {
                break;
            }
            i += 1;
        }
        out.push((i - start) as u8);
        out.extend(&bytes[start..i]);
    }
}

/// A `.hdr` file of the map, scanlines run-length encoded or flat, with `header` lines.
fn hdr_bytes(width: usize, height: usize, pixels: &[Rgb], rle: bool, header: &str) -> Vec<u8> {
    let mut out = format!("#?RADIANCE\n{header}FORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n")
        .into_bytes();
    for row in pixels.chunks(width) {
        let px: Vec<[u8; 4]> = row.iter().map(|&c| rgbe(c)).collect();
        if rle {
            out.extend([2, 2, (width >> 8) as u8, width as u8]);
            for c in 0..4 {
                let comp: Vec<u8> = px.iter().map(|p| p[c]).collect();
                rle_component(&comp, &mut out);
            }
        } else {
            px.iter().for_each(|p| out.extend(p));
        }
    }
    out
}

fn write_both(dir: &Path, width: usize, height: usize) -> Vec<Rgb> {
    let pixels = texels(width, height);
    let image = Image {
        width,
        height,
        pixels: pixels.clone(),
        spp: 1,
        partial: false,
    };
    write_exr(&dir.join("map.exr"), &image).unwrap();
    std::fs::write(
        dir.join("map.hdr"),
        hdr_bytes(width, height, &pixels, true, ""),
    )
    .unwrap();
    let flat = hdr_bytes(width, height, &pixels, false, "EXPOSURE=1.0\n");
    std::fs::write(dir.join("flat.hdr"), flat).unwrap();
    pixels
}

/// RGBE keeps 8 bits of the largest channel: each channel is within half a
/// step, max/256, of its value (the step is at most max/128).
fn assert_quantised(got: Rgb, want: Rgb, what: &str) {
    let tolerance = want.max_channel() / 256.0 * (1.0 + 1e-5);
    for c in 0..3 {
        assert!(
            (got[c] - want[c]).abs() <= tolerance,
            "{what}: channel {c}: {} vs {}",
            got[c],
            want[c]
        );
    }
}

#[test]
fn hdr_reads_like_the_same_map_written_as_exr() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (45, 12);
    write_both(dir.path(), w, h);
    let (ew, eh, exr) = read_exr(&dir.path().join("map.exr")).unwrap();
    assert_eq!((ew, eh), (w, h));
    let rle_len = std::fs::metadata(dir.path().join("map.hdr")).unwrap().len();
    let flat_len = std::fs::metadata(dir.path().join("flat.hdr"))
        .unwrap()
        .len();
    assert!(
        rle_len < flat_len,
        "the RLE file is compressed: {rle_len} vs {flat_len}"
    );
    for name in ["map.hdr", "flat.hdr"] {
        let (hw, hh, hdr) = read_hdr(&dir.path().join(name)).unwrap();
        assert_eq!((hw, hh), (w, h), "{name}");
        for (i, (&a, &b)) in hdr.iter().zip(&exr).enumerate() {
            assert_quantised(a, b, &format!("{name} pixel {i}"));
        }
    }
}

/// A camera that sees only the environment (its rays miss everything), or
/// a quad emitting the texture in front of it: each pixel is a lookup.
fn lookups(dir: &Path, map: &str, as_texture: bool) -> Vec<Rgb> {
    let file = dir.join(map).display().to_string().replace('\\', "/");
    let body = if as_texture {
        format!(
            "[[shape]]\ntype = \"quad\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nsize = [4.0, 4.0]\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\nemission = {{ type = \"image\", file = \"{file}\" }}\n"
        )
    } else {
        format!("[[light]]\ntype = \"environment_map\"\nfile = \"{file}\"\n")
    };
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 60.0\nresolution = [16, 12]\n[integrator]\nspp = 1\nmax_depth = 1\n{body}"
    );
    let scene = scene_from_str(&text);
    let mut out = Vec::new();
    for y in 0..12 {
        for x in 0..16 {
            out.push(brume::render::pixel_sample(&scene, x, y, 0));
        }
    }
    out
}

#[test]
fn hdr_environment_maps_and_textures_render_like_their_exr_twins() {
    let dir = tempfile::tempdir().unwrap();
    let pixels = write_both(dir.path(), 45, 12);
    let brightest = pixels.iter().map(|c| c.max_channel()).fold(0.0, f32::max);
    for as_texture in [false, true] {
        let exr = lookups(dir.path(), "map.exr", as_texture);
        let hdr = lookups(dir.path(), "map.hdr", as_texture);
        assert!(exr.iter().any(|c| c.max_channel() > 0.0));
        for (i, (a, b)) in hdr.iter().zip(&exr).enumerate() {
            // A lookup blends texels: within the brightest texel's half step.
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= brightest / 256.0 * 1.0001,
                    "texture {as_texture} pixel {i}: {a:?} vs {b:?}"
                );
            }
        }
    }
}

/// Damaged or unsupported files through `brume render`: exit 2, one line
/// naming the key and the file.
#[test]
fn damaged_hdr_files_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (64, 64);
    let pixels = texels(w, h);
    let good = hdr_bytes(w, h, &pixels, true, "");
    let header_end = good.windows(2).position(|p| p == b"\n-").unwrap() + 1;
    let header_len = header_end + format!("-Y {h} +X {w}\n").len();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "text",
            b"hello, world\n".to_vec(),
            "not a Radiance HDR image",
        ),
        (
            "cut below what the size needs",
            good[..header_len + 100].to_vec(),
            "declares 64x64 pixels",
        ),
        (
            "cut inside a scanline",
            good[..good.len() - 40].to_vec(),
            "truncated",
        ),
        (
            "huge declared size",
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 200000 +X 200000\n\x02\x02".to_vec(),
            "declares 200000x200000 pixels",
        ),
        (
            "other orientation",
            String::from_utf8_lossy(&good[..header_len])
                .replace("-Y 64 +X 64", "+Y 64 +X 64")
                .into_bytes(),
            "orientation `+Y 64 +X 64` is not supported",
        ),
        (
            "xyze",
            b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\0\0\0\0".to_vec(),
            "FORMAT=32-bit_rle_xyze is not supported",
        ),
        (
            "no end of header",
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n".to_vec(),
            "ends inside its header",
        ),
    ];
    for (what, bytes, message) in cases {
        std::fs::write(dir.path().join("sky.hdr"), &bytes).unwrap();
        let scene = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [4, 4]\n[[light]]\ntype = \"environment_map\"\nfile = \"sky.hdr\"\n";
        std::fs::write(dir.path().join("s.toml"), scene).unwrap();
        let out = brume()
            .current_dir(dir.path())
            .args(["render", "s.toml"])
            .output()
            .unwrap();
        assert_refused(&out, &["light[0].file", "sky.hdr", message], what);
        assert!(!dir.path().join("s.exr").exists(), "{what}: wrote an image");
    }
}
