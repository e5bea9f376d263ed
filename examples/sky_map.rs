//! Writes `scenes/sky.exr`, the procedural HDR sky of the gallery and tests.
//!
//! Run: `cargo run --release --example sky_map [OUT.exr]`.
//!
//! The sky is made here, not photographed: a lat-long map (brume's
//! convention, see `brume::light::envmap`) holding a blue gradient from a pale
//! horizon to a deep zenith, a bright aureole around the sun's direction
//! (the sun disk itself stays a separate `sun` light in the scenes) and a
//! dim, warm ground below the horizon with a soft transition.

use brume::film::image_io::{write_exr, Image};
use brume::math::color::Rgb;
use brume::math::Vec3;
use std::f32::consts::PI;
use std::path::PathBuf;

const WIDTH: usize = 256;
const HEIGHT: usize = 128;

/// Radiance of the sky toward `d` with the sun toward `to_sun`.
fn sky(d: Vec3, to_sun: Vec3) -> Rgb {
    let zenith = Rgb::new(0.10, 0.22, 0.60);
    let horizon = Rgb::new(0.55, 0.65, 0.80);
    let ground = Rgb::new(0.16, 0.14, 0.11);
    let h = d.y;
    let base = if h >= 0.0 {
        let s = h.powf(0.4);
        horizon * (1.0 - s) + zenith * s
    } else {
        // A few degrees of blend so the horizon is not a hard edge.
        let t = (-h / 0.05).min(1.0);
        horizon * (1.0 - t) + ground * t
    };
    let cos_sun = d.dot(to_sun).clamp(-1.0, 1.0);
    let angle = cos_sun.acos();
    // Aureole: strong forward scattering around the sun, warm tinted.
    let aureole = Rgb::new(3.0, 2.6, 2.0) * (-angle / 0.08).exp()
        + Rgb::new(0.5, 0.45, 0.35) * (-angle / 0.5).exp();
    if h >= -0.02 {
        base + aureole
    } else {
        base
    }
}

fn main() {
    let out = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/sky.exr"));
    // The gallery cloud's sun travels along (-0.6, -0.6, 0.5).
    let to_sun = Vec3::new(0.6, 0.6, -0.5).normalize();
    let mut pixels = Vec::with_capacity(WIDTH * HEIGHT);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let theta = PI * (y as f32 + 0.5) / HEIGHT as f32;
            let phi = 2.0 * PI * (x as f32 + 0.5) / WIDTH as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            pixels.push(sky(d, to_sun));
        }
    }
    let image = Image {
        width: WIDTH,
        height: HEIGHT,
        pixels,
        spp: 1,
        partial: false,
    };
    if let Err(e) = write_exr(&out, &image) {
        eprintln!("{e}");
        std::process::exit(1);
    }
    println!("wrote {}", out.display());
}
