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
//! majorant_cell = 4                     # cell size in voxels (default: chosen)
//! velocity_grid = "vel"                 # vec3s velocity (units/s) for motion blur
//! velocity_scale = 1.0                  # multiplies the velocities
//! ```
//!
//! `file` may hold a frame pattern (`smoke.####.vdb`, see `animation`),
//! resolved for the frame being rendered. The velocity grid only matters
//! with a camera shutter; see `medium::motion`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::animation::{self, Timing};
use super::coefficients::build_phase;
use super::description::VdbDesc;
use super::files::{check_input, Format};
use super::overflow;
use super::validate::Check;
use super::vdb_emission::{build_emission, Brightest};
use super::vdb_grids::{check_finite, check_values, load};
use crate::error::Result;
use crate::math::color::Rgb;
use crate::medium::{
    GridMedium, GridMediumParams, GridMotion, MajorantMode, MajorantTooLarge, Medium,
};
use crate::volume::{load_vec3_grid, MAX_VDB_BYTES};

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
    check_input(
        check,
        &f("file"),
        "VDB file",
        &path,
        Format::Vdb,
        MAX_VDB_BYTES,
    )?;
    let scales = build_scales(desc, field, check)?;
    let motion = build_motion(desc, &path, field, check, timing)?;
    let density = load(&path, &desc.grid, (&f("file"), &f("grid")), check)?;
    overflow::product(
        check,
        &f("density_scale"),
        (Rgb::splat(scales.density_scale), "density_scale"),
        (scales.sigma_t_scale, "sigma_t_scale"),
    )?;
    let peak = scales.density_scale * scales.sigma_t_scale.max_channel();
    let census = check_values(
        &density,
        (&f("grid"), &f("density_scale")),
        peak,
        true,
        check,
    )?;
    let (emission, brightest) = build_emission(desc, &path, field, check)?;
    check_source_term(brightest, &scales, census.max_finite, field, check)?;
    // Moving: the grid is built in the file's frame, placed per time.
    let (to_world, keys) =
        super::keyframes::build_placement(desc.transform.as_ref(), field, check)?.split();
    let params = GridMediumParams {
        to_world,
        density_scale: scales.density_scale,
        sigma_t_scale: scales.sigma_t_scale,
        albedo: scales.albedo,
        phase: build_phase(desc.phase.as_ref(), field, check)?,
        emission,
        majorant: scales.majorant,
        cell_size: scales.cell,
    };
    let medium = GridMedium::try_new_moving(density, params, motion)
        .map_err(|e| majorant_error(desc, field, check, timing, &e))?;
    Ok(Medium::Grid(Arc::new(medium)).moved_by(keys))
}

/// The checked scale, albedo and majorant keys of a `type = "vdb"` entry.
struct VdbScales {
    density_scale: f32,
    sigma_t_scale: Rgb,
    albedo: Rgb,
    majorant: MajorantMode,
    /// `majorant_cell`: the majorant cell size in voxels, if the scene fixes it.
    cell: Option<i32>,
}

/// Largest `majorant_cell` (voxels): one cell then spans any volume a file can hold.
const MAX_MAJORANT_CELL: u32 = 1 << 16;

/// Reads `density_scale`, `sigma_t_scale`, `albedo`, `majorant` and `majorant_cell` (defaults when absent).
fn build_scales(desc: &VdbDesc, field: &str, check: &Check) -> Result<VdbScales> {
    let f = |name: &str| format!("{field}.{name}");
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
    let cell = build_majorant_cell(desc, &majorant, field, check)?;
    Ok(VdbScales {
        density_scale,
        sigma_t_scale,
        albedo,
        majorant,
        cell,
    })
}

/// Refuses emission whose source term σa·Le could overflow, and warns when σa is zero.
fn check_source_term(
    brightest: Brightest,
    scales: &VdbScales,
    max_density: f32,
    field: &str,
    check: &Check,
) -> Result<()> {
    let Some((le, key)) = brightest else {
        return Ok(());
    };
    let absorbing = (Rgb::WHITE - scales.albedo) * scales.sigma_t_scale;
    // the densest voxel's σa times the brightest Le bounds the source term σa·Le
    let sigma_a = absorbing * (max_density * scales.density_scale);
    overflow::product(
        check,
        &key,
        (sigma_a, "the densest voxel's sigma_a"),
        (le, "the brightest emission"),
    )?;
    super::coefficients::warn_inert_emission(field, absorbing, check);
    Ok(())
}

/// The checked `majorant_cell` (1 to [`MAX_MAJORANT_CELL`] voxels, only with `majorant = "grid"`).
fn build_majorant_cell(
    desc: &VdbDesc,
    majorant: &MajorantMode,
    field: &str,
    check: &Check,
) -> Result<Option<i32>> {
    let Some(n) = desc.majorant_cell else {
        return Ok(None);
    };
    let key = format!("{field}.majorant_cell");
    if !(1..=MAX_MAJORANT_CELL).contains(&n) {
        return Err(check.error(
            &key,
            format!("must be 1 to {MAX_MAJORANT_CELL} voxels, got {n}"),
        ));
    }
    if *majorant != MajorantMode::Grid {
        return Err(check.error(
            &key,
            "needs majorant = \"grid\" (a global majorant has no cells)",
        ));
    }
    Ok(Some(n as i32))
}

/// The error for a majorant grid over the memory limit, on the key that
/// sizes it: the velocity (scale) for a moving medium, the grid for a still one.
fn majorant_error(
    desc: &VdbDesc,
    field: &str,
    check: &Check,
    timing: &Timing,
    e: &MajorantTooLarge,
) -> crate::error::Error {
    let Some(r) = e.motion_radius else {
        return check.error(
            &format!("{field}.grid"),
            format!("grid '{}' needs a majorant grid of {}", desc.grid, e.grid),
        );
    };
    let key = match desc.velocity_scale {
        Some(_) => "velocity_scale",
        None => "velocity_grid",
    };
    let shutter = timing.shutter.unwrap_or_default();
    check.error(
        &format!("{field}.{key}"),
        format!(
            "over the shutter {shutter:?} the medium moves up to {:.3e} voxels, so its majorant grid needs {}; \
             a smaller velocity_scale or shutter moves it less",
            r.max_element(),
            e.grid
        ),
    )
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
