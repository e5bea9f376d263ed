//! `type = "environment_map"` lights: reading the EXR and checking its texels.

use super::description::Color;
use super::validate::Check;
use crate::error::Result;
use crate::light::envmap::EnvMap;
use crate::math::Quat;
use std::path::Path;

/// Loads the map in `path` with `scale` and `rotate` (degrees about X, then Y, then Z).
pub(super) fn build(
    check: &Check,
    field: &str,
    path: &Path,
    scale: Color,
    rotate: Option<[f32; 3]>,
) -> Result<EnvMap> {
    let file_field = format!("{field}.file");
    if let Err(problem) = crate::error::regular_file(path) {
        return Err(check.error(
            &file_field,
            format!("cannot read environment map {}: {problem}", path.display()),
        ));
    }
    let (width, height, texels) = crate::film::image_io::read_exr(path).map_err(|e| {
        check.error(
            &file_field,
            format!("cannot read environment map {}: {e}", path.display()),
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
    EnvMap::new(width, height, texels, scale, rotation).ok_or_else(|| {
        check.error(
            &file_field,
            format!("environment map {} is black everywhere", path.display()),
        )
    })
}
