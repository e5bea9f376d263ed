//! Turning `[[medium]]` entries into media.

use super::coefficients::{build_phase, check_emission, coefficients};
use super::description::{BoundsDesc, MediumDesc};
use super::shapes::build_transform;
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
use crate::math::Bounds3;
use crate::medium::{HomogeneousMedium, Medium, Region};
use std::path::Path;

/// The region of a bounded medium, or all space with `global = true`.
fn build_region(
    bounds: Option<&BoundsDesc>,
    global: bool,
    transform: Option<&super::description::TransformDesc>,
    field: &str,
    check: &Check,
) -> Result<Region> {
    match (bounds, global) {
        (Some(_), true) => {
            Err(check.error(&format!("{field}.global"), "a global medium has no bounds"))
        }
        (None, false) => Err(check.error(field, "needs bounds (box or sphere) or global = true")),
        (None, true) => {
            if transform.is_some() {
                return Err(check.error(
                    &format!("{field}.transform"),
                    "a global medium has no transform",
                ));
            }
            Ok(Region::Everywhere)
        }
        (Some(b), false) => {
            let to_world = build_transform(transform, field, check)?;
            let world_to_local = to_world.inverse();
            Ok(match b {
                BoundsDesc::Box { min, max } => {
                    let min = check.vec3(&format!("{field}.bounds.min"), *min)?;
                    let max = check.vec3(&format!("{field}.bounds.max"), *max)?;
                    if !(min.cmplt(max).all()) {
                        return Err(check.error(
                            &format!("{field}.bounds"),
                            "min must be below max on every axis",
                        ));
                    }
                    Region::boxed(world_to_local, Bounds3 { min, max })
                }
                BoundsDesc::Sphere { center, radius } => Region::Sphere {
                    world_to_local,
                    center: check.vec3(&format!("{field}.bounds.center"), *center)?,
                    radius: check.positive(&format!("{field}.bounds.radius"), *radius)?,
                },
            })
        }
    }
}

/// The medium of one `[[medium]]` entry.
pub(crate) fn build_medium(
    desc: &MediumDesc,
    field: &str,
    check: &Check,
    base: &Path,
    timing: &super::animation::Timing,
) -> Result<Medium> {
    match desc {
        MediumDesc::Homogeneous {
            sigma_a,
            sigma_s,
            sigma_t,
            albedo,
            emission,
            phase,
            bounds,
            global,
            transform,
        } => {
            let (sigma_a, sigma_s) =
                coefficients(*sigma_a, *sigma_s, *sigma_t, *albedo, field, check)?;
            let emission = match emission {
                Some(e) => check.color(&format!("{field}.emission"), *e)?,
                None => Rgb::BLACK,
            };
            if !emission.is_black() {
                check_emission(field, sigma_a, emission, check)?;
            }
            // Moving: the region is built in its local frame, placed per time.
            let keys = super::keyframes::moving_keys(transform.as_ref(), field, check)?;
            let region_transform = match (&keys, *global) {
                (Some(_), false) => None,
                _ => transform.as_ref(),
            };
            let medium = Medium::Homogeneous(HomogeneousMedium {
                sigma_a,
                sigma_s,
                emission,
                phase: build_phase(phase.as_ref(), field, check)?,
                region: build_region(bounds.as_ref(), *global, region_transform, field, check)?,
            });
            Ok(medium.moved_by(keys))
        }
        MediumDesc::HeightFog { .. } => super::fog::build_height_fog(desc, field, check),
        MediumDesc::Vdb(vdb) => super::vdb::build_vdb_medium(vdb, field, check, base, timing),
        MediumDesc::Vol(vol) => super::vol::build_vol_medium(vol, field, check, base, timing),
    }
}
