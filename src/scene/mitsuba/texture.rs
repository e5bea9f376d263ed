//! `<texture>`: checkerboard and bitmap, mapped onto brume's checkerboard and
//! image textures. Mitsuba looks up a bitmap with v growing down its rows
//! and each shape has its own (u, v), so whether a texture can be matched
//! depends on the shape it is on ([`UvFrame`]).

use super::mechanics::Node;
use super::values::{ColorParam, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{Color, TextureDesc, UvScale};

/// How the (u, v) Mitsuba gives a shape relates to brume's (u, v) on the imported shape.
#[derive(Clone, Copy)]
pub(crate) enum UvFrame {
    /// The same coordinates (rectangle, disk, ply, obj with flip_tex_coords = false).
    Same,
    /// The same u, Mitsuba's v is 1 − brume's (obj, whose v Mitsuba flips by default;
    /// a rectangle or disk turned over by flip_normals; a cube).
    Flipped,
}

/// A `<texture>` on a shape whose coordinates relate to brume's by `frame`.
pub(crate) fn read(ctx: &Ctx, node: &Node, frame: UvFrame) -> Result<TextureDesc> {
    let kind = node.required("type")?;
    if !matches!(kind, "checkerboard" | "bitmap") {
        return Err(unsupported(node, "this texture (checkerboard, bitmap)"));
    }
    let p = ctx.props(node)?;
    let to_uv = to_uv(&p)?;
    let mut desc = TextureDesc {
        kind: String::new(),
        file: None,
        wrap: None,
        filter: None,
        color_space: None,
        scale: None,
        a: None,
        b: None,
        uv_scale: None,
        uv_offset: None,
    };
    // Mitsuba looks up (su u + tu, sv v + tv) of its (u, v) on the shape.
    let ToUv { su, sv, tu, tv } = to_uv;
    // The same in brume's (u, v) on the shape: offset + slope · v.
    let (v_offset, v_slope) = match frame {
        UvFrame::Flipped => (sv + tv, -sv),
        _ => (tv, sv),
    };
    let (period, v_offset, v_slope) = if kind == "checkerboard" {
        desc.kind = "checkerboard".into();
        desc.a = Some(constant(&p, "color0", 0.4)?);
        desc.b = Some(constant(&p, "color1", 0.2)?);
        // Both boards put color0 / a in [0, ½)² and repeat with period 1.
        (Some(1.0), v_offset, v_slope)
    } else {
        desc.kind = "image".into();
        // Mitsuba's bitmap v runs down the rows, brume's up them: v ↦ 1 − v.
        (bitmap(ctx, &p, &mut desc)?, 1.0 - v_offset, -v_slope)
    };
    // An offset of whole periods of a repeating texture changes nothing: left out.
    let needed = |offset: f64| match period {
        Some(period) if (offset / period).fract() == 0.0 => 0.0,
        _ => offset,
    };
    let (u_offset, v_offset) = (needed(tu), needed(v_offset));
    desc.uv_scale = Some(UvScale::Each([su as f32, v_slope as f32]));
    if (u_offset, v_offset) != (0.0, 0.0) {
        desc.uv_offset = Some([u_offset as f32, v_offset as f32]);
    }
    p.finish()?;
    Ok(desc)
}

/// A `to_uv` of scales and translations of u and v.
struct ToUv {
    su: f64,
    sv: f64,
    tu: f64,
    tv: f64,
}

/// `to_uv`: a scale and a translation of u and v (a rotation or shear is refused).
fn to_uv(p: &Props) -> Result<ToUv> {
    let Some(m) = p.transform("to_uv")? else {
        return Ok(ToUv {
            su: 1.0,
            sv: 1.0,
            tu: 0.0,
            tv: 0.0,
        });
    };
    let at = p.node_of("to_uv").unwrap_or(p.owner);
    let (su, sv) = (m.x_axis.x, m.y_axis.y);
    let (tu, tv) = (m.w_axis.x, m.w_axis.y);
    if m.x_axis.y != 0.0 || m.y_axis.x != 0.0 {
        return Err(unsupported(
            at,
            "a to_uv with rotation or shear of the texture coordinates (scales and translations only)",
        ));
    }
    if su == 0.0 || sv == 0.0 || ![su, sv, tu, tv].iter().all(|v| v.is_finite()) {
        return Err(at.error("to_uv must scale u and v by finite, non-zero factors and translate them by finite amounts"));
    }
    Ok(ToUv { su, sv, tu, tv })
}

/// A constant colour of a checkerboard (a nested texture is refused).
fn constant(p: &Props, key: &str, grey: f32) -> Result<Color> {
    match p.color(key)? {
        None => Ok(Color([grey; 3])),
        Some(ColorParam::Rgb(c)) => Ok(Color(c.map(|v| v as f32))),
        Some(ColorParam::Texture(t)) => Err(unsupported(t.at, "a texture inside a checkerboard")),
    }
}

/// `bitmap`: filename, filter_type, wrap_mode and raw; its period in (u, v)
/// (1 repeating, 2 mirrored, none clamped).
fn bitmap(ctx: &Ctx, p: &Props, desc: &mut TextureDesc) -> Result<Option<f64>> {
    let (name, at) = p
        .string("filename")?
        .ok_or_else(|| p.owner.error("give <string name=\"filename\">"))?;
    desc.file = Some(ctx.file(name, at)?);
    match p.string("filter_type")? {
        None | Some(("bilinear", _)) => {}
        Some(("nearest", _)) => desc.filter = Some("nearest".into()),
        Some((other, at)) => {
            return Err(at.error(format!(
                "unknown filter_type `{other}` (Mitsuba's are bilinear and nearest)"
            )))
        }
    }
    let (wrap, period) = match p.string("wrap_mode")? {
        None | Some(("repeat", _)) => ("repeat", Some(1.0)),
        Some(("mirror", _)) => ("mirror", Some(2.0)),
        Some(("clamp", _)) => ("clamp", None),
        Some((other, at)) => {
            return Err(at.error(format!(
                "unknown wrap_mode `{other}` (Mitsuba's are repeat, mirror and clamp)"
            )))
        }
    };
    desc.wrap = Some(wrap.into());
    // Mitsuba decodes 8-bit data through the sRGB curve unless raw; brume's
    // PNGs are sRGB unless declared linear, and EXR/HDR are linear either way.
    if p.bool("raw")? == Some(true) {
        desc.color_space = Some("linear".into());
    }
    Ok(period)
}
