//! `<medium type="homogeneous">` with `<phase>`, and where media go.
//!
//! Mitsuba sets the medium a ray travels in from the interface it last
//! crossed (a shape's `interior`/`exterior`, the sensor's medium); brume
//! fills space by containment (a shape's `interior`, or a global medium)
//! and adds media that overlap. Where the two agree the media are placed by
//! containment, so the scene renders with every integrator:
//! - one medium outside every shape (the sensor's and every shape's
//!   exterior) becomes a global medium, with no interior media;
//! - else media inside closed see-through shapes (no exterior of their
//!   own), objects inside them declaring that medium as their exterior, no
//!   other shape's bounds overlapping a medium shape, and a camera inside
//!   one only if the sensor names its medium.
//!
//! Any other arrangement keeps Mitsuba's rule ([`InterfaceDesc`]): each
//! medium once, unbounded, and each shape's interior/exterior indices into
//! them; the path tracer then carries the current medium along its rays.

mod heterogeneous;

use super::mechanics::Node;
use super::shape::Imported;
use super::values::{ColorParam, Obj, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{Color, InterfaceDesc, MediumDesc, PhaseDesc};

/// Where the imported media go.
pub(crate) struct Placed<'a> {
    /// Each shape's interior medium, in shape order (containment only).
    pub interiors: Vec<Option<MediumDesc>>,
    /// The media filling space (`[[medium]]` entries), each with its element.
    pub media: Vec<(MediumDesc, &'a Node)>,
    /// Mitsuba's interface rule, where containment would render differently.
    pub interfaces: Option<InterfaceDesc>,
}

/// Identity of a medium: the element itself (a `<ref>` resolves to it).
fn key(obj: &Obj) -> *const Node {
    obj.node
}

/// Places the media of `shapes` and the sensor's.
pub(crate) fn place<'a>(
    ctx: &Ctx<'a>,
    shapes: &[Imported<'a>],
    sensor: Option<Obj<'a>>,
    eye: [f32; 3],
) -> Result<Placed<'a>> {
    let interior_keys: Vec<_> = shapes
        .iter()
        .filter_map(|s| s.interior.as_ref().map(key))
        .collect();
    let outside: Vec<Obj> = shapes
        .iter()
        .filter_map(|s| s.exterior)
        .chain(sensor)
        .filter(|m| !interior_keys.contains(&key(m)))
        .collect();
    let one_outside = outside.iter().all(|m| key(m) == key(&outside[0]));
    match outside.first() {
        Some(global) if one_outside && global_agrees(shapes, sensor, *global) => {
            place_global(ctx, shapes, *global)
        }
        None if interiors_agree(shapes, sensor, eye) => match place_interiors(ctx, shapes)? {
            Some(placed) => Ok(placed),
            None => place_interfaces(ctx, shapes, sensor),
        },
        _ => place_interfaces(ctx, shapes, sensor),
    }
}

/// Media inside shapes only: each shape's interior by containment, or
/// `None` when a medium's box does not hold its shape (containment would
/// fill the whole shape, Mitsuba's rule keeps the medium in its box).
fn place_interiors<'a>(ctx: &Ctx<'a>, shapes: &[Imported<'a>]) -> Result<Option<Placed<'a>>> {
    let mut interiors = Vec::new();
    for s in shapes {
        interiors.push(match s.interior {
            Some(m) => match heterogeneous::fit_interior(read(ctx, m.node)?, s.bounds) {
                Some(fitted) => Some(fitted),
                None => return Ok(None),
            },
            None => None,
        });
    }
    Ok(Some(Placed {
        interiors,
        media: Vec::new(),
        interfaces: None,
    }))
}

/// True when containment and Mitsuba's rule agree for media inside shapes:
/// no invisible null shape, and every medium shape passes [`medium_shape_agrees`].
fn interiors_agree(shapes: &[Imported], sensor: Option<Obj>, eye: [f32; 3]) -> bool {
    shapes.iter().enumerate().all(|(i, s)| match s.interior {
        None => !s.null,
        Some(m) => medium_shape_agrees(shapes, i, &m, sensor, eye),
    })
}

/// A medium shape both rules read alike: closed, see-through, no exterior
/// medium, nothing overlapping it that does not live in its medium, the
/// camera inside only if the sensor says so.
fn medium_shape_agrees(
    shapes: &[Imported],
    i: usize,
    m: &Obj,
    sensor: Option<Obj>,
    eye: [f32; 3],
) -> bool {
    let s = &shapes[i];
    use crate::scene::description::ShapeType;
    let closed = !matches!(s.desc.kind, ShapeType::Quad | ShapeType::Disk);
    if !closed || !s.transmissive || s.exterior.is_some() {
        return false;
    }
    let Some((lo, hi)) = s.bounds else {
        return true; // a mesh file that cannot be read (building the scene reports it)
    };
    let overlapped = shapes.iter().enumerate().any(|(j, other)| {
        let Some((olo, ohi)) = other.bounds else {
            return false;
        };
        let overlap = (0..3).all(|a| olo[a] < hi[a] && lo[a] < ohi[a]);
        j != i && overlap && other.exterior.map(|e| key(&e)) != Some(key(m))
    });
    let inside = (0..3).all(|a| lo[a] < eye[a] as f64 && (eye[a] as f64) < hi[a]);
    !overlapped && (!inside || sensor.map(|e| key(&e)) == Some(key(m)))
}

/// True when one medium around everything reads alike under both rules:
/// the sensor is in it, every shape has it outside, and inside too if light
/// passes through the surface (and no other medium inside).
fn global_agrees(shapes: &[Imported], sensor: Option<Obj>, global: Obj) -> bool {
    let same = |m: Option<Obj>| m.map(|m| key(&m)) == Some(key(&global));
    same(sensor)
        && shapes.iter().all(|s| {
            same(s.exterior)
                && (s.interior.is_none() || same(s.interior))
                && (!s.transmissive || same(s.interior))
                && !s.null
        })
}

/// One medium around everything, as brume's global medium.
fn place_global<'a>(ctx: &Ctx<'a>, shapes: &[Imported<'a>], global: Obj<'a>) -> Result<Placed<'a>> {
    Ok(Placed {
        interiors: shapes.iter().map(|_| None).collect(),
        media: vec![(unbounded(ctx, global.node)?, global.node)],
        interfaces: None,
    })
}

/// A medium filling space: a homogeneous one made global (a grid, or a
/// constant σt bounded by its constant volume's box, stays in its box).
fn unbounded(ctx: &Ctx, node: &Node) -> Result<MediumDesc> {
    let mut medium = read(ctx, node)?;
    if let MediumDesc::Homogeneous {
        global: g,
        bounds: None,
        ..
    } = &mut medium
    {
        *g = true;
    }
    Ok(medium)
}

/// Mitsuba's rule kept: every medium once, unbounded, and each shape's
/// interior and exterior (and the sensor's medium) as indices into them.
fn place_interfaces<'a>(
    ctx: &Ctx<'a>,
    shapes: &[Imported<'a>],
    sensor: Option<Obj<'a>>,
) -> Result<Placed<'a>> {
    let mut media: Vec<(MediumDesc, &'a Node)> = Vec::new();
    let mut index = |m: Option<Obj<'a>>| -> Result<Option<u32>> {
        let Some(m) = m else {
            return Ok(None);
        };
        if let Some(i) = media.iter().position(|(_, n)| std::ptr::eq(*n, m.node)) {
            return Ok(Some(i as u32));
        }
        media.push((unbounded(ctx, m.node)?, m.node));
        Ok(Some(media.len() as u32 - 1))
    };
    let camera = index(sensor)?;
    let mut sides = Vec::new();
    for s in shapes {
        sides.push(match (s.interior, s.exterior) {
            (None, None) => None,
            (interior, exterior) => Some([index(interior)?, index(exterior)?]),
        });
    }
    Ok(Placed {
        interiors: shapes.iter().map(|_| None).collect(),
        media,
        interfaces: Some(InterfaceDesc {
            shapes: sides,
            camera,
        }),
    })
}

/// A `<medium>`: `homogeneous` or `heterogeneous`.
pub(crate) fn read(ctx: &Ctx, node: &Node) -> Result<MediumDesc> {
    match node.required("type")? {
        "homogeneous" => read_homogeneous(ctx, node),
        "heterogeneous" => heterogeneous::read(ctx, node),
        _ => Err(unsupported(
            node,
            "this medium (homogeneous, heterogeneous)",
        )),
    }
}

/// `<medium type="homogeneous">`: σt = scale · sigma_t, albedo σs/σt.
fn read_homogeneous(ctx: &Ctx, node: &Node) -> Result<MediumDesc> {
    let p = ctx.props(node)?;
    let sigma_t = coefficient(ctx, &p, "sigma_t", 1.0)?;
    let albedo = coefficient(ctx, &p, "albedo", 0.75)?;
    let scale = p.float("scale")?.unwrap_or(1.0);
    // Sampling strategies, not the medium's look.
    p.bool("sample_emitters")?;
    p.bool("has_spectral_extinction")?;
    let phase = match p.object("phase", None) {
        Some(ph) => phase(ctx, ph.node)?,
        None => None,
    };
    p.finish()?;
    Ok(MediumDesc::Homogeneous {
        sigma_a: None,
        sigma_s: None,
        sigma_t: Some(Color(sigma_t.map(|v| (v * scale) as f32))),
        albedo: Some(Color(albedo.map(|v| v as f32))),
        emission: None,
        phase,
        bounds: None,
        global: false,
        transform: None,
    })
}

/// A medium coefficient: a number, `<rgb>`, `<spectrum>` or `<volume type="constvolume">`.
fn coefficient(ctx: &Ctx, p: &Props, key: &str, default: f64) -> Result<[f64; 3]> {
    if let Some(v) = p.object("volume", Some(key)) {
        if v.node.attr("type") != Some("constvolume") {
            return Err(unsupported(v.at, "a grid volume in a homogeneous medium"));
        }
        let inner = ctx.props(v.node)?;
        let value = constant(&inner, "value", 1.0)?;
        inner.finish()?;
        return Ok(value);
    }
    constant(p, key, default)
}

/// A constant colour parameter.
pub(crate) fn constant(p: &Props, key: &str, default: f64) -> Result<[f64; 3]> {
    match p.color(key)? {
        None => Ok([default; 3]),
        Some(ColorParam::Rgb(c)) => Ok(c),
        Some(ColorParam::Texture(t)) => Err(unsupported(t.at, "a texture as a medium coefficient")),
    }
}

/// `<phase>`: isotropic (brume's default) or hg (Mitsuba's default g = 0.8).
pub(crate) fn phase(ctx: &Ctx, node: &Node) -> Result<Option<PhaseDesc>> {
    let p = ctx.props(node)?;
    let phase = match node.required("type")? {
        "isotropic" => None,
        "hg" => Some(PhaseDesc::Hg {
            g: p.float("g")?.unwrap_or(0.8),
        }),
        _ => return Err(unsupported(node, "this phase function (isotropic, hg)")),
    };
    p.finish()?;
    Ok(phase)
}
