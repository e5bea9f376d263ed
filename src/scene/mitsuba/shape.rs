//! `<shape>`: sphere, cube, rectangle, disk, obj and ply, with their BSDF, area
//! emitter and interior/exterior media.

use super::bsdf::Surface;
use super::mechanics::Node;
use super::texture::UvFrame;
use super::transform::{axes, to_brume};
use super::values::{Obj, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{
    Color, ColorOrTexture, MaterialDesc, ShapeDesc, ShapeType, UvAxesDesc,
};
use glam::{DMat3, DMat4, DVec3};

/// A shape read from the XML, before media are placed.
pub(crate) struct Imported<'a> {
    /// The `<shape>` element.
    pub node: &'a Node,
    /// brume's shape (its `interior` is set when media are placed).
    pub desc: ShapeDesc,
    /// The medium inside (`name="interior"`).
    pub interior: Option<Obj<'a>>,
    /// The medium outside (`name="exterior"`).
    pub exterior: Option<Obj<'a>>,
    /// Its BSDF is null (no surface at all).
    pub null: bool,
    /// Light passes through the surface (null or dielectric).
    pub transmissive: bool,
    /// World-space bounds (for the overlap check of media).
    pub bounds: Option<(DVec3, DVec3)>,
}

/// One `<shape>`.
pub(crate) fn read<'a>(ctx: &Ctx<'a>, node: &'a Node) -> Result<Imported<'a>> {
    let kind = node.required("type")?;
    let p = ctx.props(node)?;
    let flip = p.bool("flip_normals")?.unwrap_or(false);
    let (mut desc, bounds) = geometry(ctx, &p, kind, flip)?;
    let frame = uv_frame(&p, kind, flip)?;
    let surface = match p.object("bsdf", None) {
        Some(b) => super::bsdf::read(ctx, b, frame)?,
        None => Surface {
            material: Some(MaterialDesc::Diffuse {
                albedo: ColorOrTexture::Color(Color([0.5; 3])),
            }),
            one_sided: true,
            transmissive: false,
        },
    };
    if let Some(e) = p.object("emitter", None) {
        desc.emission = Some(ColorOrTexture::Color(super::emitter::area(ctx, e.node)?));
    }
    let interior = p.object("medium", Some("interior"));
    let exterior = p.object("medium", Some("exterior"));
    if let Some(m) = p
        .objects("medium")
        .into_iter()
        .find(|m| !matches!(m.name, Some("interior" | "exterior")))
    {
        return Err(m
            .at
            .error("a shape's medium needs name=\"interior\" or name=\"exterior\""));
    }
    p.finish()?;
    let null = surface.material.is_none();
    desc.material = surface.material;
    if flip && !matches!(kind, "rectangle" | "disk") {
        flip_closed(node, &mut desc, surface.one_sided, interior.or(exterior))?;
    }
    if surface.one_sided && matches!(kind, "rectangle" | "disk" | "obj" | "ply") {
        ctx.warn(
            node,
            "Mitsuba's BSDF is black from behind, brume's shades both sides: \
             wrap it in <bsdf type=\"twosided\"> if the back is ever seen",
        );
    }
    Ok(Imported {
        node,
        desc,
        interior,
        exterior,
        null,
        transmissive: surface.transmissive,
        bounds,
    })
}

/// World bounds (where known before files are read).
type Bounds = Option<(DVec3, DVec3)>;

/// The shape's geometry and placement, by `type`.
fn geometry(ctx: &Ctx, p: &Props, kind: &str, flip: bool) -> Result<(ShapeDesc, Bounds)> {
    let node = p.owner;
    let to_world = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let at = p.node_of("to_world").unwrap_or(node);
    let mut desc = blank(ShapeType::Sphere);
    let bounds = match kind {
        "sphere" => {
            let center = p.point("center")?.unwrap_or(DVec3::ZERO);
            let radius = p.float("radius")?.unwrap_or(1.0);
            desc.center = Some(center.as_vec3().to_array());
            desc.radius = Some(radius as f32);
            desc.transform = to_brume(&to_world, at)?;
            desc.uv_axes = Some(sphere_uv_axes(&to_world));
            Some(box_bounds(&to_world, center, DVec3::splat(radius)))
        }
        "cube" => {
            desc.kind = ShapeType::Box;
            desc.center = Some([0.0; 3]);
            desc.size = Some(vec![2.0; 3]);
            desc.face_uv = Some("mitsuba".into());
            desc.transform = to_brume(&to_world, at)?;
            Some(box_bounds(&to_world, DVec3::ZERO, DVec3::ONE))
        }
        "rectangle" => {
            rectangle(&mut desc, &to_world, flip, at)?;
            let half = DVec3::new(1.0, 1.0, 0.0);
            Some(box_bounds(&to_world, DVec3::ZERO, half))
        }
        "disk" => {
            disk(&mut desc, &to_world, flip, at)?;
            let half = DVec3::new(1.0, 1.0, 0.0);
            Some(box_bounds(&to_world, DVec3::ZERO, half))
        }
        "obj" | "ply" => {
            mesh(ctx, p, &mut desc)?;
            desc.transform = to_brume(&to_world, at)?;
            let file = desc.file.as_deref().expect("mesh() sets the file");
            mesh_bounds(file, kind)
                .map(|(lo, hi)| box_bounds(&to_world, (lo + hi) / 2.0, (hi - lo) / 2.0))
        }
        _ => {
            return Err(unsupported(
                node,
                "this shape (sphere, cube, rectangle, disk, obj, ply)",
            ))
        }
    };
    Ok((desc, bounds))
}

/// `<shape type="obj">` or `"ply"`: the file; face normals are refused.
fn mesh(ctx: &Ctx, p: &Props, desc: &mut ShapeDesc) -> Result<()> {
    let (name, file_at) = p
        .string("filename")?
        .ok_or_else(|| p.owner.error("give <string name=\"filename\">"))?;
    desc.kind = ShapeType::Mesh;
    desc.file = Some(ctx.file(name, file_at)?);
    if p.bool("face_normals")? == Some(true) {
        return Err(unsupported(
            p.owner,
            "face_normals (brume shades with the mesh's vertex normals when it has them)",
        ));
    }
    Ok(())
}

/// How Mitsuba's texture coordinates on a `kind` shape relate to brume's on
/// the shape it becomes (docs/textures.md has brume's, README.md Mitsuba's).
fn uv_frame(p: &Props, kind: &str, flip: bool) -> Result<UvFrame> {
    Ok(match kind {
        // Mitsuba: u, v = (x + 1)/2, (y + 1)/2 on the local square. brume's
        // quad runs u along local X and v along normal × u: along local Y
        // unless flip_normals or a mirroring to_world turns the normal.
        "rectangle" => {
            let m = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
            if (DMat3::from_mat4(m).determinant() < 0.0) != flip {
                UvFrame::Flipped
            } else {
                UvFrame::Same
            }
        }
        // Mitsuba flips an OBJ's v (1 − vt) unless told not to; brume uses vt as written.
        "obj" if p.bool("flip_tex_coords")?.unwrap_or(true) => UvFrame::Flipped,
        "obj" | "ply" => UvFrame::Same,
        // brume's sphere takes Mitsuba's axes (`sphere_uv_axes`).
        "sphere" => UvFrame::Same,
        // Both: (r, φ/2π ∈ [0, 1)), φ from local X toward local Y in Mitsuba,
        // from u_axis toward normal × u_axis in brume, which flip_normals turns.
        "disk" if flip => UvFrame::Flipped,
        "disk" => UvFrame::Same,
        // The cube (geometry() has refused every other type): brume's box with
        // face_uv = "mitsuba" runs (u, 1 − v) over each face of Mitsuba's cube.
        _ => UvFrame::Flipped,
    })
}

/// Mitsuba's sphere coordinates: u = φ / 2π from local X toward local Y,
/// v = θ / π from local Z, turned by `to_world`. brume's v = 1 − θ / π from
/// its pole and u from its seam toward seam × pole: the pole is local −Z
/// and the seam local X (then seam × pole = local Y).
fn sphere_uv_axes(to_world: &DMat4) -> UvAxesDesc {
    let linear = DMat3::from_mat4(*to_world);
    let pole = -(linear * DVec3::Z).normalize();
    let seam = (linear * DVec3::X).normalize();
    UvAxesDesc {
        pole: pole.as_vec3().to_array(),
        seam: seam.as_vec3().to_array(),
    }
}

/// A shape description with nothing set but its type.
fn blank(kind: ShapeType) -> ShapeDesc {
    ShapeDesc {
        kind,
        center: None,
        radius: None,
        normal: None,
        size: None,
        u_axis: None,
        file: None,
        material: None,
        emission: None,
        two_sided: false,
        transform: None,
        interior: None,
        filter: None,
        uv_axes: None,
        face_uv: None,
    }
}

/// Mitsuba's rectangle: [-1, 1]² in the local XY plane, normal +Z, mapped by `m`.
fn rectangle(desc: &mut ShapeDesc, m: &DMat4, flip: bool, at: &Node) -> Result<()> {
    let Some((cols, lengths)) = axes(m) else {
        return Err(unsupported(
            at,
            "a rectangle to_world with shear (a parallelogram)",
        ));
    };
    let linear = DMat3::from_mat4(*m);
    let normal = (linear.inverse().transpose() * DVec3::Z).normalize();
    let normal = if flip { -normal } else { normal };
    desc.kind = ShapeType::Quad;
    desc.center = Some(m.transform_point3(DVec3::ZERO).as_vec3().to_array());
    desc.normal = Some(normal.as_vec3().to_array());
    desc.u_axis = Some((cols[0] / lengths.x).as_vec3().to_array());
    desc.size = Some(vec![2.0 * lengths.x as f32, 2.0 * lengths.y as f32]);
    Ok(())
}

/// Mitsuba's disk: the unit disk in the local XY plane, normal +Z, mapped by
/// `m`, which must keep it round (equal X and Y scales) and not mirror it
/// (brume's polar angle turns from `u_axis` toward normal × `u_axis`).
fn disk(desc: &mut ShapeDesc, m: &DMat4, flip: bool, at: &Node) -> Result<()> {
    let Some((cols, lengths)) = axes(m) else {
        return Err(unsupported(at, "a disk to_world with shear"));
    };
    if (lengths.x - lengths.y).abs() > 1e-6 * lengths.x.max(lengths.y) {
        return Err(unsupported(
            at,
            "a disk to_world scaling X and Y differently (an ellipse; brume's disk is round)",
        ));
    }
    if DMat3::from_cols(cols[0], cols[1], cols[2]).determinant() < 0.0 {
        return Err(unsupported(at, "a mirroring to_world (negative scale)"));
    }
    let normal = cols[0].cross(cols[1]).normalize();
    let normal = if flip { -normal } else { normal };
    desc.kind = ShapeType::Disk;
    desc.center = Some(m.transform_point3(DVec3::ZERO).as_vec3().to_array());
    desc.normal = Some(normal.as_vec3().to_array());
    desc.u_axis = Some((cols[0] / lengths.x).as_vec3().to_array());
    desc.radius = Some(lengths.x as f32);
    Ok(())
}

/// `flip_normals` on a closed shape (sphere, cube, mesh): Mitsuba turns its
/// inside out. brume's closed shapes keep their outward normals, so only what
/// the normal does not change is accepted: a two-sided or null surface, a thin
/// sheet, and a dielectric, whose interior index becomes the outside one
/// (relative index 1/η); emission, media and one-sided BSDFs are refused.
fn flip_closed(
    node: &Node,
    desc: &mut ShapeDesc,
    one_sided: bool,
    medium: Option<Obj>,
) -> Result<()> {
    let refuse = |why: &str| Err(unsupported(node, &format!("flip_normals on a {why}")));
    if desc.emission.is_some() {
        return refuse("closed shape that emits (brume's spheres, boxes and meshes emit along their own normals)");
    }
    if medium.is_some() {
        return refuse("closed shape holding a medium (it would hold it outside)");
    }
    match &mut desc.material {
        _ if one_sided => refuse(
            "closed shape with a one-sided BSDF (Mitsuba shows its black back from outside; \
             wrap the BSDF in <bsdf type=\"twosided\"> if both sides should shade)",
        ),
        Some(MaterialDesc::Dielectric { ior, .. }) => {
            *ior = 1.0 / *ior;
            Ok(())
        }
        _ => Ok(()),
    }
}

/// The box of a mesh file's vertices, so that media placement sees meshes
/// nested in or overlapping medium shapes. A file that cannot be read gives
/// none here: building the scene reads it again and reports the problem.
fn mesh_bounds(file: &std::path::Path, kind: &str) -> Option<(DVec3, DVec3)> {
    let positions: Vec<DVec3> = if kind == "ply" {
        let bytes = std::fs::read(file).ok()?;
        let mesh = crate::scene::ply::parse(&bytes).ok()?;
        mesh.positions.iter().map(|v| v.as_dvec3()).collect()
    } else {
        let (models, _) = tobj::load_obj(file, &tobj::LoadOptions::default()).ok()?;
        models
            .iter()
            .flat_map(|m| m.mesh.positions.chunks_exact(3))
            .map(|v| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64))
            .collect()
    };
    let lo = positions.iter().copied().reduce(DVec3::min)?;
    let hi = positions.iter().copied().reduce(DVec3::max)?;
    Some((lo, hi))
}

/// World bounds of the local box `center ± half` mapped by `m`.
fn box_bounds(m: &DMat4, center: DVec3, half: DVec3) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..8 {
        let sign = DVec3::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
            if i & 4 == 0 { -1.0 } else { 1.0 },
        );
        let p = m.transform_point3(center + sign * half);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    (lo, hi)
}
