//! `<medium type="heterogeneous">` with `<volume type="gridvolume">` σt and
//! albedo, imported as a `type = "vol"` medium (`scene::vol`).
//!
//! Mitsuba's semantics, from its plugin documentation: σt(x) = scale ·
//! sigma_t(x), albedo looked up at the same point; a grid volume fills the
//! unit cube (or, with `use_grid_bbox`, its file's bounding box) mapped by
//! its `to_world`, is looked up trilinearly with clamped indices, and the
//! medium is zero outside σt's box. brume's `vol` medium has one placement
//! for both grids, so a σt and an albedo grid with different `to_world` or
//! `use_grid_bbox` are refused. A constant σt (a number, RGB or
//! `constvolume`) is a homogeneous medium bounded by σt's box: the
//! constant volume's unit cube mapped by its `to_world` (identity for a
//! bare number); a `to_world` that turns the cube off the world axes is
//! refused, as Mitsuba's releases disagree on that box.

use glam::{DMat4, DVec3};

use super::super::mechanics::Node;
use super::super::transform::to_brume;
use super::super::values::{Obj, Props};
use super::super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{BoundsDesc, Color, MediumDesc, PhaseDesc, VolDesc};
use std::path::PathBuf;

/// A `sigma_t` or `albedo` parameter of a heterogeneous medium.
enum Param<'a> {
    /// A constant (number, `<rgb>`, `<spectrum>`, `constvolume`), with the
    /// volume's `to_world` and the element it came from.
    Constant([f64; 3], DMat4, &'a Node),
    /// A grid volume.
    Grid(GridVolume<'a>),
}

/// A `<volume type="gridvolume">`.
struct GridVolume<'a> {
    file: PathBuf,
    to_world: DMat4,
    use_grid_bbox: bool,
    at: Obj<'a>,
}

/// `<medium type="heterogeneous">` as a `type = "vol"` description.
pub(super) fn read(ctx: &Ctx, node: &Node) -> Result<MediumDesc> {
    let p = ctx.props(node)?;
    let sigma_t = param(ctx, &p, "sigma_t", 1.0)?;
    let albedo = param(ctx, &p, "albedo", 0.75)?;
    let scale = p.float("scale")?.unwrap_or(1.0);
    // Sampling strategies, not the medium's look.
    p.bool("sample_emitters")?;
    p.bool("has_spectral_extinction")?;
    let phase = match p.object("phase", None) {
        Some(ph) => super::phase(ctx, ph.node)?,
        None => None,
    };
    p.finish()?;
    let grid = match sigma_t {
        Param::Grid(g) => g,
        Param::Constant(value, to_world, at) => {
            let sigma_t = value.map(|v| v * scale);
            return constant_sigma_t(sigma_t, &to_world, at, albedo, phase);
        }
    };
    let (albedo, albedo_file) = match albedo {
        Param::Constant(a, ..) => (Some(Color(a.map(|v| v as f32))), None),
        Param::Grid(a) => {
            if a.to_world != grid.to_world || a.use_grid_bbox != grid.use_grid_bbox {
                return Err(unsupported(
                    a.at.at,
                    "an albedo grid placed differently from the sigma_t grid \
                     (different to_world or use_grid_bbox)",
                ));
            }
            (None, Some(a.file))
        }
    };
    Ok(MediumDesc::Vol(VolDesc {
        sigma_t_file: grid.file,
        scale: Some(scale as f32),
        albedo,
        albedo_file,
        use_grid_bbox: grid.use_grid_bbox,
        phase,
        transform: to_brume(&grid.to_world, grid.at.at)?,
    }))
}

/// A constant σt (already scaled) as a homogeneous medium bounded by the
/// constant volume's unit cube under `to_world` (from the element `at`).
fn constant_sigma_t(
    sigma_t: [f64; 3],
    to_world: &DMat4,
    at: &Node,
    albedo: Param,
    phase: Option<PhaseDesc>,
) -> Result<MediumDesc> {
    const GRID_ALBEDO: &str =
        "an albedo grid with a constant sigma_t (brume's vol medium needs a sigma_t grid)";
    let albedo = match albedo {
        Param::Constant(a, ..) => a,
        Param::Grid(a) => return Err(unsupported(a.at.at, GRID_ALBEDO)),
    };
    let (min, max) = unit_cube_box(to_world, at)?;
    Ok(MediumDesc::Homogeneous {
        sigma_a: None,
        sigma_s: None,
        sigma_t: Some(Color(sigma_t.map(|v| v as f32))),
        albedo: Some(Color(albedo.map(|v| v as f32))),
        emission: None,
        phase,
        bounds: Some(BoundsDesc::Box { min, max }),
        global: false,
        transform: None,
    })
}

/// The world box of the unit cube under `to_world`, which may only scale
/// (by nonzero factors, of either sign) and translate: Mitsuba bounds a
/// volume by a world-axis box, and its releases build that box differently
/// from a turned cube (two corners or eight), so a turn is refused.
fn unit_cube_box(to_world: &DMat4, at: &Node) -> Result<([f32; 3], [f32; 3])> {
    let m = to_world.to_cols_array_2d();
    // The axis columns may hold only their own axis (no turn, no projection).
    let off_axes = (0..3).any(|c| (0..4).any(|r| r != c && m[c][r] != 0.0));
    let diagonal = DVec3::new(m[0][0], m[1][1], m[2][2]);
    if off_axes || m[3][3] != 1.0 || diagonal.cmpeq(DVec3::ZERO).any() {
        return Err(unsupported(
            at,
            "a constant sigma_t volume whose to_world rotates, shears or flattens the unit cube \
             (brume bounds it by a box; scale and translate only)",
        ));
    }
    let a = to_world.transform_point3(DVec3::ZERO);
    let b = to_world.transform_point3(DVec3::ONE);
    Ok((a.min(b).as_vec3().to_array(), a.max(b).as_vec3().to_array()))
}

/// A constant-σt medium (bounded by a box) inside a shape whose world
/// bounds are `shape`: the box is moot where it holds the shape (within a
/// millionth of its size, for rounding of the two transforms). brume cannot
/// clip an interior to a box, so any other arrangement is `None`: the
/// caller keeps Mitsuba's interface rule, where the medium stays in its box.
pub(super) fn fit_interior(
    mut medium: MediumDesc,
    shape: Option<(DVec3, DVec3)>,
) -> Option<MediumDesc> {
    let MediumDesc::Homogeneous { bounds, .. } = &mut medium else {
        return Some(medium);
    };
    let Some(BoundsDesc::Box { min, max }) = bounds else {
        return Some(medium);
    };
    let (lo, hi) = (
        DVec3::from(min.map(f64::from)),
        DVec3::from(max.map(f64::from)),
    );
    let slack = (hi - lo) * 1e-6;
    let holds = shape
        .is_some_and(|(slo, shi)| (lo - slack).cmple(slo).all() && shi.cmple(hi + slack).all());
    if !holds {
        return None;
    }
    *bounds = None;
    Some(medium)
}

/// `key` as a constant or a grid volume.
fn param<'a>(ctx: &Ctx<'a>, p: &Props<'a>, key: &str, default: f64) -> Result<Param<'a>> {
    let Some(v) = p.object("volume", Some(key)) else {
        // A bare value is a constant volume over the unit cube.
        let value = super::constant(p, key, default)?;
        return Ok(Param::Constant(
            value,
            DMat4::IDENTITY,
            p.node_of(key).unwrap_or(p.owner),
        ));
    };
    match v.node.required("type")? {
        "constvolume" => {
            let inner = ctx.props(v.node)?;
            let value = super::constant(&inner, "value", 1.0)?;
            // Bounds a constant σt; places nothing a constant albedo could show.
            let to_world = inner.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
            inner.finish()?;
            Ok(Param::Constant(value, to_world, v.node))
        }
        "gridvolume" | "grid" => grid_volume(ctx, v).map(Param::Grid),
        _ => Err(unsupported(v.node, "this volume (constvolume, gridvolume)")),
    }
}

/// The parameters of a `<volume type="gridvolume">`.
fn grid_volume<'a>(ctx: &Ctx<'a>, v: Obj<'a>) -> Result<GridVolume<'a>> {
    let p = ctx.props(v.node)?;
    let (name, file_at) = p
        .string("filename")?
        .ok_or_else(|| v.node.error("give <string name=\"filename\">"))?;
    let file = ctx.file(name, file_at)?;
    if let Some((mode, at)) = p.string("filter_type")? {
        if mode != "trilinear" {
            return Err(unsupported(at, "this filter_type (trilinear)"));
        }
    }
    if let Some((mode, at)) = p.string("wrap_mode")? {
        if mode != "clamp" {
            return Err(unsupported(at, "this wrap_mode (clamp)"));
        }
    }
    // RGB mode converts no colour (`raw`); `accel` and `max_value` change
    // how Mitsuba samples, not the medium (brume finds its own majorants).
    p.bool("raw")?;
    p.bool("accel")?;
    p.float("max_value")?;
    let to_world = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let use_grid_bbox = p.bool("use_grid_bbox")?.unwrap_or(false);
    p.finish()?;
    Ok(GridVolume {
        file,
        to_world,
        use_grid_bbox,
        at: v,
    })
}
