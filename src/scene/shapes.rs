//! Turning `[[shape]]` entries (and OBJ files) into primitives.

use super::description::{ShapeDesc, ShapeType, TransformDesc};
use super::files::{check_input, Format};
use super::resolve;
use super::validate::Check;
use crate::error::Result;
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
        ShapeType::Sphere => &["center", "radius"],
        ShapeType::Quad => &["center", "normal", "size", "u_axis"],
        ShapeType::Box => &["center", "size"],
        ShapeType::Mesh => &["file"],
    };
    let present = [
        ("center", shape.center.is_some()),
        ("radius", shape.radius.is_some()),
        ("normal", shape.normal.is_some()),
        ("size", shape.size.is_some()),
        ("u_axis", shape.u_axis.is_some()),
        ("file", shape.file.is_some()),
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
    let size = |n: usize| -> Result<Vec<f32>> {
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
    };
    let parallelogram = |c: Vec3, eu: Vec3, ev: Vec3| Primitive::Parallelogram {
        corner: m.transform_point3(c - 0.5 * (eu + ev)),
        edge_u: m.transform_vector3(eu),
        edge_v: m.transform_vector3(ev),
    };
    let primitives = match shape.kind {
        ShapeType::Sphere => {
            let radius = check.positive(
                &format!("{field}.radius"),
                required(shape.radius, field, "radius", check)?,
            )?;
            let (scale, _, _) = m.to_scale_rotation_translation();
            if (scale.max_element() - scale.min_element()).abs() > 1e-5 * scale.max_element() {
                return Err(check.error(
                    &format!("{field}.transform.scale"),
                    "a sphere needs a uniform scale",
                ));
            }
            vec![Primitive::Sphere {
                center: m.transform_point3(center),
                radius: radius * scale.x,
            }]
        }
        ShapeType::Quad => {
            let normal = check.direction(
                &format!("{field}.normal"),
                required(shape.normal, field, "normal", check)?,
            )?;
            let s = size(2)?;
            let u_dir = match shape.u_axis {
                Some(u) => {
                    let u = check.direction(&format!("{field}.u_axis"), u)?;
                    (u - normal * u.dot(normal))
                        .try_normalize()
                        .ok_or_else(|| {
                            check.error(&format!("{field}.u_axis"), "is parallel to the normal")
                        })?
                }
                None => Frame::from_z(normal).x,
            };
            let v_dir = normal.cross(u_dir);
            // edge_u × edge_v must point along the normal: u × (n × u) = n.
            vec![parallelogram(center, u_dir * s[0], v_dir * s[1])]
        }
        ShapeType::Box => {
            let s = size(3)?;
            let h = Vec3::new(s[0], s[1], s[2]) * 0.5;
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
                    faces.push(parallelogram(center + n * h[axis], eu, ev));
                }
            }
            faces
        }
        ShapeType::Mesh => {
            let file = shape
                .file
                .as_ref()
                .ok_or_else(|| check.error(&format!("{field}.file"), "missing"))?;
            let path = resolve(base, file);
            let mesh = load_obj(&path, &m, &format!("{field}.file"), check)?;
            return Ok(BuiltShape { keys, ..mesh });
        }
    };
    Ok(BuiltShape {
        primitives,
        texcoords: None,
        keys,
    })
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
    let normal_matrix = m.matrix3.inverse().transpose();
    let mut prims = Vec::new();
    let mut texcoords = Vec::new();
    let mut all_have_uv = true;
    for model in &models {
        let mesh = &model.mesh;
        let has_uv = !mesh.texcoords.is_empty();
        all_have_uv &= has_uv;
        let uv = |i: u32| -> Option<Vec2> {
            let k = 2 * i as usize;
            Some(Vec2::new(
                *mesh.texcoords.get(k)?,
                *mesh.texcoords.get(k + 1)?,
            ))
        };
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
                Some(n) => (normal_matrix * Vec3::new(n[0], n[1], n[2])).normalize_or_zero(),
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
            prims.push(Primitive::Triangle {
                p,
                n: [normal(tri[0]), normal(tri[1]), normal(tri[2])],
            });
            if has_uv {
                let t = [uv(tri[0]), uv(tri[1]), uv(tri[2])];
                let [Some(a), Some(b), Some(c)] = t else {
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
                texcoords.push([a, b, c]);
            } else {
                texcoords.push(crate::geometry::BARYCENTRIC_UV);
            }
        }
    }
    if prims.is_empty() {
        return Err(bad(
            "holds no triangles (no face `f` with 3 or more vertices): is it a Wavefront OBJ file?"
                .into(),
        ));
    }
    Ok(BuiltShape {
        primitives: prims,
        texcoords: all_have_uv.then_some(texcoords),
        keys: None,
    })
}
