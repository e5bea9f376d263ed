//! `<medium type="homogeneous">` with `<phase>`, and where media go.
//!
//! Mitsuba sets the medium a ray travels in from the interface it last
//! crossed (a shape's `interior`/`exterior`, the sensor's medium); brume
//! fills space by containment (a shape's `interior`, or a global medium)
//! and adds media that overlap. The two agree for the arrangements accepted
//! here; the others are refused, naming the shape:
//! - one medium outside every shape (the sensor's and every shape's
//!   exterior) becomes a global medium, with no interior media;
//! - else media inside closed shapes (no exterior of their own), objects
//!   inside them declaring that medium as their exterior, no other shape's
//!   bounds overlapping a medium shape, and a camera inside one only if the
//!   sensor names its medium.

mod heterogeneous;

use super::mechanics::Node;
use super::shape::Imported;
use super::values::{ColorParam, Obj, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{Color, MediumDesc, PhaseDesc};

/// Where the imported media go.
pub(crate) struct Placed<'a> {
    /// Each shape's interior medium, in shape order.
    pub interiors: Vec<Option<MediumDesc>>,
    /// A medium filling space, with its element.
    pub global: Option<(MediumDesc, &'a Node)>,
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
    if let Some(second) = outside.iter().find(|m| key(m) != key(&outside[0])) {
        return Err(unsupported(
            second.at,
            "two different media outside shapes (brume's global medium is one)",
        ));
    }
    if let Some(global) = outside.first() {
        return place_global(ctx, shapes, sensor, *global);
    }
    for s in shapes {
        if s.null && s.interior.is_none() {
            return Err(unsupported(
                s.node,
                "a null surface with no medium inside (it is invisible)",
            ));
        }
    }
    let mut interiors = Vec::new();
    for (i, s) in shapes.iter().enumerate() {
        let Some(m) = s.interior else {
            interiors.push(None);
            continue;
        };
        check_medium_shape(shapes, i, &m, sensor, eye)?;
        interiors.push(Some(read(ctx, m.node)?));
    }
    Ok(Placed {
        interiors,
        global: None,
    })
}

/// A medium shape: closed, no exterior medium, nothing overlapping it that
/// does not live in its medium, the camera inside only if the sensor says so.
fn check_medium_shape(
    shapes: &[Imported],
    i: usize,
    m: &Obj,
    sensor: Option<Obj>,
    eye: [f32; 3],
) -> Result<()> {
    let s = &shapes[i];
    use crate::scene::description::ShapeType;
    if matches!(s.desc.kind, ShapeType::Quad | ShapeType::Disk) {
        return Err(unsupported(
            s.node,
            "a medium inside a rectangle or disk (not a closed shape)",
        ));
    }
    if !s.transmissive {
        return Err(unsupported(
            s.node,
            "a medium inside an opaque shape (light never reaches it)",
        ));
    }
    if s.exterior.is_some() {
        return Err(unsupported(
            s.node,
            "a medium shape with its own exterior medium (nested media add in brume)",
        ));
    }
    let Some((lo, hi)) = s.bounds else {
        return Ok(()); // OBJ bounds are not known before the mesh is read
    };
    for (j, other) in shapes.iter().enumerate() {
        let Some((olo, ohi)) = other.bounds else {
            continue;
        };
        let overlap = (0..3).all(|a| olo[a] < hi[a] && lo[a] < ohi[a]);
        if j != i && overlap && other.exterior.map(|e| key(&e)) != Some(key(m)) {
            return Err(unsupported(
                other.node,
                &format!(
                    "a shape overlapping the medium shape at line {} without naming that medium \
                     as its exterior (Mitsuba's medium follows the last interface crossed, \
                     brume's the shapes that contain the point)",
                    s.node.line
                ),
            ));
        }
    }
    let inside = (0..3).all(|a| lo[a] < eye[a] as f64 && (eye[a] as f64) < hi[a]);
    if inside && sensor.map(|e| key(&e)) != Some(key(m)) {
        return Err(unsupported(
            s.node,
            "the camera is inside this medium shape but the sensor does not name its medium",
        ));
    }
    Ok(())
}

/// One medium around everything: every shape must have it outside, and
/// inside too if light passes through the surface.
fn place_global<'a>(
    ctx: &Ctx<'a>,
    shapes: &[Imported<'a>],
    sensor: Option<Obj<'a>>,
    global: Obj<'a>,
) -> Result<Placed<'a>> {
    let same = |m: Option<Obj>| m.map(|m| key(&m)) == Some(key(&global));
    let what = global.node.what();
    if !same(sensor) {
        return Err(unsupported(
            global.at,
            &format!("{what} outside shapes while the sensor is in no medium"),
        ));
    }
    for s in shapes {
        if !same(s.exterior) {
            return Err(unsupported(
                s.node,
                &format!("a shape without exterior {what} while the camera is in it (Mitsuba would leave the medium at this surface)"),
            ));
        }
        if s.interior.is_some() && !same(s.interior) {
            return Err(unsupported(s.node, "a medium inside a shape that is itself inside a global medium (brume adds overlapping media)"));
        }
        if s.transmissive && !same(s.interior) {
            return Err(unsupported(
                s.node,
                &format!("a see-through shape in {what} without it inside too"),
            ));
        }
        if s.null {
            return Err(unsupported(
                s.node,
                "a null shape inside the global medium (it changes nothing: remove it)",
            ));
        }
    }
    let mut medium = read(ctx, global.node)?;
    if let MediumDesc::Homogeneous { global: g, .. } = &mut medium {
        *g = true;
    }
    Ok(Placed {
        interiors: shapes.iter().map(|_| None).collect(),
        global: Some((medium, global.node)),
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
