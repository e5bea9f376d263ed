//! `[[medium]] type = "vol"`: a grid medium from Mitsuba `.vol` files, with
//! Mitsuba's `heterogeneous` semantics (what the XML importer produces).
//!
//! ```toml
//! [[medium]]
//! type = "vol"
//! sigma_t_file = "smoke.vol"    # 1 or 3 channels; σt = scale · value (1/m)
//! scale = 20.0                  # default 1
//! albedo = [0.9, 0.9, 0.9]      # constant, default 1; or:
//! albedo_file = "albedo.vol"    # 1 or 3 channels, values in [0, 1]
//! use_grid_bbox = false         # grids fill the unit cube (default) or their file's box
//! phase = { type = "hg", g = 0.3 }
//! transform = { translate = [-0.5, 0.0, -0.5] }   # places the box
//! ```
//!
//! Each grid fills the unit cube (or its file's bounding box), voxel
//! centres at (i + 0.5)/res, looked up trilinearly with indices clamped to
//! the edge. σt is zero outside the σt grid's box; the albedo grid is
//! looked up clamped wherever σt is not zero (see `medium::channels`).

use std::path::Path;
use std::sync::Arc;

use super::animation::Timing;
use super::coefficients::build_phase;
use super::description::VolDesc;
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
use crate::math::{Affine3A, Bounds3};
use crate::medium::{
    AlbedoGrid, ChannelGrids, GridEmission, GridMedium, GridMediumParams, MajorantMode, Medium,
    RgbGrids,
};
use crate::volume::{FloatGrid, VolFile};

/// The grid medium of one `type = "vol"` entry.
pub(crate) fn build_vol_medium(
    desc: &VolDesc,
    field: &str,
    check: &Check,
    base: &Path,
    _timing: &Timing,
) -> Result<Medium> {
    let f = |name: &str| format!("{field}.{name}");
    let sigma_t = read(&desc.sigma_t_file, &f("sigma_t_file"), base, check)?;
    check_values(&sigma_t, 0.0..=f32::MAX, &f("sigma_t_file"), check)?;
    let scale = build_scale(desc, &sigma_t, field, check)?;
    let (albedo, albedo_file) = build_albedo(desc, field, base, check)?;
    let (to_world, keys) =
        super::keyframes::build_placement(desc.transform.as_ref(), field, check)?.split();
    let params = GridMediumParams {
        to_world,
        density_scale: scale,
        sigma_t_scale: Rgb::WHITE,
        albedo,
        phase: build_phase(desc.phase.as_ref(), field, check)?,
        emission: GridEmission::None,
        majorant: MajorantMode::Grid,
        cell_size: None,
    };
    let place = |v: &VolFile| v.index_to_local(desc.use_grid_bbox);
    let density = sigma_t.channel_grid(None, place(&sigma_t)?)?;
    let mut medium = GridMedium::try_new_moving(density, params, None).map_err(|e| {
        check.error(
            &f("sigma_t_file"),
            format!("needs a majorant grid of {}", e.grid),
        )
    })?;
    let (min, max) = sigma_t.index_box();
    medium.set_clip(Bounds3 { min, max });
    let channels = ChannelGrids {
        sigma_t: match sigma_t.channels {
            3 => Some(RgbGrids(rgb_grids(&sigma_t, desc.use_grid_bbox)?)),
            _ => None,
        },
        albedo: match &albedo_file {
            Some(v) => Some(albedo_grid(v, desc.use_grid_bbox, &to_world)?),
            None => None,
        },
    };
    if channels.sigma_t.is_some() || channels.albedo.is_some() {
        medium.set_channels(channels);
    }
    Ok(Medium::Grid(Arc::new(medium)).moved_by(keys))
}

/// The checked `scale`: finite, ≥ 0, and times the largest σt still finite.
fn build_scale(desc: &VolDesc, sigma_t: &VolFile, field: &str, check: &Check) -> Result<f32> {
    let key = format!("{field}.scale");
    let scale = check.finite(&key, desc.scale.unwrap_or(1.0))?;
    if scale < 0.0 {
        return Err(check.error(&key, "must not be negative"));
    }
    if !(scale * sigma_t.max_value()).is_finite() {
        return Err(check.error(
            &key,
            "times the largest sigma_t value overflows single precision",
        ));
    }
    Ok(scale)
}

/// The constant albedo (default 1) and the albedo grid file, at most one of them written.
fn build_albedo(
    desc: &VolDesc,
    field: &str,
    base: &Path,
    check: &Check,
) -> Result<(Rgb, Option<VolFile>)> {
    let f = |name: &str| format!("{field}.{name}");
    match (&desc.albedo, &desc.albedo_file) {
        (Some(_), Some(_)) => {
            Err(check.error(&f("albedo"), "give albedo or albedo_file, not both"))
        }
        (Some(a), None) => Ok((check.albedo(&f("albedo"), *a)?, None)),
        (None, None) => Ok((Rgb::WHITE, None)),
        (None, Some(p)) => {
            let v = read(p, &f("albedo_file"), base, check)?;
            check_values(&v, 0.0..=1.0, &f("albedo_file"), check)?;
            Ok((Rgb::WHITE, Some(v)))
        }
    }
}

/// Reads the `.vol` file `written` (relative to the scene), errors naming `key` and the file.
fn read(written: &Path, key: &str, base: &Path, check: &Check) -> Result<VolFile> {
    let path = super::resolve(base, written);
    VolFile::read(&path).map_err(|e| check.error(key, e.to_string()))
}

/// Refuses a value outside `range` (or not finite), naming the file and the cell.
fn check_values(
    v: &VolFile,
    range: std::ops::RangeInclusive<f32>,
    key: &str,
    check: &Check,
) -> Result<()> {
    let Some(i) = v.data.iter().position(|x| !range.contains(x)) else {
        return Ok(());
    };
    let cell = i / v.channels;
    let [rx, ry, _] = v.res;
    let (x, y, z) = (cell % rx, (cell / rx) % ry, cell / (rx * ry));
    Err(check.error(
        key,
        format!(
            "{}: value {} at cell ({x}, {y}, {z}) channel {} is outside [{}, {}]",
            v.path.display(),
            v.data[i],
            i % v.channels,
            range.start(),
            range.end()
        ),
    ))
}

/// The three channels of `v` as grids on its index map.
fn rgb_grids(v: &VolFile, use_grid_bbox: bool) -> Result<[FloatGrid; 3]> {
    let t = v.index_to_local(use_grid_bbox)?;
    Ok([
        v.channel_grid(Some(0), t.clone())?,
        v.channel_grid(Some(1), t.clone())?,
        v.channel_grid(Some(2), t)?,
    ])
}

/// The albedo grid of `v` (1 or 3 channels) placed by `to_world`.
fn albedo_grid(v: &VolFile, use_grid_bbox: bool, to_world: &Affine3A) -> Result<AlbedoGrid> {
    let t = v.index_to_local(use_grid_bbox)?;
    let grids = (0..v.channels)
        .map(|c| v.channel_grid(Some(c), t.clone()))
        .collect::<Result<Vec<_>>>()?;
    Ok(AlbedoGrid::new(grids, v.res, to_world).expect("1 or 3 albedo channels"))
}
