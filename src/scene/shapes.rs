//! Turning `[[shape]]` entries (and OBJ files) into primitives.

use super::description::{ShapeDesc, ShapeType, TransformDesc};
use super::files::{check_input, Format};
use super::resolve;
use super::validate::Check;
use crate::error::{Error, Result};
use crate::geometry::Primitive;
use crate::math::keyframes::Keyframes;
use crate::math::{Affine3A, Frame, Vec2, Vec3};
use std::path::Path;

/// The affine map of a `transform = { ... }` table (identity when absent; keyframes refused).
pub(crate) fn build_transform(
    t: Option<&TransformDesc>,
    field: &str,
    check: &Check,
) -> Result<Affine3A> {
    super::keyframes::build_still(t, field, "this", check)
}

/// Names the keys set on `shape` that its type does not use.
fn reject_foreign_keys(shape: &ShapeDesc, field: &str, check: &Check) -> Result<()> {
    let used: &[&str] = match shape.kind {
        ShapeType::Sphere => &["center", "radius", "uv_axes"],
        ShapeType::Quad => &["center", "normal", "size", "u_axis"],
        ShapeType::Box => &["center", "size", "face_uv"],
        ShapeType::Disk => &["center", "normal", "radius", "u_axis"],
        ShapeType::Mesh => &["file"],
        ShapeType::Slab => &["file", "filter"],
    };
    let present = [
        ("center", shape.center.is_some()),
        ("radius", shape.radius.is_some()),
        ("normal", shape.normal.is_some()),
        ("size", shape.size.is_some()),
        ("u_axis", shape.u_axis.is_some()),
        ("file", shape.file.is_some()),
        ("filter", shape.filter.is_some()),
        ("uv_axes", shape.uv_axes.is_some()),
        ("face_uv", shape.face_uv.is_some()),
    ];
    for (key, set) in present {
        if set && !used.contains(&key) {
            return Err(check.error(
                &format!("{field}.{key}"),
                format!("unknown key for a shape of type {:?}", shape.kind).to_lowercase(),
            ));
        }
    }
    Ok(())
}

fn required<T: Copy>(v: Option<T>, field: &str, key: &str, check: &Check) -> Result<T> {
    v.ok_or_else(|| check.error(&format!("{field}.{key}"), "missing"))
}

/// The primitives of one shape, with texture coordinates.
pub(crate) struct BuiltShape {
    /// Primitives in world space.
    pub primitives: Vec<Primitive>,
    /// Per-corner texture coordinates of each triangle of a mesh with `vt`
    /// lines; `None` for a mesh without (built-in shapes have their own, see `Geometry::uv`).
    pub texcoords: Option<Vec<[Vec2; 3]>>,
    /// The keyframes of a shape that moves; its primitives are then in its local frame.
    pub keys: Option<Keyframes>,
    /// A sphere's texture axes `[seam, pole, seam × pole]` (`uv_axes`).
    pub uv_axes: Option<[Vec3; 3]>,
}

/// The primitives of one shape entry, in world space.
pub(crate) fn build_shape(
    shape: &ShapeDesc,
    field: &str,
    check: &Check,
    base: &Path,
) -> Result<BuiltShape> {
    reject_foreign_keys(shape, field, check)?;
    // A moving shape is built in its local frame (keyframes place it per ray time).
    let (m, keys) =
        super::keyframes::build_placement(shape.transform.as_ref(), field, check)?.split();
    let center = check.vec3(&format!("{field}.center"), shape.center.unwrap_or([0.0; 3]))?;
    let primitives = match shape.kind {
        ShapeType::Sphere => vec![sphere(shape, &m, center, field, check)?],
        ShapeType::Quad => vec![quad(shape, &m, center, field, check)?],
        ShapeType::Box => box_faces(shape, &m, center, field, check)?,
        ShapeType::Disk => vec![disk(shape, &m, center, field, check)?],
        // A slab has no primitives: it is a box answered from its file (`slab_keys`).
        ShapeType::Slab => Vec::new(),
        ShapeType::Mesh => {
            let file = shape
                .file
                .as_ref()
                .ok_or_else(|| check.error(&format!("{field}.file"), "missing"))?;
            let path = resolve(base, file);
            let is_ply = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
            let key = format!("{field}.file");
            let mesh = if is_ply {
                load_ply(&path, &m, &key, check)?
            } else {
                load_obj(&path, &m, &key, check)?
            };
            return Ok(BuiltShape { keys, ..mesh });
        }
    };
    Ok(BuiltShape {
        primitives,
        texcoords: None,
        keys,
        uv_axes: uv_axes(shape, field, check)?,
    })
}

/// A sphere's `uv_axes`: unit pole and seam, the seam perpendicular to the pole.
fn uv_axes(shape: &ShapeDesc, field: &str, check: &Check) -> Result<Option<[Vec3; 3]>> {
    let Some(axes) = shape.uv_axes else {
        return Ok(None);
    };
    let unit = |key: &str, v: [f32; 3]| -> Result<Vec3> {
        let key = format!("{field}.uv_axes.{key}");
        let v = check.vec3(&key, v)?;
        match v.try_normalize() {
            Some(v) => Ok(v),
            None => Err(check.error(&key, "must not be zero")),
        }
    };
    let (pole, seam) = (unit("pole", axes.pole)?, unit("seam", axes.seam)?);
    if pole.dot(seam).abs() > 1e-3 {
        return Err(check.error(
            &format!("{field}.uv_axes.seam"),
            "must be perpendicular to the pole",
        ));
    }
    // Exactly perpendicular, so that the three axes rotate without scaling.
    let seam = (seam - pole * pole.dot(seam)).normalize();
    Ok(Some([seam, pole, seam.cross(pole)]))
}

/// The `n` positive numbers of `size`, each checked under its own index.
fn sizes(shape: &ShapeDesc, n: usize, field: &str, check: &Check) -> Result<Vec<f32>> {
    let s = shape
        .size
        .as_ref()
        .ok_or_else(|| check.error(&format!("{field}.size"), "missing"))?;
    if s.len() != n {
        return Err(check.error(&format!("{field}.size"), format!("must have {n} numbers")));
    }
    s.iter()
        .enumerate()
        .map(|(i, &v)| check.positive(&format!("{field}.size[{i}]"), v))
        .collect()
}

/// The world-space parallelogram centred on local `c` with local edges `eu`, `ev`.
fn parallelogram(m: &Affine3A, c: Vec3, eu: Vec3, ev: Vec3) -> Primitive {
    Primitive::Parallelogram {
        corner: m.transform_point3(c - 0.5 * (eu + ev)),
        edge_u: m.transform_vector3(eu),
        edge_v: m.transform_vector3(ev),
    }
}

/// A `type = "sphere"` shape; its transform must scale uniformly to stay a sphere.
fn sphere(
    shape: &ShapeDesc,
    m: &Affine3A,
    center: Vec3,
    field: &str,
    check: &Check,
) -> Result<Primitive> {
    let radius = check.positive(
        &format!("{field}.radius"),
        required(shape.radius, field, "radius", check)?,
    )?;
    Ok(Primitive::Sphere {
        center: m.transform_point3(center),
        radius: radius * uniform_scale(m, "sphere", field, check)?,
    })
}

/// The scale of a transform that scales all axes alike (a sphere stays a sphere, a disk a disk).
fn uniform_scale(m: &Affine3A, kind: &str, field: &str, check: &Check) -> Result<f32> {
    let (scale, _, _) = m.to_scale_rotation_translation();
    if (scale.max_element() - scale.min_element()).abs() > 1e-5 * scale.max_element() {
        return Err(check.error(
            &format!("{field}.transform.scale"),
            format!("a {kind} needs a uniform scale"),
        ));
    }
    Ok(scale.x)
}

/// The unit tangent `u` made perpendicular to `normal`, or any tangent when `u` is not given.
fn tangent(u: Option<[f32; 3]>, normal: Vec3, field: &str, check: &Check) -> Result<Vec3> {
    let Some(u) = u else {
        return Ok(Frame::from_z(normal).x);
    };
    let u = check.direction(&format!("{field}.u_axis"), u)?;
    (u - normal * u.dot(normal))
        .try_normalize()
        .ok_or_else(|| check.error(&format!("{field}.u_axis"), "is parallel to the normal"))
}

/// A `type = "disk"` shape; like a sphere, its transform must scale uniformly.
fn disk(
    shape: &ShapeDesc,
    m: &Affine3A,
    center: Vec3,
    field: &str,
    check: &Check,
) -> Result<Primitive> {
    let radius = check.positive(
        &format!("{field}.radius"),
        required(shape.radius, field, "radius", check)?,
    )?;
    let normal = check.direction(
        &format!("{field}.normal"),
        required(shape.normal, field, "normal", check)?,
    )?;
    let u_axis = tangent(shape.u_axis, normal, field, check)?;
    let scale = uniform_scale(m, "disk", field, check)?;
    // A uniform scale with a rotation keeps both unit and perpendicular once renormalised.
    let normal = m.transform_vector3(normal).normalize();
    let u_axis = m.transform_vector3(u_axis).normalize();
    Ok(Primitive::Disk {
        center: m.transform_point3(center),
        normal,
        u_axis,
        radius: radius * scale,
    })
}

/// A `type = "quad"` shape, its `u_axis` made perpendicular to its normal.
fn quad(
    shape: &ShapeDesc,
    m: &Affine3A,
    center: Vec3,
    field: &str,
    check: &Check,
) -> Result<Primitive> {
    let normal = check.direction(
        &format!("{field}.normal"),
        required(shape.normal, field, "normal", check)?,
    )?;
    let s = sizes(shape, 2, field, check)?;
    let u_dir = tangent(shape.u_axis, normal, field, check)?;
    let v_dir = normal.cross(u_dir);
    // edge_u × edge_v must point along the normal: u × (n × u) = n.
    Ok(parallelogram(m, center, u_dir * s[0], v_dir * s[1]))
}

/// The six outward-facing faces of a `type = "box"` shape.
fn box_faces(
    shape: &ShapeDesc,
    m: &Affine3A,
    center: Vec3,
    field: &str,
    check: &Check,
) -> Result<Vec<Primitive>> {
    let s = sizes(shape, 3, field, check)?;
    let h = Vec3::new(s[0], s[1], s[2]) * 0.5;
    match shape.face_uv.as_deref() {
        None | Some("brume") => {}
        Some("mitsuba") => return Ok(mitsuba_cube_faces(m, center, h)),
        Some(other) => {
            return Err(check.error(
                &format!("{field}.face_uv"),
                format!("unknown face layout `{other}`, expected \"brume\" or \"mitsuba\""),
            ))
        }
    }
    let mut faces = Vec::with_capacity(6);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let mut eu = Vec3::ZERO;
            let mut ev = Vec3::ZERO;
            eu[(axis + 1) % 3] = 2.0 * h[(axis + 1) % 3];
            ev[(axis + 2) % 3] = 2.0 * h[(axis + 2) % 3];
            if sign < 0.0 {
                std::mem::swap(&mut eu, &mut ev);
            }
            faces.push(parallelogram(m, center + n * h[axis], eu, ev));
        }
    }
    Ok(faces)
}

/// The faces of Mitsuba 3's `cube` (its corners, face order and texture
/// coordinates: each face's corners with uv (0, 1), (1, 1), (1, 0), (0, 0)
/// in that order), as parallelograms from the corner at uv (0, 1): their
/// (s, t) is Mitsuba's (u, 1 − v), their normal (first edge × second) faces out.
fn mitsuba_cube_faces(m: &Affine3A, center: Vec3, h: Vec3) -> Vec<Primitive> {
    // Per face, the corners at uv (0, 1), (1, 1) and (0, 0), as signs of the half sizes.
    const FACES: [[[f32; 3]; 3]; 6] = [
        [[1.0, -1.0, -1.0], [1.0, -1.0, 1.0], [-1.0, -1.0, -1.0]],
        [[1.0, 1.0, -1.0], [-1.0, 1.0, -1.0], [1.0, 1.0, 1.0]],
        [[1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [1.0, -1.0, 1.0]],
        [[1.0, -1.0, 1.0], [1.0, 1.0, 1.0], [-1.0, -1.0, 1.0]],
        [[-1.0, -1.0, 1.0], [-1.0, 1.0, 1.0], [-1.0, -1.0, -1.0]],
        [[1.0, 1.0, -1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0]],
    ];
    FACES
        .iter()
        .map(|[v0, v1, v3]| {
            let corner = |s: &[f32; 3]| Vec3::from_array(*s) * h;
            let (p0, p1, p3) = (corner(v0), corner(v1), corner(v3));
            let (eu, ev) = (p1 - p0, p3 - p0);
            parallelogram(m, center + p0 + 0.5 * (eu + ev), eu, ev)
        })
        .collect()
}

/// Largest OBJ file read (a few tens of millions of triangles).
const MAX_OBJ_BYTES: u64 = 2 << 30;

/// Triangles of an OBJ file, transformed by `m`, with their `vt` coordinates if every model has them.
fn load_obj(path: &Path, m: &Affine3A, field: &str, check: &Check) -> Result<BuiltShape> {
    check_input(check, field, "OBJ file", path, Format::Obj, MAX_OBJ_BYTES)?;
    // every problem inside the file is reported under the key that named it
    let bad = |message: String| check.error(field, format!("{}: {message}", path.display()));
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) =
        tobj::load_obj(path, &options).map_err(|e| bad(format!("cannot read OBJ: {e}")))?;
    let mut out = ObjTriangles {
        prims: Vec::new(),
        texcoords: Vec::new(),
        normal_matrix: m.matrix3.inverse().transpose(),
    };
    let mut all_have_uv = true;
    for model in &models {
        all_have_uv &= out.append_model(model, m, &bad)?;
    }
    if out.prims.is_empty() {
        return Err(bad(
            "holds no triangles (no face `f` with 3 or more vertices): is it a Wavefront OBJ file?"
                .into(),
        ));
    }
    Ok(BuiltShape {
        primitives: out.prims,
        texcoords: all_have_uv.then_some(out.texcoords),
        keys: None,
        uv_axes: None,
    })
}

/// Largest PLY file read (as for OBJ).
const MAX_PLY_BYTES: u64 = MAX_OBJ_BYTES;

/// Triangles of a PLY file, transformed by `m`, with its texture coordinates if it has them.
fn load_ply(path: &Path, m: &Affine3A, field: &str, check: &Check) -> Result<BuiltShape> {
    check_input(check, field, "PLY file", path, Format::Ply, MAX_PLY_BYTES)?;
    let bad = |message: String| check.error(field, format!("{}: {message}", path.display()));
    let bytes = std::fs::read(path).map_err(|e| bad(format!("cannot read PLY: {e}")))?;
    let mesh = super::ply::parse(&bytes).map_err(|e| bad(format!("cannot read PLY: {e}")))?;
    let normal_matrix = m.matrix3.inverse().transpose();
    let mut primitives = Vec::with_capacity(mesh.triangles.len());
    let mut texcoords = Vec::with_capacity(mesh.triangles.len());
    for tri in &mesh.triangles {
        let p = tri.map(|i| m.transform_point3(mesh.positions[i as usize]));
        if (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0 {
            continue;
        }
        let n = match &mesh.normals {
            Some(ns) => tri.map(|i| (normal_matrix * ns[i as usize]).normalize_or_zero()),
            None => [Vec3::ZERO; 3],
        };
        primitives.push(Primitive::Triangle { p, n });
        if let Some(uvs) = &mesh.uvs {
            texcoords.push(tri.map(|i| uvs[i as usize]));
        }
    }
    if primitives.is_empty() {
        return Err(bad("holds only degenerate triangles".into()));
    }
    Ok(BuiltShape {
        primitives,
        texcoords: mesh.uvs.is_some().then_some(texcoords),
        keys: None,
        uv_axes: None,
    })
}

/// The triangles gathered from the models of one OBJ file so far.
struct ObjTriangles {
    prims: Vec<Primitive>,
    /// One entry per triangle, barycentric for models without `vt` lines.
    texcoords: Vec<[Vec2; 3]>,
    /// Carries normals to world space (inverse transpose of `m`).
    normal_matrix: glam::Mat3A,
}

impl ObjTriangles {
    /// Adds the non-degenerate triangles of `model`; returns whether it has texture coordinates.
    fn append_model(
        &mut self,
        model: &tobj::Model,
        m: &Affine3A,
        bad: &impl Fn(String) -> Error,
    ) -> Result<bool> {
        let mesh = &model.mesh;
        let has_uv = !mesh.texcoords.is_empty();
        let vertex = |i: u32| -> Option<Vec3> {
            let k = 3 * i as usize;
            let p = Vec3::new(
                *mesh.positions.get(k)?,
                *mesh.positions.get(k + 1)?,
                *mesh.positions.get(k + 2)?,
            );
            Some(m.transform_point3(p))
        };
        let normal = |i: u32| -> Vec3 {
            let k = 3 * i as usize;
            match mesh.normals.get(k..k + 3) {
                Some(n) => (self.normal_matrix * Vec3::new(n[0], n[1], n[2])).normalize_or_zero(),
                None => Vec3::ZERO,
            }
        };
        for tri in mesh.indices.chunks_exact(3) {
            let out_of_range = || bad(format!("model {:?}: face index out of range", model.name));
            let p = [
                vertex(tri[0]).ok_or_else(out_of_range)?,
                vertex(tri[1]).ok_or_else(out_of_range)?,
                vertex(tri[2]).ok_or_else(out_of_range)?,
            ];
            if !p.iter().all(|v| v.is_finite()) {
                return Err(bad(format!("model {:?}: non-finite vertex", model.name)));
            }
            if (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0 {
                continue;
            }
            let n = [normal(tri[0]), normal(tri[1]), normal(tri[2])];
            self.prims.push(Primitive::Triangle { p, n });
            let uv = if has_uv {
                triangle_uv(model, tri, bad)?
            } else {
                crate::geometry::BARYCENTRIC_UV
            };
            self.texcoords.push(uv);
        }
        Ok(has_uv)
    }
}

/// The checked `vt` coordinates of the corners `tri` of a model that has them.
fn triangle_uv(
    model: &tobj::Model,
    tri: &[u32],
    bad: &impl Fn(String) -> Error,
) -> Result<[Vec2; 3]> {
    let texcoords = &model.mesh.texcoords;
    let uv = |i: u32| -> Option<Vec2> {
        let k = 2 * i as usize;
        Some(Vec2::new(*texcoords.get(k)?, *texcoords.get(k + 1)?))
    };
    let [Some(a), Some(b), Some(c)] = [uv(tri[0]), uv(tri[1]), uv(tri[2])] else {
        return Err(bad(format!(
            "model {:?}: texture coordinate index out of range",
            model.name
        )));
    };
    if !(a.is_finite() && b.is_finite() && c.is_finite()) {
        return Err(bad(format!(
            "model {:?}: non-finite texture coordinate",
            model.name
        )));
    }
    Ok([a, b, c])
}
