//! Denoising the beauty with Intel Open Image Denoise (cargo feature
//! `denoise`), guided by the albedo and normal AOVs.
//!
//! OIDN's `RT` filter in HDR mode takes the linear beauty and, optionally,
//! albedo and normal images of the first vertex (brume's `albedo` and
//! `normal` AOVs, noisy themselves: `cleanAux` stays off, so OIDN also
//! denoises them). The result is written as its own EXR layer
//! (`denoised.R/G/B`); the beauty stays the unbiased estimate.

use crate::film::image_io::NamedChannel;
use crate::film::{Film, Layer};
use crate::math::color::Rgb;

/// Channels of the denoised layer.
pub const CHANNELS: [&str; 3] = ["denoised.R", "denoised.G", "denoised.B"];

/// True when this build can denoise (the `denoise` feature is on).
pub const AVAILABLE: bool = cfg!(feature = "denoise");

/// What `--denoise` says in a build without the feature.
pub const UNAVAILABLE: &str =
    "this brume was built without the `denoise` feature (see docs/outputs.md)";

/// The `denoised.R/G/B` channels of `film`'s beauty, guided by its albedo
/// and normal layers (a render's, or the sums of merged pieces').
pub fn denoise_film(film: &Film) -> Result<Vec<NamedChannel>, String> {
    let (Some(albedo), Some(normal)) = (film.layer("albedo"), film.layer("normal")) else {
        return Err(
            "denoising needs the albedo and normal layers, which these pieces do not hold; \
             render them with --denoise (or --aovs albedo,normal)"
                .into(),
        );
    };
    let n = film.window.area();
    let means = |l: &Layer| -> [Vec<f32>; 3] {
        std::array::from_fn(|c| (0..n).map(|i| film.mean(l, i, c)).collect())
    };
    let (a, nm) = (means(albedo), means(normal));
    let image = film.beauty_image();
    let denoised = denoise(
        image.width,
        image.height,
        &image.pixels,
        [&a[0], &a[1], &a[2]],
        [&nm[0], &nm[1], &nm[2]],
    )?;
    Ok(CHANNELS
        .iter()
        .zip(denoised)
        .map(|(name, values)| (name.to_string(), values))
        .collect())
}

/// Interleaves three planar channels into RGBRGB… for OIDN.
#[cfg_attr(not(feature = "denoise"), allow(dead_code))]
fn interleave(c: [&[f32]; 3]) -> Vec<f32> {
    (0..c[0].len())
        .flat_map(|i| [c[0][i], c[1][i], c[2][i]])
        .collect()
}

/// Denoises `beauty` (`width`×`height`) with planar albedo and normal
/// channels; returns the three planar channels of `CHANNELS`.
#[cfg(feature = "denoise")]
pub fn denoise(
    width: usize,
    height: usize,
    beauty: &[Rgb],
    albedo: [&[f32]; 3],
    normal: [&[f32]; 3],
) -> Result<[Vec<f32>; 3], String> {
    let color: Vec<f32> = beauty.iter().flat_map(|c| [c.r, c.g, c.b]).collect();
    let albedo = interleave(albedo);
    let normal = interleave(normal);
    let mut output = vec![0.0f32; color.len()];
    let device = oidn::Device::new().map_err(|e| format!("OIDN device: {e}"))?;
    let mut filter = oidn::RayTracing::try_new(&device).map_err(|e| format!("OIDN filter: {e}"))?;
    filter
        .hdr(true)
        .srgb(false)
        .clean_aux(false)
        .image_dimensions(width, height)
        .albedo_normal(&albedo, &normal);
    filter
        .filter(&color, &mut output)
        .map_err(|e| format!("OIDN: {e}"))?;
    device.get_error().map_err(|e| format!("OIDN: {e}"))?;
    let planar = |c: usize| output.iter().skip(c).step_by(3).copied().collect();
    Ok([planar(0), planar(1), planar(2)])
}

/// Without the `denoise` feature there is no denoiser: says so.
#[cfg(not(feature = "denoise"))]
pub fn denoise(
    _width: usize,
    _height: usize,
    _beauty: &[Rgb],
    _albedo: [&[f32]; 3],
    _normal: [&[f32]; 3],
) -> Result<[Vec<f32>; 3], String> {
    Err("this brume was built without the `denoise` feature \
         (build with `cargo build --release --features denoise`, see docs/outputs.md)"
        .into())
}

#[cfg(test)]
mod tests {
    #[test]
    fn interleave_orders_pixels_then_channels() {
        let (r, g, b) = ([1.0, 2.0], [3.0, 4.0], [5.0, 6.0]);
        assert_eq!(
            super::interleave([&r, &g, &b]),
            vec![1.0, 3.0, 5.0, 2.0, 4.0, 6.0]
        );
    }
}
