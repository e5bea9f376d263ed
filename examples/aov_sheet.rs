//! Lays out the layers of a brume EXR side by side in one PNG, for docs:
//! beauty, alpha, depth, normal, albedo, transmittance (and denoised, if present).
//!
//! `cargo run --release --example aov_sheet -- render.exr sheet.png`

use brume::film::image_io::{read_exr_channels, write_png_srgb8, NamedChannel};
use brume::film::tonemap::Tonemap;

/// One panel: three display values in [0, 1] per pixel, from the layer's channels.
fn panel(
    channels: &[NamedChannel],
    names: [&str; 3],
    map: impl Fn(f32) -> f32,
) -> Option<Vec<[f32; 3]>> {
    let get = |n: &str| channels.iter().find(|(c, _)| c == n).map(|(_, v)| v);
    let (a, b, c) = (get(names[0])?, get(names[1])?, get(names[2])?);
    Some(
        (0..a.len())
            .map(|i| [map(a[i]), map(b[i]), map(c[i])])
            .collect(),
    )
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (input, output) = (&args[1], &args[2]);
    let (w, h, channels) = read_exr_channels(input.as_ref()).expect("read EXR");
    let srgb = |v: f32| brume::math::color::linear_to_srgb(Tonemap::Aces.apply(v));
    let depth = channels
        .iter()
        .find(|(n, _)| n == "depth.Z")
        .map(|(_, v)| v.clone());
    let far = depth
        .iter()
        .flatten()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0f32, f32::max)
        .max(1e-6);
    let mut panels = Vec::new();
    panels.extend(panel(&channels, ["R", "G", "B"], srgb));
    panels.extend(panel(&channels, ["A", "A", "A"], |v| v.clamp(0.0, 1.0)));
    panels.extend(panel(&channels, ["depth.Z"; 3], |d| {
        if d.is_finite() {
            1.0 - d / far
        } else {
            0.0
        }
    }));
    panels.extend(panel(
        &channels,
        ["normal.X", "normal.Y", "normal.Z"],
        |n| (0.5 * n + 0.5).clamp(0.0, 1.0),
    ));
    let linear = brume::math::color::linear_to_srgb;
    panels.extend(panel(
        &channels,
        ["albedo.R", "albedo.G", "albedo.B"],
        linear,
    ));
    let transmittance = ["transmittance.R", "transmittance.G", "transmittance.B"];
    panels.extend(panel(&channels, transmittance, linear));
    panels.extend(panel(
        &channels,
        ["denoised.R", "denoised.G", "denoised.B"],
        srgb,
    ));
    let gap = 4;
    let sheet_w = panels.len() * (w + gap) - gap;
    let mut bytes = vec![255u8; sheet_w * h * 3];
    for (k, p) in panels.iter().enumerate() {
        for y in 0..h {
            for x in 0..w {
                let at = (y * sheet_w + k * (w + gap) + x) * 3;
                for c in 0..3 {
                    bytes[at + c] = (p[y * w + x][c] * 255.0 + 0.5) as u8;
                }
            }
        }
    }
    write_png_srgb8(output.as_ref(), sheet_w as u32, h as u32, &bytes).expect("write PNG");
    println!("wrote {output}: {} panels of {w}x{h}", panels.len());
}
