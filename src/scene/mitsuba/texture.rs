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
    /// a rectangle or disk turned over by flip_normals).
    Flipped,
    /// No exact match: textures on this shape are refused, for this reason.
    Refused(&'static str),
}

/// A `<texture>` on a shape whose coordinates relate to brume's by `frame`.
pub(crate) fn read(ctx: &Ctx, node: &Node, frame: UvFrame) -> Result<TextureDesc> {
    let kind = node.required("type")?;
    if !matches!(kind, "checkerboard" | "bitmap") {
        return Err(unsupported(node, "this texture (checkerboard, bitmap)"));
    }
    if let UvFrame::Refused(why) = frame {
        return Err(unsupported(node, why));
    }
    let p = ctx.props(node)?;
    let (su, sv) = to_uv(&p)?;
    let mut desc = TextureDesc {
        kind: String::new(),
        file: None,
        wrap: None,
        color_space: None,
        scale: None,
        a: None,
        b: None,
        uv_scale: None,
    };
    // brume's v coordinate of the lookup is offset + slope · v (brume's v on the shape).
    let (offset, slope, periodic) = if kind == "checkerboard" {
        desc.kind = "checkerboard".into();
        desc.a = Some(constant(&p, "color0", 0.4)?);
        desc.b = Some(constant(&p, "color1", 0.2)?);
        // Both boards put color0 / a in [0, ½)² and repeat with period 1.
        match frame {
            UvFrame::Flipped => (sv, -sv, true),
            _ => (0.0, sv, true),
        }
    } else {
        desc.kind = "image".into();
        let repeat = bitmap(ctx, &p, &mut desc)?;
        // Mitsuba's bitmap v runs down the rows, brume's up them: v ↦ 1 − v.
        match frame {
            UvFrame::Flipped => (1.0 - sv, sv, repeat),
            _ => (1.0, -sv, repeat),
        }
    };
    // brume's textures scale (u, v) but have no offset: one is only absorbed
    // when it is a whole number of periods of a repeating texture.
    if offset != 0.0 && !(periodic && offset.fract() == 0.0) {
        return Err(unsupported(
            p.node_of("to_uv").or(p.node_of("wrap_mode")).unwrap_or(node),
            &format!(
                "this to_uv / wrap_mode on this shape (Mitsuba's v runs against brume's here, \
                 which needs a v offset of {offset}; brume's textures only absorb whole periods of a repeating texture)"
            ),
        ));
    }
    desc.uv_scale = Some(UvScale::Each([su as f32, slope as f32]));
    p.finish()?;
    Ok(desc)
}

/// `to_uv`: only a scale of u and v (a rotation, shear or translation is refused).
fn to_uv(p: &Props) -> Result<(f64, f64)> {
    let Some(m) = p.transform("to_uv")? else {
        return Ok((1.0, 1.0));
    };
    let at = p.node_of("to_uv").unwrap_or(p.owner);
    let (su, sv) = (m.x_axis.x, m.y_axis.y);
    let plain = m.x_axis.y == 0.0 && m.y_axis.x == 0.0 && m.w_axis.x == 0.0 && m.w_axis.y == 0.0;
    if !plain {
        return Err(unsupported(
            at,
            "a to_uv other than a scale (rotation, shear or translation of the texture coordinates)",
        ));
    }
    if su == 0.0 || sv == 0.0 || !su.is_finite() || !sv.is_finite() {
        return Err(at.error("to_uv must scale u and v by finite, non-zero factors"));
    }
    Ok((su, sv))
}

/// A constant colour of a checkerboard (a nested texture is refused).
fn constant(p: &Props, key: &str, grey: f32) -> Result<Color> {
    match p.color(key)? {
        None => Ok(Color([grey; 3])),
        Some(ColorParam::Rgb(c)) => Ok(Color(c.map(|v| v as f32))),
        Some(ColorParam::Texture(t)) => Err(unsupported(t.at, "a texture inside a checkerboard")),
    }
}

/// `bitmap`: filename, filter_type, wrap_mode and raw; true when it repeats.
fn bitmap(ctx: &Ctx, p: &Props, desc: &mut TextureDesc) -> Result<bool> {
    let (name, at) = p
        .string("filename")?
        .ok_or_else(|| p.owner.error("give <string name=\"filename\">"))?;
    desc.file = Some(ctx.file(name, at)?);
    match p.string("filter_type")? {
        None | Some(("bilinear", _)) => {}
        Some(("nearest", at)) => {
            return Err(unsupported(
                at,
                "filter_type nearest (brume's image textures are bilinear)",
            ))
        }
        Some((other, at)) => {
            return Err(at.error(format!(
                "unknown filter_type `{other}` (Mitsuba's are bilinear and nearest)"
            )))
        }
    }
    let repeat = match p.string("wrap_mode")? {
        None | Some(("repeat", _)) => true,
        Some(("clamp", _)) => false,
        Some(("mirror", at)) => {
            return Err(unsupported(
                at,
                "wrap_mode mirror (brume's images repeat or clamp)",
            ))
        }
        Some((other, at)) => {
            return Err(at.error(format!(
                "unknown wrap_mode `{other}` (Mitsuba's are repeat, mirror and clamp)"
            )))
        }
    };
    desc.wrap = Some(if repeat { "repeat" } else { "clamp" }.into());
    // Mitsuba decodes 8-bit data through the sRGB curve unless raw; brume's
    // PNGs are sRGB unless declared linear, and EXR/HDR are linear either way.
    if p.bool("raw")? == Some(true) {
        desc.color_space = Some("linear".into());
    }
    Ok(repeat)
}
