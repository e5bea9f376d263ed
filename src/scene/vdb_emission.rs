//! Emission of a `type = "vdb"` medium: a constant `emission`, blackbody
//! emission from `temperature_grid`, or `emission_grid` values, each refused
//! when its brightest radiance overflows single precision.

use super::description::VdbDesc;
use super::overflow;
use super::validate::Check;
use super::vdb_grids::{check_values, load};
use crate::error::Result;
use crate::math::color::Rgb;
use crate::medium::blackbody::blackbody_emission;
use crate::medium::GridEmission;
use std::path::Path;

/// Kelvin per unit of temperature-grid value when `temperature_scale` is absent.
const DEFAULT_TEMPERATURE_SCALE: f32 = 1000.0;

/// The brightest emitted radiance Le of a medium and the key that set it.
pub(super) type Brightest = Option<(Rgb, String)>;

/// Emission from at most one of `emission`, `temperature_grid` and
/// `emission_grid`, with its brightest radiance (`None` without emission).
pub(super) fn build_emission(
    desc: &VdbDesc,
    path: &Path,
    field: &str,
    check: &Check,
) -> Result<(GridEmission, Brightest)> {
    let f = |name: &str| format!("{field}.{name}");
    let emission_scale = match desc.emission_scale {
        Some(c) => Some(check.color(&f("emission_scale"), c)?),
        None => None,
    };
    let given = [
        desc.emission.is_some(),
        desc.temperature_grid.is_some(),
        desc.emission_grid.is_some(),
    ];
    if given.iter().filter(|&&g| g).count() > 1 {
        return Err(check.error(
            field,
            "give at most one of emission, temperature_grid and emission_grid",
        ));
    }
    if desc.temperature_scale.is_some() && desc.temperature_grid.is_none() {
        return Err(check.error(&f("temperature_scale"), "needs temperature_grid"));
    }
    if let Some(le) = desc.emission {
        if emission_scale.is_some() {
            return Err(check.error(
                &f("emission_scale"),
                "applies to temperature_grid or emission_grid, not to emission",
            ));
        }
        let le = check.color(&f("emission"), le)?;
        return Ok((GridEmission::Constant(le), Some((le, f("emission")))));
    }
    let emission_scale = emission_scale.unwrap_or(Rgb::WHITE);
    if let Some(name) = &desc.temperature_grid {
        return blackbody(desc, name, emission_scale, path, field, check);
    }
    if let Some(name) = &desc.emission_grid {
        return radiance_grid(desc, name, emission_scale, path, field, check);
    }
    if desc.emission_scale.is_some() {
        return Err(check.error(
            &f("emission_scale"),
            "needs temperature_grid or emission_grid",
        ));
    }
    Ok((GridEmission::None, None))
}

/// Emission from the radiance values of grid `name`, times `emission_scale`.
fn radiance_grid(
    desc: &VdbDesc,
    name: &str,
    emission_scale: Rgb,
    path: &Path,
    field: &str,
    check: &Check,
) -> Result<(GridEmission, Brightest)> {
    let f = |name: &str| format!("{field}.{name}");
    let grid = load(path, name, (&f("file"), &f("emission_grid")), check)?;
    let scale_field = match desc.emission_scale {
        Some(_) => f("emission_scale"),
        None => f("emission_grid"),
    };
    let census = check_values(
        &grid,
        (&f("emission_grid"), &scale_field),
        emission_scale.max_channel(),
        false,
        check,
    )?;
    let brightest = emission_scale * census.max_finite.max(0.0);
    let emission = GridEmission::Grid {
        grid,
        emission_scale,
    };
    Ok((emission, Some((brightest, scale_field))))
}

/// Blackbody emission from grid `name`: Le = emission_scale · chroma(T) · (T / 1000 K)⁴.
fn blackbody(
    desc: &VdbDesc,
    name: &str,
    emission_scale: Rgb,
    path: &Path,
    field: &str,
    check: &Check,
) -> Result<(GridEmission, Brightest)> {
    let f = |name: &str| format!("{field}.{name}");
    let scale = desc.temperature_scale.unwrap_or(DEFAULT_TEMPERATURE_SCALE);
    let temperature = load(path, name, (&f("file"), &f("temperature_grid")), check)?;
    let scale_field = match desc.temperature_scale {
        Some(_) => f("temperature_scale"),
        None => f("temperature_grid"),
    };
    let temperature_scale = check.positive(&f("temperature_scale"), scale)?;
    let census = check_values(
        &temperature,
        (&f("temperature_grid"), &scale_field),
        temperature_scale,
        false,
        check,
    )?;
    // (T / 1000 K)⁴ leaves f32 above about 1.4e12 K
    let hottest = census.max_finite.max(0.0) as f64 * temperature_scale as f64;
    let le = blackbody_emission(hottest);
    overflow::fits(
        check,
        &scale_field,
        le.max_channel(),
        (hottest / 1000.0).powi(4),
        || format!("(T / 1000 K)⁴ at the hottest voxel's {hottest:.3e} K"),
    )?;
    let key = match desc.emission_scale {
        Some(_) => f("emission_scale"),
        None => scale_field,
    };
    overflow::product(
        check,
        &key,
        (le, "the hottest voxel's radiance"),
        (emission_scale, "emission_scale"),
    )?;
    let emission = GridEmission::Blackbody {
        temperature,
        temperature_scale,
        emission_scale,
    };
    Ok((emission, Some((le * emission_scale, key))))
}
