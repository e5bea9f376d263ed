//! `[slab]` (the box `brume slab bake` records) and `type = "slab"` shapes
//! (a baked slab placed in a scene), checked in the user's words.

use super::description::{SceneDesc, ShapeDesc, SlabDesc};
use super::validate::Check;
use super::{resolve, shapes};
use crate::error::Result;
use crate::geometry::slab::{Filter, Grid, LightSlab, SlabShape};
use crate::math::{Bounds3, Vec3};
use std::path::Path;

/// Nodes per position axis when `[slab] spatial` is not given: about one
/// node per 5 pixels of a box filling half of a 512² view.
pub const DEFAULT_SPATIAL: u32 = 64;
/// Nodes per slope axis when `[slab] angular` is not given: a slope step of 2/15.
pub const DEFAULT_ANGULAR: u32 = 16;

/// What `[slab]` asks to bake: the box and the grid of lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabSpec {
    /// The box, in the scene's space.
    pub bounds: Bounds3,
    /// Nodes per axis.
    pub grid: Grid,
}

/// The `[slab]` table, checked; `None` without one.
pub(super) fn build_slab_table(desc: &SceneDesc, check: &Check) -> Result<Option<SlabSpec>> {
    let Some(s) = &desc.slab else {
        return Ok(None);
    };
    Ok(Some(slab_spec(s, check)?))
}

fn slab_spec(s: &SlabDesc, check: &Check) -> Result<SlabSpec> {
    let min = check.vec3("slab.min", s.min)?;
    let max = check.vec3("slab.max", s.max)?;
    for (axis, name) in ["x", "y", "z"].iter().enumerate() {
        if min[axis] >= max[axis] {
            return Err(check.error(
                "slab.max",
                format!(
                    "must be above slab.min on every axis, but {name} is {} for max and {} for min",
                    max[axis], min[axis]
                ),
            ));
        }
    }
    let nodes = |key: &str, v: Option<u32>, default: u32| -> Result<u32> {
        let v = v.unwrap_or(default);
        let max = crate::geometry::slab::format::MAX_NODES;
        if !(2..=max).contains(&v) {
            return Err(check.error(
                key,
                format!("must be a whole number from 2 to {max} (nodes per axis, edges included), got {v}"),
            ));
        }
        Ok(v)
    };
    Ok(SlabSpec {
        bounds: Bounds3::new(min, max),
        grid: Grid {
            spatial: nodes("slab.spatial", s.spatial, DEFAULT_SPATIAL)?,
            angular: nodes("slab.angular", s.angular, DEFAULT_ANGULAR)?,
        },
    })
}

/// The keys a slab shape does not take: it has no surface, light or medium.
fn refuse_surface_keys(shape: &ShapeDesc, field: &str, check: &Check) -> Result<()> {
    let present = [
        ("material", shape.material.is_some()),
        ("emission", shape.emission.is_some()),
        ("two_sided", shape.two_sided),
        ("interior", shape.interior.is_some()),
    ];
    for (key, set) in present {
        if set {
            return Err(check.error(
                &format!("{field}.{key}"),
                "a slab shape takes only file, filter and transform: its light was baked \
                 (the viewing scene's lights do not relight it)",
            ));
        }
    }
    Ok(())
}

/// A `type = "slab"` shape: its file read and placed by its transform.
pub(super) fn build_slab_shape(
    shape: &ShapeDesc,
    (index, field): (u32, &str),
    check: &Check,
    (base, cache): (&Path, &super::InputCache),
) -> Result<SlabShape> {
    refuse_surface_keys(shape, field, check)?;
    let filter = match shape.filter.as_deref() {
        None | Some("quadrilinear") => Filter::Quadrilinear,
        Some("nearest") => Filter::Nearest,
        Some(other) => {
            return Err(check.error(
                &format!("{field}.filter"),
                format!("expected \"quadrilinear\" or \"nearest\", got {:?}", other),
            ))
        }
    };
    let file = shape
        .file
        .as_ref()
        .ok_or_else(|| check.error(&format!("{field}.file"), "missing (the .slab file to show)"))?;
    let path = resolve(base, file);
    let key = format!("{field}.file");
    if let Some(problem) = crate::error::input_file_problem(&path, u64::MAX) {
        return Err(check.error(
            &key,
            format!("cannot read slab file {}: {problem}", path.display()),
        ));
    }
    let slab = cache
        .slab(&path, || LightSlab::read(&path))
        .map_err(|problem| check.error(&key, format!("{} {problem}", path.display())))?;
    let to_world = shapes::build_transform(shape.transform.as_ref(), field, check)?;
    Ok(SlabShape::new(index, slab, to_world, filter))
}

/// Refuses a scene whose camera is inside a slab's box, or that renders
/// slabs with what cannot show them.
pub(super) fn check_slab_use(
    desc: &SceneDesc,
    slabs: &[SlabShape],
    camera: Vec3,
    check: &Check,
) -> Result<()> {
    for s in slabs {
        let field = format!("shape[{}]", s.shape);
        if s.contains(camera) {
            let b = s.bounds();
            return Err(check.error(
                &field,
                format!(
                    "the camera (camera.position {}) is inside this slab's box ({} to {}); \
                     a slab records light leaving its box and is seen from outside only",
                    vec3_words(camera),
                    vec3_words(b.min),
                    vec3_words(b.max)
                ),
            ));
        }
        if desc.integrator.kind != "path" {
            return Err(check.error(
                &field,
                format!(
                    "integrator.type = {:?} cannot show a slab; slabs are shown by the path tracer (type = \"path\")",
                    desc.integrator.kind
                ),
            ));
        }
        if !desc.film.aovs.is_empty() {
            return Err(check.error(
                &field,
                "the AOVs (film.aovs) do not see slabs yet; render a scene with slabs without AOVs",
            ));
        }
    }
    Ok(())
}

/// `[x, y, z]` as a scene file writes it.
fn vec3_words(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}
