//! `[[shape]] interior = { ... }`: the medium filling a closed shape.
//!
//! ```toml
//! [[shape]]
//! type = "mesh"
//! file = "cube.obj"
//! interior = { type = "homogeneous", sigma_t = 2.0, albedo = 0.8 }
//! ```
//!
//! A shape without `material` is an index-matched boundary: it is not a
//! surface at all, only the bounds of its medium. With a dielectric
//! `material` it is also a glass surface. See `medium::interior`.

use super::coefficients::{build_phase, coefficients, warn_inert_emission};
use super::description::{MediumDesc, ShapeDesc, ShapeType};
use super::shapes::build_transform;
use super::validate::Check;
use crate::error::Result;
use crate::geometry::closed::ClosedMesh;
use crate::geometry::Primitive;
use crate::math::color::Rgb;
use crate::math::{Affine3A, Bounds3, Vec3};
use crate::medium::{
    HomogeneousMedium, InteriorContent, InteriorMedium, Medium, Region, ShapeMask,
};
use std::path::Path;
use std::sync::Arc;

/// How the shape's surface treats rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Boundary {
    /// No surface: the shape only bounds its medium.
    IndexMatched,
    /// A dielectric surface that rays refract through.
    Dielectric,
}

/// The boundary kind of a shape with an interior, refusing materials that would hide it.
pub(crate) fn boundary(shape: &ShapeDesc, field: &str, check: &Check) -> Result<Boundary> {
    if shape.emission.is_some() {
        return Err(check.error(
            &format!("{field}.emission"),
            "a shape with an interior cannot emit; put the emission in the interior medium",
        ));
    }
    match &shape.material {
        None => Ok(Boundary::IndexMatched),
        Some(super::description::MaterialDesc::Dielectric { .. }) => Ok(Boundary::Dielectric),
        Some(_) => Err(check.error(
            &format!("{field}.material"),
            "a shape with an interior needs a dielectric material (light must get in), \
             or no material for an index-matched (invisible) boundary",
        )),
    }
}

/// The medium inside `shape`, whose world-space primitives are `prims`.
pub(crate) fn build_interior(
    shape: &ShapeDesc,
    prims: &[Primitive],
    field: &str,
    check: &Check,
    base: &Path,
    timing: &super::animation::Timing,
) -> Result<Option<Medium>> {
    let Some(desc) = &shape.interior else {
        return Ok(None);
    };
    let f = format!("{field}.interior");
    let mask = build_mask(shape, prims, field, check, base)?;
    check_winding(shape, &mask, field, check)?;
    let content = match desc {
        MediumDesc::Homogeneous {
            bounds,
            global,
            transform,
            ..
        } => {
            reject_placement_keys(bounds.is_some(), *global, transform.is_some(), &f, check)?;
            let medium = homogeneous_interior(desc, &f, check)?;
            // A sphere or box is a region already: the plain bounded medium, no mask needed.
            if let ShapeMask::Region(region) = mask {
                return Ok(Some(Medium::Homogeneous(HomogeneousMedium {
                    region,
                    ..medium
                })));
            }
            InteriorContent::Homogeneous(medium)
        }
        MediumDesc::Vdb(vdb) => match super::vdb::build_vdb_medium(vdb, &f, check, base, timing)? {
            Medium::Grid(grid) => InteriorContent::Grid(grid),
            _ => unreachable!("a vdb description builds a grid medium"),
        },
        MediumDesc::Vol(vol) => match super::vol::build_vol_medium(vol, &f, check, base, timing)? {
            Medium::Grid(grid) => InteriorContent::Grid(grid),
            _ => return Err(check.error(&f, "a vol interior cannot have keyframes")),
        },
        MediumDesc::HeightFog { .. } => {
            return Err(check.error(
                &f,
                "height fog fills all space; an interior is `homogeneous`, `vdb` or `vol`",
            ))
        }
    };
    Ok(Some(Medium::Interior(Arc::new(InteriorMedium {
        content,
        mask,
    }))))
}

/// Refuses an inward-wound mesh behind a dielectric boundary.
fn check_winding(shape: &ShapeDesc, mask: &ShapeMask, field: &str, check: &Check) -> Result<()> {
    if let ShapeMask::Mesh(mesh) = mask {
        // A dielectric's normal side is outside: an inward-wound glass would be inside out.
        if boundary(shape, field, check)? == Boundary::Dielectric && !mesh.is_outward() {
            return Err(check.error(
                &format!("{field}.file"),
                "the mesh is wound inward (clockwise seen from outside); a dielectric boundary \
                 needs outward normals: reverse the order of each face's vertices",
            ));
        }
    }
    Ok(())
}

/// Refuses `bounds`, `global` and `transform` on an interior (`f`), which its shape sets.
fn reject_placement_keys(
    bounds: bool,
    global: bool,
    transform: bool,
    f: &str,
    check: &Check,
) -> Result<()> {
    for (key, set) in [
        ("bounds", bounds),
        ("global", global),
        ("transform", transform),
    ] {
        if set {
            return Err(check.error(
                &format!("{f}.{key}"),
                "an interior medium is bounded and placed by its shape; remove this key",
            ));
        }
    }
    Ok(())
}

/// The coefficients, emission and phase of a homogeneous interior `desc` (at `f`), filling all space.
fn homogeneous_interior(desc: &MediumDesc, f: &str, check: &Check) -> Result<HomogeneousMedium> {
    let MediumDesc::Homogeneous {
        sigma_a,
        sigma_s,
        sigma_t,
        albedo,
        emission,
        phase,
        ..
    } = desc
    else {
        unreachable!("called on a homogeneous description only")
    };
    let (sigma_a, sigma_s) = coefficients(*sigma_a, *sigma_s, *sigma_t, *albedo, f, check)?;
    let emission = match emission {
        Some(e) => check.color(&format!("{f}.emission"), *e)?,
        None => Rgb::BLACK,
    };
    if !emission.is_black() {
        warn_inert_emission(f, sigma_a, check);
    }
    Ok(HomogeneousMedium {
        sigma_a,
        sigma_s,
        emission,
        phase: build_phase(phase.as_ref(), f, check)?,
        region: Region::Everywhere,
    })
}

/// The closed volume of a sphere, box or mesh shape.
fn build_mask(
    shape: &ShapeDesc,
    prims: &[Primitive],
    field: &str,
    check: &Check,
    base: &Path,
) -> Result<ShapeMask> {
    match shape.kind {
        ShapeType::Sphere => match prims {
            [Primitive::Sphere { center, radius }] => Ok(ShapeMask::Region(Region::Sphere {
                world_to_local: Affine3A::IDENTITY,
                center: *center,
                radius: *radius,
            })),
            _ => unreachable!("a sphere shape is one sphere primitive"),
        },
        ShapeType::Box => {
            // Already validated by build_shape.
            let center = Vec3::from_array(shape.center.unwrap_or([0.0; 3]));
            let size = shape.size.as_deref().unwrap_or(&[]);
            let half = Vec3::new(size[0], size[1], size[2]) * 0.5;
            let to_world = build_transform(shape.transform.as_ref(), field, check)?
                * Affine3A::from_translation(center);
            Ok(ShapeMask::Region(Region::boxed(
                to_world.inverse(),
                Bounds3::new(-half, half),
            )))
        }
        ShapeType::Mesh => {
            let file = shape.file.as_deref().unwrap_or(Path::new(""));
            ClosedMesh::new(prims.to_vec())
                .map(|m| ShapeMask::Mesh(Arc::new(m)))
                .map_err(|e| {
                    check.error(
                        &format!("{field}.interior"),
                        format!("{}: {e}", super::resolve(base, file).display()),
                    )
                })
        }
        ShapeType::Slab => Err(check.error(
            &format!("{field}.interior"),
            "a slab's box holds baked light, not a medium; bake the medium into it instead",
        )),
        ShapeType::Quad | ShapeType::Disk => Err(check.error(
            &format!("{field}.interior"),
            format!(
                "a {} encloses no volume; an interior needs a sphere, box or closed mesh",
                if shape.kind == ShapeType::Quad {
                    "quad"
                } else {
                    "disk"
                }
            ),
        )),
    }
}
