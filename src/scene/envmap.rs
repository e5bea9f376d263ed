//! `type = "environment_map"` lights: reading the EXR or Radiance HDR and checking its texels.

use super::description::{Color, MapFilterDesc};
use super::files::{check_input, Format};
use super::textures::MAX_TEXTURE_BYTES;
use super::validate::Check;
use crate::error::Result;
use crate::light::envmap::{EnvMap, Filter};
use crate::math::color::Rgb;
use crate::math::Quat;
use std::path::Path;

/// Loads the map in `path` with `scale` and `rotate` (degrees about X, then
/// Y, then Z), filtered by `filter`.
pub(super) fn build(
    check: &Check,
    field: &str,
    path: &Path,
    (scale, rotate): (Color, Option<[f32; 3]>),
    filter: MapFilterDesc,
) -> Result<EnvMap> {
    let file_field = format!("{field}.file");
    let what = "environment map";
    // Radiance files by their extension; anything else must be an EXR.
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let format = match ext.to_ascii_lowercase().as_str() {
        "hdr" | "pic" => Format::Hdr,
        _ => Format::Exr,
    };
    check_input(check, &file_field, what, path, format, MAX_TEXTURE_BYTES)?;
    let read = match format {
        Format::Hdr => crate::film::image_io::read_hdr(path),
        _ => crate::film::image_io::read_exr(path),
    };
    let (width, height, texels) = read.map_err(|e| {
        let message = super::files::input_message(e);
        check.error(
            &file_field,
            format!("cannot read {what} {}: {message}", path.display()),
        )
    })?;
    super::textures::check_finite_texels(check, &file_field, path, width, &texels)?;
    let scale = check.color(&format!("{field}.scale"), scale)?;
    let rotation = match rotate {
        Some(r) => {
            let r = check.vec3(&format!("{field}.rotate"), r)?;
            Quat::from_rotation_z(r.z.to_radians())
                * Quat::from_rotation_y(r.y.to_radians())
                * Quat::from_rotation_x(r.x.to_radians())
        }
        None => Quat::IDENTITY,
    };
    let scale_field = match scale == Rgb::WHITE {
        true => file_field.clone(),
        false => format!("{field}.scale"),
    };
    check_scaled(check, &scale_field, &texels, scale)?;
    let filter = match filter {
        MapFilterDesc::Nearest => Filter::Nearest,
        MapFilterDesc::Bilinear => Filter::Bilinear,
    };
    EnvMap::filtered(width, height, texels, scale, rotation, filter).ok_or_else(|| {
        check.error(
            &file_field,
            format!("environment map {} is black everywhere", path.display()),
        )
    })
}

/// Refuses a map whose brightest texel times `scale` overflows f32: its
/// sampling distribution would have an infinite total (it used to be
/// reported as "black everywhere").
fn check_scaled(check: &Check, field: &str, texels: &[Rgb], scale: Rgb) -> Result<()> {
    let brightest = super::overflow::brightest(texels.iter().copied());
    super::overflow::product(
        check,
        field,
        (brightest, "the brightest texel"),
        (scale, "scale"),
    )?;
    // the sampling weight is the luminance, a weighted sum of the channels
    let luminance = texels
        .iter()
        .map(|&t| (t * scale).luminance())
        .fold(0.0, f32::max);
    super::overflow::fits(check, field, luminance, luminance as f64, || {
        "the brightest texel's luminance times scale".into()
    })
}
