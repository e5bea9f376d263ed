//! `<medium type="heterogeneous">` with `<volume type="gridvolume">` σt and
//! albedo, imported as a `type = "vol"` medium (`scene::vol`).
//!
//! Mitsuba's semantics, from its plugin documentation: σt(x) = scale ·
//! sigma_t(x), albedo looked up at the same point; a grid volume fills the
//! unit cube (or, with `use_grid_bbox`, its file's bounding box) mapped by
//! its `to_world`, is looked up trilinearly with clamped indices, and the
//! medium is zero outside σt's box. brume's `vol` medium has one placement
//! for both grids, so a σt and an albedo grid with different `to_world` or
//! `use_grid_bbox` are refused, as is a constant σt (Mitsuba clips it to
//! the constant volume's unit cube, which a homogeneous medium does not).

use glam::DMat4;

use super::super::mechanics::Node;
use super::super::transform::to_brume;
use super::super::values::{Obj, Props};
use super::super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{Color, MediumDesc, VolDesc};
use std::path::PathBuf;

/// A `sigma_t` or `albedo` parameter of a heterogeneous medium.
enum Param<'a> {
    /// A constant (number, `<rgb>`, `<spectrum>`, `constvolume`).
    Constant([f64; 3]),
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
        Param::Constant(_) => {
            return Err(unsupported(
                node,
                "a heterogeneous medium with a constant sigma_t (Mitsuba clips it to the \
                 constant volume's unit cube; write a homogeneous medium in a cube shape)",
            ))
        }
    };
    let (albedo, albedo_file) = match albedo {
        Param::Constant(a) => (Some(Color(a.map(|v| v as f32))), None),
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

/// `key` as a constant or a grid volume.
fn param<'a>(ctx: &Ctx<'a>, p: &Props<'a>, key: &str, default: f64) -> Result<Param<'a>> {
    let Some(v) = p.object("volume", Some(key)) else {
        return super::constant(p, key, default).map(Param::Constant);
    };
    match v.node.required("type")? {
        "constvolume" => {
            let inner = ctx.props(v.node)?;
            let value = super::constant(&inner, "value", 1.0)?;
            inner.transform("to_world")?; // places nothing a constant albedo could show
            inner.finish()?;
            Ok(Param::Constant(value))
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
