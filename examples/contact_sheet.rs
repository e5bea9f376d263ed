//! Tiles brume EXRs of one size into one PNG (a contact sheet of frames), for docs.
//!
//! `cargo run --release --example contact_sheet -- COLUMNS sheet.png a.exr b.exr …`
//! The panels run left to right, then top to bottom, tone-mapped like `brume
//! render --png` with its default (ACES, exposure 0).

use brume::film::image_io::{read_exr, write_png_srgb8};
use brume::film::tonemap::Tonemap;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: contact_sheet COLUMNS sheet.png a.exr b.exr …";
    let (Some(columns), Some(output)) = (args.first(), args.get(1)) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let columns: usize = match columns.parse() {
        Ok(c) if c > 0 => c,
        _ => {
            eprintln!("COLUMNS must be a whole number above 0, got `{columns}`; {usage}");
            std::process::exit(2);
        }
    };
    let inputs = &args[2..];
    if inputs.is_empty() {
        eprintln!("{usage}");
        std::process::exit(2);
    }
    let mut panels = Vec::new();
    for input in inputs {
        match read_exr(input.as_ref()) {
            Ok(p) => panels.push(p),
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(2);
            }
        }
    }
    let (w, h) = (panels[0].0, panels[0].1);
    if let Some(k) = panels.iter().position(|p| (p.0, p.1) != (w, h)) {
        eprintln!(
            "error: {} is {}x{}, but {} is {w}x{h}: every panel must have one size",
            inputs[k], panels[k].0, panels[k].1, inputs[0]
        );
        std::process::exit(2);
    }
    let gap = 4;
    let columns = columns.min(panels.len());
    let rows = panels.len().div_ceil(columns);
    let sheet_w = columns * (w + gap) - gap;
    let sheet_h = rows * (h + gap) - gap;
    let mut bytes = vec![255u8; sheet_w * sheet_h * 3];
    let srgb = |v: f32| brume::math::color::linear_to_srgb(Tonemap::Aces.apply(v));
    for (k, (_, _, pixels)) in panels.iter().enumerate() {
        let (x0, y0) = ((k % columns) * (w + gap), (k / columns) * (h + gap));
        for y in 0..h {
            for x in 0..w {
                let p = pixels[y * w + x];
                let at = ((y0 + y) * sheet_w + x0 + x) * 3;
                for (c, v) in [p.r, p.g, p.b].into_iter().enumerate() {
                    bytes[at + c] = (srgb(v).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
                }
            }
        }
    }
    if let Err(e) = write_png_srgb8(output.as_ref(), sheet_w as u32, sheet_h as u32, &bytes) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
