//! The grids of a `type = "vdb"` medium, read and checked: loading errors
//! that name the field, and the value checks every grid (density,
//! temperature, emission) passes before it is rendered.

use super::overflow;
use super::validate::Check;
use crate::error::Result;
use crate::volume::{load_float_grid, FloatGrid, VolumeError};
use std::path::Path;

/// Loads grid `name` of `path`, turning a volume error into one that names the
/// field: the grid's field for a grid problem, `file_field` when the file
/// itself cannot be read (not a VDB, damaged header).
pub(super) fn load(
    path: &Path,
    name: &str,
    (file_field, field): (&str, &str),
    check: &Check,
) -> Result<FloatGrid> {
    load_float_grid(path, name).map_err(|e| {
        let culprit = match e {
            VolumeError::Io { .. } | VolumeError::BadFile { .. } => file_field,
            _ => field,
        };
        check.error(culprit, e.to_string())
    })
}

/// Refuses a grid brume cannot render: NaN or infinite values (tracking
/// against an infinite majorant never ends), values whose product with
/// `scale` overflows f32, or no positive value at all (a level set given as
/// a density renders as nothing); warns when some values are negative (they
/// count as 0). `fields` are (the grid's field, the scale's field).
pub(super) fn check_values(
    grid: &FloatGrid,
    fields: (&str, &str),
    scale: f32,
    density: bool,
    check: &Check,
) -> Result<crate::volume::ValueCensus> {
    let c = check_finite(grid, fields, scale, check)?;
    let name = grid.name();
    if density && c.max_finite <= 0.0 && scale > 0.0 {
        return Err(check.error(
            fields.0,
            format!(
                "grid '{name}' has no positive value (values from {} to {}), so it renders as empty space; \
                 a level set (signed distance) is not a density",
                c.min_finite, c.max_finite
            ),
        ));
    }
    if c.negative > 0 {
        check.warn(
            fields.0,
            format!(
                "{} of the {} stored values of grid '{name}' are negative (down to {}); they count as 0",
                c.negative, c.stored, c.min_finite
            ),
        );
    }
    Ok(c)
}

/// Refuses NaN or infinite values and values whose product with `scale`
/// overflows f32; returns the grid's value census.
pub(super) fn check_finite(
    grid: &FloatGrid,
    fields: (&str, &str),
    scale: f32,
    check: &Check,
) -> Result<crate::volume::ValueCensus> {
    let c = grid.value_census();
    let name = grid.name();
    if c.nonfinite() > 0 {
        return Err(check.error(
            fields.0,
            format!(
                "grid '{name}' holds {} non-finite values ({} NaN, {} +inf, {} -inf) among its {} stored values; \
                 brume needs finite values (`brume info` counts them)",
                c.nonfinite(),
                c.nan,
                c.pos_inf,
                c.neg_inf,
                c.stored
            ),
        ));
    }
    let largest = c.max_finite.abs().max(c.min_finite.abs());
    if !(largest * scale).is_finite() {
        return Err(check.error(
            fields.1,
            format!(
                "{} times the largest value {} of grid '{name}' overflows single precision (above 3.4e38)",
                overflow::num(scale),
                overflow::num(largest)
            ),
        ));
    }
    Ok(c)
}
