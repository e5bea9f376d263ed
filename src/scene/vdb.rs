//! `[[medium]] type = "vdb"`: a grid medium read from an OpenVDB file.
//!
//! ```toml
//! [[medium]]
//! type = "vdb"
//! file = "../volumes/smoke_plume.vdb"   # relative to the scene file
//! grid = "density"                      # default "density"
//! density_scale = 20.0                  # σt per unit density (1/m), default 1
//! sigma_t_scale = [1.0, 1.0, 1.0]       # per-channel factor on density_scale
//! albedo = [0.9, 0.9, 0.9]              # σs/σt, default 1
//! phase = { type = "hg", g = 0.3 }
//! transform = { translate = [-1.0, 0.0, -1.0] }
//! temperature_grid = "temperature"      # blackbody emission (or emission_grid, or emission)
//! temperature_scale = 1000.0            # kelvin per unit of grid value
//! emission_scale = 1.0                  # multiplies Le
//! majorant = "grid"                     # or "global"
//! velocity_grid = "vel"                 # vec3s velocity (units/s) for motion blur
//! velocity_scale = 1.0                  # multiplies the velocities
//! ```
//!
//! `file` may hold a frame pattern (`smoke.####.vdb`, see `animation`),
//! resolved for the frame being rendered. The velocity grid only matters
//! with a camera shutter; see `medium::motion`.

use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::animation::{self, Timing};
use super::description::{Color, PhaseDesc, TransformDesc};
use super::media::build_phase;
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
use crate::medium::{GridEmission, GridMedium, GridMediumParams, GridMotion, MajorantMode, Medium};
use crate::volume::{load_float_grid, load_vec3_grid, FloatGrid, VolumeError, MAX_VDB_BYTES};

/// The fields of a `type = "vdb"` medium.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VdbDesc {
    /// OpenVDB file, relative to the scene file.
    pub file: PathBuf,
    /// Name of the density grid.
    #[serde(default = "default_grid")]
    pub grid: String,
    /// Extinction per unit density (1/m).
    #[serde(default = "default_density_scale")]
    pub density_scale: f32,
    /// Per-channel factor on `density_scale` (chromatic extinction).
    #[serde(default)]
    pub sigma_t_scale: Option<Color>,
    /// Single-scattering albedo σs/σt (default 1).
    #[serde(default)]
    pub albedo: Option<Color>,
    /// Phase function (default isotropic).
    #[serde(default)]
    pub phase: Option<PhaseDesc>,
    /// Placement after the file's own index → world map.
    #[serde(default)]
    pub transform: Option<TransformDesc>,
    /// Constant emitted radiance Le.
    #[serde(default)]
    pub emission: Option<Color>,
    /// Temperature grid for blackbody emission.
    #[serde(default)]
    pub temperature_grid: Option<String>,
    /// Kelvin per unit of temperature-grid value.
    #[serde(default)]
    pub temperature_scale: Option<f32>,
    /// Grid whose value times `emission_scale` is Le.
    #[serde(default)]
    pub emission_grid: Option<String>,
    /// Factor on grid-driven emission (default 1).
    #[serde(default)]
    pub emission_scale: Option<Color>,
    /// `"grid"` (default) or `"global"`.
    #[serde(default)]
    pub majorant: Option<String>,
    /// Name of a vec3s velocity grid (file world units per second) for motion blur.
    #[serde(default)]
    pub velocity_grid: Option<String>,
    /// Factor on the velocities (default 1).
    #[serde(default)]
    pub velocity_scale: Option<f32>,
}

fn default_grid() -> String {
    "density".into()
}
fn default_density_scale() -> f32 {
    1.0
}

/// Kelvin per unit of temperature-grid value when `temperature_scale` is absent.
const DEFAULT_TEMPERATURE_SCALE: f32 = 1000.0;

/// Loads grid `name` of `path`, turning a volume error into one that names the
/// field: the grid's field for a grid problem, `file_field` when the file
/// itself cannot be read (not a VDB, damaged header).
fn load(
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
fn check_values(
    grid: &FloatGrid,
    fields: (&str, &str),
    scale: f32,
    density: bool,
    check: &Check,
) -> Result<()> {
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
    Ok(())
}

/// Refuses NaN or infinite values and values whose product with `scale`
/// overflows f32; returns the grid's value census.
fn check_finite(
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
                "{scale} times the largest value {largest:e} of grid '{name}' overflows single precision (above 3.4e38)"
            ),
        ));
    }
    Ok(c)
}

/// The grid medium of one `type = "vdb"` entry.
pub(crate) fn build_vdb_medium(
    desc: &VdbDesc,
    field: &str,
    check: &Check,
    base: &Path,
    timing: &Timing,
) -> Result<Medium> {
    let f = |name: &str| format!("{field}.{name}");
    let path = frame_file(&super::resolve(base, &desc.file), &f("file"), check, timing)?;
    if let Some(problem) = crate::error::input_file_problem(&path, MAX_VDB_BYTES) {
        return Err(check.error(
            &f("file"),
            format!("cannot read VDB file {}: {problem}", path.display()),
        ));
    }
    let density_scale = check.finite(&f("density_scale"), desc.density_scale)?;
    if density_scale < 0.0 {
        return Err(check.error(&f("density_scale"), "must not be negative"));
    }
    let sigma_t_scale = match desc.sigma_t_scale {
        Some(c) => check.color(&f("sigma_t_scale"), c)?,
        None => Rgb::WHITE,
    };
    let albedo = match desc.albedo {
        Some(a) => check.albedo(&f("albedo"), a)?,
        None => Rgb::WHITE,
    };
    let majorant = match desc.majorant.as_deref() {
        None | Some("grid") => MajorantMode::Grid,
        Some("global") => MajorantMode::Global,
        Some(other) => {
            return Err(check.error(
                &f("majorant"),
                format!("must be \"grid\" or \"global\", got \"{other}\""),
            ))
        }
    };
    let motion = build_motion(desc, &path, field, check, timing)?;
    let density = load(&path, &desc.grid, (&f("file"), &f("grid")), check)?;
    let peak = density_scale * sigma_t_scale.max_channel();
    check_values(
        &density,
        (&f("grid"), &f("density_scale")),
        peak,
        true,
        check,
    )?;
    let emission = build_emission(desc, &path, field, check)?;
    if !matches!(emission, GridEmission::None) {
        super::media::warn_inert_emission(field, (Rgb::WHITE - albedo) * sigma_t_scale, check);
    }
    // Moving: the grid is built in the file's frame, placed per time.
    let (to_world, keys) =
        super::keyframes::build_placement(desc.transform.as_ref(), field, check)?.split();
    let params = GridMediumParams {
        to_world,
        density_scale,
        sigma_t_scale,
        albedo,
        phase: build_phase(desc.phase.as_ref(), field, check)?,
        emission,
        majorant,
        cell_size: None,
    };
    Ok(Medium::Grid(Arc::new(GridMedium::new_moving(density, params, motion))).moved_by(keys))
}

/// The file of the frame being rendered: a pattern resolved, a plain path unchanged.
fn frame_file(path: &Path, field: &str, check: &Check, timing: &Timing) -> Result<PathBuf> {
    if !animation::has_pattern(path) {
        return Ok(path.to_path_buf());
    }
    let Some(frame) = timing.frame else {
        return Err(check.error(
            field,
            format!(
                "{} holds a frame pattern: render it with --frames",
                path.display()
            ),
        ));
    };
    animation::resolve_frame(path, frame, timing.frame_offset, timing.missing)
        .map_err(|message| check.error(field, message))
}

/// Velocity motion blur when the medium names a velocity grid and the camera has a shutter.
fn build_motion(
    desc: &VdbDesc,
    path: &Path,
    field: &str,
    check: &Check,
    timing: &Timing,
) -> Result<Option<GridMotion>> {
    let f = |name: &str| format!("{field}.{name}");
    let scale = match desc.velocity_scale {
        Some(s) => {
            if desc.velocity_grid.is_none() {
                return Err(check.error(&f("velocity_scale"), "needs velocity_grid"));
            }
            check.finite(&f("velocity_scale"), s)?
        }
        None => 1.0,
    };
    let (Some(name), Some(shutter)) = (&desc.velocity_grid, timing.shutter) else {
        return Ok(None);
    };
    let velocity =
        load_vec3_grid(path, name).map_err(|e| check.error(&f("velocity_grid"), e.to_string()))?;
    // velocities are signed: only non-finite and overflowing values are refused
    for axis in 0..3 {
        check_finite(
            velocity.component(axis),
            (&f("velocity_grid"), &f("velocity_scale")),
            scale / timing.fps,
            check,
        )?;
    }
    Ok(Some(GridMotion {
        velocity,
        scale: scale / timing.fps,
        shutter,
    }))
}

/// Emission from at most one of `emission`, `temperature_grid` and `emission_grid`.
fn build_emission(desc: &VdbDesc, path: &Path, field: &str, check: &Check) -> Result<GridEmission> {
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
        return Ok(GridEmission::Constant(check.color(&f("emission"), le)?));
    }
    let emission_scale = emission_scale.unwrap_or(Rgb::WHITE);
    if let Some(name) = &desc.temperature_grid {
        let scale = desc.temperature_scale.unwrap_or(DEFAULT_TEMPERATURE_SCALE);
        let temperature = load(path, name, (&f("file"), &f("temperature_grid")), check)?;
        let scale_field = match desc.temperature_scale {
            Some(_) => f("temperature_scale"),
            None => f("temperature_grid"),
        };
        let temperature_scale = check.positive(&f("temperature_scale"), scale)?;
        check_values(
            &temperature,
            (&f("temperature_grid"), &scale_field),
            temperature_scale,
            false,
            check,
        )?;
        return Ok(GridEmission::Blackbody {
            temperature,
            temperature_scale,
            emission_scale,
        });
    }
    if let Some(name) = &desc.emission_grid {
        let grid = load(path, name, (&f("file"), &f("emission_grid")), check)?;
        let scale_field = match desc.emission_scale {
            Some(_) => f("emission_scale"),
            None => f("emission_grid"),
        };
        check_values(
            &grid,
            (&f("emission_grid"), &scale_field),
            emission_scale.max_channel(),
            false,
            check,
        )?;
        return Ok(GridEmission::Grid {
            grid,
            emission_scale,
        });
    }
    if desc.emission_scale.is_some() {
        return Err(check.error(
            &f("emission_scale"),
            "needs temperature_grid or emission_grid",
        ));
    }
    Ok(GridEmission::None)
}
