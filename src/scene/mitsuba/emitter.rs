//! `<emitter>`: point, spot, directional, constant, envmap, and area (on a shape).

use super::mechanics::Node;
use super::transform::rotate_degrees;
use super::values::{ColorParam, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{Color, LightDesc, MapFilterDesc, SpotEdgeDesc};
use glam::{DMat3, DMat4, DVec3};

/// A light of the scene (not an area emitter: those belong to shapes).
pub(crate) fn read(ctx: &Ctx, node: &Node) -> Result<LightDesc> {
    let kind = node.required("type")?;
    let p = ctx.props(node)?;
    let to_world = p.transform("to_world")?;
    let m = to_world.unwrap_or(DMat4::IDENTITY);
    let light = match kind {
        "point" => {
            let position = match (p.point("position")?, to_world) {
                (Some(_), Some(_)) => {
                    return Err(node.error("give either position or to_world, not both"))
                }
                (Some(pos), None) => pos,
                (None, _) => m.transform_point3(DVec3::ZERO),
            };
            LightDesc::Point {
                position: position.as_vec3().to_array(),
                intensity: constant(&p, "intensity")?,
            }
        }
        "spot" => spot(&p, &m)?,
        "directional" => {
            let direction = match (p.point("direction")?, to_world) {
                (Some(_), Some(_)) => {
                    return Err(node.error("give either direction or to_world, not both"))
                }
                (Some(d), None) => d,
                (None, _) => m.transform_vector3(DVec3::Z),
            };
            LightDesc::Sun {
                direction: direction.as_vec3().to_array(),
                irradiance: constant(&p, "irradiance")?,
                angular_radius: 0.0,
            }
        }
        "constant" => LightDesc::Environment {
            radiance: constant(&p, "radiance")?,
        },
        "envmap" => envmap(ctx, &p, &m)?,
        "area" => return Err(node.error(
            "an area emitter belongs inside the <shape> that emits (brume: the shape's emission)",
        )),
        _ => return Err(unsupported(node, "this emitter")),
    };
    p.finish()?;
    Ok(light)
}

/// The radiance of `<emitter type="area">` inside a shape (one-sided, along the normal).
pub(crate) fn area(ctx: &Ctx, node: &Node) -> Result<Color> {
    if node.required("type")? != "area" {
        return Err(unsupported(node, "a non-area emitter inside a <shape>"));
    }
    let p = ctx.props(node)?;
    let radiance = constant(&p, "radiance")?;
    p.finish()?;
    Ok(radiance)
}

/// A constant colour parameter (Mitsuba's default 1); textures are refused here.
fn constant(p: &Props, key: &str) -> Result<Color> {
    match p.color(key)? {
        None => Ok(Color([1.0; 3])),
        Some(ColorParam::Rgb(c)) => Ok(Color(c.map(|v| v as f32))),
        Some(ColorParam::Texture(t)) => Err(unsupported(t.at, "a textured emitter")),
    }
}

/// `<emitter type="spot">`: full intensity inside `beam_width`, falling
/// linearly in angle to 0 at `cutoff_angle` (brume's `cone_edge = "linear"`).
fn spot(p: &Props, m: &DMat4) -> Result<LightDesc> {
    let cutoff = p.float("cutoff_angle")?.unwrap_or(20.0);
    let beam = p.float("beam_width")?.unwrap_or(cutoff * 0.75);
    if !(0.0..=cutoff).contains(&beam) {
        return Err(p.node_of("beam_width").unwrap_or(p.owner).error(format!(
            "beam_width {beam} must lie between 0 and cutoff_angle {cutoff}"
        )));
    }
    if let Some(at) = p.node_of("texture") {
        return Err(unsupported(at, "a spot light's projected texture"));
    }
    let f = |v: DVec3| v.as_vec3().to_array();
    Ok(LightDesc::Spot {
        position: f(m.transform_point3(DVec3::ZERO)),
        look_at: f(m.transform_point3(DVec3::Z)),
        intensity: constant(p, "intensity")?,
        cone_angle: cutoff as f32,
        cone_falloff: Some((cutoff - beam) as f32),
        cone_edge: SpotEdgeDesc::Linear,
    })
}

/// `<emitter type="envmap">`: Mitsuba's texel (u, v) looks along
/// (sin 2πu sin πv, cos πv, −cos 2πu sin πv) in the map's frame, brume's
/// along (cos 2πu sin πv, cos πv, sin 2πu sin πv): a turn of 90° about +Y,
/// applied before `to_world`.
fn envmap(ctx: &Ctx, p: &Props, m: &DMat4) -> Result<LightDesc> {
    let (name, at) = p
        .string("filename")?
        .ok_or_else(|| p.owner.error("give <string name=\"filename\">"))?;
    let file = ctx.file(name, at)?;
    let scale = p.float("scale")?.unwrap_or(1.0) as f32;
    let linear = DMat3::from_mat4(*m);
    let lengths = DVec3::new(
        linear.x_axis.length(),
        linear.y_axis.length(),
        linear.z_axis.length(),
    );
    let orthonormal = (linear.transpose() * linear - DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .all(|v| v.abs() < 1e-6);
    if !orthonormal || linear.determinant() < 0.0 || lengths.min_element() <= 0.0 {
        return Err(unsupported(
            p.node_of("to_world").unwrap_or(p.owner),
            "an envmap to_world other than a rotation",
        ));
    }
    let rotation = linear * DMat3::from_rotation_y(90f64.to_radians());
    // Mitsuba interpolates the map bilinearly.
    Ok(LightDesc::EnvironmentMap {
        file,
        scale: Color([scale; 3]),
        rotate: Some(rotate_degrees(&rotation).unwrap_or([0.0; 3])),
        filter: MapFilterDesc::Bilinear,
    })
}
